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
    /// the rig file that wrote it. The core knows no geometry format, so the default
    /// refuses; the `sinew` facade's source (`sinew::io::mesh_file::MeshFileSource`)
    /// loads Wavefront OBJ and glTF meshes.
    fn load_value(&self, path: &Path, ty: AttrType) -> Result<Value, String> {
        Err(format!(
            "cannot load a {ty} from {}: mesh files need the sinew facade (load the rig with sinew::io::mesh_file::load_rig)",
            path.display()
        ))
    }
}

/// Reads files from disk (regular files up to 64 MiB).
#[derive(Clone, Copy, Debug, Default)]
pub struct FsSource;

impl RigSource for FsSource {
    fn read(&self, path: &Path) -> std::io::Result<String> {
        let meta = std::fs::metadata(path)?;
        if !meta.is_file() {
            return Err(std::io::Error::other("not a regular file"));
        }
        if meta.len() > 64 << 20 {
            return Err(std::io::Error::other("file is larger than 64 MiB"));
        }
        std::fs::read_to_string(path)
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
