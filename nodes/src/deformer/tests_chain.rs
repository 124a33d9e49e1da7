//! Deformer chains: the order is the connection order, and reordering two deformers gives the
//! expected, different result.

use std::f32::consts::{FRAC_1_SQRT_2, PI};
use std::sync::Arc;

use glam::{DMat4, DVec3, Vec3};
use sinew_core::{Graph, Mesh};

use super::testing::{both, graph, set};

/// `mesh → first → second`, each a node named by the pair (name, type).
fn chain(m: Mesh, first: (&str, &str), second: (&str, &str)) -> Graph {
    let mut g = graph();
    g.add_node("mesh", "body").unwrap();
    set(&mut g, "body.inMesh", Arc::new(m));
    for (name, ty) in [first, second] {
        if g.node_id(name).is_err() {
            g.add_node(ty, name).unwrap();
        }
    }
    g.connect_path("body.outMesh", &format!("{}.inputGeometry", first.0))
        .unwrap();
    g.connect_path(
        &format!("{}.outputGeometry", first.0),
        &format!("{}.inputGeometry", second.0),
    )
    .unwrap();
    g
}

fn point(p: Vec3) -> Mesh {
    Mesh {
        positions: vec![p, p + Vec3::Z],
        ..Default::default()
    }
}

#[test]
fn scale_then_translate_differs_from_translate_then_scale() {
    let setup = |g: &mut Graph| {
        set(g, "scale.matrix", DMat4::from_scale(DVec3::splat(2.0)));
        set(g, "move.matrix", DMat4::from_translation(DVec3::X));
    };
    let p = Vec3::new(1.0, 0.5, 0.0);
    let mut a = chain(point(p), ("scale", "cluster"), ("move", "cluster"));
    setup(&mut a);
    // 2p + x.
    assert_eq!(
        both(&mut a, "move.outputGeometry").positions[0],
        Vec3::new(3.0, 1.0, 0.0)
    );
    let mut b = chain(point(p), ("move", "cluster"), ("scale", "cluster"));
    setup(&mut b);
    // 2(p + x).
    assert_eq!(
        both(&mut b, "scale.outputGeometry").positions[0],
        Vec3::new(4.0, 1.0, 0.0)
    );
}

#[test]
fn cluster_and_bend_in_either_order() {
    let setup = |g: &mut Graph| {
        g.add_node("deformBend", "h").unwrap();
        g.connect_path("h.deformerData", "bend.deformerData").unwrap();
        set(g, "h.curvature", 90.0);
        set(g, "h.lowBound", 0.0);
        set(g, "move.matrix", DMat4::from_translation(DVec3::Y * 0.5));
    };
    let r = 2.0 / PI;
    let p = Vec3::new(0.0, 0.5, 0.0);
    // Move first: the point reaches y = 1, the bar's end, which the bend puts at (r, r).
    let mut a = chain(point(p), ("move", "cluster"), ("bend", "nonLinear"));
    setup(&mut a);
    let got = both(&mut a, "bend.outputGeometry").positions[0];
    assert!((got - Vec3::new(r, r, 0.0)).length() < 1e-6, "{got}");
    // Bend first: y = 0.5 is 45° round the arc, then moved up by 0.5.
    let mut b = chain(point(p), ("bend", "nonLinear"), ("move", "cluster"));
    setup(&mut b);
    let got = both(&mut b, "move.outputGeometry").positions[0];
    let want = Vec3::new(r * (1.0 - FRAC_1_SQRT_2), r * FRAC_1_SQRT_2 + 0.5, 0.0);
    assert!((got - want).length() < 1e-6, "{got} vs {want}");
}
