//! Matrix utility node plugins with Maya 2020+ names: `decomposeMatrix`,
//! `composeMatrix`, `multMatrix`, `inverseMatrix`, `pickMatrix`,
//! `eulerToQuat` and `quatToEuler`.
//!
//! Matrix conventions (glam column vectors; Maya's row-vector products
//! reversed) are in [`super::math`]. Angles on plugs are degrees.

use glam::{DMat4, DQuat, DVec3};
use sinew_core::{ComputeContext, ComputeError, Input, MultiInput, NodeSpec, NodeType, Output, SpecError, Unit};

use super::dag_nodes::{deg_to_rad, rad_to_deg, rotate_order, ROTATE_ORDERS};
use super::math::{
    affine_inverse, compose, compose_quat, decompose, decompose_quat, euler_to_quat, quat_to_euler, Decomposed,
};

/// The inverse of `m`, or the identity when `m` is singular (determinant 0),
/// not finite, or its inverse overflows. Never NaN.
///
/// An affine `m` (last row `0 0 0 1`) is inverted as one ([`affine_inverse`]).
pub fn inverse_or_identity(m: DMat4) -> DMat4 {
    if let Some((inv, det)) = affine_inverse(&m) {
        return if det != 0.0 && det.is_finite() && inv.is_finite() {
            inv
        } else {
            DMat4::IDENTITY
        };
    }
    if !m.is_finite() {
        return DMat4::IDENTITY;
    }
    let det = m.determinant();
    if det == 0.0 || !det.is_finite() {
        return DMat4::IDENTITY;
    }
    let inv = m.inverse();
    if inv.is_finite() {
        inv
    } else {
        DMat4::IDENTITY
    }
}

/// Declares `inputRotateOrder` (Maya's rotate-order enum).
fn rotate_order_input(s: &mut sinew_core::SpecBuilder) -> Input<i64> {
    let h = s.input_enum("inputRotateOrder", &ROTATE_ORDERS, 0);
    s.keyable(h, false).attr_doc(h, "rotate order of the euler angles");
    h
}

/// `decomposeMatrix`: splits `inputMatrix` into `outputTranslate`,
/// `outputRotate` (deg, in `inputRotateOrder`), `outputScale`, `outputShear`
/// and `outputQuat`, so that `composeMatrix` rebuilds it (glam
/// `T * R * SH * S`; see [`decompose`]). A mirroring matrix gets a negative Z
/// scale. Fallback: a non-finite input gives the identity decomposition
/// (translate 0, rotate 0, scale 1, shear 0, identity quaternion).
pub struct DecomposeMatrix {
    spec: NodeSpec,
    input_matrix: Input<DMat4>,
    input_rotate_order: Input<i64>,
    translate: Output<DVec3>,
    rotate: Output<DVec3>,
    scale: Output<DVec3>,
    shear: Output<DVec3>,
    quat: Output<DQuat>,
}

impl DecomposeMatrix {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("decomposeMatrix");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[
            ("inputMatrix", "imat"),
            ("outputTranslate", "ot"),
            ("outputRotate", "or"),
            ("outputScale", "os"),
            ("outputShear", "osh"),
        ]);
        s.doc("splits a matrix into translate, rotate (deg), scale, shear and quaternion");
        let input_matrix = s.input("inputMatrix", DMat4::IDENTITY);
        let input_rotate_order = rotate_order_input(&mut s);
        let translate = s.output("outputTranslate", DVec3::ZERO);
        let rotate = s.output("outputRotate", DVec3::ZERO);
        s.unit(rotate, Unit::Degrees);
        let scale = s.output("outputScale", DVec3::ONE);
        let shear = s.output("outputShear", DVec3::ZERO);
        let quat = s.output("outputQuat", DQuat::IDENTITY);
        Ok(DecomposeMatrix {
            spec: s.build()?,
            input_matrix,
            input_rotate_order,
            translate,
            rotate,
            scale,
            shear,
            quat,
        })
    }
}

impl NodeType for DecomposeMatrix {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let order = rotate_order(ctx.get(self.input_rotate_order));
        let d = decompose(ctx.get(self.input_matrix), order).unwrap_or(Decomposed::IDENTITY);
        ctx.set(self.translate, d.translate);
        ctx.set(self.rotate, rad_to_deg(d.rotate));
        ctx.set(self.scale, d.scale);
        ctx.set(self.shear, d.shear);
        ctx.set(self.quat, d.quat);
        Ok(())
    }
}

/// `composeMatrix`: `outputMatrix` = glam `T * R * SH * S` (Maya
/// `S·SH·R·T`) from `inputTranslate`, `inputRotate` (deg, in
/// `inputRotateOrder`) or `inputQuat` (when `useEulerRotation` is off),
/// `inputScale` and `inputShear`. Fallbacks: a zero or non-finite quaternion
/// counts as identity; non-finite components count as identity values.
pub struct ComposeMatrix {
    spec: NodeSpec,
    translate: Input<DVec3>,
    rotate: Input<DVec3>,
    scale: Input<DVec3>,
    shear: Input<DVec3>,
    rotate_order: Input<i64>,
    quat: Input<DQuat>,
    use_euler: Input<bool>,
    out: Output<DMat4>,
}

impl ComposeMatrix {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("composeMatrix");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[
            ("inputTranslate", "it"),
            ("inputRotate", "ir"),
            ("inputScale", "is"),
            ("outputMatrix", "omat"),
        ]);
        s.doc("builds a matrix from translate, rotate (deg) or quaternion, scale and shear");
        let translate = s.input("inputTranslate", DVec3::ZERO);
        let rotate = s.input("inputRotate", DVec3::ZERO);
        s.unit(rotate, Unit::Degrees);
        let scale = s.input("inputScale", DVec3::ONE);
        let shear = s.input("inputShear", DVec3::ZERO);
        let rotate_order = rotate_order_input(&mut s);
        let quat = s.input("inputQuat", DQuat::IDENTITY);
        let use_euler = s.input("useEulerRotation", true);
        s.attr_doc(use_euler, "on: rotation from inputRotate; off: from inputQuat");
        let out = s.output("outputMatrix", DMat4::IDENTITY);
        Ok(ComposeMatrix {
            spec: s.build()?,
            translate,
            rotate,
            scale,
            shear,
            rotate_order,
            quat,
            use_euler,
            out,
        })
    }
}

impl NodeType for ComposeMatrix {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let t = ctx.get(self.translate);
        let s = ctx.get(self.scale);
        let sh = ctx.get(self.shear);
        let m = if ctx.get(self.use_euler) {
            let order = rotate_order(ctx.get(self.rotate_order));
            compose(t, deg_to_rad(ctx.get(self.rotate)), order, s, sh)
        } else {
            compose_quat(t, ctx.get(self.quat), s, sh)
        };
        ctx.set(self.out, m);
        Ok(())
    }
}

/// `multMatrix`: `matrixSum` is the product of the existing `matrixIn[i]`
/// in index order, Maya `m[0]·m[1]·…` (row vectors), i.e. glam
/// `m[n-1] * … * m[0]`: `matrixIn[0]` is applied first. No elements give the
/// identity. Overflow is not masked (it is a property of the inputs).
pub struct MultMatrix {
    spec: NodeSpec,
    matrix_in: MultiInput<DMat4>,
    out: Output<DMat4>,
}

impl MultMatrix {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("multMatrix");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[("matrixIn", "i"), ("matrixSum", "o")]);
        s.doc("product of matrixIn[0..n] in index order (matrixIn[0] applied first)");
        let matrix_in = s.multi_input("matrixIn", DMat4::IDENTITY);
        let out = s.output("matrixSum", DMat4::IDENTITY);
        Ok(MultMatrix {
            spec: s.build()?,
            matrix_in,
            out,
        })
    }
}

impl NodeType for MultMatrix {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let mut acc = DMat4::IDENTITY;
        let mut k = 0;
        while let Some((_, m)) = ctx.multi_at(self.matrix_in, k) {
            acc = m * acc;
            k += 1;
        }
        ctx.set(self.out, acc);
        Ok(())
    }
}

/// `inverseMatrix`: `outputMatrix` is the inverse of `inputMatrix`.
/// Fallback: a singular (determinant exactly 0) or non-finite input gives the
/// identity (see [`inverse_or_identity`]).
pub struct InverseMatrix {
    spec: NodeSpec,
    input: Input<DMat4>,
    out: Output<DMat4>,
}

impl InverseMatrix {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("inverseMatrix");
        s.doc("inverse of inputMatrix; identity when it is singular");
        let input = s.input("inputMatrix", DMat4::IDENTITY);
        let out = s.output("outputMatrix", DMat4::IDENTITY);
        Ok(InverseMatrix {
            spec: s.build()?,
            input,
            out,
        })
    }
}

impl NodeType for InverseMatrix {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let m = ctx.get(self.input);
        ctx.set(self.out, inverse_or_identity(m));
        Ok(())
    }
}

/// `pickMatrix`: rebuilds `inputMatrix` from the components whose
/// `useTranslate` / `useRotate` / `useScale` / `useShear` flag is on; the
/// others are set to identity (translate 0, no rotation, scale 1, shear 0).
/// With every flag on the input passes through unchanged (bit for bit).
/// Fallback: a non-finite input decomposes as the identity.
pub struct PickMatrix {
    spec: NodeSpec,
    input: Input<DMat4>,
    use_translate: Input<bool>,
    use_rotate: Input<bool>,
    use_scale: Input<bool>,
    use_shear: Input<bool>,
    out: Output<DMat4>,
}

impl PickMatrix {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("pickMatrix");
        s.doc("keeps the chosen components (translate, rotate, scale, shear) of a matrix");
        let input = s.input("inputMatrix", DMat4::IDENTITY);
        let use_translate = s.input("useTranslate", true);
        let use_rotate = s.input("useRotate", true);
        let use_scale = s.input("useScale", true);
        let use_shear = s.input("useShear", true);
        let out = s.output("outputMatrix", DMat4::IDENTITY);
        Ok(PickMatrix {
            spec: s.build()?,
            input,
            use_translate,
            use_rotate,
            use_scale,
            use_shear,
            out,
        })
    }
}

impl NodeType for PickMatrix {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let m = ctx.get(self.input);
        let flags = [
            ctx.get(self.use_translate),
            ctx.get(self.use_rotate),
            ctx.get(self.use_scale),
            ctx.get(self.use_shear),
        ];
        let out = if flags.iter().all(|&f| f) && m.is_finite() {
            m
        } else {
            let d = Decomposed::IDENTITY;
            let identity = (d.translate, d.quat, d.scale, d.shear);
            let (t, q, s, sh) = match (m.is_finite(), flags[1] || flags[2] || flags[3]) {
                (false, _) => identity,
                (true, true) => decompose_quat(m).unwrap_or(identity),
                // Translation only: nothing to decompose.
                (true, false) => (m.w_axis.truncate(), d.quat, d.scale, d.shear),
            };
            compose_quat(
                if flags[0] { t } else { DVec3::ZERO },
                if flags[1] { q } else { DQuat::IDENTITY },
                if flags[2] { s } else { DVec3::ONE },
                if flags[3] { sh } else { DVec3::ZERO },
            )
        };
        ctx.set(self.out, out);
        Ok(())
    }
}

/// `eulerToQuat`: `outputQuat` is the rotation of `inputRotate` (deg) in
/// `inputRotateOrder`. Non-finite angles count as 0.
pub struct EulerToQuat {
    spec: NodeSpec,
    rotate: Input<DVec3>,
    order: Input<i64>,
    out: Output<DQuat>,
}

impl EulerToQuat {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("eulerToQuat");
        s.doc("quaternion of euler angles (deg) in a rotate order");
        let rotate = s.input("inputRotate", DVec3::ZERO);
        s.unit(rotate, Unit::Degrees);
        let order = rotate_order_input(&mut s);
        let out = s.output("outputQuat", DQuat::IDENTITY);
        Ok(EulerToQuat {
            spec: s.build()?,
            rotate,
            order,
            out,
        })
    }
}

impl NodeType for EulerToQuat {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let order = rotate_order(ctx.get(self.order));
        let q = euler_to_quat(deg_to_rad(ctx.get(self.rotate)), order);
        ctx.set(self.out, q);
        Ok(())
    }
}

/// `quatToEuler`: `outputRotate` (deg, in `inputRotateOrder`) of
/// `inputQuat` (normalized first). First and last angles in [-180, 180],
/// middle in [-90, 90]. Fallback: a zero or non-finite quaternion counts as
/// identity (rotate 0).
pub struct QuatToEuler {
    spec: NodeSpec,
    quat: Input<DQuat>,
    order: Input<i64>,
    out: Output<DVec3>,
}

impl QuatToEuler {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("quatToEuler");
        s.doc("euler angles (deg) of a quaternion in a rotate order");
        let quat = s.input("inputQuat", DQuat::IDENTITY);
        let order = rotate_order_input(&mut s);
        let out = s.output("outputRotate", DVec3::ZERO);
        s.unit(out, Unit::Degrees);
        Ok(QuatToEuler {
            spec: s.build()?,
            quat,
            order,
            out,
        })
    }
}

impl NodeType for QuatToEuler {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let order = rotate_order(ctx.get(self.order));
        let r = quat_to_euler(ctx.get(self.quat), order);
        ctx.set(self.out, rad_to_deg(r));
        Ok(())
    }
}
