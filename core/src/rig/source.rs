//! Where rig files come from: the [`RigSource`] trait, the file system ([`FsSource`]),
//! memory ([`MemSource`], for tests and fuzzing), and lexical path normalization.

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};

use crate::value::{AttrType, Value};

/// Where rig and component files come from (the file system, or memory for
/// tests and fuzzing).
pub trait RigSource {
    /// The text of the file at `path`.
    fn read(&self, path: &Path) -> std::io::Result<String>;

    /// The names of the files in the directory `dir`, for "did you mean" hints when a
    /// file is missing (none by default).
    fn file_names(&self, dir: &Path) -> Vec<String> {
        let _ = dir;
        Vec::new()
    }

    /// Loads the value of an attribute of type `ty` written in a rig file as a file
    /// reference, `File("body.obj")`; `path` is already resolved against the directory of
    /// the rig file that wrote it. The core reads sinew value files
    /// ([`crate::value_file`], what importers write for large arrays) from disk and knows
    /// no geometry format; the `sinew` facade's source
    /// (`sinew::io::mesh_file::MeshFileSource`) adds Wavefront OBJ and glTF meshes.
    fn load_value(&self, path: &Path, ty: AttrType) -> Result<Value, String> {
        let _ = ty;
        Err(format!(
            "cannot load {}: this rig source reads no value files",
            path.display()
        ))
    }
}

/// Reads files from disk: rig text through [`crate::files::read_text`] (regular files up
/// to [`crate::files::RIG_TEXT`]), value files through [`load_value_file`].
#[derive(Clone, Copy, Debug, Default)]
pub struct FsSource;

impl RigSource for FsSource {
    fn read(&self, path: &Path) -> std::io::Result<String> {
        crate::files::read_text(path, crate::files::RIG_TEXT)
    }

    fn file_names(&self, dir: &Path) -> Vec<String> {
        let dir = if dir.as_os_str().is_empty() {
            Path::new(".")
        } else {
            dir
        };
        let Ok(entries) = std::fs::read_dir(dir) else {
            return Vec::new();
        };
        entries
            .filter_map(Result::ok)
            .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
            .filter_map(|e| e.file_name().into_string().ok())
            .take(10_000)
            .collect()
    }

    fn load_value(&self, path: &Path, ty: AttrType) -> Result<Value, String> {
        load_value_file(path, ty)
    }
}

/// Loads a sinew value file ([`crate::value_file`]) from disk, read through
/// [`crate::files::read_file`] with the [`crate::files::DATA`] limit. Any other file is
/// refused, naming the facade for meshes.
pub fn load_value_file(path: &Path, ty: AttrType) -> Result<Value, String> {
    let bytes = crate::files::read_file(path, crate::files::DATA)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    if !crate::value_file::is_value_file(&bytes) {
        return Err(format!(
            "cannot load a {ty} from {}: it is not a sinew value file, and mesh files need the sinew facade (load the rig with sinew::io::mesh_file::load_rig)",
            path.display()
        ));
    }
    crate::value_file::value_from_bytes(&bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// Files held in memory, by path.
#[derive(Clone, Debug, Default)]
pub struct MemSource {
    /// The files.
    pub files: HashMap<PathBuf, String>,
}

impl RigSource for MemSource {
    fn read(&self, path: &Path) -> std::io::Result<String> {
        self.files
            .get(path)
            .cloned()
            .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"))
    }

    fn file_names(&self, dir: &Path) -> Vec<String> {
        self.files
            .keys()
            .filter(|p| p.parent().unwrap_or(Path::new("")) == dir)
            .filter_map(|p| p.file_name()?.to_str().map(str::to_string))
            .collect()
    }
}

/// Lexically normalizes a path (`a/./b/../c` → `a/c`) without touching the disk.
pub fn normalize(p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    out.push("..");
                }
            }
            c => out.push(c.as_os_str()),
        }
    }
    out
}
