//! `motionPath`: an object travelling along a curve, optionally turned to follow it.

use glam::{DMat3, DMat4, DQuat, DVec3};
use sinew_core::{ComputeContext, ComputeError, Input, NodeSpec, NodeType, Output, SpecError, Unit};

use super::cache::{curve_of, CurveIn};
use super::curve_eval::frenet;
use super::frame::axes_frame;
use crate::constraint::{world_up, ROTATE_ORDERS};
use crate::transform::dag_nodes::rad_to_deg;
use crate::transform::euler::{mat3_to_euler, RotateOrder};

/// Maya's `frontAxis` / `upAxis` choices.
pub const AXES: [&str; 3] = ["x", "y", "z"];

/// Maya's `worldUpType` choices for motion paths (`MPxMotionPathNode::worldUpVectorValue`).
pub const WORLD_UP_TYPES: [&str; 5] = ["scene", "object", "objectRotation", "vector", "normal"];

/// `motionPath`: the position on `geometryPath` at `uValue`, and with `follow` an
/// orientation that follows the curve (Maya's node; defaults as Maya's node: `frontAxis` y,
/// `upAxis` z, `worldUpType` vector, `worldUpVector` +Y, `bankScale` 1, `bankLimit` 90°).
///
/// * Position: `uValue` is the curve parameter, or with `fractionMode` the fraction of the
///   arc length (0..1, clamped on open curves, wrapped on periodic ones). Parameters out
///   of range clamp (open) or wrap (periodic). Output `allCoordinates` (`xCoordinate`...).
/// * `follow`: local `frontAxis` along the unit tangent (negated by `inverseFront`), local
///   `upAxis` along the up reference made orthogonal to it (negated by `inverseUp`), the
///   third axis completing a right-handed frame. Up reference by `worldUpType`: `scene` +Y,
///   `object` towards the translation of `worldUpMatrix`, `objectRotation` `worldUpVector`
///   turned by `worldUpMatrix`, `vector` `worldUpVector`, `normal` the curve's principal
///   normal. An up reference parallel to the tangent falls back to a fixed orthogonal
///   vector; equal front and up axes use the axis after front.
/// * `bank`: the up axis tilts towards the centre of curvature by `bankScale · κ_side`
///   radians, `κ_side` the curvature (1/length) in the front–side plane, at most
///   `bankLimit` degrees. Maya does not document its bank formula; this one is sinew's.
/// * Twists (degrees): `frontTwist`, then `upTwist`, then `sideTwist`, each about that
///   local axis of the frame.
/// * Outputs: `orientMatrix` (the world rotation; identity without follow) and `rotate`
///   (its Euler angles in degrees in `rotateOrder`; connect `rotateOrder` on to the object,
///   as Maya does). No curve connected: position 0.
pub struct MotionPath {
    spec: NodeSpec,
    path: CurveIn,
    u_value: Input<f64>,
    fraction_mode: Input<bool>,
    follow: Input<bool>,
    front_axis: Input<i64>,
    up_axis: Input<i64>,
    world_up_type: Input<i64>,
    world_up_vector: Input<DVec3>,
    world_up_matrix: Input<DMat4>,
    inverse_front: Input<bool>,
    inverse_up: Input<bool>,
    bank: Input<bool>,
    bank_scale: Input<f64>,
    bank_limit: Input<f64>,
    front_twist: Input<f64>,
    up_twist: Input<f64>,
    side_twist: Input<f64>,
    rotate_order: Input<i64>,
    all_coordinates: Output<DVec3>,
    rotate: Output<DVec3>,
    orient_matrix: Output<DMat4>,
}

impl MotionPath {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("motionPath");
        // Short names as Maya writes them in scenes (connectAttr "curveShape1.ws" "motionPath1.gp" ...).
        b.maya_names(&[
            ("geometryPath", "gp"),
            ("uValue", "u"),
            ("fractionMode", "fm"),
            ("follow", "f"),
            ("frontAxis", "fa"),
            ("upAxis", "ua"),
            ("worldUpType", "wut"),
            ("worldUpVector", "wu"),
            ("inverseFront", "if"),
            ("bank", "b"),
            ("bankScale", "bs"),
            ("frontTwist", "ft"),
            ("upTwist", "ut"),
            ("sideTwist", "st"),
            ("allCoordinates", "ac"),
            ("xCoordinate", "xc"),
            ("yCoordinate", "yc"),
            ("zCoordinate", "zc"),
            ("rotate", "r"),
            ("rotateOrder", "ro"),
        ]);
        b.doc("position (and with follow, orientation) along a curve at uValue");
        let path = CurveIn::declare(&mut b, "geometryPath", "the path (connect worldSpace[0])", true);
        let u_value = b.input("uValue", 0.0);
        let fraction_mode = b.input("fractionMode", false);
        let follow = b.input("follow", false);
        let front_axis = b.input_enum("frontAxis", &AXES, 1);
        let up_axis = b.input_enum("upAxis", &AXES, 2);
        let world_up_type = b.input_enum("worldUpType", &WORLD_UP_TYPES, 3);
        let world_up_vector = b.input("worldUpVector", DVec3::Y);
        let world_up_matrix = b.input("worldUpMatrix", DMat4::IDENTITY);
        let inverse_front = b.input("inverseFront", false);
        let inverse_up = b.input("inverseUp", false);
        let bank = b.input("bank", false);
        let bank_scale = b.input("bankScale", 1.0);
        let bank_limit = b.input("bankLimit", 90.0);
        let front_twist = b.input("frontTwist", 0.0);
        let up_twist = b.input("upTwist", 0.0);
        let side_twist = b.input("sideTwist", 0.0);
        let rotate_order = b.input_enum("rotateOrder", &ROTATE_ORDERS, 0);
        let all_coordinates = b.output("allCoordinates", DVec3::ZERO);
        let rotate = b.output("rotate", DVec3::ZERO);
        let orient_matrix = b.output("orientMatrix", DMat4::IDENTITY);
        b.child_names(all_coordinates, ["xCoordinate", "yCoordinate", "zCoordinate"]);
        b.mirror(world_up_vector, sinew_core::MirrorRole::WorldVector);
        for h in [bank_limit, front_twist, up_twist, side_twist] {
            b.unit(h, Unit::Degrees);
        }
        b.unit(rotate, Unit::Degrees).unit(all_coordinates, Unit::Distance);
        b.attr_doc(u_value, "curve parameter, or arc-length fraction with fractionMode")
            .attr_doc(fraction_mode, "uValue is a fraction 0..1 of the arc length")
            .attr_doc(follow, "orient along the path")
            .attr_doc(front_axis, "local axis along the tangent")
            .attr_doc(up_axis, "local axis towards the up reference")
            .attr_doc(world_up_type, "what the up axis follows (see the node docs)")
            .attr_doc(world_up_vector, "up direction (vector, objectRotation)")
            .attr_doc(
                world_up_matrix,
                "world matrix of the up object (object, objectRotation)",
            )
            .attr_doc(inverse_front, "point the front axis backwards along the path")
            .attr_doc(inverse_up, "point the up axis away from the up reference")
            .attr_doc(bank, "tilt into turns")
            .attr_doc(bank_scale, "bank angle per unit of curvature (radians · length)")
            .attr_doc(bank_limit, "largest bank angle, degrees")
            .attr_doc(front_twist, "twist about the front axis, degrees")
            .attr_doc(up_twist, "twist about the up axis, degrees")
            .attr_doc(side_twist, "twist about the side axis, degrees")
            .attr_doc(
                rotate_order,
                "rotate order of the rotate output (connect on to the object)",
            )
            .attr_doc(all_coordinates, "position on the path")
            .attr_doc(rotate, "orientation as Euler angles (degrees, rotateOrder)")
            .attr_doc(orient_matrix, "orientation as a rotation matrix");
        let query: Vec<_> = b.input_ids().into_iter().filter(|&id| id != path.curve.id()).collect();
        let mut with_cache = query.clone();
        with_cache.push(path.cache.id());
        b.affects(&with_cache, &[all_coordinates.id(), rotate.id(), orient_matrix.id()]);
        Ok(MotionPath {
            spec: b.build()?,
            path,
            u_value,
            fraction_mode,
            follow,
            front_axis,
            up_axis,
            world_up_type,
            world_up_vector,
            world_up_matrix,
            inverse_front,
            inverse_up,
            bank,
            bank_scale,
            bank_limit,
            front_twist,
            up_twist,
            side_twist,
            rotate_order,
            all_coordinates,
            rotate,
            orient_matrix,
        })
    }
}

impl NodeType for MotionPath {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if self.path.compute(ctx) {
            return Ok(());
        }
        let obj = self.path.get(ctx);
        let curve = curve_of(&obj, "motionPath.geometryPath")?;
        let Some(c) = curve else {
            ctx.set(self.all_coordinates, DVec3::ZERO);
            ctx.set(self.rotate, DVec3::ZERO);
            ctx.set(self.orient_matrix, DMat4::IDENTITY);
            return Ok(());
        };
        let u = ctx.get(self.u_value);
        let t = if ctx.get(self.fraction_mode) {
            let f = if c.direction().is_periodic() {
                u.rem_euclid(1.0)
            } else {
                u.clamp(0.0, 1.0)
            };
            c.param_at_length(f * c.length())
        } else {
            u
        };
        let e = c.eval(t);
        ctx.set(self.all_coordinates, e.position);
        let rot = if ctx.get(self.follow) {
            self.orientation(ctx, &e)
        } else {
            DMat3::IDENTITY
        };
        let order = RotateOrder::from_index(ctx.get(self.rotate_order)).unwrap_or_default();
        ctx.set(self.rotate, rad_to_deg(mat3_to_euler(rot, order)));
        ctx.set(self.orient_matrix, DMat4::from_mat3(rot));
        Ok(())
    }
}

impl MotionPath {
    /// The followed orientation at `e` (see the node docs).
    fn orientation(&self, ctx: &ComputeContext<'_>, e: &super::curve_eval::CurvePoint) -> DMat3 {
        let f = frenet(e);
        let front = f.normalized_tangent * if ctx.get(self.inverse_front) { -1.0 } else { 1.0 };
        let wu = ctx.get(self.world_up_vector);
        let wum = ctx.get(self.world_up_matrix);
        let mut up = match ctx.get(self.world_up_type) {
            4 => f.normalized_normal,
            kind => world_up(kind, e.position, wu, wum),
        };
        if ctx.get(self.inverse_up) {
            up = -up;
        }
        let fa = ctx.get(self.front_axis).clamp(0, 2) as usize;
        let ua = ctx.get(self.up_axis).clamp(0, 2) as usize;
        let mut m = axes_frame(fa, 1.0, front, ua, 1.0, up);
        let ua = if ua == fa { (fa + 1) % 3 } else { ua };
        if ctx.get(self.bank) {
            let speed2 = e.d1.length_squared();
            let side = m.col(3 - fa - ua);
            let kappa_side = if speed2 > 0.0 { f.normal.dot(side) / speed2 } else { 0.0 };
            let limit = ctx.get(self.bank_limit).abs().to_radians();
            let angle = (ctx.get(self.bank_scale) * kappa_side).clamp(-limit, limit);
            if angle.is_finite() && angle != 0.0 {
                let up_dir = m.col(ua);
                let tilted = up_dir * angle.cos() + side * angle.sin();
                m = axes_frame(fa, 1.0, m.col(fa), ua, 1.0, tilted);
            }
        }
        let twist = |axis: usize, deg: f64| DQuat::from_axis_angle(DVec3::AXES[axis], deg.to_radians());
        let side_axis = 3 - fa - ua;
        let local = twist(fa, ctx.get(self.front_twist))
            * twist(ua, ctx.get(self.up_twist))
            * twist(side_axis, ctx.get(self.side_twist));
        m * DMat3::from_quat(local)
    }
}
