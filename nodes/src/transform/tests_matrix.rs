//! Graph-level tests of the matrix utility nodes: decompose/compose,
//! multMatrix order, inverseMatrix fallback, pickMatrix, euler/quat,
//! blendMatrix stacking, aimMatrix modes, and lazy == compiled.

use std::f64::consts::FRAC_1_SQRT_2;

use glam::{DMat3, DMat4, DQuat, DVec3};
use proptest::prelude::*;
use sinew_core::{Graph, Value};

use super::euler::RotateOrder;
use super::tests_nodes::{assert_close, assert_lazy_compiled_same, graph, mat, set, v3, vec};

fn m(x: DMat4) -> Value {
    Value::Matrix(x)
}

fn quat(g: &mut Graph, path: &str) -> DQuat {
    match g.get_path(path).unwrap() {
        Value::Quat(q) => q,
        v => panic!("{path} is not a quat: {v:?}"),
    }
}

/// translate (1,2,3), rotate Z 90, scale (2,3,4), written out by hand:
/// X axis → 2·Y = (0,2,0), Y axis → 3·(-X) = (-3,0,0), Z axis → (0,0,4).
fn trs_by_hand() -> DMat4 {
    DMat4::from_cols(
        glam::DVec4::new(0.0, 2.0, 0.0, 0.0),
        glam::DVec4::new(-3.0, 0.0, 0.0, 0.0),
        glam::DVec4::new(0.0, 0.0, 4.0, 0.0),
        glam::DVec4::new(1.0, 2.0, 3.0, 1.0),
    )
}

#[test]
fn decompose_and_compose_known_matrix() {
    let mut g = graph();
    g.add_node("decomposeMatrix", "dm").unwrap();
    set(&mut g, "dm.inputMatrix", m(trs_by_hand()));
    assert_close(vec(&mut g, "dm.outputTranslate"), DVec3::new(1.0, 2.0, 3.0), 0.0, "t");
    assert_close(vec(&mut g, "dm.outputRotate"), DVec3::new(0.0, 0.0, 90.0), 1e-13, "r");
    assert_close(vec(&mut g, "dm.outputScale"), DVec3::new(2.0, 3.0, 4.0), 1e-15, "s");
    assert_close(vec(&mut g, "dm.outputShear"), DVec3::ZERO, 1e-15, "sh");
    // 90° about Z: (0, 0, sin 45°, cos 45°)
    let q = quat(&mut g, "dm.outputQuat");
    assert!(
        q.abs_diff_eq(DQuat::from_xyzw(0.0, 0.0, FRAC_1_SQRT_2, FRAC_1_SQRT_2), 1e-15)
            || q.abs_diff_eq(-DQuat::from_xyzw(0.0, 0.0, FRAC_1_SQRT_2, FRAC_1_SQRT_2), 1e-15)
    );

    g.add_node("composeMatrix", "cm").unwrap();
    set(&mut g, "cm.inputTranslate", v3(1.0, 2.0, 3.0));
    set(&mut g, "cm.inputRotate", v3(0.0, 0.0, 90.0));
    set(&mut g, "cm.inputScale", v3(2.0, 3.0, 4.0));
    assert!(mat(&mut g, "cm.outputMatrix").abs_diff_eq(trs_by_hand(), 1e-15));
    // the same from a quaternion
    set(&mut g, "cm.useEulerRotation", Value::Bool(false));
    set(
        &mut g,
        "cm.inputQuat",
        Value::Quat(DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2)),
    );
    assert!(mat(&mut g, "cm.outputMatrix").abs_diff_eq(trs_by_hand(), 1e-15));
    // shear xy = 1 (scale 1, no rotation): (0,1,0) → (1,1,0)
    set(&mut g, "cm.useEulerRotation", Value::Bool(true));
    set(&mut g, "cm.inputRotate", v3(0.0, 0.0, 0.0));
    set(&mut g, "cm.inputScale", v3(1.0, 1.0, 1.0));
    set(&mut g, "cm.inputShear", v3(1.0, 0.0, 0.0));
    let c = mat(&mut g, "cm.outputMatrix");
    assert_close(c.transform_vector3(DVec3::Y), DVec3::new(1.0, 1.0, 0.0), 0.0, "shear");
    // rotate order: (90,90,90) in zyx sends X to Z and Y to -Y (see tests_nodes)
    set(&mut g, "cm.inputShear", v3(0.0, 0.0, 0.0));
    set(&mut g, "cm.inputRotate", v3(90.0, 90.0, 90.0));
    set(&mut g, "cm.inputRotateOrder", Value::Enum(5));
    let c = mat(&mut g, "cm.outputMatrix");
    assert_close(c.transform_vector3(DVec3::X), DVec3::Z, 1e-15, "zyx X");
    assert_close(c.transform_vector3(DVec3::Y), -DVec3::Y, 1e-15, "zyx Y");
    assert_lazy_compiled_same(
        &mut g,
        &[
            "cm.outputMatrix",
            "dm.outputTranslate",
            "dm.outputRotate",
            "dm.outputScale",
            "dm.outputShear",
            "dm.outputQuat",
        ],
    );
}

fn order_strategy() -> impl Strategy<Value = i64> {
    0i64..6
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// composeMatrix → decomposeMatrix gives the inputs back for
    /// non-degenerate values: positive scale, angles inside the principal
    /// range (first/last in (-170°, 170°), middle in (-80°, 80°)).
    #[test]
    fn decompose_compose_roundtrip_through_nodes(
        order in order_strategy(),
        t in (-50.0..50.0, -50.0..50.0, -50.0..50.0),
        r in (-170.0..170.0, -170.0..170.0, -170.0..170.0),
        s in (0.1..5.0, 0.1..5.0, 0.1..5.0),
        sh in (-1.0..1.0, -1.0..1.0, -1.0..1.0),
    ) {
        let mut r = DVec3::new(r.0, r.1, r.2);
        let mid = RotateOrder::from_index(order).unwrap_or_default().axes()[1];
        r[mid] *= 80.0 / 170.0;
        let (t, s, sh) = (DVec3::new(t.0, t.1, t.2), DVec3::new(s.0, s.1, s.2), DVec3::new(sh.0, sh.1, sh.2));
        let mut g = graph();
        g.add_node("composeMatrix", "cm").unwrap();
        g.add_node("decomposeMatrix", "dm").unwrap();
        g.connect_path("cm.outputMatrix", "dm.inputMatrix").unwrap();
        set(&mut g, "cm.inputTranslate", Value::Vec3(t));
        set(&mut g, "cm.inputRotate", Value::Vec3(r));
        set(&mut g, "cm.inputScale", Value::Vec3(s));
        set(&mut g, "cm.inputShear", Value::Vec3(sh));
        set(&mut g, "cm.inputRotateOrder", Value::Enum(order));
        set(&mut g, "dm.inputRotateOrder", Value::Enum(order));
        prop_assert!((vec(&mut g, "dm.outputTranslate") - t).abs().max_element() < 1e-12);
        prop_assert!((vec(&mut g, "dm.outputRotate") - r).abs().max_element() < 1e-8);
        prop_assert!((vec(&mut g, "dm.outputScale") - s).abs().max_element() < 1e-12);
        prop_assert!((vec(&mut g, "dm.outputShear") - sh).abs().max_element() < 1e-12);
    }
}

/// matrixIn[0] = translate (1,0,0), matrixIn[1] = 90° about Z. Maya's
/// `m0 · m1` applies m0 first: the origin goes to (1,0,0), then turns to
/// (0,1,0). (The other order would leave it at (1,0,0).) A sparse element
/// [5] = scale 2 applies last: (0,2,0). No elements: identity.
#[test]
fn mult_matrix_applies_index_order() {
    let mut g = graph();
    g.add_node("multMatrix", "mm").unwrap();
    assert_eq!(mat(&mut g, "mm.matrixSum"), DMat4::IDENTITY);
    set(&mut g, "mm.matrixIn[0]", m(DMat4::from_translation(DVec3::X)));
    set(
        &mut g,
        "mm.matrixIn[1]",
        m(DMat4::from_rotation_z(std::f64::consts::FRAC_PI_2)),
    );
    let p = mat(&mut g, "mm.matrixSum").transform_point3(DVec3::ZERO);
    assert_close(p, DVec3::Y, 1e-15, "two");
    set(&mut g, "mm.matrixIn[5]", m(DMat4::from_scale(DVec3::splat(2.0))));
    let p = mat(&mut g, "mm.matrixSum").transform_point3(DVec3::ZERO);
    assert_close(p, DVec3::new(0.0, 2.0, 0.0), 1e-15, "three");
    assert_lazy_compiled_same(&mut g, &["mm.matrixSum"]);
}

/// inverse of translate (1,2,3) · scale 2 maps (3,4,5) = 2·(1,1,1) + (1,2,3)
/// back to (1,1,1). Singular (a zero scale, or all zeros) gives identity.
#[test]
fn inverse_matrix_and_singular_fallback() {
    let mut g = graph();
    g.add_node("inverseMatrix", "im").unwrap();
    let a = DMat4::from_translation(DVec3::new(1.0, 2.0, 3.0)) * DMat4::from_scale(DVec3::splat(2.0));
    set(&mut g, "im.inputMatrix", m(a));
    let inv = mat(&mut g, "im.outputMatrix");
    assert_close(
        inv.transform_point3(DVec3::new(3.0, 4.0, 5.0)),
        DVec3::ONE,
        1e-15,
        "inverse",
    );
    assert_lazy_compiled_same(&mut g, &["im.outputMatrix"]);
    set(
        &mut g,
        "im.inputMatrix",
        m(DMat4::from_scale(DVec3::new(1.0, 0.0, 1.0))),
    );
    assert_eq!(mat(&mut g, "im.outputMatrix"), DMat4::IDENTITY);
    set(&mut g, "im.inputMatrix", m(DMat4::ZERO));
    assert_eq!(mat(&mut g, "im.outputMatrix"), DMat4::IDENTITY);
    assert_lazy_compiled_same(&mut g, &["im.outputMatrix"]);
}

/// From translate (1,2,3), rotate Z 90, scale (2,3,4):
/// * useRotate off → T·S: X axis (2,0,0), Y axis (0,3,0), origin (1,2,3);
/// * useScale off → T·R: X axis (0,1,0), Y axis (-1,0,0);
/// * useTranslate off → origin at 0, axes unchanged;
/// * all on → the input, bit for bit.
#[test]
fn pick_matrix_components() {
    let mut g = graph();
    g.add_node("pickMatrix", "pm").unwrap();
    set(&mut g, "pm.inputMatrix", m(trs_by_hand()));
    assert_eq!(mat(&mut g, "pm.outputMatrix"), trs_by_hand());
    set(&mut g, "pm.useRotate", Value::Bool(false));
    let o = DMat3::from_mat4(mat(&mut g, "pm.outputMatrix"));
    assert_close(o.x_axis, DVec3::new(2.0, 0.0, 0.0), 1e-15, "no rot X");
    assert_close(o.y_axis, DVec3::new(0.0, 3.0, 0.0), 1e-15, "no rot Y");
    assert_close(
        mat(&mut g, "pm.outputMatrix").w_axis.truncate(),
        DVec3::new(1.0, 2.0, 3.0),
        0.0,
        "t",
    );
    set(&mut g, "pm.useRotate", Value::Bool(true));
    set(&mut g, "pm.useScale", Value::Bool(false));
    let o = DMat3::from_mat4(mat(&mut g, "pm.outputMatrix"));
    assert_close(o.x_axis, DVec3::Y, 1e-15, "no scale X");
    assert_close(o.y_axis, -DVec3::X, 1e-15, "no scale Y");
    set(&mut g, "pm.useScale", Value::Bool(true));
    set(&mut g, "pm.useTranslate", Value::Bool(false));
    let o = mat(&mut g, "pm.outputMatrix");
    assert_eq!(o.w_axis.truncate(), DVec3::ZERO);
    assert!(DMat3::from_mat4(o).abs_diff_eq(DMat3::from_mat4(trs_by_hand()), 1e-15));
    assert_lazy_compiled_same(&mut g, &["pm.outputMatrix"]);
    // Translation only (no decomposition needed): exactly the translation matrix.
    for flag in ["pm.useRotate", "pm.useScale", "pm.useShear"] {
        set(&mut g, flag, Value::Bool(false));
    }
    set(&mut g, "pm.useTranslate", Value::Bool(true));
    assert_eq!(
        mat(&mut g, "pm.outputMatrix"),
        DMat4::from_translation(DVec3::new(1.0, 2.0, 3.0))
    );
    assert_lazy_compiled_same(&mut g, &["pm.outputMatrix"]);
}

/// eulerToQuat (0,0,90) = (0,0,sin 45°,cos 45°); quatToEuler returns the
/// angles for an in-range rotation in every order; a zero quaternion gives 0.
#[test]
fn euler_quat_nodes() {
    let mut g = graph();
    g.add_node("eulerToQuat", "eq").unwrap();
    g.add_node("quatToEuler", "qe").unwrap();
    set(&mut g, "eq.inputRotate", v3(0.0, 0.0, 90.0));
    let q = quat(&mut g, "eq.outputQuat");
    assert!(q.abs_diff_eq(DQuat::from_xyzw(0.0, 0.0, FRAC_1_SQRT_2, FRAC_1_SQRT_2), 1e-15));
    g.connect_path("eq.outputQuat", "qe.inputQuat").unwrap();
    set(&mut g, "eq.inputRotate", v3(30.0, -45.0, 60.0));
    for order in 0..6 {
        set(&mut g, "eq.inputRotateOrder", Value::Enum(order));
        set(&mut g, "qe.inputRotateOrder", Value::Enum(order));
        assert_close(
            vec(&mut g, "qe.outputRotate"),
            DVec3::new(30.0, -45.0, 60.0),
            1e-12,
            "roundtrip",
        );
    }
    assert_lazy_compiled_same(&mut g, &["eq.outputQuat", "qe.outputRotate"]);
    g.disconnect_path("eq.outputQuat", "qe.inputQuat").unwrap();
    set(
        &mut g,
        "qe.inputQuat",
        Value::Quat(DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0)),
    );
    assert_eq!(vec(&mut g, "qe.outputRotate"), DVec3::ZERO);
}

/// Ordered blend. One target translate (2,0,0) + 90° about Z at weight 0.5:
/// halfway is translate (1,0,0) and 45° about Z. Maya's docs: weights
/// 1, 1/2, 1/3 over three targets give their equal average — targets
/// T(3,0,0), T(0,3,0), T(0,0,3) → (3,0,0) → (1.5,1.5,0) → (1,1,1).
/// envelope 0.5 halves that; enable off passes the input.
#[test]
fn blend_matrix_stacks_targets() {
    let mut g = graph();
    g.add_node("blendMatrix", "bm").unwrap();
    let target =
        DMat4::from_translation(DVec3::new(2.0, 0.0, 0.0)) * DMat4::from_rotation_z(std::f64::consts::FRAC_PI_2);
    set(&mut g, "bm.targetMatrix[0]", m(target));
    // weight element missing: default 1, the target exactly
    assert_eq!(mat(&mut g, "bm.outputMatrix"), target);
    set(&mut g, "bm.weight[0]", Value::Float(0.5));
    let o = mat(&mut g, "bm.outputMatrix");
    assert_close(o.w_axis.truncate(), DVec3::X, 1e-15, "half t");
    let h = std::f64::consts::FRAC_PI_4;
    assert_close(
        o.transform_vector3(DVec3::X),
        DVec3::new(h.cos(), h.sin(), 0.0),
        1e-15,
        "half r",
    );
    assert_lazy_compiled_same(&mut g, &["bm.outputMatrix"]);

    let mut g = graph();
    g.add_node("blendMatrix", "bm").unwrap();
    for (i, (t, w)) in [(DVec3::X, 1.0), (DVec3::Y, 0.5), (DVec3::Z, 1.0 / 3.0)]
        .iter()
        .enumerate()
    {
        set(
            &mut g,
            &format!("bm.targetMatrix[{i}]"),
            m(DMat4::from_translation(*t * 3.0)),
        );
        set(&mut g, &format!("bm.weight[{i}]"), Value::Float(*w));
    }
    set(&mut g, "bm.inputMatrix", m(DMat4::from_scale(DVec3::splat(5.0))));
    // the first target has weight 1, so the input's scale 5 is fully replaced
    let o = mat(&mut g, "bm.outputMatrix");
    assert_close(o.w_axis.truncate(), DVec3::ONE, 1e-14, "average");
    assert!(DMat3::from_mat4(o).abs_diff_eq(DMat3::IDENTITY, 1e-14));
    set(&mut g, "bm.inputMatrix", m(DMat4::IDENTITY));
    set(&mut g, "bm.envelope", Value::Float(0.5));
    assert_close(
        mat(&mut g, "bm.outputMatrix").w_axis.truncate(),
        DVec3::splat(0.5),
        1e-14,
        "envelope",
    );
    assert_lazy_compiled_same(&mut g, &["bm.outputMatrix"]);
    set(&mut g, "bm.enable", Value::Bool(false));
    assert_eq!(mat(&mut g, "bm.outputMatrix"), DMat4::IDENTITY);
}

fn axes(g: &mut Graph, path: &str) -> DMat3 {
    DMat3::from_mat4(mat(g, path))
}

/// Input at (1,0,0), unrotated. Expected frames (columns = where X, Y, Z go):
/// * aim X at (1,5,0), secondary none: shortest turn X→Y is 90° about Z:
///   (Y, -X, Z).
/// * + secondary aim Y at (1,0,7): X→Y, Y→Z, Z = X'×Y' = Y×Z = X.
/// * align X with (0,0,1): shortest turn X→Z is 90° about -Y: Y stays,
///   Z' = X'×Y' = Z×Y = -X.
/// * lockAxis + secondary align Y with Z: X stays, Y→Z, Z→X×Z = -Y.
///
/// Scale (2,2,2) on the input is kept; position is kept.
#[test]
fn aim_matrix_modes() {
    let mut g = graph();
    g.add_node("aimMatrix", "am").unwrap();
    let input = DMat4::from_translation(DVec3::X);
    set(&mut g, "am.inputMatrix", m(input));
    set(
        &mut g,
        "am.primaryTargetMatrix",
        m(DMat4::from_translation(DVec3::new(1.0, 5.0, 0.0))),
    );
    let expect = |a: DVec3, b: DVec3, c: DVec3| DMat3::from_cols(a, b, c);
    let (x, y, z) = (DVec3::X, DVec3::Y, DVec3::Z);
    assert!(axes(&mut g, "am.outputMatrix").abs_diff_eq(expect(y, -x, z), 1e-15));
    assert_close(mat(&mut g, "am.outputMatrix").w_axis.truncate(), x, 0.0, "position");

    set(&mut g, "am.secondaryMode", Value::Enum(1));
    set(
        &mut g,
        "am.secondaryTargetMatrix",
        m(DMat4::from_translation(DVec3::new(1.0, 0.0, 7.0))),
    );
    assert!(axes(&mut g, "am.outputMatrix").abs_diff_eq(expect(y, z, x), 1e-15));
    assert_lazy_compiled_same(&mut g, &["am.outputMatrix"]);

    set(&mut g, "am.secondaryMode", Value::Enum(0));
    set(&mut g, "am.primaryMode", Value::Enum(2));
    set(&mut g, "am.primaryTargetVector", v3(0.0, 0.0, 1.0));
    assert!(axes(&mut g, "am.outputMatrix").abs_diff_eq(expect(z, y, -x), 1e-15));

    set(&mut g, "am.primaryMode", Value::Enum(0));
    set(&mut g, "am.secondaryMode", Value::Enum(2));
    set(&mut g, "am.secondaryTargetVector", v3(0.0, 0.0, 1.0));
    set(
        &mut g,
        "am.inputMatrix",
        m(input * DMat4::from_scale(DVec3::splat(2.0))),
    );
    assert!(axes(&mut g, "am.outputMatrix").abs_diff_eq(expect(x * 2.0, z * 2.0, -y * 2.0), 1e-14));
    assert_lazy_compiled_same(&mut g, &["am.outputMatrix"]);

    // degenerate: aiming at its own position leaves the input as it was
    set(&mut g, "am.inputMatrix", m(input));
    set(&mut g, "am.primaryMode", Value::Enum(1));
    set(&mut g, "am.primaryTargetMatrix", m(input));
    set(&mut g, "am.primaryTargetVector", v3(0.0, 0.0, 0.0));
    set(&mut g, "am.secondaryMode", Value::Enum(0));
    let o = mat(&mut g, "am.outputMatrix");
    assert!(o.is_finite() && o.abs_diff_eq(input, 1e-15));
    // envelope 0: the input, exactly
    set(
        &mut g,
        "am.primaryTargetMatrix",
        m(DMat4::from_translation(DVec3::new(1.0, 5.0, 0.0))),
    );
    set(&mut g, "am.envelope", Value::Float(0.0));
    assert_eq!(mat(&mut g, "am.outputMatrix"), input);
}

/// `inverse_or_identity` of `m` against glam's 4×4 inverse: the same matrix up to rounding
/// (relative to its size), or the identity in the same cases.
fn check_inverse(m: DMat4) {
    use super::math::{affine_inverse, is_affine};
    use super::matrix_nodes::inverse_or_identity;
    let got = inverse_or_identity(m);
    let det = m.determinant();
    let full = m.inverse();
    let expect_identity = !m.is_finite() || det == 0.0 || !det.is_finite() || !full.is_finite();
    if expect_identity {
        // The 3×3 determinant of an affine matrix can round differently from glam's 4×4 one
        // only for (nearly) singular matrices: then either result is acceptable, but never NaN.
        assert!(got.is_finite(), "{m}");
        if !m.is_finite() || !is_affine(&m) {
            assert_eq!(got, DMat4::IDENTITY, "{m}");
        }
        return;
    }
    let scale = full.to_cols_array().iter().fold(1.0f64, |a, x| a.max(x.abs()));
    assert!(got.abs_diff_eq(full, 1e-12 * scale), "{m}: {got} vs {full}");
    if let Some((inv, d)) = affine_inverse(&m) {
        assert_eq!(inv, got);
        assert!((d - det).abs() <= 1e-12 * det.abs().max(1.0), "{d} vs {det}");
        assert!((m * inv).abs_diff_eq(DMat4::IDENTITY, 1e-9 * scale.max(1.0)));
    } else {
        // not affine: glam's inverse, bit for bit
        assert_eq!(
            got.to_cols_array().map(f64::to_bits),
            full.to_cols_array().map(f64::to_bits)
        );
    }
}

/// Affine and projective matrices, singular ones (a zero axis, a zero matrix), non-finite
/// ones, a signed-zero last row and huge and tiny scales.
#[test]
fn inverse_or_identity_affine_path_edge_cases() {
    let r = DMat4::from_rotation_translation(DQuat::from_rotation_x(0.7), DVec3::new(1.0, -2.0, 3.0));
    let mut neg_zero_row = r;
    neg_zero_row.x_axis.w = -0.0;
    let mut projective = r;
    projective.x_axis.w = 0.25;
    for m in [
        DMat4::IDENTITY,
        DMat4::ZERO,
        r,
        neg_zero_row,
        projective,
        r * DMat4::from_scale(DVec3::new(2.0, 0.0, 1.0)),
        r * DMat4::from_scale(DVec3::new(-1.0, 3.0, 0.5)),
        r * DMat4::from_scale(DVec3::splat(1e-120)),
        r * DMat4::from_scale(DVec3::splat(1e120)),
        DMat4::from_translation(DVec3::new(f64::NAN, 0.0, 0.0)),
        DMat4::from_scale(DVec3::new(f64::INFINITY, 1.0, 1.0)),
    ] {
        check_inverse(m);
    }
}

proptest! {
    #[test]
    fn inverse_or_identity_matches_the_full_inverse(
        r in (-4.0f64..4.0, -4.0f64..4.0, -4.0f64..4.0),
        s in (0.1f64..5.0, 0.1f64..5.0, -5.0f64..5.0),
        sh in (-0.5f64..0.5, -0.5f64..0.5, -0.5f64..0.5),
        t in (-100.0f64..100.0, -100.0f64..100.0, -100.0f64..100.0),
        w in prop_oneof![Just(0.0), -0.5f64..0.5],
    ) {
        let rot = DVec3::new(r.0, r.1, r.2);
        let m = super::math::compose(
            DVec3::new(t.0, t.1, t.2), rot, RotateOrder::Zxy, DVec3::new(s.0, s.1, s.2), DVec3::new(sh.0, sh.1, sh.2),
        );
        check_inverse(m);
        let mut p = m;
        p.y_axis.w = w;
        check_inverse(p);
    }
}
