//! Maya's quatNodes plug-in (`quatAdd`, `quatSub`, `quatProd`, `quatNegate`,
//! `quatConjugate`, `quatInvert`, `quatNormalize`, `quatSlerp`,
//! `quatToAxisAngle`, `axisAngleToQuat`; `eulerToQuat`/`quatToEuler` live in
//! [`crate::transform`]) and `angleBetween`.
//!
//! Attribute names are Maya's (`input1Quat`, `input2Quat`, `inputQuat`,
//! `inputT`, `outputQuat`, `inputAxis`, `inputAngle`, `outputAxis`,
//! `outputAngle`; `angleBetween`: `vector1`, `vector2`, `angle`, `axis`,
//! `euler`). A sinew quaternion is one `quat` attribute (x, y, z, w); Maya's
//! per-component children (`input1QuatX`...) are not addressable in sinew.
//!
//! # Product order
//! Maya composes rotations for row vectors, and `MQuaternion` products match
//! `MMatrix` products (as in Direct3D): `quatProd` gives the rotation
//! `input1Quat` followed by `input2Quat`, which is glam's (column-vector)
//! `input2 * input1`. See [`crate::transform::math`] for the matrix side.
//!
//! The nodes are total: a non-finite quaternion counts as the identity
//! (after [`finite_quat`]), angles on plugs are degrees, and each node
//! documents its degenerate cases.

use glam::{DQuat, DVec3, DVec4};
use sinew_core::{finite, ComputeContext, ComputeError, Input, NodeSpec, NodeType, Output, Registry, SpecError, Unit};

use crate::math::finite3;
use crate::math::vector::{length, unit};
use crate::transform::math::{quat_to_euler, slerp_shortest, RotateOrder};

#[cfg(test)]
mod tests;

/// `q` with non-finite components replaced: a quaternion that is not finite
/// becomes the identity; finite quaternions pass unchanged (not normalized).
pub fn finite_quat(q: DQuat) -> DQuat {
    if q.is_finite() {
        q
    } else {
        DQuat::IDENTITY
    }
}

/// `q / |q|`, scaled first so huge or tiny quaternions normalize exactly; a
/// zero or non-finite quaternion gives the identity.
pub fn normalize_quat(q: DQuat) -> DQuat {
    let v = DVec4::from(q);
    let m = v.abs().max_element();
    if !(m > 0.0 && m.is_finite()) {
        return DQuat::IDENTITY;
    }
    let v = v / m;
    DQuat::from_vec4(v / v.length())
}

/// The multiplicative inverse `conj(q) / |q|²` (for a unit quaternion the
/// conjugate); a zero or non-finite quaternion gives the identity. The
/// result saturates at `±f64::MAX` for tiny `|q|`.
pub fn invert_quat(q: DQuat) -> DQuat {
    let v = DVec4::from(q);
    let m = v.abs().max_element();
    if !(m > 0.0 && m.is_finite()) {
        return DQuat::IDENTITY;
    }
    // conj(q)/|q|² = conj(q/m) / (m · |q/m|²), without squaring m.
    let s = v / m;
    let c = DVec4::new(-s.x, -s.y, -s.z, s.w) / (s.length_squared() * m);
    DQuat::from_vec4(finite4(c))
}

fn finite4(v: DVec4) -> DVec4 {
    DVec4::new(finite(v.x), finite(v.y), finite(v.z), finite(v.w))
}

/// Which way `quatSlerp` goes round (Maya's `angleType`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AngleType {
    /// The shorter of the two arcs (the rotation by at most 180 degrees).
    Shortest,
    /// Along the arc to `input2Quat` as given (no sign flip).
    Positive,
    /// Along the arc to `-input2Quat`: the other way round.
    Negative,
}

/// Maya's `angleType` choices, in enum order.
pub const ANGLE_TYPES: [&str; 3] = ["shortest", "positive", "negative"];

impl AngleType {
    /// The angle type of an enum index (unknown indices are `Shortest`).
    pub fn from_index(i: i64) -> Self {
        match i {
            1 => AngleType::Positive,
            2 => AngleType::Negative,
            _ => AngleType::Shortest,
        }
    }
}

/// Spherical interpolation from `a` (t = 0) to `b` (t = 1) along the great
/// arc through them, without choosing a hemisphere; both are normalized
/// first. For antipodal inputs (`b = -a`, a full turn) the arc goes through
/// the quaternion perpendicular to `a` in the (x, y) / (z, w) planes.
pub fn slerp_arc(a: DQuat, b: DQuat, t: f64) -> DQuat {
    let (a, b) = (normalize_quat(a), normalize_quat(b));
    let t = if t.is_finite() { t } else { 0.0 };
    let d = a.dot(b).clamp(-1.0, 1.0);
    if d > 1.0 - 1e-10 {
        return normalize_quat(a * (1.0 - t) + b * t);
    }
    if d < -1.0 + 1e-10 {
        let p = DQuat::from_xyzw(-a.y, a.x, -a.w, a.z);
        let phi = std::f64::consts::PI * t;
        return normalize_quat(a * phi.cos() + p * phi.sin());
    }
    let theta = d.acos();
    let s = theta.sin();
    normalize_quat(a * (((1.0 - t) * theta).sin() / s) + b * ((t * theta).sin() / s))
}

/// `quatSlerp`'s interpolation for an [`AngleType`].
pub fn quat_slerp(a: DQuat, b: DQuat, t: f64, kind: AngleType) -> DQuat {
    match kind {
        AngleType::Shortest => slerp_shortest(a, b, t),
        AngleType::Positive => slerp_arc(a, b, t),
        AngleType::Negative => slerp_arc(a, -b, t),
    }
}

/// The unit axis and angle (radians, in [0, π]) of the rotation `q`
/// (normalized first, taken with `w >= 0`). No rotation gives axis X and angle 0.
pub fn to_axis_angle(q: DQuat) -> (DVec3, f64) {
    let q = normalize_quat(q);
    let q = if q.w < 0.0 { -q } else { q };
    let v = DVec3::new(q.x, q.y, q.z);
    let s = length(v);
    if s == 0.0 {
        return (DVec3::X, 0.0);
    }
    (v / s, 2.0 * s.atan2(q.w))
}

/// The rotation by `angle` radians about `axis` (normalized first); a zero or
/// non-finite axis gives the identity.
pub fn from_axis_angle(axis: DVec3, angle: f64) -> DQuat {
    let axis = unit(finite3(axis));
    if axis == DVec3::ZERO || !angle.is_finite() {
        return DQuat::IDENTITY;
    }
    DQuat::from_axis_angle(axis, angle)
}

/// The operation of a [`QuatNode`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QuatOp {
    /// `quatAdd`: component-wise `input1Quat + input2Quat`.
    Add,
    /// `quatSub`: component-wise `input1Quat - input2Quat`.
    Sub,
    /// `quatProd`: the rotation `input1Quat` then `input2Quat`.
    Prod,
    /// `quatNegate`: `-inputQuat` (the same rotation).
    Negate,
    /// `quatConjugate`: `(-x, -y, -z, w)`.
    Conjugate,
    /// `quatInvert`: `conj(q)/|q|²`.
    Invert,
    /// `quatNormalize`: `q/|q|`.
    Normalize,
}

impl QuatOp {
    /// Every operation with its Maya name and doc line.
    pub const ALL: [(QuatOp, &'static str, &'static str); 7] = [
        (QuatOp::Add, "quatAdd", "outputQuat = input1Quat + input2Quat, component-wise"),
        (QuatOp::Sub, "quatSub", "outputQuat = input1Quat - input2Quat, component-wise"),
        (
            QuatOp::Prod,
            "quatProd",
            "outputQuat = the rotation input1Quat followed by input2Quat (Maya's row-vector product; glam input2 * input1)",
        ),
        (QuatOp::Negate, "quatNegate", "outputQuat = -inputQuat (the same rotation)"),
        (QuatOp::Conjugate, "quatConjugate", "outputQuat = (-x, -y, -z, w)"),
        (
            QuatOp::Invert,
            "quatInvert",
            "outputQuat = conj(inputQuat) / |inputQuat|^2; zero gives identity",
        ),
        (
            QuatOp::Normalize,
            "quatNormalize",
            "outputQuat = inputQuat / |inputQuat|; zero gives identity",
        ),
    ];

    fn binary(self) -> bool {
        matches!(self, QuatOp::Add | QuatOp::Sub | QuatOp::Prod)
    }

    /// The operation on `a` (and `b` for the binary ones), inputs made finite first.
    pub fn apply(self, a: DQuat, b: DQuat) -> DQuat {
        let (a, b) = (finite_quat(a), finite_quat(b));
        let v = |q: DQuat| finite4(DVec4::from(q));
        let r = match self {
            QuatOp::Add => v(a) + v(b),
            QuatOp::Sub => v(a) - v(b),
            QuatOp::Prod => v(b * a),
            QuatOp::Negate => -v(a),
            QuatOp::Conjugate => v(a.conjugate()),
            QuatOp::Invert => v(invert_quat(a)),
            QuatOp::Normalize => v(normalize_quat(a)),
        };
        DQuat::from_vec4(finite4(r))
    }
}

/// One of the quatNodes plug-in's algebra nodes (see [`QuatOp`]).
pub struct QuatNode {
    spec: NodeSpec,
    op: QuatOp,
    a: Input<DQuat>,
    b: Option<Input<DQuat>>,
    out: Output<DQuat>,
}

impl QuatNode {
    /// The node type of `op` named `name`.
    pub fn new(op: QuatOp, name: &str, doc: &str) -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder(name);
        s.doc(doc);
        let (a, b) = if op.binary() {
            let a = s.input("input1Quat", DQuat::IDENTITY);
            (a, Some(s.input("input2Quat", DQuat::IDENTITY)))
        } else {
            (s.input("inputQuat", DQuat::IDENTITY), None)
        };
        let out = s.output("outputQuat", DQuat::IDENTITY);
        Ok(QuatNode {
            spec: s.build()?,
            op,
            a,
            b,
            out,
        })
    }
}

impl NodeType for QuatNode {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let a = ctx.get(self.a);
        let b = self.b.map_or(DQuat::IDENTITY, |h| ctx.get(h));
        ctx.set(self.out, self.op.apply(a, b));
        Ok(())
    }
}

/// Maya's `quatSlerp`: `outputQuat` interpolates from `input1Quat` (`inputT`
/// 0) to `input2Quat` (1) along the arc [`AngleType`] picks; `inputT`
/// outside [0, 1] extrapolates along the same arc, a non-finite `inputT`
/// counts as 0. Inputs are normalized first (zero → identity).
pub struct QuatSlerp {
    spec: NodeSpec,
    a: Input<DQuat>,
    b: Input<DQuat>,
    t: Input<f64>,
    angle_type: Input<i64>,
    out: Output<DQuat>,
}

impl QuatSlerp {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("quatSlerp");
        s.doc("outputQuat = slerp(input1Quat, input2Quat, inputT) along the arc angleType picks");
        let a = s.input("input1Quat", DQuat::IDENTITY);
        let b = s.input("input2Quat", DQuat::IDENTITY);
        let t = s.input("inputT", 0.0);
        s.attr_doc(t, "0 gives input1Quat, 1 gives input2Quat");
        let angle_type = s.input_enum("angleType", &ANGLE_TYPES, 0);
        s.attr_doc(
            angle_type,
            "shortest arc, the arc to input2Quat as given (positive) or to -input2Quat (negative)",
        );
        let out = s.output("outputQuat", DQuat::IDENTITY);
        Ok(QuatSlerp {
            spec: s.build()?,
            a,
            b,
            t,
            angle_type,
            out,
        })
    }
}

impl NodeType for QuatSlerp {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let kind = AngleType::from_index(ctx.get(self.angle_type));
        let q = quat_slerp(ctx.get(self.a), ctx.get(self.b), ctx.get(self.t), kind);
        ctx.set(self.out, q);
        Ok(())
    }
}

/// Maya's `quatToAxisAngle`: `outputAxis` (unit) and `outputAngle` (degrees,
/// in [0, 180]) of `inputQuat` (normalized first; `q` and `-q` give the same
/// pair). No rotation gives axis (1, 0, 0) and angle 0.
pub struct QuatToAxisAngle {
    spec: NodeSpec,
    q: Input<DQuat>,
    axis: Output<DVec3>,
    angle: Output<f64>,
}

impl QuatToAxisAngle {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("quatToAxisAngle");
        s.doc("outputAxis (unit) and outputAngle (degrees, 0..180) of inputQuat");
        let q = s.input("inputQuat", DQuat::IDENTITY);
        let axis = s.output("outputAxis", DVec3::X);
        let angle = s.output("outputAngle", 0.0);
        s.unit(angle, Unit::Degrees);
        Ok(QuatToAxisAngle {
            spec: s.build()?,
            q,
            axis,
            angle,
        })
    }
}

impl NodeType for QuatToAxisAngle {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let (axis, angle) = to_axis_angle(ctx.get(self.q));
        ctx.set(self.axis, axis);
        ctx.set(self.angle, angle.to_degrees());
        Ok(())
    }
}

/// Maya's `axisAngleToQuat`: `outputQuat` rotates by `inputAngle` (degrees)
/// about `inputAxis` (normalized first). A zero axis gives the identity.
pub struct AxisAngleToQuat {
    spec: NodeSpec,
    axis: Input<DVec3>,
    angle: Input<f64>,
    out: Output<DQuat>,
}

impl AxisAngleToQuat {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("axisAngleToQuat");
        s.doc("outputQuat = the rotation by inputAngle (degrees) about inputAxis");
        let axis = s.input("inputAxis", DVec3::X);
        let angle = s.input("inputAngle", 0.0);
        s.unit(angle, Unit::Degrees);
        let out = s.output("outputQuat", DQuat::IDENTITY);
        Ok(AxisAngleToQuat {
            spec: s.build()?,
            axis,
            angle,
            out,
        })
    }
}

impl NodeType for AxisAngleToQuat {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let q = from_axis_angle(ctx.get(self.axis), ctx.get(self.angle).to_radians());
        ctx.set(self.out, q);
        Ok(())
    }
}

/// Maya's `angleBetween`: the rotation taking `vector1` onto `vector2`
/// (defaults (1, 0, 0) both): `angle` (degrees, in [0, 180]), `axis` (the
/// unit `vector1 × vector2`) and `euler` (the same rotation as xyz euler
/// angles, degrees).
///
/// Degenerate inputs: a zero vector, or parallel vectors, give angle 0, axis
/// (0, 0, 0) and euler 0; opposite vectors give angle 180 about an axis
/// perpendicular to `vector1` (the one [`DQuat::from_rotation_arc`] picks).
pub struct AngleBetween {
    spec: NodeSpec,
    v1: Input<DVec3>,
    v2: Input<DVec3>,
    angle: Output<f64>,
    axis: Output<DVec3>,
    euler: Output<DVec3>,
}

impl AngleBetween {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("angleBetween");
        s.doc("angle (degrees), axis and euler of the rotation taking vector1 onto vector2");
        let v1 = s.input("vector1", DVec3::X);
        let v2 = s.input("vector2", DVec3::X);
        let angle = s.output("angle", 0.0);
        let axis = s.output("axis", DVec3::ZERO);
        let euler = s.output("euler", DVec3::ZERO);
        s.unit(angle, Unit::Degrees).unit(euler, Unit::Degrees);
        Ok(AngleBetween {
            spec: s.build()?,
            v1,
            v2,
            angle,
            axis,
            euler,
        })
    }
}

/// The rotation taking `a` onto `b` as (unit axis or zero, angle in radians,
/// quaternion); see [`AngleBetween`] for the degenerate cases.
pub fn angle_between(a: DVec3, b: DVec3) -> (DVec3, f64, DQuat) {
    let (a, b) = (unit(finite3(a)), unit(finite3(b)));
    if a == DVec3::ZERO || b == DVec3::ZERO {
        return (DVec3::ZERO, 0.0, DQuat::IDENTITY);
    }
    let c = a.cross(b);
    let angle = length(c).atan2(a.dot(b));
    let axis = unit(c);
    if axis == DVec3::ZERO && angle < std::f64::consts::FRAC_PI_2 {
        return (DVec3::ZERO, 0.0, DQuat::IDENTITY);
    }
    let q = DQuat::from_rotation_arc(a, b);
    let axis = if axis == DVec3::ZERO { to_axis_angle(q).0 } else { axis };
    (axis, angle, q)
}

impl NodeType for AngleBetween {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let (axis, angle, q) = angle_between(ctx.get(self.v1), ctx.get(self.v2));
        if ctx.wants(self.angle) {
            ctx.set(self.angle, angle.to_degrees());
        }
        if ctx.wants(self.axis) {
            ctx.set(self.axis, axis);
        }
        if ctx.wants(self.euler) {
            let e = quat_to_euler(q, RotateOrder::Xyz);
            ctx.set(
                self.euler,
                DVec3::new(e.x.to_degrees(), e.y.to_degrees(), e.z.to_degrees()),
            );
        }
        Ok(())
    }
}

/// Registers this family's node types.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    for (op, name, doc) in QuatOp::ALL {
        registry.register(QuatNode::new(op, name, doc)?)?;
    }
    registry.register(QuatSlerp::new()?)?;
    registry.register(QuatToAxisAngle::new()?)?;
    registry.register(AxisAngleToQuat::new()?)?;
    registry.register(AngleBetween::new()?)?;
    Ok(())
}
