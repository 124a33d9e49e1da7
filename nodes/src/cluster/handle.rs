//! `cluster`: every active vertex follows the handle's transform since bind, scaled by its
//! weight and the envelope (Maya's cluster deformer).
//!
//! Attributes (besides the shared ones of [`crate::deformer::base`]):
//! - `matrix` (matrix): the handle's world matrix (connect `handle.worldMatrix`).
//! - `bindPreMatrix` (matrix): the inverse of the handle's world matrix at bind time.
//! - `weightedMatrix` (matrix): the handle's local matrix (connect `handle.matrix`), used
//!   instead of `matrix · bindPreMatrix` when `relative` is on, so moving the handle's parents
//!   does not deform (Maya's relative mode).
//! - `relative` (bool, false).
//! - `geomMatrix` (matrix): the deformed mesh's world matrix (identity when the mesh is in
//!   world space, as a skinCluster's output is).
//!
//! Formula, in the mesh's object space with `G = geomMatrix`:
//! `D = G⁻¹ · (relative ? weightedMatrix : matrix · bindPreMatrix) · G` (column vectors), and
//! `out = p + weight · envelope · (D·p − p)`. At rest (`matrix · bindPreMatrix = I`) the
//! mesh is unchanged; weight 0.5 moves a vertex halfway to where the handle takes it.

use glam::{DMat4, Mat4};
use sinew_core::{AttrId, ComputeContext, ComputeError, Input, SpecBuilder};

use crate::deformer::base::{deform_points, finite_matrix, inverse, Affine, Deformer, DeformerAttrs, Job};

/// The handles of the cluster transform attributes, shared with `softMod`.
#[derive(Clone, Copy, Debug)]
pub struct HandleAttrs {
    /// `matrix`.
    pub matrix: Input<DMat4>,
    /// `bindPreMatrix`.
    pub bind_pre: Input<DMat4>,
    /// `weightedMatrix`.
    pub weighted: Input<DMat4>,
    /// `relative`.
    pub relative: Input<bool>,
    /// `geomMatrix`.
    pub geom: Input<DMat4>,
}

impl HandleAttrs {
    /// Declares the attributes.
    pub fn declare(s: &mut SpecBuilder) -> Self {
        let matrix = s.input("matrix", DMat4::IDENTITY);
        let bind_pre = s.input("bindPreMatrix", DMat4::IDENTITY);
        let weighted = s.input("weightedMatrix", DMat4::IDENTITY);
        let relative = s.input("relative", false);
        let geom = s.input("geomMatrix", DMat4::IDENTITY);
        s.attr_doc(matrix, "the handle's world matrix")
            .attr_doc(bind_pre, "inverse of the handle's world matrix at bind")
            .attr_doc(weighted, "the handle's local matrix (relative mode)")
            .attr_doc(
                relative,
                "use weightedMatrix only (parents of the handle do not deform)",
            )
            .attr_doc(geom, "the deformed mesh's world matrix");
        // Maya's short names (node reference, Nodes/cluster.html and Nodes/softMod.html).
        s.short_name(matrix, "ma")
            .short_name(bind_pre, "pm")
            .short_name(weighted, "wt")
            .short_name(relative, "rel")
            .short_name(geom, "gm");
        HandleAttrs {
            matrix,
            bind_pre,
            weighted,
            relative,
            geom,
        }
    }

    /// The ids, for `affects`.
    pub fn ids(&self) -> Vec<AttrId> {
        vec![
            self.matrix.id(),
            self.bind_pre.id(),
            self.weighted.id(),
            self.relative.id(),
            self.geom.id(),
        ]
    }

    /// The deformation matrix `D` in object space, and `G` (see the module docs).
    pub fn read(&self, ty: &str, ctx: &ComputeContext<'_>) -> Result<(Mat4, DMat4), ComputeError> {
        let g = finite_matrix(ty, "geomMatrix", ctx.get(self.geom))?;
        let world = if ctx.get(self.relative) {
            finite_matrix(ty, "weightedMatrix", ctx.get(self.weighted))?
        } else {
            finite_matrix(ty, "matrix", ctx.get(self.matrix))?
                * finite_matrix(ty, "bindPreMatrix", ctx.get(self.bind_pre))?
        };
        let d = if g == DMat4::IDENTITY {
            world
        } else {
            inverse(ty, "geomMatrix", g)? * world * g
        };
        Ok((d.as_mat4(), g))
    }
}

/// The `cluster` deformer.
pub struct Cluster {
    handle: HandleAttrs,
}

impl Deformer for Cluster {
    type Frame = Mat4;

    fn declare(s: &mut SpecBuilder, _base: &DeformerAttrs) -> (Self, Vec<AttrId>) {
        // Maya's cluster short names (node reference, *cluster*).
        s.maya_names(&[
            ("matrix", "ma"),
            ("bindPreMatrix", "pm"),
            ("weightedMatrix", "wt"),
            ("relative", "rel"),
            ("geomMatrix", "gm"),
        ]);
        let handle = HandleAttrs::declare(s);
        let ids = handle.ids();
        (Cluster { handle }, ids)
    }

    fn prepare(&self, ty: &str, ctx: &ComputeContext<'_>) -> Result<Mat4, ComputeError> {
        Ok(self.handle.read(ty, ctx)?.0)
    }

    fn deform(&self, _ty: &str, d: &Mat4, job: Job<'_>) -> Result<(), ComputeError> {
        let d = Affine::new(*d);
        deform_points(&job.input.positions, job.out, job.membership, job.envelope, |_, p| {
            d.apply(p)
        });
        Ok(())
    }
}
