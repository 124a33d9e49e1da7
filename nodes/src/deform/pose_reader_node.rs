//! The `poseReader` node: a 0..1 weight from the angle between a joint's axis and a
//! reference axis, with a smooth cone falloff, to drive corrective blend shapes.
//!
//! Maya has no built-in pose reader; the attribute names follow Michael Comet's widely used
//! `poseReader` plugin where it has one (`worldMatrixLiveIn`, `worldMatrixPoseIn`,
//! `readAxis`, `outWeight`), with the axes as vectors instead of an enum.
//!
//! Inputs: `worldMatrixLiveIn` (the reading joint's world matrix), `readAxis` (vec3, the
//! joint-local axis that is read, default +X), `worldMatrixPoseIn` (the reference's world
//! matrix: the joint's parent, a locator, or identity for world space), `poseAxis` (vec3,
//! the reference-local target direction, default +X), `minAngle` (degrees, 0: full weight
//! inside), `maxAngle` (degrees, 45: zero weight beyond).
//!
//! Outputs: `outWeight` (1 inside `minAngle`, 0 beyond `maxAngle`, `1 − smoothstep` in
//! between, see [`super::pose_reader`]) and `outAngle` (degrees, in `[0, 180]`).
//!
//! Degenerate input (a zero axis, or an axis that a singular matrix maps to zero): weight 0
//! and angle 0. `maxAngle <= minAngle` is a hard cone edge.

use glam::{DMat4, DVec3};
use sinew_core::{ComputeContext, ComputeError, Input, NodeSpec, NodeType, Output, SpecError, Unit};

use super::pose_reader::{pose_reader, Cone};

/// The `poseReader` node (see the module docs).
pub struct PoseReader {
    spec: NodeSpec,
    live: Input<DMat4>,
    read_axis: Input<DVec3>,
    pose: Input<DMat4>,
    pose_axis: Input<DVec3>,
    min_angle: Input<f64>,
    max_angle: Input<f64>,
    out_weight: Output<f64>,
    out_angle: Output<f64>,
}

impl PoseReader {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("poseReader");
        s.doc("cone-falloff weight of the angle between a joint axis and a reference axis");
        let live = s.input("worldMatrixLiveIn", DMat4::IDENTITY);
        let read_axis = s.input("readAxis", DVec3::X);
        let pose = s.input("worldMatrixPoseIn", DMat4::IDENTITY);
        let pose_axis = s.input("poseAxis", DVec3::X);
        let min_angle = s.input("minAngle", 0.0);
        let max_angle = s.input("maxAngle", 45.0);
        let out_weight = s.output("outWeight", 0.0);
        let out_angle = s.output("outAngle", 0.0);
        s.unit(min_angle, Unit::Degrees)
            .unit(max_angle, Unit::Degrees)
            .unit(out_angle, Unit::Degrees)
            .attr_doc(live, "world matrix of the joint being read")
            .attr_doc(read_axis, "joint-local axis that is read")
            .attr_doc(pose, "world matrix of the reference (parent, locator, or identity)")
            .attr_doc(pose_axis, "reference-local direction of the target pose")
            .attr_doc(min_angle, "full weight within this angle")
            .attr_doc(max_angle, "zero weight beyond this angle")
            .attr_doc(out_weight, "0..1 pose weight")
            .attr_doc(out_angle, "angle between the two axes in world space");
        Ok(PoseReader {
            spec: s.build()?,
            live,
            read_axis,
            pose,
            pose_axis,
            min_angle,
            max_angle,
            out_weight,
            out_angle,
        })
    }
}

impl NodeType for PoseReader {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let cone = Cone {
            min_angle: ctx.get(self.min_angle).to_radians(),
            max_angle: ctx.get(self.max_angle).to_radians(),
        };
        let (w, angle) = pose_reader(
            &ctx.get(self.live),
            ctx.get(self.read_axis),
            &ctx.get(self.pose),
            ctx.get(self.pose_axis),
            cone,
        );
        ctx.set(self.out_weight, w);
        ctx.set(self.out_angle, angle.unwrap_or(0.0).to_degrees());
        Ok(())
    }
}
