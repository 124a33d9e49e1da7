//! The import report: what each Maya node became, what was skipped and why, every
//! warning with its `file:line:col`, and every connection that was dropped.

use std::collections::BTreeMap;
use std::fmt::Write as _;

/// What became of one Maya node type.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TypeCount {
    /// Nodes of the type in the file.
    pub total: usize,
    /// Mapped to sinew nodes.
    pub mapped: usize,
    /// Folded into other nodes (deformer plumbing, IK effectors, bind poses, unit
    /// conversions that cancel out...).
    pub folded: usize,
    /// Skipped.
    pub skipped: usize,
}

/// Why a node type was skipped.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Skip {
    /// Number of nodes.
    pub count: usize,
    /// The reason, for the user.
    pub reason: String,
    /// Whether at least one of them feeds something that was mapped (a skip that changes
    /// the rig; `--strict` refuses these).
    pub affects_rig: bool,
}

/// The report of one import.
#[derive(Clone, Debug, Default)]
pub struct ImportReport {
    /// Counts by Maya node type.
    pub by_type: BTreeMap<String, TypeCount>,
    /// Skipped node types with their count and reason.
    pub skipped: BTreeMap<String, Skip>,
    /// Warnings, each `file:line:col: what` (and what will differ).
    pub warnings: Vec<String>,
    /// Dropped connections, each `file:line:col: src -> dst: why`.
    pub dropped: Vec<String>,
    /// How many of the dropped connections ended at a mapped node (they change the rig).
    pub dropped_into_rig: usize,
    /// Statements skipped by the reader, `file:line:col: why`.
    pub statements: Vec<String>,
    /// Values set in the file on attributes sinew has no counterpart of, by `type.attr`
    /// (display colours, limits, UI state...), with how many times.
    pub ignored_values: BTreeMap<String, usize>,
    /// Number of sinew nodes and connections written.
    pub rig_nodes: usize,
    /// Connections written.
    pub rig_connections: usize,
}

impl ImportReport {
    /// Counts one node of `ty` with an outcome.
    pub fn count(&mut self, ty: &str, outcome: Outcome) {
        let c = self.by_type.entry(ty.to_string()).or_default();
        c.total += 1;
        match outcome {
            Outcome::Mapped => c.mapped += 1,
            Outcome::Folded => c.folded += 1,
            Outcome::Skipped => c.skipped += 1,
        }
    }

    /// Records a skipped node of `ty`.
    pub fn skip(&mut self, ty: &str, reason: &str, affects_rig: bool) {
        let s = self.skipped.entry(ty.to_string()).or_insert_with(|| Skip {
            count: 0,
            reason: reason.to_string(),
            affects_rig: false,
        });
        s.count += 1;
        s.affects_rig |= affects_rig;
    }

    /// Whether `--strict` refuses this import: a skipped type or a dropped connection that
    /// changes the rig.
    pub fn strict_failures(&self) -> Vec<String> {
        let mut out: Vec<String> = self
            .skipped
            .iter()
            .filter(|(_, s)| s.affects_rig)
            .map(|(t, s)| format!("{} node(s) of type {t} skipped: {}", s.count, s.reason))
            .collect();
        if self.dropped_into_rig > 0 {
            out.push(format!("{} connection(s) into the rig dropped", self.dropped_into_rig));
        }
        out
    }

    /// The summary `sinew import` prints.
    pub fn summary(&self) -> String {
        let mut s = String::new();
        let total: usize = self.by_type.values().map(|c| c.total).sum();
        let mapped: usize = self.by_type.values().map(|c| c.mapped).sum();
        let folded: usize = self.by_type.values().map(|c| c.folded).sum();
        let skipped: usize = self.by_type.values().map(|c| c.skipped).sum();
        let _ = writeln!(
            s,
            "{total} Maya nodes: {mapped} mapped, {folded} folded into others, {skipped} skipped; rig: {} sinew nodes, {} connections",
            self.rig_nodes, self.rig_connections
        );
        let _ = writeln!(s, "by type (mapped / folded / skipped of total):");
        for (t, c) in &self.by_type {
            let _ = writeln!(
                s,
                "  {t:<24} {:>4} / {:>4} / {:>4} of {:>4}",
                c.mapped, c.folded, c.skipped, c.total
            );
        }
        if !self.skipped.is_empty() {
            let _ = writeln!(s, "skipped types:");
            for (t, k) in &self.skipped {
                let mark = if k.affects_rig { " [affects the rig]" } else { "" };
                let _ = writeln!(s, "  {t} ({}): {}{mark}", k.count, k.reason);
            }
        }
        if !self.statements.is_empty() {
            let _ = writeln!(s, "statements skipped: {}", self.statements.len());
            for w in &self.statements {
                let _ = writeln!(s, "  {w}");
            }
        }
        if !self.ignored_values.is_empty() {
            let n: usize = self.ignored_values.values().sum();
            let _ = writeln!(
                s,
                "values without a sinew attribute (not imported): {n} ({} attributes: {})",
                self.ignored_values.len(),
                self.ignored_values
                    .keys()
                    .take(40)
                    .cloned()
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
        let _ = writeln!(s, "warnings: {}", self.warnings.len());
        for w in &self.warnings {
            let _ = writeln!(s, "  warning: {w}");
        }
        let _ = writeln!(
            s,
            "dropped connections: {} ({} into the rig)",
            self.dropped.len(),
            self.dropped_into_rig
        );
        for d in &self.dropped {
            let _ = writeln!(s, "  {d}");
        }
        s
    }
}

/// What became of one node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Mapped to a sinew node.
    Mapped,
    /// Folded into other nodes.
    Folded,
    /// Skipped.
    Skipped,
}
