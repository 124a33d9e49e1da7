//! `pairBlend`: blends two translate/rotate pairs (FK/IK switches, constraint vs. animation).

use glam::DVec3;
use sinew_core::{
    AttrId, ComputeContext, ComputeError, Input, KnownInputs, NodeSpec, NodeType, Output, SpecError, Unit,
};

use super::{finite3, node_type};
use crate::transform::math::{euler_to_quat, quat_to_euler_closest, slerp_shortest, RotateOrder};

/// Maya's `pairBlend`: `weight` 0 gives input 1, 1 gives input 2.
///
/// - `outTranslate = inTranslate1 + (inTranslate2 - inTranslate1) * weight`.
/// - `rotInterpolation = euler` (Maya's default): the same lerp on the euler
///   angles (degrees). `quaternion`: both rotations (in `rotateOrder`) are
///   turned into quaternions, slerped along the shorter arc and turned back
///   into the euler triple (in `rotateOrder`) closest to the euler lerp, so
///   the output has no flips and equals `inRotate1` at weight 0 and
///   `inRotate2` at weight 1 up to rounding.
///
/// `weight` is clamped to [0, 1] (Maya's attribute range). At exactly 0 the outputs
/// are input 1 and at exactly 1 input 2, bit for bit (made finite), without reading the
/// other pair: a compiled program does not evaluate what feeds it (an FK/IK switch at
/// FK runs no IK; see [`NodeType::unread_inputs`]). Differences from
/// Maya: the per-axis `translateXMode`... and `rotateMode` switches are not
/// modelled (always "blend inputs"). The vec3 children have Maya's names,
/// with the pair number last: `inTranslateX1`..`inTranslateZ1`,
/// `inTranslateX2`.., `inRotateX1`.., `inRotateX2`.. (Maya's pairBlend node
/// reference lists exactly these); the outputs have `outTranslateX`...
pub struct PairBlend {
    spec: NodeSpec,
    in_translate1: Input<DVec3>,
    in_translate2: Input<DVec3>,
    in_rotate1: Input<DVec3>,
    in_rotate2: Input<DVec3>,
    weight: Input<f64>,
    rot_interpolation: Input<i64>,
    rotate_order: Input<i64>,
    out_translate: Output<DVec3>,
    out_rotate: Output<DVec3>,
}

impl PairBlend {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("pairBlend");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[
            ("inTranslate1", "it1"),
            ("inTranslateX1", "itx1"),
            ("inTranslateY1", "ity1"),
            ("inTranslateZ1", "itz1"),
            ("inTranslate2", "it2"),
            ("inTranslateX2", "itx2"),
            ("inTranslateY2", "ity2"),
            ("inTranslateZ2", "itz2"),
            ("inRotate1", "ir1"),
            ("inRotateX1", "irx1"),
            ("inRotateY1", "iry1"),
            ("inRotateZ1", "irz1"),
            ("inRotate2", "ir2"),
            ("inRotateX2", "irx2"),
            ("inRotateY2", "iry2"),
            ("inRotateZ2", "irz2"),
            ("weight", "w"),
            ("rotInterpolation", "ri"),
            ("outTranslate", "ot"),
            ("outRotate", "or"),
        ]);
        s.doc("blends translate/rotate pair 1 (weight 0) and pair 2 (weight 1); euler or quaternion rotations");
        let in_translate1 = s.input("inTranslate1", DVec3::ZERO);
        let in_translate2 = s.input("inTranslate2", DVec3::ZERO);
        let in_rotate1 = s.input("inRotate1", DVec3::ZERO);
        let in_rotate2 = s.input("inRotate2", DVec3::ZERO);
        let weight = s.input("weight", 1.0);
        let rot_interpolation = s.input_enum("rotInterpolation", &["euler", "quaternion"], 0);
        let rotate_order = s.input_enum("rotateOrder", &["xyz", "yzx", "zxy", "xzy", "yxz", "zyx"], 0);
        let out_translate = s.output("outTranslate", DVec3::ZERO);
        let out_rotate = s.output("outRotate", DVec3::ZERO);
        s.child_names(in_translate1, ["inTranslateX1", "inTranslateY1", "inTranslateZ1"]);
        s.child_names(in_translate2, ["inTranslateX2", "inTranslateY2", "inTranslateZ2"]);
        s.child_names(in_rotate1, ["inRotateX1", "inRotateY1", "inRotateZ1"]);
        s.child_names(in_rotate2, ["inRotateX2", "inRotateY2", "inRotateZ2"]);
        for h in [in_rotate1, in_rotate2] {
            s.unit(h, Unit::Degrees);
        }
        s.unit(out_rotate, Unit::Degrees);
        for h in [in_translate1, in_translate2] {
            s.unit(h, Unit::Distance);
        }
        s.unit(out_translate, Unit::Distance);
        s.attr_doc(weight, "0 gives input 1, 1 gives input 2 (clamped to [0, 1])");
        s.affects(
            &[in_translate1.id(), in_translate2.id(), weight.id()],
            &[out_translate.id()],
        );
        s.affects(
            &[
                in_rotate1.id(),
                in_rotate2.id(),
                weight.id(),
                rot_interpolation.id(),
                rotate_order.id(),
            ],
            &[out_rotate.id()],
        );
        Ok(PairBlend {
            spec: s.build()?,
            in_translate1,
            in_translate2,
            in_rotate1,
            in_rotate2,
            weight,
            rot_interpolation,
            rotate_order,
            out_translate,
            out_rotate,
        })
    }

    fn run(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let w = clamp_weight(ctx.get(self.weight));
        // The end points read one pair only (the contract of `unread`).
        if w == 0.0 || w == 1.0 {
            let (t, r) = if w == 0.0 {
                (self.in_translate1, self.in_rotate1)
            } else {
                (self.in_translate2, self.in_rotate2)
            };
            if ctx.wants(self.out_translate) {
                ctx.set(self.out_translate, finite3(ctx.get(t)));
            }
            if ctx.wants(self.out_rotate) {
                ctx.set(self.out_rotate, finite3(ctx.get(r)));
            }
            return Ok(());
        }
        if ctx.wants(self.out_translate) {
            let (a, b) = (ctx.get(self.in_translate1), ctx.get(self.in_translate2));
            ctx.set(self.out_translate, finite3(a + (b - a) * w));
        }
        if ctx.wants(self.out_rotate) {
            let (a, b) = (ctx.get(self.in_rotate1), ctx.get(self.in_rotate2));
            let lerp = finite3(a + (b - a) * w);
            let r = if ctx.get(self.rot_interpolation) == 1 {
                let order = RotateOrder::from_index(ctx.get(self.rotate_order)).unwrap_or_default();
                let rad = |v: DVec3| DVec3::new(v.x.to_radians(), v.y.to_radians(), v.z.to_radians());
                let q = slerp_shortest(euler_to_quat(rad(a), order), euler_to_quat(rad(b), order), w);
                let e = quat_to_euler_closest(q, order, rad(lerp));
                finite3(DVec3::new(e.x.to_degrees(), e.y.to_degrees(), e.z.to_degrees()))
            } else {
                lerp
            };
            ctx.set(self.out_rotate, r);
        }
        Ok(())
    }

    /// The pair a known weight of exactly 0 or 1 leaves unread.
    fn unread(&self, known: &KnownInputs<'_>) -> Vec<AttrId> {
        match known.get(self.weight).map(clamp_weight) {
            Some(0.0) => vec![self.in_translate2.id(), self.in_rotate2.id()],
            Some(1.0) => vec![self.in_translate1.id(), self.in_rotate1.id()],
            _ => Vec::new(),
        }
    }
}
node_type!(PairBlend, unread);

/// `weight` as the blend uses it: NaN counts as 0, others are clamped to [0, 1].
fn clamp_weight(w: f64) -> f64 {
    if w.is_nan() {
        0.0
    } else {
        w.clamp(0.0, 1.0)
    }
}
