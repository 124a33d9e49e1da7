//! Prints a fingerprint (a hash of every bit) of the skeleton and the bone-heat weights
//! of a dozen procedural meshes, and of the volume stages' intermediate results, so a
//! speed change can be checked to leave the results bit for bit the same: run it before
//! and after and compare the output.
//!
//! Run: `cargo run --profile bench-quick -p sinew-nodes --example skeletonize_fingerprint`.

use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};

use glam::Vec3;
use sinew_core::Mesh;
use sinew_nodes::skeletonize::volume::curve_graph;
use sinew_nodes::skeletonize::{bone_heat_weights, shapes, skeletonize, SkeletonizeParams, Template, WeightParams};

/// The meshes: humanoids of several densities, stars, a plus, a torus, separate parts.
fn meshes() -> Vec<(String, Mesh)> {
    let mut out: Vec<(String, Mesh)> = [300, 2_000, 20_000]
        .iter()
        .map(|&n| (format!("humanoid_near({n})"), shapes::humanoid_near(n)))
        .collect();
    out.push(("humanoid(12)".into(), shapes::humanoid(12)));
    out.push(("star(5)".into(), shapes::star(5, 1.0, 0.12, 16)));
    out.push(("star(3)".into(), shapes::star(3, 1.0, 0.2, 12)));
    out.push(("plus".into(), shapes::plus(1.0, 0.15, 16)));
    out.push(("torus".into(), shapes::torus(1.0, 0.25, 32, 12)));
    out.push((
        "bent limb".into(),
        shapes::merge(&[
            shapes::capsule(Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0), 0.1, 16),
            shapes::capsule(Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.3, 0.8, 0.1), 0.08, 16),
        ]),
    ));
    out.push((
        "separate parts".into(),
        shapes::merge(&[
            shapes::capsule(Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 0.2, 16),
            shapes::capsule(Vec3::new(0.0, 1.5, 0.0), Vec3::new(0.0, 1.5, 0.0), 0.15, 16),
        ]),
    ));
    let mut open = shapes::humanoid(16);
    open.triangles.truncate(open.triangles.len() - 7);
    out.push(("open humanoid".into(), open));
    out
}

fn hash_f64s(h: &mut DefaultHasher, xs: impl IntoIterator<Item = f64>) {
    for x in xs {
        x.to_bits().hash(h);
    }
}

fn main() {
    let wp = WeightParams::default();
    for (name, mesh) in meshes() {
        let mut h = DefaultHasher::new();
        let params = SkeletonizeParams::default();
        let vp = params.volume_params(params.resolution);
        let cells = match curve_graph(&mesh, &vp, true) {
            Some((g, report, solid)) => {
                solid.inside.hash(&mut h);
                solid.shell.hash(&mut h);
                hash_f64s(&mut h, g.points.iter().flat_map(|p| p.to_array()));
                hash_f64s(&mut h, g.radius.iter().copied());
                g.adj.hash(&mut h);
                g.alive.hash(&mut h);
                format!("{:?}", report.parts).hash(&mut h);
                format!("{:?}", report.mirror).hash(&mut h);
                report.mirror_mismatch.to_bits().hash(&mut h);
                report.cells
            }
            None => 0,
        };
        let mut joints = 0;
        for p in [
            params,
            SkeletonizeParams {
                bones_per_branch: Some(3),
                ..params
            },
            SkeletonizeParams {
                template: Some(Template::Humanoid),
                ..params
            },
        ] {
            match skeletonize(&mesh, &p) {
                Ok(s) => {
                    joints = joints.max(s.len());
                    s.names.hash(&mut h);
                    s.parents.hash(&mut h);
                    hash_f64s(&mut h, s.positions.iter().flat_map(|p| p.to_array()));
                    hash_f64s(&mut h, s.orientations.iter().flat_map(|q| q.to_array()));
                    match bone_heat_weights(&mesh, &s, &wp) {
                        Ok(w) => {
                            w.offsets.hash(&mut h);
                            w.joints.hash(&mut h);
                            w.weights.iter().map(|x| x.to_bits()).collect::<Vec<_>>().hash(&mut h);
                        }
                        Err(e) => e.to_string().hash(&mut h),
                    }
                }
                Err(e) => e.to_string().hash(&mut h),
            }
        }
        println!(
            "{name:<22} {:>7} vertices {cells:>7} cells {joints:>3} joints  {:016x}",
            mesh.positions.len(),
            h.finish()
        );
    }
}
