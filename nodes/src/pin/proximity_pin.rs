//! `proximityPin`: matrices bound to the closest point of a mesh, following it as it deforms.

use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3, Vec3};
use sinew_core::{
    ComputeContext, ComputeError, Input, Mesh, MultiInput, MultiOutput, NodeSpec, NodeType, ObjectRef, Output,
    SpecError,
};

use super::common::{to_matrix, FrameRead, PinFrame};
use crate::deform::closest_point::MeshIndex;
use crate::deform::surface::evaluate;
use crate::transform::matrix_nodes::inverse_or_identity;

/// Maya's `coordMode` choices: where the tangent of each frame comes from.
pub const COORD_MODES: [&str; 2] = ["edge", "uv"];

/// One bound input matrix: where it sits on the original mesh and its offset from the frame
/// there.
#[derive(Clone, Copy, Debug)]
struct Binding {
    index: u32,
    triangle: u32,
    barycentric: Vec3,
    /// `frame⁻¹ · inputMatrix`, in the frame of the original mesh.
    offset: DMat4,
}

/// The bind of every `inputMatrix` element (`bindCache` output).
#[derive(Clone, Debug, Default)]
struct Bind {
    bindings: Vec<Binding>,
    triangles: usize,
}

/// `proximityPin` (Maya 2020): each `inputMatrix[i]` is bound to the point of
/// `originalGeometry` closest to its translation, and `outputMatrix[i]` follows that point
/// on `deformedGeometry` (same triangles), keeping its offset.
///
/// * Bind (its own group, `bindCache`, recomputed only when the original mesh, the input
///   matrices, `coordMode` or the axes change): the closest point (triangle, barycentric
///   weights) and the frame `F₀` there; offset `O = F₀⁻¹ · inputMatrix[i]`.
/// * Each evaluation: the frame `F₁` at the same triangle and weights of the deformed mesh;
///   `outputMatrix[i] = F₁ · O`, where `offsetTranslation` off drops the offset's
///   translation (the pin sits on the surface) and `offsetOrientation` off its rotation (the
///   pin takes the frame's orientation). Both default on, so an undeformed mesh gives back
///   `inputMatrix[i]` exactly in rotation and translation (to rounding). `envelope`
///   blends from `inputMatrix[i]` (0) to that (1): translation linearly, rotation by slerp,
///   the input's scale kept.
/// * Frames: the normal axis along the interpolated normal, the tangent axis along the
///   triangle's first edge (`coordMode` edge, 0, the default) or `∂P/∂u` from its UVs (uv,
///   1; falls back to a fixed vector orthogonal to the normal without UVs); see the module
///   docs for axes and `relativeSpaceMode`.
/// * An empty original mesh, or a deformed mesh with other triangles, passes the input
///   matrices through unchanged; elements without an input matrix output identity.
pub struct ProximityPin {
    spec: NodeSpec,
    original: Input<Arc<Mesh>>,
    deformed: Input<Arc<Mesh>>,
    input_matrix: MultiInput<DMat4>,
    coord_mode: Input<i64>,
    offset_translation: Input<bool>,
    offset_orientation: Input<bool>,
    envelope: Input<f64>,
    frame: PinFrame,
    bind: Output<ObjectRef>,
    output: MultiOutput<DMat4>,
}

impl ProximityPin {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("proximityPin");
        // Maya's short names (node reference; omat, nrm and rsmd as uvPin's in Maya-written scenes).
        b.maya_names(&[
            ("deformedGeometry", "curgeom"),
            ("coordMode", "crdm"),
            ("envelope", "en"),
            ("inputMatrix", "imat"),
            ("normalAxis", "nrm"),
            ("relativeSpaceMode", "rsmd"),
            ("outputMatrix", "omat"),
        ]);
        b.doc("matrices that follow the closest point of a deforming mesh, offset kept");
        let original = b.input("originalGeometry", Arc::new(Mesh::default()));
        let deformed = b.input("deformedGeometry", Arc::new(Mesh::default()));
        let input_matrix = b.multi_input("inputMatrix", DMat4::IDENTITY);
        let coord_mode = b.input_enum("coordMode", &COORD_MODES, 0);
        let offset_translation = b.input("offsetTranslation", true);
        let offset_orientation = b.input("offsetOrientation", true);
        let envelope = b.input("envelope", 1.0);
        let frame = PinFrame::declare(&mut b);
        let bind = b.output("bindCache", ObjectRef::default());
        let output = b.multi_output("outputMatrix", DMat4::IDENTITY);
        b.attr_doc(original, "the undeformed mesh the matrices are bound to")
            .attr_doc(deformed, "the deforming mesh (same triangles)")
            .attr_doc(
                input_matrix,
                "matrix i at bind time (world matrix of the pinned object)",
            )
            .attr_doc(
                coord_mode,
                "tangent from the triangle's first edge (edge) or from its UVs (uv)",
            )
            .attr_doc(offset_translation, "keep the offset from the surface point")
            .attr_doc(offset_orientation, "keep the orientation offset from the surface frame")
            .attr_doc(envelope, "0 = input matrices, 1 = pinned")
            .attr_doc(bind, "closest points and offsets of the input matrices")
            .attr_doc(output, "pinned matrix i");
        b.affects(
            &[
                original.id(),
                input_matrix.id(),
                coord_mode.id(),
                frame.normal_axis.id(),
                frame.tangent_axis.id(),
            ],
            &[bind.id()],
        );
        let mut ins = vec![
            bind.id(),
            deformed.id(),
            input_matrix.id(),
            coord_mode.id(),
            offset_translation.id(),
            offset_orientation.id(),
            envelope.id(),
        ];
        ins.extend(frame.ids());
        b.affects(&ins, &[output.id()]);
        Ok(ProximityPin {
            spec: b.build()?,
            original,
            deformed,
            input_matrix,
            coord_mode,
            offset_translation,
            offset_orientation,
            envelope,
            frame,
            bind,
            output,
        })
    }

    fn compute_bind(&self, ctx: &mut ComputeContext<'_>) {
        let mesh = ctx.get(self.original);
        let frame = self.frame.read(ctx);
        let edge = ctx.get(self.coord_mode) == 0;
        let index = MeshIndex::build(&mesh);
        let mut bind = Bind {
            bindings: Vec::new(),
            triangles: mesh.triangles.len(),
        };
        for k in 0..ctx.multi_len(self.input_matrix) {
            let Some((i, m)) = ctx.multi_at(self.input_matrix, k) else {
                continue;
            };
            let p = m.w_axis.truncate().as_vec3();
            if !m.is_finite() {
                continue;
            }
            let Some(hit) = index.closest_point(&mesh, p) else {
                continue;
            };
            let Some(f0) = surface_frame(&mesh, hit.triangle, hit.barycentric, edge, &frame) else {
                continue;
            };
            bind.bindings.push(Binding {
                index: i,
                triangle: hit.triangle,
                barycentric: hit.barycentric,
                offset: inverse_or_identity(f0) * m,
            });
        }
        ctx.set(self.bind, ObjectRef::new(bind));
    }
}

/// The frame (rotation from the axes, position) at a barycentric point of `mesh`, or `None`
/// when the triangle is out of range.
fn surface_frame(mesh: &Mesh, triangle: u32, bary: Vec3, edge: bool, frame: &FrameRead) -> Option<DMat4> {
    let sp = evaluate(mesh, triangle, bary)?;
    let tangent = if edge {
        let t = mesh.triangles.get(triangle as usize)?;
        let p = |i: u32| mesh.positions.get(i as usize).map(|v| v.as_dvec3());
        p(t[1])? - p(t[0])?
    } else {
        sp.tangent_u.as_dvec3()
    };
    Some(to_matrix(
        frame.rotation(sp.normal.as_dvec3(), tangent),
        sp.position.as_dvec3(),
    ))
}

/// `from` blended towards `to` by `t`: translation linearly, rotation by slerp, `from`'s scale.
fn blend(from: DMat4, to: DMat4, t: f64) -> DMat4 {
    let (s0, r0, p0) = from.to_scale_rotation_translation();
    let (_, r1, p1) = to.to_scale_rotation_translation();
    let r = if r0.dot(r1) < 0.0 { -r1 } else { r1 };
    DMat4::from_scale_rotation_translation(s0, DQuat::slerp(r0, r, t), p0.lerp(p1, t))
}

impl NodeType for ProximityPin {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if ctx.wants(self.bind) {
            self.compute_bind(ctx);
            return Ok(());
        }
        let frame = self.frame.read(ctx);
        let edge = ctx.get(self.coord_mode) == 0;
        let keep_t = ctx.get(self.offset_translation);
        let keep_r = ctx.get(self.offset_orientation);
        let env = ctx.get(self.envelope);
        let env = if env.is_finite() { env.clamp(0.0, 1.0) } else { 0.0 };
        let deformed = ctx.get(self.deformed);
        let bind_ref = ctx.get_output(self.bind);
        let bind = bind_ref.downcast::<Bind>();
        let usable = bind.filter(|b| b.triangles > 0 && b.triangles == deformed.triangles.len());
        for k in 0..ctx.multi_out_len(self.output) {
            let i = ctx.multi_out_index(self.output, k).unwrap_or(0);
            let input = ctx.get_at(self.input_matrix, i);
            let pinned = usable
                .and_then(|b| b.bindings.iter().find(|x| x.index == i))
                .and_then(|b| {
                    let f1 = surface_frame(&deformed, b.triangle, b.barycentric, edge, &frame)?;
                    let mut o = b.offset;
                    if !keep_r {
                        let (s, _, t) = o.to_scale_rotation_translation();
                        o = DMat4::from_scale_rotation_translation(s, DQuat::IDENTITY, t);
                    }
                    if !keep_t {
                        o.w_axis = DVec3::ZERO.extend(1.0);
                    }
                    Some(f1 * o)
                });
            let out = match (input, pinned) {
                (Some(m), Some(p)) if env < 1.0 => frame.in_space(blend(m, p, env)),
                (_, Some(p)) => frame.in_space(p),
                (Some(m), None) => m,
                (None, None) => DMat4::IDENTITY,
            };
            ctx.set_elem(self.output, k, out);
        }
        Ok(())
    }
}
