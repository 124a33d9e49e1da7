//! Meshes from files: Wavefront OBJ ([`crate::obj`]) and glTF (the first primitive of the
//! first mesh, through [`super::read_gltf`]), and the rig-file hook that resolves
//! `inMesh: File("body.obj")` references ([`MeshFileSource`], [`load_rig`]), along with
//! the value files importers write (`File("x.data/…bin")`, read by the core).
//!
//! Every file is read through [`sinew_core::files`]: regular files only, at most
//! [`sinew_core::files::DATA`] (1 GiB).
//!
//! OBJ: the file's vertex order is kept exactly (vertex `i` is the `i`-th `v` line), every
//! object and group is merged into one mesh, polygons are triangulated as fans; see
//! [`crate::obj`] for normals and UVs. Materials are ignored.

use std::path::Path;
use std::sync::Arc;

use sinew_core::files::{read_text, DATA};
use sinew_core::rig::{normalize, FsSource, LoadLimits, RigSource};
use sinew_core::{AttrType, Diagnostics, LoadedRig, Mesh, Registry, Value};

/// Whether `path` names a mesh file format [`load_mesh`] reads (by extension).
pub fn is_mesh_file(path: &Path) -> bool {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    matches!(ext.as_str(), "obj" | "gltf" | "glb")
}

/// Loads a mesh from an `.obj`, `.gltf` or `.glb` file (chosen by extension, case
/// insensitive). The result is validated ([`Mesh::validate`]).
pub fn load_mesh(path: impl AsRef<Path>) -> Result<Mesh, String> {
    let path = path.as_ref();
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    let mesh = match ext.as_str() {
        "obj" => load_obj(path)?,
        "gltf" | "glb" => load_gltf_mesh(path)?,
        _ => {
            return Err(format!(
                "{}: unknown mesh file type; use .obj, .gltf or .glb",
                path.display()
            ))
        }
    };
    mesh.validate().map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(mesh)
}

/// Reads a Wavefront OBJ file into one triangle mesh in the file's vertex order (see
/// [`crate::obj`]).
pub fn load_obj(path: &Path) -> Result<Mesh, String> {
    let text = read_text(path, DATA).map_err(|e| format!("{}: cannot read OBJ: {e}", path.display()))?;
    crate::obj::parse_obj(&text).map_err(|e| format!("{}:{e}", path.display()))
}

/// Reads the first primitive of the first mesh of a glTF file.
pub fn load_gltf_mesh(path: &Path) -> Result<Mesh, String> {
    let scene = super::read_gltf(path).map_err(|e| format!("{}: {e}", path.display()))?;
    scene
        .meshes
        .into_iter()
        .flat_map(|m| m.primitives)
        .next()
        .map(|p| p.mesh)
        .ok_or_else(|| format!("{}: the glTF file has no mesh primitive", path.display()))
}

/// A [`RigSource`] that reads rig files from disk like [`FsSource`] and resolves
/// `File("...")` references on mesh attributes with [`load_mesh`] (other references, to
/// value files, as [`FsSource`] does).
#[derive(Clone, Copy, Debug, Default)]
pub struct MeshFileSource;

impl RigSource for MeshFileSource {
    fn read(&self, path: &Path) -> std::io::Result<String> {
        FsSource.read(path)
    }

    fn file_names(&self, dir: &Path) -> Vec<String> {
        FsSource.file_names(dir)
    }

    fn load_value(&self, path: &Path, ty: AttrType) -> Result<Value, String> {
        match ty {
            AttrType::Mesh if is_mesh_file(path) => load_mesh(path).map(|m| Value::Mesh(Arc::new(m))),
            _ => FsSource.load_value(path, ty),
        }
    }
}

/// Loads a rig file whose mesh attributes may reference files (`inMesh: File("body.obj")`,
/// relative to the rig file). Same as [`sinew_core::load_rig`] otherwise.
pub fn load_rig(path: &Path, registry: &Arc<Registry>) -> Result<LoadedRig, Diagnostics> {
    load_rig_with_limits(path, registry, LoadLimits::default())
}

/// [`load_rig`] with chosen [`LoadLimits`] (the most nodes the rig may expand to).
pub fn load_rig_with_limits(
    path: &Path,
    registry: &Arc<Registry>,
    limits: LoadLimits,
) -> Result<LoadedRig, Diagnostics> {
    let key = normalize(path);
    match MeshFileSource.read(&key) {
        Ok(text) => sinew_core::rig::load_rig_with_limits(&text, &key, registry, &MeshFileSource, limits),
        // Let the core loader produce its usual "cannot read rig file" diagnostic.
        Err(_) => sinew_core::load_rig(&key, registry),
    }
}

/// The canonical text of a rig file whose mesh attributes may reference files (what
/// `sinew fmt` writes): like [`sinew_core::rig::format_rig_file`], but `File("...")`
/// references load, and are written back as references rather than inline data.
pub fn format_rig_file(path: &Path, registry: &Arc<Registry>) -> Result<String, Diagnostics> {
    let rig = load_rig(path, registry)?;
    Ok(sinew_core::rig::save_rig(&rig.graph, &rig.document))
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};

    use super::*;

    fn dir() -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("sinew-mesh-file-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    const QUAD: &str = "# a unit quad in XY, two triangles after triangulation\n\
        v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
        vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
        f 1/1 2/2 3/3 4/4\n";

    #[test]
    fn obj_quad_is_triangulated_with_uvs_and_normals() {
        let p = dir().join("quad.obj");
        std::fs::write(&p, QUAD).unwrap();
        let m = load_mesh(&p).unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.triangles.len(), 2);
        assert_eq!(m.uvs[2], Vec2::new(1.0, 1.0));
        // No `vn` lines: normals are recomputed; the quad is counter-clockwise seen from +Z.
        assert!(m.normals.iter().all(|n| (*n - Vec3::Z).length() < 1e-6));
    }

    #[test]
    fn bad_files_give_messages() {
        assert!(load_mesh("nowhere/x.obj").unwrap_err().contains("cannot read OBJ"));
        assert!(load_mesh("x.stl").unwrap_err().contains("unknown mesh file type"));
    }

    #[test]
    fn rig_file_references_a_mesh_relative_to_itself() {
        let d = dir().join("rig");
        std::fs::create_dir_all(d.join("geo")).unwrap();
        std::fs::write(d.join("geo/quad.obj"), QUAD).unwrap();
        let rig = "Rig(nodes: { \"body\": mesh(inMesh: File(\"geo/quad.obj\")) })";
        std::fs::write(d.join("r.rig"), rig).unwrap();
        let registry = sinew_nodes::registry().unwrap();
        let mut loaded = load_rig(&d.join("r.rig"), &registry).unwrap();
        let Value::Mesh(m) = loaded.graph.get_path("body.outMesh").unwrap() else {
            panic!("not a mesh")
        };
        assert_eq!(m.triangles.len(), 2);
        // The core loader alone refuses, naming the facade.
        let err = sinew_core::load_rig(&d.join("r.rig"), &registry)
            .unwrap_err()
            .to_string();
        assert!(err.contains("sinew facade"), "{err}");
    }

    /// `sinew fmt` keeps `File(..)` references (relative to the rig file) instead of
    /// inlining the mesh, and inlines the data once the value no longer matches the file.
    #[test]
    fn formatting_keeps_file_references() {
        let d = dir().join("fmt");
        std::fs::create_dir_all(d.join("geo")).unwrap();
        std::fs::create_dir_all(d.join("rigs")).unwrap();
        std::fs::write(d.join("geo/quad.obj"), QUAD).unwrap();
        let rig = "Rig(nodes: { \"body\": mesh(inMesh: File(\"../geo/quad.obj\")) })";
        std::fs::write(d.join("rigs/r.rig"), rig).unwrap();
        let registry = sinew_nodes::registry().unwrap();
        let text = format_rig_file(&d.join("rigs/r.rig"), &registry).unwrap();
        assert!(text.contains("inMesh: File(\"../geo/quad.obj\")"), "{text}");
        assert!(!text.contains("positions"), "no inline mesh data: {text}");
        // Formatting is idempotent.
        std::fs::write(d.join("rigs/r.rig"), &text).unwrap();
        assert_eq!(format_rig_file(&d.join("rigs/r.rig"), &registry).unwrap(), text);
        // A changed value is written inline.
        let mut loaded = load_rig(&d.join("rigs/r.rig"), &registry).unwrap();
        let quad = load_mesh(d.join("geo/quad.obj")).unwrap();
        let mut moved = quad.clone();
        moved.positions[0].x += 1.0;
        loaded
            .graph
            .set_path("body.inMesh", Value::Mesh(Arc::new(moved)))
            .unwrap();
        let saved = sinew_core::rig::save_rig(&loaded.graph, &loaded.document);
        assert!(!saved.contains("File("), "{saved}");
    }
}
