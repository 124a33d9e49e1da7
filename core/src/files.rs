//! Reading input files: every file sinew reads — rig and component files, meshes (OBJ,
//! glTF/GLB and the buffers a glTF names by URI), BVH motion, value files written by
//! importers, joint maps — goes through [`read_file`] or [`read_text`], which refuse
//! anything but a regular file (a device such as `/dev/zero`, a pipe or a folder would be
//! read until memory runs out, or forever) and files over a size limit named in the error.
//!
//! The limits:
//! - [`RIG_TEXT`], 64 MiB: rig and component files (RON text; the loader keeps a syntax
//!   tree of the whole file, about fifteen times its size). Importers keep their rig text
//!   small by writing large arrays to value files (`File("x.data/…bin")`).
//! - [`DATA`], 1 GiB: everything else (meshes, motion capture, glTF buffers, value files).

use std::io::Read;
use std::path::Path;

/// A size limit for one kind of file, named in the error when a file exceeds it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FileLimit {
    /// The largest accepted size in bytes.
    pub bytes: u64,
    /// What kind of files it applies to (`"rig files"`).
    pub applies_to: &'static str,
}

/// The limit for rig and component files: 64 MiB.
pub const RIG_TEXT: FileLimit = FileLimit {
    bytes: 64 << 20,
    applies_to: "rig files",
};

/// The limit for meshes, motion capture, glTF buffers and value files: 1 GiB.
pub const DATA: FileLimit = FileLimit {
    bytes: 1 << 30,
    applies_to: "model and data files",
};

/// `bytes` as a short human size (`64 MiB`, `1 GiB`, `12.5 MiB`, `300 bytes`).
pub fn human_size(bytes: u64) -> String {
    const UNITS: [(&str, u64); 3] = [("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)];
    for (unit, size) in UNITS {
        if bytes >= size {
            return if bytes % size == 0 {
                format!("{} {unit}", bytes / size)
            } else {
                format!("{:.1} {unit}", bytes as f64 / size as f64)
            };
        }
    }
    format!("{bytes} bytes")
}

fn too_large(size: u64, limit: FileLimit) -> std::io::Error {
    std::io::Error::other(format!(
        "the file is {}, over the {} limit for {}",
        human_size(size),
        human_size(limit.bytes),
        limit.applies_to
    ))
}

/// Reads a whole regular file of at most `limit` bytes (see the module docs).
pub fn read_file(path: &Path, limit: FileLimit) -> std::io::Result<Vec<u8>> {
    let not_regular = || std::io::Error::other("not a regular file (a device, pipe or folder cannot be read as input)");
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(not_regular());
    }
    if meta.len() > limit.bytes {
        return Err(too_large(meta.len(), limit));
    }
    let file = std::fs::File::open(path)?;
    // The path may have changed between the two looks: check what was opened.
    let meta = file.metadata()?;
    if !meta.is_file() {
        return Err(not_regular());
    }
    let mut bytes = Vec::with_capacity(meta.len().min(limit.bytes) as usize);
    // A file growing while it is read stops at the limit.
    file.take(limit.bytes + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit.bytes {
        return Err(too_large(bytes.len() as u64, limit));
    }
    Ok(bytes)
}

/// Reads a whole regular UTF-8 text file of at most `limit` bytes.
pub fn read_text(path: &Path, limit: FileLimit) -> std::io::Result<String> {
    String::from_utf8(read_file(path, limit)?)
        .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, format!("not UTF-8 text: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_folders_and_large_files_are_refused_with_the_limit_named() {
        let e = read_file(Path::new("/dev/zero"), DATA);
        if std::path::Path::new("/dev/zero").exists() {
            assert!(e.unwrap_err().to_string().contains("not a regular file"));
        }
        let dir = std::env::temp_dir();
        assert!(read_file(&dir, DATA)
            .unwrap_err()
            .to_string()
            .contains("not a regular file"));
        let f = dir.join(format!("sinew-files-{}.txt", std::process::id()));
        std::fs::write(&f, vec![b'a'; 2048]).unwrap();
        let small = FileLimit {
            bytes: 1024,
            applies_to: "test files",
        };
        let e = read_text(&f, small).unwrap_err().to_string();
        assert_eq!(e, "the file is 2 KiB, over the 1 KiB limit for test files");
        assert_eq!(read_text(&f, DATA).unwrap().len(), 2048);
        std::fs::write(&f, [0xff, 0xfe]).unwrap();
        assert!(read_text(&f, DATA).unwrap_err().to_string().contains("not UTF-8"));
        let _ = std::fs::remove_file(&f);
        assert_eq!(human_size(64 << 20), "64 MiB");
        assert_eq!(human_size(1 << 30), "1 GiB");
        assert_eq!(human_size(83 << 19), "41.5 MiB");
        assert_eq!(human_size(300), "300 bytes");
    }
}
