//! RON rig files: load with precise errors, components with mirroring,
//! canonical save. The format is documented in `docs/rig-format.md`.
//!
//! - [`parse`]: a RON parser keeping line/column and comments for every value
//!   ([`lex`]: RON's lexical rules, as the `ron` crate has them).
//! - [`doc`]: the document model (what a file says) and canonical printing
//!   (`doc_print`).
//! - [`typed`]: attribute values read and written by their declared type.
//! - [`mirror`]: Maya mirrorJoint *behavior* mirroring of authored values.
//! - `build`: component expansion and graph building, collecting all errors;
//!   `source`: where files come from ([`RigSource`]).
//! - `save`: graph to canonical text, and [`graph_eq`] for round-trip tests;
//!   `fmt_comments` carries the file's comments over to it and `fmt_print` lays it out.
//! - [`diag`]: `file:line:col: error: message` diagnostics with hints.
//!
//! Invariants: a failed load returns every error it found and no graph;
//! `load(save(g)) == g` (by [`graph_eq`]); `save(load(text))` is a fixed
//! point after one pass; no input makes the loader panic.

mod assemble;
mod build;
mod canon;
mod checks;
#[doc(hidden)]
pub mod comment_check;
mod custom_decl;
pub mod diag;
pub mod doc;
mod doc_print;
pub mod expand;
mod expand_run;
mod export;
mod fmt_comments;
mod fmt_print;
pub mod lex;
pub mod mirror;
pub mod parse;
mod save;
mod source;
pub mod typed;
mod typed_surface;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_comments;
#[cfg(test)]
mod tests_custom;
#[cfg(test)]
mod tests_errors;
#[cfg(test)]
mod tests_fuzz;
#[cfg(test)]
mod tests_limits;
#[cfg(test)]
mod tests_names;
#[cfg(test)]
mod tests_ron;

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;

pub use build::{
    load_rig, load_rig_str, load_rig_with, load_rig_with_limits, LoadLimits, LoadedRig, DEFAULT_MAX_NODES,
};
pub use custom_decl::write_attrs;
pub use diag::{Diagnostic, Diagnostics, Span};
pub use doc::RigDocument;
pub use export::{to_dot, to_json};
pub use mirror::Plane;
pub use save::{graph_eq, save_rig};
pub use source::{load_value_file, normalize, FsSource, MemSource, RigSource};

use crate::registry::Registry;

/// Loads a rig file and returns its canonical text (what `sinew fmt` writes).
pub fn format_rig_file(path: &Path, registry: &Arc<Registry>) -> Result<String, Diagnostics> {
    let rig = load_rig(path, registry)?;
    Ok(save_rig(&rig.graph, &rig.document))
}

/// Formats rig text (see [`format_rig_file`]).
pub fn format_rig_str(text: &str, virtual_path: &Path, registry: &Arc<Registry>) -> Result<String, Diagnostics> {
    let rig = load_rig_str(text, virtual_path, registry)?;
    Ok(save_rig(&rig.graph, &rig.document))
}

/// The files a rig depends on: the rig itself and every component file it
/// includes, transitively (normalized paths, the rig first). Works on broken
/// rigs too (as far as they parse), and lists missing files, so a watcher
/// can poll all of their modification times.
pub fn rig_dependencies(path: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut seen = HashSet::new();
    let mut todo = vec![normalize(path)];
    while let Some(p) = todo.pop() {
        if !seen.insert(p.clone()) {
            continue;
        }
        out.push(p.clone());
        let Ok(text) = FsSource.read(&p) else { continue };
        let fpath: Arc<Path> = Arc::from(p.as_path());
        let Ok(mut root) = parse::parse(&text, &fpath) else {
            continue;
        };
        let mut diags = Diagnostics::default();
        let doc = doc::read_document_taking(&mut root, &fpath, &mut diags);
        let dir = p.parent().unwrap_or(Path::new("")).to_path_buf();
        let bodies = std::iter::once(&doc.body).chain(doc.components.iter().map(|c| &c.body));
        for b in bodies {
            for u in &b.uses {
                if let Some((f, _)) = &u.file {
                    todo.push(normalize(&dir.join(f)));
                }
            }
        }
    }
    out
}
