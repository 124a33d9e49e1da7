//! Tests of skeleton extraction and bone-heat weights on procedural shapes.

use glam::{DVec3, Vec3};

use super::extract::{skeletonize, Skeleton, SkeletonizeParams};
use super::shapes;

fn degree(sk: &Skeleton, j: usize) -> usize {
    sk.children(j).count() + usize::from(sk.parents[j].is_some())
}

fn dump(sk: &Skeleton) -> String {
    let mut s = String::new();
    for j in 0..sk.len() {
        s += &format!(
            "{j:3} {:14} parent {:?} pos ({:.3}, {:.3}, {:.3})\n",
            sk.names[j], sk.parents[j], sk.positions[j].x, sk.positions[j].y, sk.positions[j].z
        );
    }
    s
}

#[test]
fn explore() {
    let p = SkeletonizeParams::default();
    for (name, m) in [
        ("capsule", shapes::capsule(Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), 0.2, 24)),
        ("plus", shapes::plus(1.0, 0.15, 24)),
        ("star5", shapes::star(5, 1.0, 0.12, 24)),
        ("humanoid", shapes::humanoid(24)),
    ] {
        let sk = skeletonize(&m, &p).unwrap();
        let _ = (degree(&sk, 0), DVec3::ZERO);
        println!("== {name}: {} verts\n{}", m.positions.len(), dump(&sk));
    }
}
