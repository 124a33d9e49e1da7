//! Maya ASCII (`.ma`) import: a reader for the MEL subset Maya writes and the mapping of
//! Maya's nodes onto sinew's plugins, with Maya's conventions kept (units, short attribute
//! names, the deformer plumbing collapsed into a chain). See `docs/maya-import.md`.
//!
//! Layers, each its own module: [`lex`] (tokens with byte spans), [`parse`] (statements
//! into the [`scene`] model), [`values`] (typed `setAttr` values), [`plug`] and [`names`]
//! (plug paths, DAG paths), [`units`] (the unit rules), [`attrs`] (Maya's attribute
//! names), [`map`] (the mappers, one module per family) and [`report`].
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let registry = sinew_nodes::registry()?;
//! let imp = sinew_io::maya::import_maya_file("scene.ma".as_ref(), &registry, &Default::default())?;
//! println!("{}", imp.report.summary());
//! imp.rig.write(&registry, "scene.ron".as_ref())?;
//! # Ok(()) }
//! ```

pub mod attrs;
pub mod lex;
pub mod map;
pub mod names;
pub mod parse;
pub mod plug;
pub mod report;
pub mod scene;
pub mod units;
pub mod values;

use std::fmt;
use std::path::Path;
use std::sync::Arc;

use glam::DMat4;
use sinew_core::Registry;

use crate::rig_builder::RigBuilder;
use map::Importer;
pub use report::ImportReport;

/// An import error at a place in the file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MayaError {
    /// File name.
    pub file: String,
    /// Line (from 1; 0 when the error has no place).
    pub line: u32,
    /// Column (from 1).
    pub col: u32,
    /// What is wrong.
    pub message: String,
    /// How to fix it.
    pub hint: String,
}

impl fmt::Display for MayaError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line > 0 {
            write!(f, "{}:{}:{}: error: {}", self.file, self.line, self.col, self.message)?;
        } else {
            write!(f, "{}: error: {}", self.file, self.message)?;
        }
        if !self.hint.is_empty() {
            write!(f, "\n  hint: {}", self.hint)?;
        }
        Ok(())
    }
}

impl std::error::Error for MayaError {}

/// Options of an import.
#[derive(Clone, Debug)]
pub struct MayaImportOptions {
    /// Rig name (`None`: the file's stem).
    pub name: Option<String>,
    /// Factor applied to every length (1 keeps the file's linear unit).
    pub scale: f64,
    /// Fail when a node type that feeds the rig is skipped or a connection into the rig is
    /// dropped.
    pub strict: bool,
}

impl Default for MayaImportOptions {
    fn default() -> Self {
        MayaImportOptions {
            name: None,
            scale: 1.0,
            strict: false,
        }
    }
}

/// A joint's stored bind data.
#[derive(Clone, Debug)]
pub struct JointBind {
    /// The sinew joint.
    pub joint: String,
    /// `.bps`: its world matrix at bind, as Maya stored it (sinew units).
    pub bind_pose: Option<DMat4>,
}

/// A skinCluster influence's stored bind data.
#[derive(Clone, Debug)]
pub struct InfluenceBind {
    /// The sinew skinCluster.
    pub skin: String,
    /// The influence's sinew node.
    pub joint: String,
    /// Its Maya influence index (`matrix[index]`).
    pub index: u32,
    /// `.pm[i]`: the inverse of the influence's world matrix at bind (sinew units).
    pub bind_pre_matrix: DMat4,
}

/// What an import produced.
#[derive(Clone, Debug)]
pub struct MayaImport {
    /// The rig (write it with [`RigBuilder::write`]).
    pub rig: RigBuilder,
    /// The report.
    pub report: ImportReport,
    /// The file's current frame (`time1.outTime`), the pose its stored values are at.
    pub current_frame: f64,
    /// Frames that hold a key of a time curve, sorted.
    pub keyed_frames: Vec<f64>,
    /// Joints with their stored bind pose.
    pub joints: Vec<JointBind>,
    /// Skin influences with their stored bind pre-matrix.
    pub influences: Vec<InfluenceBind>,
}

/// Decodes a file's bytes: UTF-8, or (when not valid UTF-8, as Maya's `Codeset: 1252`
/// files can be) each byte as the Latin-1 character of the same number.
pub fn decode_text(bytes: &[u8]) -> String {
    match std::str::from_utf8(bytes) {
        Ok(s) => s.to_string(),
        Err(_) => bytes.iter().map(|&b| b as char).collect(),
    }
}

/// Imports a `.ma` file.
pub fn import_maya_file(
    path: &Path,
    registry: &Arc<Registry>,
    opts: &MayaImportOptions,
) -> Result<MayaImport, MayaError> {
    let file = path.display().to_string();
    // Regular files only, within the size limit (a device such as /dev/zero is refused).
    let bytes = sinew_core::files::read_file(path, sinew_core::files::DATA).map_err(|e| MayaError {
        file: file.clone(),
        line: 0,
        col: 0,
        message: format!("cannot read the file: {e}"),
        hint: "check the path".into(),
    })?;
    let mut opts = opts.clone();
    if opts.name.is_none() {
        opts.name = path.file_stem().and_then(|s| s.to_str()).map(str::to_string);
    }
    import_maya(&decode_text(&bytes), &file, registry, &opts)
}

/// Imports Maya ASCII text; `file` names it in messages.
pub fn import_maya(
    text: &str,
    file: &str,
    registry: &Arc<Registry>,
    opts: &MayaImportOptions,
) -> Result<MayaImport, MayaError> {
    let mut scene = parse::parse(text).map_err(|e| {
        // The line index is built only for an error: the importer builds its own.
        let (line, col) = lex::LineIndex::new(text).line_col(text, e.offset);
        MayaError {
            file: file.to_string(),
            line,
            col,
            message: e.message,
            hint: e.hint,
        }
    })?;
    if !(opts.scale.is_finite() && opts.scale > 0.0) {
        return Err(MayaError {
            file: file.to_string(),
            line: 0,
            col: 0,
            message: format!("--scale {} must be a positive number", opts.scale),
            hint: "give the factor lengths are multiplied by, such as 0.01 for centimetres to metres".into(),
        });
    }
    let name = opts.name.clone().unwrap_or_else(|| "imported".into());
    let mut imp = Importer::new(file, text, &mut scene, registry, &name, opts.scale);
    map::run(&mut imp)?;
    let (current_frame, keyed_frames, range) = timing(&imp);
    imp.rig.frames = range.or(Some((current_frame, current_frame)));
    let (joints, influences) = bind_data(&imp);
    let report = imp.report.clone();
    if opts.strict {
        let fails = report.strict_failures();
        if !fails.is_empty() {
            return Err(MayaError {
                file: file.to_string(),
                line: 0,
                col: 0,
                message: format!("--strict: {}", fails.join("; ")),
                hint: "run without --strict to import anyway; the report lists what was skipped".into(),
            });
        }
    }
    Ok(MayaImport {
        rig: imp.rig,
        report,
        current_frame,
        keyed_frames,
        joints,
        influences,
    })
}

/// The current frame, the keyed frames, and the playback range
/// (`playbackOptions -min -max` in the scene configuration script, else the keys' range).
fn timing(imp: &Importer) -> (f64, Vec<f64>, Option<(f64, f64)>) {
    let mut current = 1.0;
    let mut range = None;
    let mut keys: Vec<f64> = Vec::new();
    for (i, n) in imp.scene.nodes.iter().enumerate() {
        if n.existing && n.name == "time1" {
            current = imp.number(i, "outTime").unwrap_or(current);
        }
        if n.ty == "script" && n.name == "sceneConfigurationScriptNode" {
            if let Some(s) = imp.set_attr(i, "before").and_then(|a| imp.values(a).string().ok()) {
                let w: Vec<&str> = s.split_whitespace().collect();
                let num = |flag: &str| {
                    w.iter()
                        .position(|x| *x == flag)
                        .and_then(|k| w.get(k + 1)?.parse::<f64>().ok())
                };
                if let (Some(a), Some(b)) = (num("-min"), num("-max")) {
                    range = Some((a, b));
                }
            }
        }
        if n.ty.starts_with("animCurveT") && imp.sinew(i).is_some() {
            for a in &n.attrs {
                let segs = imp.long_segs(i, &a.segs);
                if segs.len() == 1 && segs[0].name == "keyTimeValue" {
                    if let Ok(v) = imp.values(a).numbers() {
                        keys.extend(v.chunks(2).map(|c| c[0]));
                    }
                }
            }
        }
    }
    keys.sort_by(f64::total_cmp);
    keys.dedup();
    let range = range.or_else(|| Some((*keys.first()?, *keys.last()?)));
    (current, keys, range)
}

/// Joints' `.bps` and skin influences' `.pm[i]`, in sinew units.
fn bind_data(imp: &Importer) -> (Vec<JointBind>, Vec<InfluenceBind>) {
    let mat = |i: usize, path: &str| -> Option<DMat4> {
        let a = imp.set_attr(i, path)?;
        let mut m = imp.values(a).matrix().ok()?;
        let t = m.w_axis;
        m.w_axis = glam::DVec4::new(
            imp.units.internal_length(t.x),
            imp.units.internal_length(t.y),
            imp.units.internal_length(t.z),
            t.w,
        );
        Some(m)
    };
    let mut joints = Vec::new();
    let mut infl = Vec::new();
    for (i, n) in imp.scene.nodes.iter().enumerate() {
        if n.ty == "joint" {
            if let Some(j) = imp.sinew(i) {
                joints.push(JointBind {
                    joint: j.to_string(),
                    bind_pose: mat(i, "bindPose"),
                });
            }
        }
        if n.ty == "skinCluster" {
            let Some(skin) = imp.sinew(i) else { continue };
            for c in imp.conns_into(i) {
                let conn = &imp.scene.connections[c];
                let segs = imp.long_segs(i, &conn.dst.segs);
                let (Some(src), Some(seg)) = (imp.ends[c].0, segs.first()) else {
                    continue;
                };
                let Some(plug::Index::One(j)) = seg.index.filter(|_| seg.name == "matrix") else {
                    continue;
                };
                if let (Some(joint), Some(pm)) = (imp.sinew(src), mat(i, &format!("bindPreMatrix[{j}]"))) {
                    infl.push(InfluenceBind {
                        skin: skin.to_string(),
                        joint: joint.to_string(),
                        index: j,
                        bind_pre_matrix: pm,
                    });
                }
            }
        }
    }
    (joints, infl)
}

#[cfg(test)]
mod tests;
