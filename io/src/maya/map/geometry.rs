//! Meshes and their deformer chains.
//!
//! Each visible Maya mesh becomes a sinew `mesh` node. A mesh with its own data (`.vt`,
//! `.fc`, `.pt`) holds it (in the data sidecar). A mesh fed by Maya's deformer plumbing —
//! `*ShapeOrig → groupParts → tweak → groupParts → blendShape → ... → skinCluster → shape`
//! — becomes the same chain in sinew, collapsed: the intermediate `*Orig` mesh (or the
//! creation node) holds the geometry with its tweaks folded in, then one sinew node per
//! deformer in Maya's order, then the shape. `groupParts`, `groupId`, the deformer sets
//! and the `tweak` node are folded (see [`super::deform`]).
//!
//! A deformed mesh's sinew node takes the transform's `worldMatrix` unless the chain ends
//! in a skinCluster, whose output is already in world space (see [`super::skin`]).

use std::sync::Arc;

use sinew_core::{AttrSpec, Value};

use super::deform::{walk_chain, Base, Chain};
use super::meshdata::{add_offsets, faces_from_edges, orient_to_axis, poly_cube, poly_plane, PolyMesh};
use super::plugs::long_segs;
use super::{blend, skin, Importer, Status};
use crate::maya::plug::Index;
use crate::maya::scene::SetAttr;
use crate::maya::MayaError;

/// The custom attribute on a mesh split along UV seams holding each vertex's Maya index.
pub const MAYA_VERTEX: &str = "mayaVertex";

/// Maps every visible mesh with its chain (intermediate meshes come along as chain bases).
pub fn map_geometry(imp: &mut Importer) -> Result<(), MayaError> {
    for i in 0..imp.scene.nodes.len() {
        if imp.node(i).ty != "mesh" || imp.handled(i) || imp.number(i, "intermediateObject") == Some(1.0) {
            continue;
        }
        map_shape(imp, i)?;
    }
    for i in 0..imp.scene.nodes.len() {
        if imp.node(i).ty == "mesh" && !imp.handled(i) {
            imp.set_status(i, Status::Folded);
        }
    }
    Ok(())
}

/// Deformers that smooth over the mesh's edges: on a mesh split along UV seams they see
/// the seam as an open border.
const TOPOLOGICAL: [&str; 4] = ["deltaMush", "tension", "wrap", "proximityWrap"];

/// Maps one visible mesh and its chain.
fn map_shape(imp: &mut Importer, shape: usize) -> Result<(), MayaError> {
    let chain = walk_chain(imp, shape);
    let owner = imp.parent(shape).and_then(|p| imp.sinew(p)).map(str::to_string);
    let at = imp.node(shape).at;
    // Without deformers the shape holds its geometry itself (following a creation node or
    // another mesh into its `inMesh`); with deformers the chain's base holds it.
    let base_node = match &chain.base {
        Base::Unsupported(m, why) => {
            let msg = format!(
                "{}: its geometry comes from {} ({why}); the mesh is not imported",
                imp.node(shape).name,
                imp.node(*m).name
            );
            imp.warn(at, msg);
            imp.set_status(shape, Status::Skipped(why.clone()));
            return Ok(());
        }
        _ if chain.deformers.is_empty() => None,
        Base::Own => None,
        Base::Mesh(m) | Base::Creator(m) => Some(*m),
    };
    let data_maya = base_node.unwrap_or(shape);
    let Some(mut poly) = static_geometry(imp, data_maya)? else {
        let msg = format!(
            "{} has no geometry in the file; it is not imported",
            imp.node(shape).name
        );
        imp.warn(at, msg);
        imp.set_status(shape, Status::Skipped("no geometry".into()));
        return Ok(());
    };
    super::deform::fold_tweaks(imp, &chain, &mut poly);
    let units = imp.units.clone();
    let converted = poly
        .to_mesh(|p| {
            glam::DVec3::new(
                units.internal_length(p.x),
                units.internal_length(p.y),
                units.internal_length(p.z),
            )
        })
        .map_err(|e| {
            imp.error(
                at,
                format!("{}: {e}", imp.node(shape).name),
                "the mesh data in the file is inconsistent",
            )
        })?;
    let (mesh, map) = (converted.mesh, converted.map);
    if poly.holes > 0 {
        let msg = format!(
            "{}: {} faces have holes; the holes are filled",
            imp.node(shape).name,
            poly.holes
        );
        imp.warn(at, msg);
    }
    if converted.corners_without_uv > 0 {
        let msg = format!(
            "{}: {} face corners have no UV in the first UV set; their vertices take the UV of another face, or (0, 0)",
            imp.node(shape).name,
            converted.corners_without_uv
        );
        imp.warn(at, msg);
    }
    if !map.copies.is_empty() {
        for &d in &chain.deformers {
            if TOPOLOGICAL.contains(&imp.node(d).ty.as_str()) {
                let msg = format!(
                    "{}: {} is split along its UV seams ({} vertices added), so {} ({}) smooths across a seam as across an open border",
                    imp.node(shape).name,
                    imp.node(data_maya).name,
                    map.copies.len(),
                    imp.node(d).name,
                    imp.node(d).ty
                );
                imp.warn(imp.node(d).at, msg);
            }
        }
    }
    // Maya's points in sinew units (what blendShape targets are measured against).
    let base_points: Vec<glam::Vec3> = mesh.positions[..map.maya].to_vec();
    // The data node.
    let raw = imp.names.sinew_name(imp.scene, data_maya);
    let data_name = imp.unique(&raw);
    let data_index = imp.add(&data_name, "mesh", None, true);
    imp.acc.set(&data_name, "inMesh", Value::Mesh(Arc::new(mesh)));
    if !map.copies.is_empty() {
        let spec = AttrSpec::custom(MAYA_VERTEX, Value::FloatArray(Arc::new(Vec::new()))).with_doc(
            "Maya's vertex index of each vertex, as a float array (the mesh is split along its UV seams; vertices past Maya's count copy the one named here)",
        );
        imp.rig.add_custom(data_index, spec);
        imp.acc
            .set(&data_name, MAYA_VERTEX, Value::FloatArray(Arc::new(map.maya_index())));
    }
    if let Some(o) = imp.parent(data_maya).and_then(|p| imp.sinew(p)).map(str::to_string) {
        if data_maya == shape || chain.deformers.is_empty() {
            imp.connect(format!("{o}.worldMatrix"), format!("{data_name}.worldMatrix"), at);
        }
    }
    imp.set_status(data_maya, Status::Mapped(data_name.clone()));
    if data_maya == shape {
        fold_chain(imp, &chain);
        return Ok(());
    }
    let base_plug = format!("{data_name}.outMesh");
    let mut geom = base_plug.clone();
    let mut skinned = false;
    for &d in &chain.deformers {
        let ty = imp.node(d).ty.clone();
        geom = match ty.as_str() {
            "tweak" => geom,
            "blendShape" => blend::map_blend_shape(imp, d, &geom, &base_points, &map)?,
            "skinCluster" => {
                skinned = true;
                skin::map_skin_cluster(imp, d, &geom, &map)?
            }
            _ if super::deformer::supported(imp, &ty) => {
                let place = super::deformer::Place {
                    geom: &geom,
                    base: &base_plug,
                    world: if skinned { None } else { owner.as_deref() },
                    chain: &chain,
                    map: &map,
                };
                super::deformer::map_deformer(imp, d, &place)?
            }
            _ => {
                let msg = format!(
                    "deformer {} ({ty}) is not supported by sinew: {} is imported without its effect (the shape shows its input instead)",
                    imp.node(d).name,
                    imp.node(shape).name
                );
                imp.warn(imp.node(d).at, msg);
                let name = imp.node(d).name.clone();
                imp.report.skip(
                    &ty,
                    &name,
                    "deformer sinew does not have: the mesh is imported without it",
                    true,
                );
                imp.set_status(d, Status::Skipped("unsupported deformer".into()));
                geom
            }
        };
        if matches!(ty.as_str(), "skinCluster" | "blendShape") && super::deform::membership(imp, &chain, d).is_some() {
            let msg = format!(
                "{}: the {ty} acts on part of {} in Maya; sinew's acts on every vertex",
                imp.node(d).name,
                imp.node(shape).name
            );
            imp.warn(imp.node(d).at, msg);
        }
    }
    let raw = imp.names.sinew_name(imp.scene, shape);
    let name = imp.unique(&raw);
    imp.add(&name, "mesh", None, false);
    imp.connect(geom, format!("{name}.inMesh"), at);
    if !skinned {
        if let Some(o) = &owner {
            imp.connect(format!("{o}.worldMatrix"), format!("{name}.worldMatrix"), at);
        }
    }
    imp.set_status(shape, Status::Mapped(name));
    fold_chain(imp, &chain);
    Ok(())
}

/// Marks the chain's plumbing as folded and its connections as consumed.
fn fold_chain(imp: &mut Importer, chain: &Chain) {
    for &n in &chain.folded {
        if !imp.handled(n) {
            imp.set_status(n, Status::Folded);
        }
    }
    for &c in &chain.conns {
        imp.consume(c);
    }
}

/// The data of a mesh without deformers: its own `.vt/.ed/.fc`, or the creation node
/// feeding it, plus its `.pt` tweaks; `None` when there is none.
pub fn static_geometry(imp: &mut Importer, m: usize) -> Result<Option<PolyMesh>, MayaError> {
    static_geometry_depth(imp, m, 0)
}

fn static_geometry_depth(imp: &mut Importer, m: usize, depth: usize) -> Result<Option<PolyMesh>, MayaError> {
    let node = imp.node(m);
    if depth > 32 {
        return Ok(None);
    }
    let mut poly = if node.ty != "mesh" {
        creator_geometry(imp, m)?
    } else if let Some((c, src, _)) = imp.input_conn(m, "inMesh") {
        let p = if imp.node(src).ty == "mesh" {
            static_geometry_depth(imp, src, depth + 1)?
        } else {
            creator_geometry(imp, src)?
        };
        let Some(p) = p else { return Ok(None) };
        imp.consume(c);
        Some(p)
    } else {
        own_geometry(imp, m)?
    };
    if let (Some(p), "mesh") = (&mut poly, node.ty.as_str()) {
        let tweaks = indexed_vec3(imp, m, "pnts")?;
        add_offsets(&mut p.points, &tweaks);
    }
    Ok(poly)
}

/// Geometry of a poly creation node (`polyCube`, `polyPlane`); `None` (with a warning)
/// for other kinds.
fn creator_geometry(imp: &mut Importer, n: usize) -> Result<Option<PolyMesh>, MayaError> {
    let num = |imp: &Importer, a: &str, d: f64| imp.number(n, a).unwrap_or(d);
    let len = |imp: &Importer, a: &str| imp.units.cm_per_unit * num(imp, a, 1.0);
    let axis = |imp: &Importer| -> glam::DVec3 {
        imp.set_attr(n, "axis")
            .and_then(|a| imp.values(a).exactly(3).ok())
            .map_or(glam::DVec3::Y, |v| glam::DVec3::new(v[0], v[1], v[2]))
    };
    let mut poly = match imp.node(n).ty.as_str() {
        "polyCube" => {
            let subdiv = ["subdivisionsWidth", "subdivisionsHeight", "subdivisionsDepth"]
                .iter()
                .any(|a| num(imp, a, 1.0) != 1.0);
            if subdiv {
                let msg = format!(
                    "{}: polyCube with more than one subdivision per side is not generated; the mesh is not imported",
                    imp.node(n).name
                );
                imp.warn(imp.node(n).at, msg);
                return Ok(None);
            }
            poly_cube(len(imp, "width"), len(imp, "height"), len(imp, "depth"))
        }
        "polyPlane" => {
            let sw = num(imp, "subdivisionsWidth", 10.0).clamp(1.0, 10_000.0) as u32;
            let sh = num(imp, "subdivisionsHeight", 10.0).clamp(1.0, 10_000.0) as u32;
            poly_plane(len(imp, "width"), len(imp, "height"), sw, sh)
        }
        other => {
            let msg = format!(
                "{}: geometry from a {other} node is not generated (sinew reads polyCube, polyPlane and stored meshes)",
                imp.node(n).name
            );
            imp.warn(imp.node(n).at, msg);
            return Ok(None);
        }
    };
    orient_to_axis(&mut poly, axis(imp));
    if !imp.handled(n) {
        imp.set_status(n, Status::Folded);
    }
    Ok(Some(poly))
}

/// Indexed vec3 values of a multi attribute (`.pt[0:6]`, `.vt[k]`), by element.
fn indexed_vec3(imp: &Importer, m: usize, attr: &str) -> Result<Vec<(u32, glam::DVec3)>, MayaError> {
    let mut out = Vec::new();
    for a in attrs_of(imp, m, attr) {
        let Some(idx) = a.segs.first().and_then(|s| s.index) else {
            continue;
        };
        let Some((x, y)) = idx.bounds() else {
            continue;
        };
        let n = (y - x + 1) as usize;
        let v = imp.values(a).elements(n, 3).map_err(|e| {
            imp.error(
                e.offset,
                format!("{}.{attr}: {}", imp.node(m).name, e.message),
                "each element needs 3 numbers",
            )
        })?;
        for (k, c) in v.chunks(3).enumerate() {
            out.push((x + k as u32, glam::DVec3::new(c[0], c[1], c[2])));
        }
    }
    Ok(out)
}

/// The `setAttr`s of node `m` on attribute `attr` (long name, any index).
fn attrs_of<'a>(imp: &Importer<'a>, m: usize, attr: &str) -> Vec<&'a SetAttr> {
    imp.node(m)
        .attrs
        .iter()
        .filter(|a| {
            let segs = long_segs(imp, m, &a.segs[..1]);
            segs[0].name == attr && !a.values.is_empty()
        })
        .collect()
}

/// A mesh's own data: points `.vt`, edges `.ed`, faces `.fc`, UVs `.uvst[0].uvsp`.
fn own_geometry(imp: &Importer, m: usize) -> Result<Option<PolyMesh>, MayaError> {
    let name = &imp.node(m).name;
    let verts = indexed_vec3(imp, m, "vrts")?;
    if verts.is_empty() {
        return Ok(None);
    }
    let n = verts.iter().map(|(k, _)| *k as usize + 1).max().unwrap_or(0);
    let mut points = vec![glam::DVec3::ZERO; n];
    for (k, p) in verts {
        points[k as usize] = p;
    }
    let mut edges = Vec::new();
    for (k, e) in indexed_vec3(imp, m, "edge")? {
        let k = k as usize;
        if edges.len() <= k {
            edges.resize(k + 1, (0, 0));
        }
        edges[k] = (e.x as u32, e.y as u32);
    }
    let mut face_edges = Vec::new();
    let mut face_uvs = Vec::new();
    let mut holes = 0;
    for a in attrs_of(imp, m, "face") {
        let faces = imp.values(a).poly_faces().map_err(|e| {
            imp.error(
                e.offset,
                format!("{name}.fc: {}", e.message),
                "the polyFaces value is malformed",
            )
        })?;
        for f in faces {
            holes += usize::from(!f.holes.is_empty());
            face_uvs.push(
                f.uvs
                    .iter()
                    .find(|(set, _)| *set == 0)
                    .map(|(_, u)| u.iter().map(|&x| x.max(0) as u32).collect())
                    .unwrap_or_default(),
            );
            face_edges.push(f.edges);
        }
    }
    let faces = faces_from_edges(&edges, &face_edges).map_err(|e| {
        imp.error(
            imp.node(m).at,
            format!("{name}: {e}"),
            "the mesh data in the file is inconsistent",
        )
    })?;
    let mut uv_points = Vec::new();
    for a in imp.node(m).attrs.iter() {
        let segs = long_segs(imp, m, &a.segs);
        let is_uv = segs.len() == 2
            && segs[0].name == "uvSet"
            && matches!(segs[0].index, Some(Index::One(0)))
            && segs[1].name == "uvSetPoints";
        let Some(idx) = segs
            .get(1)
            .and_then(|s| s.index)
            .filter(|_| is_uv && !a.values.is_empty())
        else {
            continue;
        };
        let Some((x, y)) = idx.bounds() else {
            continue;
        };
        let v = imp.values(a).elements((y - x + 1) as usize, 2).map_err(|e| {
            imp.error(
                e.offset,
                format!("{name}.uvsp: {}", e.message),
                "each UV needs 2 numbers",
            )
        })?;
        for (k, c) in v.chunks(2).enumerate() {
            let at = (x as usize) + k;
            if uv_points.len() <= at {
                uv_points.resize(at + 1, glam::Vec2::ZERO);
            }
            uv_points[at] = glam::Vec2::new(c[0] as f32, c[1] as f32);
        }
    }
    Ok(Some(PolyMesh {
        points,
        faces,
        uv_points,
        face_uvs,
        holes,
    }))
}
