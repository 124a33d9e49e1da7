//! Surface attachment nodes: `follicle` (pin a frame to a mesh at a UV) and
//! `closestPointOnMesh` (the closest surface point to a position, with its UV).
//!
//! **follicle** inputs: `inputMesh` (the deformed mesh), `uvMesh` (optional: a mesh with the
//! same triangles and UVs whose shape does not animate, normally the undeformed source of
//! `inputMesh`), `inputWorldMatrix` (the mesh's object-to-world matrix), `parameterU`,
//! `parameterV`. Outputs: `outTranslate`, `outRotate` (degrees, rotate order xyz),
//! `outMatrix`, `outNormal`, `outTangent` (world space), `validUv`, and `uvIndex` (object).
//!
//! Avoiding a UV index rebuild per frame: UVs do not move when a mesh deforms, so the
//! [`UvIndex`] is built in its own compute group from `uvMesh` alone, once per topology/UV
//! change. Every frame the follicle only locates `(u, v)` in that index (O(log n)) and
//! evaluates the triangle's barycentric point on the deformed `inputMesh` (O(1)). With
//! `uvMesh` unset (no triangles) it falls back to a brute-force scan of `inputMesh`
//! (O(triangles) per evaluation, no allocation): fine for small meshes, slow for big ones.
//! [`super::bind::create_closest_follicle`] connects `uvMesh` for you.
//!
//! Frame convention: local X = the surface's `u` tangent (∂P/∂u made orthogonal to the
//! normal), Y = the normal, Z = X × Y; so a follicle on a `polyPlane` (normal +Y, `u` along
//! +X) has zero rotation. In world space the normal goes through the cofactor of
//! `inputWorldMatrix` and the frame is re-orthonormalized, so the output carries no scale.
//! A UV outside every UV triangle (or a mesh without UVs) gives `validUv = false` and the
//! local identity frame (`outMatrix = inputWorldMatrix` without its scale).
//!
//! **On a NURBS surface** (ribbons): connect a `nurbsSurface`'s `local` to `inputSurface`
//! (and its transform's worldMatrix to `inputWorldMatrix`). When `inputSurface` has control
//! points it is used instead of `inputMesh`: `parameterU`/`parameterV` are fractions 0..1 of
//! the surface's domains (Maya's follicles on surfaces use normalized parameters; out of range
//! clamps, or wraps on periodic directions), the frame is X = `∂S/∂u`, Y = the normal
//! `∂S/∂u × ∂S/∂v`, evaluated in `f64`, and `validUv` is true. The surface is validated once
//! per change in its own group (`surfaceCache`).
//!
//! **closestPointOnMesh** inputs: `inMesh`, `inPosition` (world space), `inputMatrix` (the
//! mesh's world matrix). Outputs (Maya's `result` children): `position`, `normal`,
//! `parameterU`, `parameterV`, `closestFaceIndex` (a *triangle* index: meshes here are
//! triangulated), `closestVertexIndex` (the hit triangle's vertex with the largest
//! barycentric weight), and `meshIndex` (object). The [`MeshIndex`] (a BVH) is built in a
//! group that reads only `inMesh`, so moving `inPosition` queries the existing index. A
//! deforming `inMesh` rebuilds it every frame: use it for attach-time queries and static
//! meshes, and follicles for per-frame attachment. An empty mesh gives `position =
//! inPosition`, normal +Y, UV 0 and indices -1; a singular `inputMatrix` is an error.

use std::sync::Arc;

use glam::{DMat3, DMat4, DQuat, DVec3, Mat3A, Vec3};
use sinew_core::{ComputeContext, ComputeError, Input, Mesh, NodeSpec, NodeType, ObjectRef, Output, SpecError, Unit};

use super::closest_point::MeshIndex;
use super::mesh_nodes::cofactor;
use super::surface::{evaluate, point_at_uv, SurfacePoint, UvIndex};
use crate::nurbs::cache::{surface_of, SurfaceIn};
use crate::transform::dag_nodes::rad_to_deg;
use crate::transform::math::{quat_to_euler, RotateOrder};

/// The follicle's precomputed UV lookup (`uvIndex` output).
#[derive(Clone, Debug, Default)]
pub struct FollicleUvCache {
    /// The index over `mesh`'s UV triangles.
    pub index: UvIndex,
    /// The UV source mesh the index was built from (`uvMesh`).
    pub mesh: Arc<Mesh>,
}

/// A world-space frame from a local point, normal and tangent (see the module docs).
/// Returns (rotation columns X, Y, Z; position).
pub fn world_frame(world: &DMat4, position: Vec3, normal: Vec3, tangent: Vec3) -> (DMat3, DVec3) {
    let m3 = DMat3::from_mat4(*world);
    let p = world.transform_point3(position.as_dvec3());
    let cof = cofactor(Mat3A::from(m3.as_mat3())).as_dmat3();
    let y = (cof * normal.as_dvec3()).try_normalize().unwrap_or(DVec3::Y);
    let tw = m3 * tangent.as_dvec3();
    let x = (tw - y * y.dot(tw))
        .try_normalize()
        .unwrap_or_else(|| y.any_orthonormal_vector());
    (DMat3::from_cols(x, y, x.cross(y)), p)
}

/// [`world_frame`] in `f64` throughout (for NURBS surfaces, whose points are `f64`): the
/// normal goes through the cofactor of the matrix's 3x3 part, the tangent through the matrix
/// and is made orthogonal to the normal. Returns (rotation columns X = tangent, Y = normal,
/// Z = X × Y; position).
pub fn world_frame_f64(world: &DMat4, position: DVec3, normal: DVec3, tangent: DVec3) -> (DMat3, DVec3) {
    let m3 = DMat3::from_mat4(*world);
    let p = world.transform_point3(position);
    let cof = DMat3::from_cols(
        m3.y_axis.cross(m3.z_axis),
        m3.z_axis.cross(m3.x_axis),
        m3.x_axis.cross(m3.y_axis),
    );
    let y = (cof * normal).try_normalize().unwrap_or(DVec3::Y);
    let tw = m3 * tangent;
    let x = (tw - y * y.dot(tw))
        .try_normalize()
        .unwrap_or_else(|| y.any_orthonormal_vector());
    (DMat3::from_cols(x, y, x.cross(y)), p)
}

/// Euler angles in degrees (xyz order) of a rotation matrix.
pub fn rotate_degrees(rot: &DMat3) -> DVec3 {
    rad_to_deg(quat_to_euler(DQuat::from_mat3(rot), RotateOrder::Xyz))
}

/// The `follicle` node (see the module docs).
pub struct Follicle {
    spec: NodeSpec,
    input_mesh: Input<Arc<Mesh>>,
    uv_mesh: Input<Arc<Mesh>>,
    world: Input<DMat4>,
    u: Input<f64>,
    v: Input<f64>,
    uv_index: Output<ObjectRef>,
    surface: SurfaceIn,
    out_translate: Output<DVec3>,
    out_rotate: Output<DVec3>,
    out_matrix: Output<DMat4>,
    out_normal: Output<DVec3>,
    out_tangent: Output<DVec3>,
    valid_uv: Output<bool>,
}

impl Follicle {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("follicle");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[
            ("inputMesh", "inm"),
            ("inputWorldMatrix", "iwm"),
            ("inputSurface", "is"),
            ("parameterU", "pu"),
            ("parameterV", "pv"),
            ("outTranslate", "ot"),
            ("outRotate", "or"),
        ]);
        s.doc("pins a frame to inputMesh at (parameterU, parameterV)");
        let input_mesh = s.input("inputMesh", Arc::new(Mesh::default()));
        let uv_mesh = s.input("uvMesh", Arc::new(Mesh::default()));
        let world = s.input("inputWorldMatrix", DMat4::IDENTITY);
        let u = s.input("parameterU", 0.0);
        let v = s.input("parameterV", 0.0);
        let uv_index = s.output("uvIndex", ObjectRef::default());
        let surface = SurfaceIn::declare(
            &mut s,
            "inputSurface",
            "a NURBS surface to stick to instead of inputMesh (used when it has control points)",
        );
        let out_translate = s.output("outTranslate", DVec3::ZERO);
        let out_rotate = s.output("outRotate", DVec3::ZERO);
        let out_matrix = s.output("outMatrix", DMat4::IDENTITY);
        let out_normal = s.output("outNormal", DVec3::Y);
        let out_tangent = s.output("outTangent", DVec3::X);
        let valid_uv = s.output("validUv", false);
        s.unit(out_rotate, Unit::Degrees)
            .attr_doc(input_mesh, "the (deformed) mesh to stick to")
            .attr_doc(
                uv_mesh,
                "undeformed mesh with the same triangles and UVs (indexed once)",
            )
            .attr_doc(world, "object-to-world matrix of the mesh")
            .attr_doc(u, "U coordinate on the mesh's UVs")
            .attr_doc(v, "V coordinate on the mesh's UVs")
            .attr_doc(uv_index, "UV lookup built from uvMesh (FollicleUvCache)")
            .attr_doc(out_translate, "world position on the surface")
            .attr_doc(out_rotate, "world rotation (xyz): X = u tangent, Y = normal")
            .attr_doc(out_matrix, "world frame without scale")
            .attr_doc(out_normal, "world surface normal")
            .attr_doc(out_tangent, "world u tangent")
            .attr_doc(valid_uv, "whether (u, v) lies on the mesh's UVs");
        s.affects(&[uv_mesh.id()], &[uv_index.id()]);
        s.affects(
            &[
                uv_index.id(),
                surface.cache.id(),
                input_mesh.id(),
                world.id(),
                u.id(),
                v.id(),
            ],
            &[
                out_translate.id(),
                out_rotate.id(),
                out_matrix.id(),
                out_normal.id(),
                out_tangent.id(),
                valid_uv.id(),
            ],
        );
        Ok(Follicle {
            spec: s.build()?,
            input_mesh,
            uv_mesh,
            world,
            u,
            v,
            uv_index,
            surface,
            out_translate,
            out_rotate,
            out_matrix,
            out_normal,
            out_tangent,
            valid_uv,
        })
    }

    fn locate(&self, ctx: &ComputeContext<'_>, mesh: &Mesh) -> Result<Option<SurfacePoint>, ComputeError> {
        let (u, v) = (ctx.get(self.u) as f32, ctx.get(self.v) as f32);
        locate_uv(&ctx.get_output(self.uv_index), mesh, u, v).map_err(|e| ComputeError::new(format!("follicle: {e}")))
    }
}

/// The point of `mesh` at UV `(u, v)`: through the [`FollicleUvCache`] in `cache` when it
/// holds a UV mesh (which must have `mesh`'s triangle count), else by scanning `mesh`.
pub fn locate_uv(cache: &ObjectRef, mesh: &Mesh, u: f32, v: f32) -> Result<Option<SurfacePoint>, String> {
    match cache.downcast::<FollicleUvCache>() {
        Some(c) if !c.mesh.triangles.is_empty() => {
            if c.mesh.triangles.len() != mesh.triangles.len() {
                return Err(format!(
                    "the UV mesh has {} triangles but the deformed mesh has {}; connect the undeformed version of the deformed mesh",
                    c.mesh.triangles.len(),
                    mesh.triangles.len()
                ));
            }
            Ok(c.index.locate(&c.mesh, u, v).and_then(|(t, b)| evaluate(mesh, t, b)))
        }
        _ => Ok(point_at_uv(mesh, u, v)),
    }
}

/// The [`FollicleUvCache`] of `mesh` as an object value.
pub fn uv_cache(mesh: Arc<Mesh>) -> ObjectRef {
    let index = UvIndex::build(&mesh);
    ObjectRef::new(FollicleUvCache { index, mesh })
}

impl NodeType for Follicle {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if ctx.wants(self.uv_index) {
            let mesh = ctx.get(self.uv_mesh);
            ctx.set(self.uv_index, uv_cache(mesh));
            return Ok(());
        }
        if self.surface.compute(ctx) {
            return Ok(());
        }
        let world = ctx.get(self.world);
        let surface = self.surface.get(ctx);
        let (rot, p, valid) = if let Some(s) = surface_of(&surface, "follicle.inputSurface")? {
            let (u, v) = (ctx.get(self.u), ctx.get(self.v));
            let sp = s.eval(s.dir_u().from_fraction(u), s.dir_v().from_fraction(v));
            let n = s.normal(&sp, DVec3::Y);
            let (rot, p) = world_frame_f64(&world, sp.position, n, sp.du);
            (rot, p, true)
        } else {
            let mesh = ctx.get(self.input_mesh);
            let hit = self.locate(ctx, &mesh)?;
            let (rot, p) = match hit {
                Some(sp) => world_frame(&world, sp.position, sp.normal, sp.tangent_u),
                None => world_frame(&world, Vec3::ZERO, Vec3::Y, Vec3::X),
            };
            (rot, p, hit.is_some())
        };
        ctx.set(self.out_translate, p);
        ctx.set(self.out_rotate, rotate_degrees(&rot));
        ctx.set(
            self.out_matrix,
            DMat4::from_cols(
                rot.x_axis.extend(0.0),
                rot.y_axis.extend(0.0),
                rot.z_axis.extend(0.0),
                p.extend(1.0),
            ),
        );
        ctx.set(self.out_normal, rot.y_axis);
        ctx.set(self.out_tangent, rot.x_axis);
        ctx.set(self.valid_uv, valid);
        Ok(())
    }
}

/// The `closestPointOnMesh` node (see the module docs).
pub struct ClosestPointOnMesh {
    spec: NodeSpec,
    in_mesh: Input<Arc<Mesh>>,
    in_position: Input<DVec3>,
    input_matrix: Input<DMat4>,
    mesh_index: Output<ObjectRef>,
    position: Output<DVec3>,
    normal: Output<DVec3>,
    parameter_u: Output<f64>,
    parameter_v: Output<f64>,
    face: Output<i64>,
    vertex: Output<i64>,
}

impl ClosestPointOnMesh {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("closestPointOnMesh");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[("inputMatrix", "ix"), ("inMesh", "im"), ("inPosition", "ip")]);
        s.doc("closest point of inMesh to inPosition, with normal, UV and face index");
        let in_mesh = s.input("inMesh", Arc::new(Mesh::default()));
        let in_position = s.input("inPosition", DVec3::ZERO);
        let input_matrix = s.input("inputMatrix", DMat4::IDENTITY);
        let mesh_index = s.output("meshIndex", ObjectRef::default());
        let position = s.output("position", DVec3::ZERO);
        let normal = s.output("normal", DVec3::Y);
        let parameter_u = s.output("parameterU", 0.0);
        let parameter_v = s.output("parameterV", 0.0);
        let face = s.output("closestFaceIndex", -1i64);
        let vertex = s.output("closestVertexIndex", -1i64);
        s.unit(in_position, Unit::Distance)
            .attr_doc(in_mesh, "the mesh (object space)")
            .attr_doc(in_position, "query point in world space")
            .attr_doc(input_matrix, "object-to-world matrix of the mesh")
            .attr_doc(mesh_index, "BVH over inMesh's triangles (MeshIndex)")
            .attr_doc(position, "closest surface point, world space")
            .attr_doc(normal, "interpolated unit normal there, world space")
            .attr_doc(parameter_u, "interpolated U there (0 without UVs)")
            .attr_doc(parameter_v, "interpolated V there (0 without UVs)")
            .attr_doc(face, "index of the closest triangle (-1 for an empty mesh)")
            .attr_doc(
                vertex,
                "closest triangle's vertex with the largest weight (-1 for an empty mesh)",
            );
        s.affects(&[in_mesh.id()], &[mesh_index.id()]);
        s.affects(
            &[mesh_index.id(), in_mesh.id(), in_position.id(), input_matrix.id()],
            &[
                position.id(),
                normal.id(),
                parameter_u.id(),
                parameter_v.id(),
                face.id(),
                vertex.id(),
            ],
        );
        Ok(ClosestPointOnMesh {
            spec: s.build()?,
            in_mesh,
            in_position,
            input_matrix,
            mesh_index,
            position,
            normal,
            parameter_u,
            parameter_v,
            face,
            vertex,
        })
    }
}

impl NodeType for ClosestPointOnMesh {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let mesh = ctx.get(self.in_mesh);
        if ctx.wants(self.mesh_index) {
            ctx.set(self.mesh_index, ObjectRef::new(MeshIndex::build(&mesh)));
            return Ok(());
        }
        let world = ctx.get(self.input_matrix);
        let q = ctx.get(self.in_position);
        let det = world.determinant();
        if det == 0.0 || !det.is_finite() {
            return Err(ComputeError::new(
                "closestPointOnMesh: inputMatrix is singular (zero scale?); give the mesh an invertible world matrix",
            ));
        }
        let local = world.inverse().transform_point3(q).as_vec3();
        let index_ref = ctx.get_output(self.mesh_index);
        let hit = index_ref
            .downcast::<MeshIndex>()
            .and_then(|index| index.closest_point(&mesh, local));
        let Some(hit) = hit else {
            ctx.set(self.position, q);
            ctx.set(self.normal, DVec3::Y);
            ctx.set(self.parameter_u, 0.0);
            ctx.set(self.parameter_v, 0.0);
            ctx.set(self.face, -1);
            ctx.set(self.vertex, -1);
            return Ok(());
        };
        let (rot, p) = world_frame(&world, hit.position, hit.normal, Vec3::X);
        let uv = hit.uv.unwrap_or_default();
        let b = hit.barycentric;
        let corner = if b.x >= b.y && b.x >= b.z {
            0
        } else if b.y >= b.z {
            1
        } else {
            2
        };
        let vertex = mesh
            .triangles
            .get(hit.triangle as usize)
            .map_or(-1, |t| t[corner] as i64);
        ctx.set(self.position, p);
        ctx.set(self.normal, rot.y_axis);
        ctx.set(self.parameter_u, uv.x as f64);
        ctx.set(self.parameter_v, uv.y as f64);
        ctx.set(self.face, hit.triangle as i64);
        ctx.set(self.vertex, vertex);
        Ok(())
    }
}
