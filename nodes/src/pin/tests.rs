//! uvPin and proximityPin against closed forms: frames on a flat ribbon surface and on a
//! polyPlane, axis choices, normalized and raw parameters, the custom space; a rigidly moved
//! mesh carrying bound matrices (output = motion · input), offsets off, envelope; lazy ==
//! compiled.

use glam::{DMat3, DMat4, DQuat, DVec3};
use sinew_core::{Graph, Value};

use crate::nurbs::tests_eval::surface;
use crate::nurbs::tests_nodes::{assert_lazy_eq_compiled, close_m, getm, graph, set, surf};

/// A flat ribbon: u along +X (length 2), v along −Z (length 1), normal S_u × S_v = +Y.
fn ribbon(g: &mut Graph) {
    g.add_node("uvPin", "pin").unwrap();
    let s = surface(
        1,
        1,
        &[
            &[[0.0, 0.0, 0.0], [0.0, 0.0, -1.0]],
            &[[2.0, 0.0, 0.0], [2.0, 0.0, -1.0]],
        ],
    );
    set(g, "pin.deformedSurface", surf(s));
}

fn tr(x: f64, y: f64, z: f64) -> DMat4 {
    DMat4::from_translation(DVec3::new(x, y, z))
}

#[test]
fn uv_pin_on_a_surface() {
    let mut g = graph();
    ribbon(&mut g);
    set(&mut g, "pin.coordinateU[0]", 0.5);
    set(&mut g, "pin.coordinateV[0]", 0.5);
    // Defaults: normal x, tangent z → X = +Y (normal), Z = +X (u tangent), Y = Z × X = +Z.
    let frame = DMat3::from_cols(DVec3::Y, DVec3::Z, DVec3::X);
    let want = DMat4::from_mat3(frame) * DMat4::IDENTITY;
    let want = DMat4::from_cols(
        want.x_axis,
        want.y_axis,
        want.z_axis,
        DVec3::new(1.0, 0.0, -0.5).extend(1.0),
    );
    assert!(close_m(getm(&mut g, "pin.outputMatrix[0]"), want, 1e-15));
    // normal y, tangent x: the identity frame, as Maya ribbons set it (nrm 1).
    set(&mut g, "pin.nrm", Value::Enum(1));
    set(&mut g, "pin.tangentAxis", Value::Enum(0));
    set(&mut g, "pin.cu[1]", 1.0);
    assert!(close_m(getm(&mut g, "pin.omat[0]"), tr(1.0, 0.0, -0.5), 1e-15));
    assert!(
        close_m(getm(&mut g, "pin.outputMatrix[1]"), tr(2.0, 0.0, 0.0), 1e-15),
        "v missing counts as 0"
    );
    // negative axes: normal −y, tangent −x turns the frame 180° about Z
    set(&mut g, "pin.nrm", Value::Enum(4));
    set(&mut g, "pin.tangentAxis", Value::Enum(3));
    let m = getm(&mut g, "pin.omat[0]");
    let rot = DMat4::from_mat3(DMat3::from_cols(DVec3::NEG_X, DVec3::NEG_Y, DVec3::Z));
    assert!(close_m(m, tr(1.0, 0.0, -0.5) * rot, 1e-15), "{m}");
    set(&mut g, "pin.nrm", Value::Enum(1));
    set(&mut g, "pin.tangentAxis", Value::Enum(0));
    // custom space: relative to a parent at (1, 0, 0)
    set(&mut g, "pin.rsmd", Value::Enum(2));
    set(&mut g, "pin.relativeSpaceMatrix", tr(1.0, 0.0, 0.0));
    assert!(close_m(getm(&mut g, "pin.omat[0]"), tr(0.0, 0.0, -0.5), 1e-15));
    set(&mut g, "pin.rsmd", Value::Enum(0));
    // raw parameters: the same as fractions on a [0, 1] domain; out of range clamps
    set(&mut g, "pin.normalizedIsoParms", false);
    set(&mut g, "pin.cu[0]", 5.0);
    assert!(close_m(getm(&mut g, "pin.omat[0]"), tr(2.0, 0.0, -0.5), 1e-15));
    assert_lazy_eq_compiled(&mut g, &["pin.outputMatrix[0]", "pin.outputMatrix[1]"]);
}

/// Two cubic spans along u (domain [0, 2]): normalized 0.25 is parameter 0.5, raw 0.5 too.
#[test]
fn uv_pin_normalized_and_raw_parameters() {
    let mut g = graph();
    g.add_node("uvPin", "pin").unwrap();
    let rows: Vec<[[f64; 3]; 2]> = (0..5).map(|i| [[i as f64, 0.0, 0.0], [i as f64, 0.0, -1.0]]).collect();
    let rows: Vec<&[[f64; 3]]> = rows.iter().map(|r| &r[..]).collect();
    set(&mut g, "pin.deformedSurface", surf(surface(3, 1, &rows)));
    set(&mut g, "pin.cu[0]", 0.25);
    let a = getm(&mut g, "pin.omat[0]");
    set(&mut g, "pin.normalizedIsoParms", false);
    set(&mut g, "pin.cu[0]", 0.5);
    let b = getm(&mut g, "pin.omat[0]");
    assert_eq!(a, b);
    // Collinear, evenly spaced control points: the curve is linear in its knots' Greville
    // abscissae, not in the parameter; the point stays on the x axis between 0 and 4.
    assert!(a.w_axis.x > 0.0 && a.w_axis.x < 4.0 && a.w_axis.y == 0.0);
}

/// A 2 × 2 polyPlane (UV u = (x + 1)/2, v = (1 − z)/2, normal +Y, u tangent +X).
#[test]
fn uv_pin_on_a_mesh() {
    let mut g = graph();
    g.add_node("polyPlane", "plane").unwrap();
    set(&mut g, "plane.width", 2.0);
    set(&mut g, "plane.height", 2.0);
    g.add_node("uvPin", "pin").unwrap();
    g.connect_path("plane.output", "pin.deformedGeometry").unwrap();
    set(&mut g, "pin.normalAxis", Value::Enum(1));
    set(&mut g, "pin.tangentAxis", Value::Enum(0));
    set(&mut g, "pin.cu[0]", 0.75);
    set(&mut g, "pin.cv[0]", 0.25);
    assert!(close_m(getm(&mut g, "pin.omat[0]"), tr(0.5, 0.0, 0.5), 1e-6));
    // outside every UV triangle: identity
    set(&mut g, "pin.cu[1]", 3.0);
    assert_eq!(getm(&mut g, "pin.omat[1]"), DMat4::IDENTITY);
    // with the original mesh indexed: the same frame
    g.connect_path("plane.output", "pin.originalGeometry").unwrap();
    assert!(close_m(getm(&mut g, "pin.omat[0]"), tr(0.5, 0.0, 0.5), 1e-6));
    assert_lazy_eq_compiled(&mut g, &["pin.omat[0]", "pin.omat[1]"]);
}

/// A polyPlane moved rigidly by `T` (through a mesh node's worldMatrix): every bound matrix
/// follows, `output = T · input`.
fn proximity(g: &mut Graph, motion: DMat4) {
    g.add_node("polyPlane", "plane").unwrap();
    set(g, "plane.width", 2.0);
    set(g, "plane.height", 2.0);
    g.add_node("mesh", "moved").unwrap();
    g.connect_path("plane.output", "moved.inMesh").unwrap();
    set(g, "moved.worldMatrix", motion);
    g.add_node("proximityPin", "pp").unwrap();
    g.connect_path("plane.output", "pp.originalGeometry").unwrap();
    g.connect_path("moved.worldMesh", "pp.deformedGeometry").unwrap();
}

#[test]
fn proximity_pin_follows_a_moved_mesh() {
    let mut g = graph();
    let motion = DMat4::from_rotation_translation(DQuat::from_rotation_z(0.4), DVec3::new(1.0, 2.0, -0.5));
    proximity(&mut g, motion);
    let input = DMat4::from_rotation_translation(DQuat::from_rotation_y(0.5), DVec3::new(0.3, 0.5, 0.2));
    set(&mut g, "pp.inputMatrix[0]", input);
    for mode in [0, 1] {
        set(&mut g, "pp.coordMode", Value::Enum(mode));
        assert!(
            close_m(getm(&mut g, "pp.outputMatrix[0]"), motion * input, 1e-6),
            "mode {mode}"
        );
    }
    // offsets off (uv mode, normal y, tangent x: the frame on the plane is the identity)
    set(&mut g, "pp.normalAxis", Value::Enum(1));
    set(&mut g, "pp.tangentAxis", Value::Enum(0));
    set(&mut g, "pp.offsetTranslation", false);
    let on_surface = motion * DMat4::from_rotation_translation(DQuat::from_rotation_y(0.5), DVec3::new(0.3, 0.0, 0.2));
    assert!(close_m(getm(&mut g, "pp.omat[0]"), on_surface, 1e-6));
    set(&mut g, "pp.offsetOrientation", false);
    assert!(close_m(getm(&mut g, "pp.omat[0]"), motion * tr(0.3, 0.0, 0.2), 1e-6));
    set(&mut g, "pp.offsetTranslation", true);
    set(&mut g, "pp.offsetOrientation", true);
    // envelope 0: the input; ½: halfway in translation
    set(&mut g, "pp.envelope", 0.0);
    assert!(close_m(getm(&mut g, "pp.omat[0]"), input, 1e-12));
    set(&mut g, "pp.envelope", 0.5);
    let half = (input.w_axis + (motion * input).w_axis) / 2.0;
    assert!((getm(&mut g, "pp.omat[0]").w_axis - half).abs().max_element() < 1e-6);
    // an element without an input matrix: identity
    assert_eq!(getm(&mut g, "pp.omat[3]"), DMat4::IDENTITY);
    assert_lazy_eq_compiled(&mut g, &["pp.outputMatrix[0]", "pp.outputMatrix[3]"]);
}

/// No original mesh, or a deformed mesh with other triangles: the inputs pass through.
#[test]
fn proximity_pin_degenerate_input() {
    let mut g = graph();
    g.add_node("proximityPin", "pp").unwrap();
    set(&mut g, "pp.inputMatrix[0]", tr(1.0, 2.0, 3.0));
    assert_eq!(getm(&mut g, "pp.omat[0]"), tr(1.0, 2.0, 3.0));
    g.add_node("polyPlane", "a").unwrap();
    g.add_node("polyCube", "b").unwrap();
    g.connect_path("a.output", "pp.originalGeometry").unwrap();
    g.connect_path("b.output", "pp.deformedGeometry").unwrap();
    assert_eq!(getm(&mut g, "pp.omat[0]"), tr(1.0, 2.0, 3.0));
    assert_lazy_eq_compiled(&mut g, &["pp.outputMatrix[0]"]);
}
