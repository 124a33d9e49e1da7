//! Output files of commands: an output never overwrites an input, and each kind of output
//! has its extension (`.ron` for rigs, `.glb`/`.gltf` for baked scenes).

use std::path::{Path, PathBuf};

/// Whether `a` and `b` name the same file: the same device and inode when both exist
/// (hard links, symlinks, `./x` vs `x`), else the same canonical parent folder and name.
pub fn same_file(a: &Path, b: &Path) -> bool {
    if let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) {
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt;
            return ma.dev() == mb.dev() && ma.ino() == mb.ino();
        }
        #[cfg(not(unix))]
        {
            let _ = (ma, mb);
        }
    }
    canonical(a) == canonical(b)
}

/// `p` with its parent folder canonicalized (the file itself may not exist yet).
fn canonical(p: &Path) -> PathBuf {
    if let Ok(c) = p.canonicalize() {
        return c;
    }
    let parent = match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let dir = parent.canonicalize().unwrap_or_else(|_| parent.to_path_buf());
    match p.file_name() {
        Some(name) => dir.join(name),
        None => dir,
    }
}

/// Refuses when an output path is one of the inputs (or two outputs are the same file).
pub fn check_outputs(inputs: &[&Path], outputs: &[&Path]) -> Result<(), String> {
    for (k, out) in outputs.iter().enumerate() {
        if let Some(inp) = inputs.iter().find(|i| same_file(i, out)) {
            return Err(format!(
                "{}: the output would overwrite the input {}; choose another output path",
                out.display(),
                inp.display()
            ));
        }
        if let Some(other) = outputs[..k].iter().find(|o| same_file(o, out)) {
            return Err(format!(
                "{} and {} are the same file; choose another output path",
                other.display(),
                out.display()
            ));
        }
    }
    Ok(())
}

/// Refuses a rig output whose name does not end in `.ron` (rigs are RON text).
pub fn require_rig_extension(out: &Path) -> Result<(), String> {
    let ext = out.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if ext.as_deref() == Some("ron") {
        Ok(())
    } else {
        Err(format!(
            "{}: a rig is written as RON text; give an output ending in .ron",
            out.display()
        ))
    }
}

/// The data sidecar written next to the rig `out`: `<stem>.data.ron`.
pub fn sidecar_of(out: &Path) -> PathBuf {
    let stem = out.file_stem().and_then(|s| s.to_str()).unwrap_or("rig");
    out.with_file_name(format!("{stem}.data.ron"))
}

/// The checks of a command writing a rig (`out`, `.ron`) and its data sidecar from `inputs`.
pub fn check_rig_output(inputs: &[&Path], out: &Path) -> Result<(), String> {
    require_rig_extension(out)?;
    check_outputs(inputs, &[out, &sidecar_of(out)])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_output_equal_to_an_input_is_refused_in_any_spelling() {
        let d = std::env::temp_dir().join(format!("sinew-paths-{}", std::process::id()));
        std::fs::create_dir_all(d.join("sub")).unwrap();
        let model = d.join("m.gltf");
        std::fs::write(&model, "{}").unwrap();
        assert!(check_outputs(&[&model], &[&model]).is_err());
        assert!(check_outputs(&[&model], &[&d.join("sub/../m.gltf")]).is_err());
        assert!(check_outputs(&[&model], &[&d.join("m.ron")]).is_ok());
        let e = check_rig_output(&[&model], &model).unwrap_err();
        assert!(e.contains(".ron"), "{e}");
        // The sidecar of `x.ron` is `x.data.ron`: an input of that name is protected too.
        let data = d.join("r.data.ron");
        std::fs::write(&data, "Rig()").unwrap();
        let e = check_rig_output(&[&data], &d.join("r.ron")).unwrap_err();
        assert!(e.contains("overwrite"), "{e}");
        #[cfg(unix)]
        {
            let link = d.join("link.gltf");
            let _ = std::fs::remove_file(&link);
            std::os::unix::fs::symlink(&model, &link).unwrap();
            assert!(check_outputs(&[&model], &[&link]).is_err(), "a symlink to the input");
        }
        let _ = std::fs::remove_dir_all(&d);
    }
}
