//! What an engine links: `cargo tree -p sinew-runtime` (normal and build dependencies)
//! must hold none of the crates of the viewer (`sinew-view`: tiny_http, notify,
//! layout-rs), the CLI (clap, serde_json) or the file formats (sinew-io, gltf, roxmltree),
//! nor the skeletonize feature's solvers (spade, faer). Skips with a message when cargo
//! cannot list the tree (no cargo on the machine running the test binary).

use std::process::Command;

/// Crates an engine build must not pull in.
const FORBIDDEN: &[&str] = &[
    "sinew",
    "sinew-view",
    "sinew-io",
    "tiny_http",
    "notify",
    "layout-rs",
    "clap",
    "serde_json",
    "ureq",
    "gltf",
    "roxmltree",
    "spade",
    "faer",
];

#[test]
fn runtime_links_no_viewer_cli_or_format_crates() {
    let cargo = option_env!("CARGO").unwrap_or("cargo");
    let manifest = concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml");
    let out = Command::new(cargo)
        .args(["tree", "--manifest-path", manifest, "-p", "sinew-runtime"])
        .args(["-e", "normal,build", "--prefix", "none", "--offline"])
        .output();
    let out = match out {
        Ok(o) if o.status.success() => o,
        Ok(o) => {
            eprintln!(
                "SKIPPED runtime_links_no_viewer_cli_or_format_crates: cargo tree failed: {}",
                String::from_utf8_lossy(&o.stderr)
            );
            return;
        }
        Err(e) => {
            eprintln!("SKIPPED runtime_links_no_viewer_cli_or_format_crates: cannot run {cargo}: {e}");
            return;
        }
    };
    let text = String::from_utf8_lossy(&out.stdout);
    // One crate per line: `name vX.Y.Z (path) (*)`.
    let crates: Vec<&str> = text.lines().filter_map(|l| l.split_whitespace().next()).collect();
    assert!(
        crates.contains(&"sinew-runtime") && crates.contains(&"sinew-core"),
        "unexpected cargo tree output:\n{text}"
    );
    let found: Vec<&&str> = FORBIDDEN.iter().filter(|f| crates.contains(f)).collect();
    assert!(
        found.is_empty(),
        "sinew-runtime depends on {found:?}; engines must not link them:\n{text}"
    );
}
