//! Mesh source nodes: the procedural primitives `polyCube`, `polySphere`, `polyCylinder`,
//! `polyPlane`, `polyCapsule` (Maya's names and attributes where Maya has them) and the
//! `mesh` shape node through which geometry set by the API, a rig file or a loader flows in.
//!
//! Primitive conventions are those of [`super::primitives`]: centred at the origin, axis of
//! revolution `+Y`, counter-clockwise triangles seen from outside, non-overlapping UVs in
//! `[0, 1]²`. Sizes are distances in scene units; a zero, negative or non-finite size is a
//! `ComputeError` naming the attribute. Subdivision counts below the primitive's minimum are
//! raised to it (as Maya does) and counts above [`MAX_SUBDIVISIONS`] are lowered to it, so a
//! typo cannot allocate gigabytes.
//!
//! A primitive's `output` depends only on its size and subdivision inputs, so it is built
//! once and shared (`Arc`) by everything downstream; nothing is rebuilt per frame.

use std::sync::Arc;

use glam::{DMat4, Mat3A, Vec3, Vec3A};
use sinew_core::{
    ComputeContext, ComputeError, Input, Mesh, NodeSpec, NodeType, Output, Registry, SpecBuilder, SpecError, Unit,
};

use super::primitives::{self, PrimitiveError};

/// Largest subdivision count a primitive accepts; larger values are lowered to it.
pub const MAX_SUBDIVISIONS: i64 = 1000;

fn count(x: i64) -> u32 {
    x.clamp(0, MAX_SUBDIVISIONS) as u32
}

fn prim_err(node: &str, e: PrimitiveError) -> ComputeError {
    ComputeError::new(format!("{node}: {e}"))
}

fn distance(s: &mut SpecBuilder, name: &str, default: f64, doc: &str) -> Input<f64> {
    let h = s.input(name, default);
    s.unit(h, Unit::Distance).attr_doc(h, doc);
    h
}

fn int(s: &mut SpecBuilder, name: &str, default: i64, doc: &str) -> Input<i64> {
    let h = s.input(name, default);
    s.attr_doc(h, doc);
    h
}

/// Which primitive a [`PolyPrimitive`] builds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Cube,
    Sphere,
    Cylinder,
    Plane,
    Capsule,
}

/// A procedural primitive node (`polyCube`, `polySphere`, `polyCylinder`, `polyPlane`,
/// `polyCapsule`): size and subdivision inputs → `output` (mesh).
///
/// Attributes (Maya defaults):
/// - `polyCube`: `width`, `height`, `depth` (1). Maya's subdivision attributes are not
///   supported: the box has one quad (two triangles) per face.
/// - `polySphere`: `radius` (1), `subdivisionsAxis` (20, ≥ 3), `subdivisionsHeight` (20, ≥ 2).
/// - `polyCylinder`: `radius` (1), `height` (2), `subdivisionsAxis` (20, ≥ 3),
///   `subdivisionsHeight` (1, ≥ 1); always capped (flat fan caps).
/// - `polyPlane`: `width` (along X), `height` (along Z, as Maya's polyPlane), (1 each),
///   `subdivisionsWidth`, `subdivisionsHeight` (10, ≥ 1). Faces `+Y`.
/// - `polyCapsule` (modelled on polyCylinder's names): `radius` (1), `height` (4, total,
///   tips included, ≥ 2·radius), `subdivisionsAxis` (20), `subdivisionsHeight` (4, bands of
///   the straight part), `subdivisionsCaps` (6, bands per hemisphere).
pub struct PolyPrimitive {
    spec: NodeSpec,
    kind: Kind,
    a: Input<f64>,
    b: Option<Input<f64>>,
    c: Option<Input<f64>>,
    n1: Option<Input<i64>>,
    n2: Option<Input<i64>>,
    n3: Option<Input<i64>>,
    output: Output<Arc<Mesh>>,
}

impl PolyPrimitive {
    fn new(kind: Kind) -> Result<Self, SpecError> {
        let name = match kind {
            Kind::Cube => "polyCube",
            Kind::Sphere => "polySphere",
            Kind::Cylinder => "polyCylinder",
            Kind::Plane => "polyPlane",
            Kind::Capsule => "polyCapsule",
        };
        let mut s = NodeSpec::builder(name);
        let (mut b, mut c, mut n1, mut n2, mut n3) = (None, None, None, None, None);
        let a;
        match kind {
            Kind::Cube => {
                s.doc("a box of width × height × depth centred at the origin, one quad per face");
                a = distance(&mut s, "width", 1.0, "size along X");
                b = Some(distance(&mut s, "height", 1.0, "size along Y"));
                c = Some(distance(&mut s, "depth", 1.0, "size along Z"));
            }
            Kind::Sphere => {
                s.doc("a UV sphere centred at the origin, poles on ±Y");
                a = distance(&mut s, "radius", 1.0, "sphere radius");
                n1 = Some(int(&mut s, "subdivisionsAxis", 20, "segments around Y (at least 3)"));
                n2 = Some(int(
                    &mut s,
                    "subdivisionsHeight",
                    20,
                    "bands from pole to pole (at least 2)",
                ));
            }
            Kind::Cylinder => {
                s.doc("a capped cylinder along Y centred at the origin");
                a = distance(&mut s, "radius", 1.0, "cylinder radius");
                b = Some(distance(&mut s, "height", 2.0, "length along Y"));
                n1 = Some(int(&mut s, "subdivisionsAxis", 20, "segments around Y (at least 3)"));
                n2 = Some(int(&mut s, "subdivisionsHeight", 1, "bands along Y (at least 1)"));
            }
            Kind::Plane => {
                s.doc("a flat grid in the XZ plane facing +Y");
                a = distance(&mut s, "width", 1.0, "size along X");
                b = Some(distance(
                    &mut s,
                    "height",
                    1.0,
                    "size along Z (Maya's polyPlane height)",
                ));
                n1 = Some(int(&mut s, "subdivisionsWidth", 10, "cells along X (at least 1)"));
                n2 = Some(int(&mut s, "subdivisionsHeight", 10, "cells along Z (at least 1)"));
            }
            Kind::Capsule => {
                s.doc("a capsule along Y: a cylinder closed by two hemispheres");
                a = distance(&mut s, "radius", 1.0, "radius of the cylinder and the hemispheres");
                b = Some(distance(
                    &mut s,
                    "height",
                    4.0,
                    "total height, tips included (at least 2 · radius)",
                ));
                n1 = Some(int(&mut s, "subdivisionsAxis", 20, "segments around Y (at least 3)"));
                n2 = Some(int(
                    &mut s,
                    "subdivisionsHeight",
                    4,
                    "bands of the straight part (at least 1)",
                ));
                n3 = Some(int(&mut s, "subdivisionsCaps", 6, "bands per hemisphere (at least 1)"));
            }
        }
        let output = s.output("output", Arc::new(Mesh::default()));
        s.attr_doc(output, "the generated mesh");
        Ok(PolyPrimitive {
            spec: s.build()?,
            kind,
            a,
            b,
            c,
            n1,
            n2,
            n3,
            output,
        })
    }

    fn build(&self, ctx: &ComputeContext<'_>) -> Result<Mesh, PrimitiveError> {
        let f = |h: Option<Input<f64>>| h.map_or(1.0, |h| ctx.get(h) as f32);
        let n = |h: Option<Input<i64>>| h.map_or(1, |h| count(ctx.get(h)));
        let a = ctx.get(self.a) as f32;
        match self.kind {
            Kind::Cube => primitives::cuboid(Vec3::new(a, f(self.b), f(self.c))),
            Kind::Sphere => primitives::uv_sphere(a, n(self.n2), n(self.n1)),
            Kind::Cylinder => primitives::cylinder(a, f(self.b), n(self.n2), n(self.n1), true),
            Kind::Plane => primitives::plane(a, f(self.b), n(self.n1), n(self.n2)),
            Kind::Capsule => primitives::capsule(a, f(self.b), n(self.n2), n(self.n1), n(self.n3)),
        }
    }
}

impl NodeType for PolyPrimitive {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn authoring_fields(&self) -> &[sinew_core::AuthoringField] {
        &crate::authoring::chain::FIELDS
    }

    fn expand(&self, cx: &mut sinew_core::ExpandContext<'_>) {
        crate::authoring::chain::expand(cx)
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let mesh = self.build(ctx).map_err(|e| prim_err(&self.spec.name, e))?;
        ctx.set(self.output, Arc::new(mesh));
        Ok(())
    }
}

/// The cofactor of a 3×3 (`det(A)·A⁻ᵀ`), which maps normals the way the skinning kernels
/// do: `(A e₁) × (A e₂) = cof(A) (e₁ × e₂)`; defined for singular matrices.
pub fn cofactor(a: Mat3A) -> Mat3A {
    Mat3A::from_cols(
        a.y_axis.cross(a.z_axis),
        a.z_axis.cross(a.x_axis),
        a.x_axis.cross(a.y_axis),
    )
}

/// Writes `src` transformed by `m` into `dst`, reusing `dst`'s buffers (no allocation once
/// they are large enough). Normals go through the cofactor and are renormalized; a normal
/// that maps to zero length keeps its input direction. Triangles and UVs are copied only
/// when they differ from what `dst` already holds.
pub fn transform_mesh_into(src: &Mesh, m: &DMat4, dst: &mut Mesh) {
    let m = m.as_mat4();
    let cof = cofactor(Mat3A::from_mat4(m));
    dst.positions.clear();
    dst.positions
        .extend(src.positions.iter().map(|&p| m.transform_point3(p)));
    dst.normals.clear();
    dst.normals.extend(
        src.normals
            .iter()
            .map(|&n| Vec3::from((cof * Vec3A::from(n)).try_normalize().unwrap_or(Vec3A::from(n)))),
    );
    copy_topology(src, dst);
}

/// Makes `dst`'s triangles and UVs equal to `src`'s, copying only when they differ.
///
/// The comparison is bitwise, one `memcmp` per buffer (it runs every frame on an unchanged
/// topology: for 40,000 triangles it costs a few microseconds).
pub fn copy_topology(src: &Mesh, dst: &mut Mesh) {
    fn bytes<T: bytemuck::Pod>(v: &[T]) -> &[u8] {
        bytemuck::cast_slice(v)
    }
    if bytes(&dst.triangles) != bytes(&src.triangles) {
        dst.triangles.clone_from(&src.triangles);
    }
    if bytes(&dst.uvs) != bytes(&src.uvs) {
        dst.uvs.clone_from(&src.uvs);
    }
}

/// `mesh`: the shape node holding geometry. `inMesh` (set by the API, a rig file's
/// `File("body.obj")` reference, or connected from a deformer) → `outMesh` (the same shared
/// data, no copy) and `worldMesh` (`inMesh` transformed by the `worldMatrix` input: positions
/// by the matrix, normals by its cofactor, renormalized).
///
/// `worldMatrix` is an *input* here (connect the parent transform's `worldMatrix`); with it
/// unconnected (identity) `worldMesh` equals `inMesh`. An invalid `inMesh` (indices out of
/// range, mismatched normals/UVs, non-finite positions) is a `ComputeError` from
/// [`Mesh::validate`].
///
/// An `inMesh` with triangles but no normals (an inline mesh written without `normals`, an
/// OBJ without `vn`) gets smooth normals, angle and area weighted as Maya's default vertex
/// normal method ([`Mesh::recompute_normals`]), so `outMesh`, `worldMesh`, the deformers
/// downstream and `sinew bake` carry shading normals instead of leaving every viewer to
/// shade the mesh faceted. They are computed when `inMesh` changes, not per frame.
///
/// In rig files a shape (this node or a poly primitive) takes the authoring field
/// `deformers: ["bs", "skin", ..]`: the deformer chain its mesh goes through, in order
/// (see [`crate::authoring::chain`]).
pub struct MeshNode {
    spec: NodeSpec,
    in_mesh: Input<Arc<Mesh>>,
    world_matrix: Input<DMat4>,
    out_mesh: Output<Arc<Mesh>>,
    world_mesh: Output<Arc<Mesh>>,
}

impl MeshNode {
    fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("mesh");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[
            ("inMesh", "i"),
            ("worldMatrix", "wm"),
            ("outMesh", "o"),
            ("worldMesh", "w"),
        ]);
        s.doc("a mesh shape: inMesh → outMesh (shared) and worldMesh (transformed by worldMatrix)");
        let in_mesh = s.input("inMesh", Arc::new(Mesh::default()));
        let world_matrix = s.input("worldMatrix", DMat4::IDENTITY);
        let out_mesh = s.output("outMesh", Arc::new(Mesh::default()));
        let world_mesh = s.output("worldMesh", Arc::new(Mesh::default()));
        s.attr_doc(in_mesh, "the geometry (object space)")
            .attr_doc(
                world_matrix,
                "object-to-world matrix, e.g. the parent transform's worldMatrix",
            )
            .attr_doc(
                out_mesh,
                "inMesh, validated and shared (smooth normals added when it has none)",
            )
            .attr_doc(world_mesh, "inMesh in world space");
        s.affects(&[in_mesh.id()], &[out_mesh.id()]);
        s.affects(&[in_mesh.id(), world_matrix.id()], &[world_mesh.id()]);
        Ok(MeshNode {
            spec: s.build()?,
            in_mesh,
            world_matrix,
            out_mesh,
            world_mesh,
        })
    }
}

impl NodeType for MeshNode {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn authoring_fields(&self) -> &[sinew_core::AuthoringField] {
        &crate::authoring::chain::FIELDS
    }

    fn expand(&self, cx: &mut sinew_core::ExpandContext<'_>) {
        crate::authoring::chain::expand(cx)
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let mut mesh = ctx.get(self.in_mesh);
        mesh.validate()
            .map_err(|e| ComputeError::new(format!("mesh.inMesh: {e}")))?;
        let needs_normals = |m: &Mesh| m.normals.is_empty() && !m.triangles.is_empty();
        if ctx.wants(self.out_mesh) {
            if needs_normals(&mesh) {
                Arc::make_mut(&mut mesh).recompute_normals();
            }
            ctx.set(self.out_mesh, mesh);
        } else if ctx.wants(self.world_mesh) {
            let m = ctx.get(self.world_matrix);
            if m == DMat4::IDENTITY && !needs_normals(&mesh) {
                ctx.set(self.world_mesh, mesh);
            } else if let Some(dst) = ctx.data_mut(self.world_mesh) {
                transform_mesh_into(&mesh, &m, dst);
                if needs_normals(dst) {
                    // Normals of the world-space surface (under a non-uniform scale these
                    // are the true normals; transforming object-space ones agrees up to
                    // rounding).
                    dst.recompute_normals();
                }
            }
        }
        Ok(())
    }
}

/// Registers the primitives and `mesh`.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    for k in [Kind::Cube, Kind::Sphere, Kind::Cylinder, Kind::Plane, Kind::Capsule] {
        registry.register(PolyPrimitive::new(k)?)?;
    }
    registry.register(MeshNode::new()?)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    #[test]
    fn copy_topology_copies_exactly_when_the_bits_differ() {
        let src = Mesh {
            triangles: vec![[0, 1, 2], [2, 1, 3]],
            uvs: vec![Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE],
            ..Default::default()
        };
        let mut dst = Mesh::default();
        copy_topology(&src, &mut dst);
        assert_eq!((&dst.triangles, &dst.uvs), (&src.triangles, &src.uvs));
        // Unchanged: the buffers are kept (no reallocation).
        let (t, u) = (dst.triangles.as_ptr(), dst.uvs.as_ptr());
        copy_topology(&src, &mut dst);
        assert_eq!((dst.triangles.as_ptr(), dst.uvs.as_ptr()), (t, u));
        // A different index, a -0.0 where src has 0.0 (equal as floats, not as bits), a
        // different length: each is copied over.
        dst.triangles[1][2] = 7;
        dst.uvs[0].x = -0.0;
        copy_topology(&src, &mut dst);
        assert_eq!(dst.triangles, src.triangles);
        assert_eq!(dst.uvs[0].x.to_bits(), 0.0f32.to_bits());
        dst.uvs.pop();
        dst.triangles.push([0, 0, 0]);
        copy_topology(&src, &mut dst);
        assert_eq!((&dst.triangles, &dst.uvs), (&src.triangles, &src.uvs));
    }
}
