//! Matrix node plugins that blend or re-orient a matrix: `blendMatrix`
//! (ordered, stacked blend toward weighted targets) and `aimMatrix`
//! (primary/secondary aim or align). Maya 2020+ names.
//!
//! Matrix conventions (glam column vectors) are in [`super::math`].

use glam::{DMat3, DMat4, DVec3};
use sinew_core::{ComputeContext, ComputeError, Input, MultiInput, NodeSpec, NodeType, Output, SpecError};

use super::math::{aim_matrix, blend_matrices, blend_matrices_by, orthonormalize};

/// One step of an ordered blend: `a` at `t = 0` (or non-finite `t`), `b`
/// exactly at `t = 1`, otherwise [`blend_matrices`] (translate, scale, shear
/// linear; rotation by shortest slerp; `t` outside [0, 1] extrapolates).
pub fn blend_step(a: DMat4, b: DMat4, t: f64) -> DMat4 {
    if t == 0.0 || !t.is_finite() {
        a
    } else if t == 1.0 {
        b
    } else {
        blend_matrices(a, b, t)
    }
}

/// `blendMatrix`: starting from `inputMatrix`, blends successively toward
/// each existing `targetMatrix[i]` (index order) with `weight[i]` (default 1
/// when that element does not exist): `acc = blend(acc, target[i], w[i])`,
/// so a later target with weight 1 overrides everything before it (Maya's
/// stacked blend, not a weighted average). Then
/// `outputMatrix = blend(inputMatrix, acc, envelope)`; `enable` off passes
/// `inputMatrix` through.
///
/// Per target (Maya's compound `target[i]`, here the parallel multis
/// `targetMatrix[i]`, `weight[i]`, `useMatrix[i]`, `translateWeight[i]`,
/// `rotateWeight[i]`, `scaleWeight[i]`, `shearWeight[i]`): `useMatrix` off
/// skips the target; each component blends by `weight · componentWeight`
/// (all default 1), so `rotateWeight[i] = 0` takes only the other components
/// of that target.
///
/// Spaces: every input matrix (`inputMatrix` and the targets) is taken into
/// `preSpaceMatrix` first (Maya `M · pre`, glam `pre * M`) and the result out
/// through `postSpaceMatrix` (`R · post`); both default to the identity, and
/// with identities the products are skipped (same bits as without them).
///
/// Fallback: a non-finite weight or envelope counts as 0; non-finite
/// matrices are blended as identity.
pub struct BlendMatrix {
    spec: NodeSpec,
    input: Input<DMat4>,
    enable: Input<bool>,
    envelope: Input<f64>,
    pre: Input<DMat4>,
    post: Input<DMat4>,
    target_matrix: MultiInput<DMat4>,
    weight: MultiInput<f64>,
    use_matrix: MultiInput<bool>,
    component_weights: [MultiInput<f64>; 4],
    out: Output<DMat4>,
}

impl BlendMatrix {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("blendMatrix");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[
            ("inputMatrix", "imat"),
            ("targetMatrix", "tmat"),
            ("weight", "wgt"),
            ("outputMatrix", "omat"),
            ("enable", "enb"),
            ("envelope", "env"),
            ("preSpaceMatrix", "premat"),
            ("postSpaceMatrix", "pstmat"),
        ]);
        s.doc("blends inputMatrix successively toward targetMatrix[i] by weight[i], scaled by envelope");
        let input = s.input("inputMatrix", DMat4::IDENTITY);
        let enable = s.input("enable", true);
        let envelope = s.input("envelope", 1.0);
        s.attr_doc(envelope, "0: inputMatrix, 1: the full stacked blend");
        let pre = s.input("preSpaceMatrix", DMat4::IDENTITY);
        s.attr_doc(pre, "every input matrix is taken into this space first");
        let post = s.input("postSpaceMatrix", DMat4::IDENTITY);
        s.attr_doc(post, "the result is taken out through this space");
        let target_matrix = s.multi_input("targetMatrix", DMat4::IDENTITY);
        s.attr_doc(target_matrix, "target[i].targetMatrix");
        let weight = s.multi_input("weight", 1.0);
        s.attr_doc(weight, "target[i].weight: blend factor over the result so far");
        let use_matrix = s.multi_input("useMatrix", true);
        s.attr_doc(use_matrix, "target[i].useMatrix: off skips the target");
        let component_weights = ["translateWeight", "rotateWeight", "scaleWeight", "shearWeight"].map(|name| {
            let h = s.multi_input(name, 1.0);
            s.attr_doc(h, "target[i]: factor on weight for this component");
            h
        });
        let out = s.output("outputMatrix", DMat4::IDENTITY);
        Ok(BlendMatrix {
            spec: s.build()?,
            input,
            enable,
            envelope,
            pre,
            post,
            target_matrix,
            weight,
            use_matrix,
            component_weights,
            out,
        })
    }
}

/// `space * m` (Maya `m · space`), skipped when `space` is exactly the identity.
pub(crate) fn into_space(space: &DMat4, m: DMat4) -> DMat4 {
    if *space == DMat4::IDENTITY {
        m
    } else {
        *space * m
    }
}

impl NodeType for BlendMatrix {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let raw = ctx.get(self.input);
        if !ctx.get(self.enable) {
            ctx.set(self.out, raw);
            return Ok(());
        }
        let pre = ctx.get(self.pre);
        let input = into_space(&pre, raw);
        let mut acc = input;
        let mut k = 0;
        while let Some((index, target)) = ctx.multi_at(self.target_matrix, k) {
            k += 1;
            if !ctx.get_at(self.use_matrix, index).unwrap_or(true) {
                continue;
            }
            let w = ctx.get_at(self.weight, index).unwrap_or(1.0);
            let c = self.component_weights.map(|h| ctx.get_at(h, index).unwrap_or(1.0));
            let target = into_space(&pre, target);
            acc = if c == [1.0; 4] {
                blend_step(acc, target, w)
            } else {
                blend_matrices_by(acc, target, c.map(|c| w * c))
            };
        }
        let out = blend_step(input, acc, ctx.get(self.envelope));
        ctx.set(self.out, into_space(&ctx.get(self.post), out));
        Ok(())
    }
}

/// `aimMatrix`: rotates `inputMatrix` about its own position so that
/// `primaryInputAxis` (in the input's space) points at / along the primary
/// target and `secondaryInputAxis` turns as close as possible toward the
/// secondary target. Scale, shear and position of the input are kept.
///
/// Modes: `primaryMode` `lockAxis` (keep the axis where it is), `aim` (toward
/// the point `primaryTargetMatrix · primaryTargetVector`), `align` (along the
/// vector `primaryTargetVector` expressed in `primaryTargetMatrix`);
/// `secondaryMode` `none` (the primary is reached by the shortest rotation
/// from the input orientation), `aim`, `align` (same meanings). `envelope`
/// blends from the input (0) to the aimed result (1); `enable` off passes the
/// input through.
///
/// Spaces: `inputMatrix` is taken into `preSpaceMatrix` first (Maya
/// `input · pre`, glam `pre * input`; the targets are not: they are points
/// and directions given in their own target matrices) and the result out
/// through `postSpaceMatrix` (`R · post`). Identities skip the products.
///
/// Fallbacks (from
/// [`aim_matrix`]): a zero aim direction (target at the input position, zero
/// align vector) leaves the primary axis where it is; a zero or parallel
/// secondary direction behaves like `none`; zero/parallel input axes use X and
/// a perpendicular axis. A non-finite `inputMatrix` gives the identity.
pub struct AimMatrix {
    spec: NodeSpec,
    input: Input<DMat4>,
    enable: Input<bool>,
    envelope: Input<f64>,
    pre: Input<DMat4>,
    post: Input<DMat4>,
    primary_axis: Input<DVec3>,
    primary_mode: Input<i64>,
    primary_vector: Input<DVec3>,
    primary_matrix: Input<DMat4>,
    secondary_axis: Input<DVec3>,
    secondary_mode: Input<i64>,
    secondary_vector: Input<DVec3>,
    secondary_matrix: Input<DMat4>,
    out: Output<DMat4>,
}

/// Index of `lockAxis` / `none`, `aim` and `align` in the mode enums.
const MODE_AIM: i64 = 1;
const MODE_ALIGN: i64 = 2;

impl AimMatrix {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("aimMatrix");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[
            ("enable", "enb"),
            ("envelope", "env"),
            ("inputMatrix", "imat"),
            ("outputMatrix", "tmat"),
            ("secondaryMode", "sm"),
            ("preSpaceMatrix", "premat"),
            ("postSpaceMatrix", "pstmat"),
        ]);
        s.doc("orients inputMatrix so primaryInputAxis aims at/aligns with a target, secondary axis toward another");
        let input = s.input("inputMatrix", DMat4::IDENTITY);
        let enable = s.input("enable", true);
        let envelope = s.input("envelope", 1.0);
        let pre = s.input("preSpaceMatrix", DMat4::IDENTITY);
        s.attr_doc(pre, "inputMatrix is taken into this space first");
        let post = s.input("postSpaceMatrix", DMat4::IDENTITY);
        s.attr_doc(post, "the result is taken out through this space");
        let primary_axis = s.input("primaryInputAxis", DVec3::X);
        let primary_mode = s.input_enum("primaryMode", &["lockAxis", "aim", "align"], MODE_AIM);
        let primary_vector = s.input("primaryTargetVector", DVec3::ZERO);
        s.attr_doc(
            primary_vector,
            "aim: a point in primaryTargetMatrix space; align: a direction in it",
        );
        let primary_matrix = s.input("primaryTargetMatrix", DMat4::IDENTITY);
        let secondary_axis = s.input("secondaryInputAxis", DVec3::Y);
        let secondary_mode = s.input_enum("secondaryMode", &["none", "aim", "align"], 0);
        let secondary_vector = s.input("secondaryTargetVector", DVec3::ZERO);
        s.attr_doc(
            secondary_vector,
            "aim: a point in secondaryTargetMatrix space; align: a direction in it",
        );
        let secondary_matrix = s.input("secondaryTargetMatrix", DMat4::IDENTITY);
        let out = s.output("outputMatrix", DMat4::IDENTITY);
        Ok(AimMatrix {
            spec: s.build()?,
            input,
            enable,
            envelope,
            pre,
            post,
            primary_axis,
            primary_mode,
            primary_vector,
            primary_matrix,
            secondary_axis,
            secondary_mode,
            secondary_vector,
            secondary_matrix,
            out,
        })
    }

    /// World-space direction for a mode: toward a point (aim), along a vector
    /// (align), or `otherwise` (lockAxis / none).
    fn direction(mode: i64, target: DMat4, vector: DVec3, position: DVec3, otherwise: DVec3) -> DVec3 {
        match mode {
            MODE_AIM => target.transform_point3(vector) - position,
            MODE_ALIGN => target.transform_vector3(vector),
            _ => otherwise,
        }
    }
}

impl NodeType for AimMatrix {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let m = ctx.get(self.input);
        if !ctx.get(self.enable) {
            ctx.set(self.out, m);
            return Ok(());
        }
        let m = into_space(&ctx.get(self.pre), m);
        if !m.is_finite() {
            ctx.set(self.out, DMat4::IDENTITY);
            return Ok(());
        }
        let position = m.w_axis.truncate();
        let m3 = DMat3::from_mat4(m);
        let rin = orthonormalize(m3);
        let primary_axis = ctx.get(self.primary_axis);
        let aim_dir = Self::direction(
            ctx.get(self.primary_mode),
            ctx.get(self.primary_matrix),
            ctx.get(self.primary_vector),
            position,
            rin * primary_axis,
        );
        let up_dir = Self::direction(
            ctx.get(self.secondary_mode),
            ctx.get(self.secondary_matrix),
            ctx.get(self.secondary_vector),
            position,
            DVec3::ZERO,
        );
        // Solve in the input's rotation frame, so "none" means the shortest
        // turn from the current orientation; rin is orthonormal (inverse = transpose).
        let back = rin.transpose();
        let local = aim_matrix(
            DVec3::ZERO,
            back * aim_dir,
            primary_axis,
            ctx.get(self.secondary_axis),
            back * up_dir,
        );
        let delta = rin * local * back;
        let aimed = DMat4::from_mat3_translation(delta * m3, position);
        let out = if aimed.is_finite() {
            blend_step(m, aimed, ctx.get(self.envelope))
        } else {
            m
        };
        ctx.set(self.out, into_space(&ctx.get(self.post), out));
        Ok(())
    }
}
