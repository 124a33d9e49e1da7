//! Mapping a parsed Maya scene onto sinew nodes.
//!
//! [`Importer`] holds the scene, the resolved names and the rig under construction. It
//! runs in phases: DAG transforms first (so everything else can name them), then the
//! geometry chains (meshes and their deformers, collapsed), then every other node through
//! the type table `types::handler_for`, then the connections that no mapper consumed.
//! Each mapper marks the Maya nodes it turned into sinew nodes (or folded into others) and
//! the connections it consumed; what is left is reported.

mod accum;
mod anim;
mod blend;
mod connect;
mod constraint;
mod dag;
mod deform;
mod geometry;
mod ik;
mod meshdata;
mod plugs;
mod skin;
mod types;
mod utility;

use std::collections::HashMap;
use std::sync::Arc;

use sinew_core::Registry;

use super::lex::LineIndex;
use super::names::NameIndex;
use super::plug::Seg;
use super::report::{ImportReport, Outcome};
use super::scene::{MaNode, MaScene, Offset, SetAttr};
use super::units::Units;
use super::values::Values;
use super::MayaError;
use crate::rig_builder::RigBuilder;

pub use accum::Accum;
pub use types::{mapped_types, TypeKind};

/// What became of a Maya node.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Status {
    /// Not handled yet.
    Pending,
    /// Mapped; the sinew node that stands for it.
    Mapped(String),
    /// Folded into other sinew nodes (its data read by a mapper).
    Folded,
    /// Skipped, with the reason.
    Skipped(String),
}

/// Where a redirected Maya plug goes.
#[derive(Clone, Debug)]
pub enum Redirect {
    /// A sinew plug path (`node.attr[i]`).
    Sinew(String),
    /// Another Maya plug (a folded node's output stands for its input's source).
    Maya(usize, Vec<Seg>),
}

/// Where a Maya node's plugs go in sinew.
#[derive(Clone, Debug, Default)]
pub struct NodeMap {
    /// The outcome.
    pub status: Option<Status>,
    /// Maya attribute paths (long names, as `a[1].b`) redirected elsewhere, for nodes
    /// whose attributes live on several sinew nodes or on none (a folded conversion).
    pub redirects: Vec<(String, Redirect)>,
    /// Maya type for plug lookups when the node maps as another type (an unknown DAG
    /// node kept as a transform).
    pub as_type: Option<&'static str>,
}

/// The import in progress.
pub struct Importer<'a> {
    /// File name for messages.
    pub file: &'a str,
    /// The file's text.
    pub src: &'a str,
    /// The parsed scene.
    pub scene: &'a MaScene,
    /// Node names and DAG paths.
    pub names: NameIndex,
    lines: LineIndex,
    /// Units (with the `--scale`).
    pub units: Units,
    /// The registry of sinew node types.
    pub registry: &'a Arc<Registry>,
    /// The rig being built.
    pub rig: RigBuilder,
    /// Per Maya node, what it became.
    pub nodes: Vec<NodeMap>,
    /// Per connection, `(source node, destination node)` when both resolve.
    pub ends: Vec<(Option<usize>, Option<usize>)>,
    /// Per connection, whether a mapper consumed it.
    pub consumed: Vec<bool>,
    /// Connections by destination node and by source node.
    by_dst: HashMap<usize, Vec<usize>>,
    by_src: HashMap<usize, Vec<usize>>,
    /// Values per sinew node, flushed into the rig at the end.
    pub acc: Accum,
    /// The report.
    pub report: ImportReport,
}

impl<'a> Importer<'a> {
    /// Prepares an import (names resolved, connections indexed).
    pub fn new(
        file: &'a str,
        src: &'a str,
        scene: &'a mut MaScene,
        registry: &'a Arc<Registry>,
        name: &str,
        scale: f64,
    ) -> Importer<'a> {
        let (names, missing) = NameIndex::build(scene);
        let scene: &'a MaScene = scene;
        let mut units = scene.units.clone();
        units.scale = scale;
        let lines = LineIndex::new(src);
        let mut imp = Importer {
            file,
            src,
            scene,
            names,
            lines,
            units,
            registry,
            rig: RigBuilder::new(name, scene.units.fps),
            nodes: vec![NodeMap::default(); scene.nodes.len()],
            ends: Vec::with_capacity(scene.connections.len()),
            consumed: vec![false; scene.connections.len()],
            by_dst: HashMap::new(),
            by_src: HashMap::new(),
            acc: Accum::default(),
            report: ImportReport::default(),
        };
        for (i, p) in missing {
            let at = scene.nodes[i].at;
            let msg = format!(
                "{} is created under {p}, which the file does not define; it is imported at the top of the hierarchy",
                scene.nodes[i].name
            );
            imp.warn(at, msg);
        }
        for (i, n) in scene.nodes.iter().enumerate() {
            if n.existing && n.ty.is_empty() {
                imp.nodes[i].as_type = default_node_type(&n.name);
            }
        }
        for note in &scene.notes {
            let s = format!("{}: {}", imp.place(note.at), note.message);
            imp.report.statements.push(s);
        }
        for (k, c) in scene.connections.iter().enumerate() {
            let resolve = |imp: &mut Importer, n: &Option<String>| -> Option<usize> {
                let n = n.as_deref()?;
                match imp.names.resolve(n) {
                    Ok(r) => r,
                    Err(c) => {
                        let msg = format!("`{n}` is ambiguous ({}); the connection is dropped", c.join(", "));
                        imp.warn(scene.connections[k].at, msg);
                        None
                    }
                }
            };
            let s = resolve(&mut imp, &c.src.node);
            let d = resolve(&mut imp, &c.dst.node);
            imp.ends.push((s, d));
            if let Some(s) = s {
                imp.by_src.entry(s).or_default().push(k);
            }
            if let Some(d) = d {
                imp.by_dst.entry(d).or_default().push(k);
            }
        }
        imp
    }

    /// `file:line:col` of a byte offset.
    pub fn place(&self, at: Offset) -> String {
        let (l, c) = self.lines.line_col(self.src, at);
        format!("{}:{l}:{c}", self.file)
    }

    /// An error at a byte offset.
    pub fn error(&self, at: Offset, message: impl Into<String>, hint: impl Into<String>) -> MayaError {
        let (line, col) = self.lines.line_col(self.src, at);
        MayaError {
            file: self.file.to_string(),
            line,
            col,
            message: message.into(),
            hint: hint.into(),
        }
    }

    /// Records a warning at a byte offset.
    pub fn warn(&mut self, at: Offset, message: impl AsRef<str>) {
        let w = format!("{}: {}", self.place(at), message.as_ref());
        self.report.warnings.push(w);
    }

    /// Maya node `i`.
    pub fn node(&self, i: usize) -> &'a MaNode {
        &self.scene.nodes[i]
    }

    /// The type used for attribute lookups of node `i`.
    pub fn ty(&self, i: usize) -> &'a str {
        match self.nodes[i].as_type {
            Some(t) => t,
            None => self.scene.nodes[i].ty.as_str(),
        }
    }

    /// The values of a `setAttr`.
    pub fn values(&self, a: &'a SetAttr) -> Values<'a> {
        Values::new(self.src, &a.values, a.at)
    }

    /// Sets the outcome of node `i` and counts it.
    pub fn set_status(&mut self, i: usize, status: Status) {
        let ty = self.scene.nodes[i].ty.clone();
        let outcome = match &status {
            Status::Mapped(_) => Outcome::Mapped,
            Status::Folded => Outcome::Folded,
            Status::Skipped(_) | Status::Pending => Outcome::Skipped,
        };
        if self.nodes[i].status.is_none() {
            self.report
                .count(if ty.is_empty() { "(default node)" } else { &ty }, outcome);
        }
        self.nodes[i].status = Some(status);
    }

    /// The sinew node node `i` maps to.
    pub fn sinew(&self, i: usize) -> Option<&str> {
        match &self.nodes[i].status {
            Some(Status::Mapped(n)) => Some(n.as_str()),
            _ => None,
        }
    }

    /// Whether node `i` has been handled.
    pub fn handled(&self, i: usize) -> bool {
        self.nodes[i].status.is_some()
    }

    /// Connections into node `i`.
    pub fn conns_into(&self, i: usize) -> Vec<usize> {
        self.by_dst.get(&i).cloned().unwrap_or_default()
    }

    /// Connections out of node `i`.
    pub fn conns_from(&self, i: usize) -> Vec<usize> {
        self.by_src.get(&i).cloned().unwrap_or_default()
    }

    /// Marks connection `c` as consumed by a mapper.
    pub fn consume(&mut self, c: usize) {
        self.consumed[c] = true;
    }

    /// The long-name segments of a path on node `i`.
    pub fn long_segs(&self, i: usize, segs: &[Seg]) -> Vec<Seg> {
        plugs::long_segs(self, i, segs)
    }

    /// The long-name path of a connection end or setAttr on node `i` (`a[1].b`).
    pub fn long_path(&self, i: usize, segs: &[Seg]) -> String {
        plugs::long_path(self, i, segs)
    }

    /// The connection into node `i` at the long path `path` (exactly), with its source
    /// node and the source's long path.
    pub fn input_conn(&self, i: usize, path: &str) -> Option<(usize, usize, String)> {
        self.conns_into(i).into_iter().find_map(|c| {
            let conn = &self.scene.connections[c];
            (self.long_path(i, &conn.dst.segs) == path).then_some(())?;
            let s = self.ends[c].0?;
            Some((c, s, self.long_path(s, &conn.src.segs)))
        })
    }

    /// The last `setAttr` of node `i` whose long path is exactly `path`.
    pub fn set_attr(&self, i: usize, path: &str) -> Option<&'a SetAttr> {
        self.node(i)
            .attrs
            .iter()
            .rev()
            .find(|a| self.long_path(i, &a.segs) == path)
    }

    /// A number set on node `i` at `path` (`None` when not set or not a number).
    pub fn number(&self, i: usize, path: &str) -> Option<f64> {
        let a = self.set_attr(i, path)?;
        self.values(a).num(0).ok()
    }

    /// The DAG parent of node `i`.
    pub fn parent(&self, i: usize) -> Option<usize> {
        self.scene.nodes[i].parent_index
    }

    /// DAG children of node `i`.
    pub fn children(&self, i: usize) -> Vec<usize> {
        (0..self.scene.nodes.len())
            .filter(|&k| self.scene.nodes[k].parent_index == Some(i))
            .collect()
    }

    /// Reserves a unique sinew node name derived from `raw`.
    pub fn unique(&mut self, raw: &str) -> String {
        self.rig.name(raw, "node")
    }

    /// Adds a sinew node; returns its rig index.
    pub fn add(&mut self, name: &str, ty: &str, parent: Option<&str>, heavy: bool) -> usize {
        let k = self.rig.add(name, ty, parent, heavy);
        self.acc.register(name, k);
        k
    }

    /// Adds a connection between sinew plugs.
    pub fn connect(&mut self, src: impl Into<String>, dst: impl Into<String>, at: Offset) {
        self.acc.connect(src.into(), dst.into(), at);
    }
}

/// The type of a Maya default node named by `select -ne` (the file does not say it).
fn default_node_type(name: &str) -> Option<&'static str> {
    match name {
        "time1" => Some("time"),
        "ikSystem" => Some("ikSystem"),
        _ => None,
    }
}

/// Runs every phase on a prepared importer.
pub fn run(imp: &mut Importer) -> Result<(), MayaError> {
    dag::map_dag(imp)?;
    geometry::map_geometry(imp)?;
    ik::map_ik(imp)?;
    for i in 0..imp.scene.nodes.len() {
        if imp.handled(i) {
            continue;
        }
        let ty = imp.ty(i).to_string();
        match types::handler_for(&ty, imp.registry) {
            Some(h) => h(imp, i)?,
            None => types::skip(imp, i),
        }
    }
    connect::map_connections(imp)?;
    accum::finish(imp)
}
