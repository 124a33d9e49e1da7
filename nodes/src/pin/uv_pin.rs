//! `uvPin`: one output matrix per UV coordinate of a mesh or a NURBS surface.

use std::sync::Arc;

use glam::{DMat4, DVec3};
use sinew_core::{
    ComputeContext, ComputeError, Input, Mesh, MultiInput, MultiOutput, NodeSpec, NodeType, ObjectRef, Output,
    SpecError,
};

use super::common::PinFrame;
use crate::deform::follicle::{locate_uv, uv_cache};
use crate::nurbs::cache::{surface_of, SurfaceIn};

/// `uvPin` (Maya 2020): `outputMatrix[i]` is a frame on the geometry at
/// (`coordinateU[i]`, `coordinateV[i]`) (Maya's `coordinate[i]` pairs, flattened).
///
/// * Geometry: `deformedSurface` (a NURBS surface; a sinew addition, as attributes are
///   typed: Maya's `deformedGeometry` takes either) when it has control points, else the
///   mesh `deformedGeometry`. For a mesh, `originalGeometry` (optional: the undeformed mesh
///   with the same triangles and UVs) is indexed once per change so each frame only looks
///   the UV up; without it the deformed mesh is scanned.
/// * On a surface, `normalizedIsoParms` on (the default) reads the coordinates as fractions
///   0..1 of the domains, off as raw parameters; out of range clamps (open) or wraps
///   (periodic). On a mesh the coordinates are UVs; a UV outside every UV triangle gives
///   the identity frame at the origin (before the space change).
/// * Frame: position on the geometry, `normalAxis` along the normal (surfaces `S_u × S_v`,
///   meshes interpolated vertex normals), `tangentAxis` along `∂P/∂u` (see the module docs
///   for the axes and `relativeSpaceMode`). Defaults: normal x, tangent z (the tangent
///   default is inferred from Maya-written scenes, which set `normalAxis` alone).
/// * A coordinate without its partner counts as 0. Outputs exist where read.
pub struct UvPin {
    spec: NodeSpec,
    deformed: Input<Arc<Mesh>>,
    original: Input<Arc<Mesh>>,
    uv_index: Output<ObjectRef>,
    surface: SurfaceIn,
    coordinate_u: MultiInput<f64>,
    coordinate_v: MultiInput<f64>,
    normalized: Input<bool>,
    frame: PinFrame,
    output: MultiOutput<DMat4>,
}

impl UvPin {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("uvPin");
        // Maya's short names (node reference; uvPin nodes in Maya-written scenes: nrm, rsmd, omat).
        b.maya_names(&[
            ("deformedGeometry", "curgeom"),
            ("coordinateU", "cu"),
            ("coordinateV", "cv"),
            ("normalAxis", "nrm"),
            ("relativeSpaceMode", "rsmd"),
            ("outputMatrix", "omat"),
        ]);
        b.doc("output matrices pinned to a mesh or NURBS surface at UV coordinates");
        let deformed = b.input("deformedGeometry", Arc::new(Mesh::default()));
        let original = b.input("originalGeometry", Arc::new(Mesh::default()));
        let uv_index = b.output("uvIndex", ObjectRef::default());
        let surface = SurfaceIn::declare(
            &mut b,
            "deformedSurface",
            "a NURBS surface to pin to (used instead of deformedGeometry when it has control points)",
        );
        let coordinate_u = b.multi_input("coordinateU", 0.0);
        let coordinate_v = b.multi_input("coordinateV", 0.0);
        let normalized = b.input("normalizedIsoParms", true);
        let frame = PinFrame::declare(&mut b);
        let output = b.multi_output("outputMatrix", DMat4::IDENTITY);
        b.attr_doc(deformed, "the (deforming) mesh to pin to")
            .attr_doc(
                original,
                "the undeformed mesh with the same triangles and UVs (indexed once)",
            )
            .attr_doc(uv_index, "UV lookup built from originalGeometry")
            .attr_doc(
                coordinate_u,
                "u of pin i (UV on meshes, parameter or fraction on surfaces)",
            )
            .attr_doc(coordinate_v, "v of pin i")
            .attr_doc(normalized, "surfaces: coordinates are fractions 0..1 of the domains")
            .attr_doc(output, "frame of pin i");
        b.affects(&[original.id()], &[uv_index.id()]);
        let mut ins = vec![
            deformed.id(),
            uv_index.id(),
            surface.cache.id(),
            coordinate_u.id(),
            coordinate_v.id(),
            normalized.id(),
        ];
        ins.extend(frame.ids());
        b.affects(&ins, &[output.id()]);
        Ok(UvPin {
            spec: b.build()?,
            deformed,
            original,
            uv_index,
            surface,
            coordinate_u,
            coordinate_v,
            normalized,
            frame,
            output,
        })
    }
}

impl NodeType for UvPin {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if ctx.wants(self.uv_index) {
            let mesh = ctx.get(self.original);
            ctx.set(self.uv_index, uv_cache(mesh));
            return Ok(());
        }
        if self.surface.compute(ctx) {
            return Ok(());
        }
        let frame = self.frame.read(ctx);
        let surface = self.surface.get(ctx);
        let surface = surface_of(&surface, "uvPin.deformedSurface")?;
        let normalized = ctx.get(self.normalized);
        let mesh = ctx.get(self.deformed);
        let index = ctx.get_output(self.uv_index);
        for k in 0..ctx.multi_out_len(self.output) {
            let i = ctx.multi_out_index(self.output, k).unwrap_or(0);
            let u = ctx.get_at(self.coordinate_u, i).unwrap_or(0.0);
            let v = ctx.get_at(self.coordinate_v, i).unwrap_or(0.0);
            let m = match surface {
                Some(s) => {
                    let (u, v) = if normalized {
                        (s.dir_u().from_fraction(u), s.dir_v().from_fraction(v))
                    } else {
                        (u, v)
                    };
                    let sp = s.eval(u, v);
                    frame.matrix(sp.position, s.normal(&sp, DVec3::Y), sp.du)
                }
                None => match locate_uv(&index, &mesh, u as f32, v as f32)
                    .map_err(|e| ComputeError::new(format!("uvPin: {e}")))?
                {
                    Some(sp) => frame.matrix(sp.position.as_dvec3(), sp.normal.as_dvec3(), sp.tangent_u.as_dvec3()),
                    None => frame.in_space(DMat4::IDENTITY),
                },
            };
            ctx.set_elem(self.output, k, m);
        }
        Ok(())
    }
}
