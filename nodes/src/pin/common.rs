//! The axis and space inputs `uvPin` and `proximityPin` share, and the frame they build.

use glam::{DMat3, DMat4, DVec3};
use sinew_core::{AttrId, ComputeContext, Input, SpecBuilder};

pub use crate::nurbs::frame::SIGNED_AXES;
use crate::nurbs::frame::{axes_frame, signed_axis};
use crate::transform::matrix_nodes::inverse_or_identity;

/// Maya's `relativeSpaceMode` choices.
pub const RELATIVE_SPACE_MODES: [&str; 3] = ["world", "local", "custom"];

/// `normalAxis`, `tangentAxis`, `relativeSpaceMode`, `relativeSpaceMatrix`.
#[derive(Clone, Copy, Debug)]
pub(super) struct PinFrame {
    pub normal_axis: Input<i64>,
    pub tangent_axis: Input<i64>,
    pub space_mode: Input<i64>,
    pub space_matrix: Input<DMat4>,
}

/// The frame settings of one compute.
#[derive(Clone, Copy, Debug)]
pub(super) struct FrameRead {
    normal: (usize, f64),
    tangent: (usize, f64),
    /// `relativeSpaceMatrix⁻¹` in custom mode, else `None`.
    relative: Option<DMat4>,
}

impl PinFrame {
    /// Declares the four inputs (`normalAxis` default x, `tangentAxis` default z).
    pub fn declare(b: &mut SpecBuilder) -> Self {
        let normal_axis = b.input_enum("normalAxis", &SIGNED_AXES, 0);
        let tangent_axis = b.input_enum("tangentAxis", &SIGNED_AXES, 2);
        let space_mode = b.input_enum("relativeSpaceMode", &RELATIVE_SPACE_MODES, 0);
        let space_matrix = b.input("relativeSpaceMatrix", DMat4::IDENTITY);
        b.attr_doc(normal_axis, "local axis along the surface normal")
            .attr_doc(tangent_axis, "local axis along the surface u tangent")
            .attr_doc(
                space_mode,
                "world / local (as the geometry arrives) or custom (relative to relativeSpaceMatrix)",
            )
            .attr_doc(space_matrix, "the space outputs are relative to in custom mode");
        PinFrame {
            normal_axis,
            tangent_axis,
            space_mode,
            space_matrix,
        }
    }

    /// The attribute ids, for `affects`.
    pub fn ids(&self) -> [AttrId; 4] {
        [
            self.normal_axis.id(),
            self.tangent_axis.id(),
            self.space_mode.id(),
            self.space_matrix.id(),
        ]
    }

    /// Reads the settings.
    pub fn read(&self, ctx: &ComputeContext<'_>) -> FrameRead {
        FrameRead {
            normal: signed_axis(ctx.get(self.normal_axis)),
            tangent: signed_axis(ctx.get(self.tangent_axis)),
            relative: (ctx.get(self.space_mode) == 2).then(|| inverse_or_identity(ctx.get(self.space_matrix))),
        }
    }
}

impl FrameRead {
    /// The rotation with the normal axis along `normal` and the tangent axis along `tangent`.
    pub fn rotation(&self, normal: DVec3, tangent: DVec3) -> DMat3 {
        axes_frame(
            self.normal.0,
            self.normal.1,
            normal,
            self.tangent.0,
            self.tangent.1,
            tangent,
        )
    }

    /// The output matrix of a frame at `position`, in the chosen space.
    pub fn matrix(&self, position: DVec3, normal: DVec3, tangent: DVec3) -> DMat4 {
        self.in_space(to_matrix(self.rotation(normal, tangent), position))
    }

    /// `m` in the chosen space.
    pub fn in_space(&self, m: DMat4) -> DMat4 {
        match self.relative {
            Some(r) => r * m,
            None => m,
        }
    }
}

/// A rigid matrix from a rotation and a position.
pub(super) fn to_matrix(rot: DMat3, p: DVec3) -> DMat4 {
    DMat4::from_cols(
        rot.x_axis.extend(0.0),
        rot.y_axis.extend(0.0),
        rot.z_axis.extend(0.0),
        p.extend(1.0),
    )
}
