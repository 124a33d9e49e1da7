//! Source positions and diagnostics: every problem in a rig file is reported
//! as `file:line:col: error: message` with a short `hint:` on how to fix it.

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A position in a source file: 1-based line and column (in characters).
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Span {
    /// The file (as given to the loader, joined with component paths).
    pub file: Arc<PathBuf>,
    /// 1-based line.
    pub line: u32,
    /// 1-based column, in characters.
    pub col: u32,
}

impl Span {
    /// A span at `line:col` of `file`.
    pub fn new(file: &Arc<PathBuf>, line: u32, col: u32) -> Self {
        Span {
            file: file.clone(),
            line,
            col,
        }
    }

    /// The same position moved `n` characters to the right (same line).
    pub fn shifted(&self, n: usize) -> Self {
        Span {
            col: self.col.saturating_add(n as u32),
            ..self.clone()
        }
    }
}

impl fmt::Display for Span {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file.display(), self.line, self.col)
    }
}

/// One error in a rig: where, what, and how to fix it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Diagnostic {
    /// Where the problem is.
    pub span: Span,
    /// What is wrong.
    pub message: String,
    /// How to fix it (one short line).
    pub hint: Option<String>,
    /// Related places (`note:` lines), e.g. the connections of a cycle or the
    /// `Use` that instantiated a component.
    pub notes: Vec<(Span, String)>,
}

impl Diagnostic {
    /// An error at `span`.
    pub fn new(span: Span, message: impl Into<String>) -> Self {
        Diagnostic {
            span,
            message: message.into(),
            hint: None,
            notes: Vec::new(),
        }
    }

    /// Adds a fix hint.
    pub fn hint(mut self, hint: impl Into<String>) -> Self {
        self.hint = Some(hint.into());
        self
    }

    /// Adds an optional fix hint.
    pub fn hint_opt(mut self, hint: Option<String>) -> Self {
        self.hint = hint;
        self
    }

    /// Adds a related place.
    pub fn note(mut self, span: Span, note: impl Into<String>) -> Self {
        self.notes.push((span, note.into()));
        self
    }

    /// The file path.
    pub fn file(&self) -> &Path {
        &self.span.file
    }

    /// Renders `file:line:col: error: message`, the hint and the notes.
    pub fn render(&self) -> String {
        let mut s = format!("{}: error: {}", self.span, self.message);
        if let Some(h) = &self.hint {
            s.push_str("\n  hint: ");
            s.push_str(h);
        }
        for (span, n) in &self.notes {
            s.push_str(&format!("\n  note: {span}: {n}"));
        }
        s
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render())
    }
}

/// All errors found while loading a rig, in file order.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Diagnostics {
    /// The errors.
    pub errors: Vec<Diagnostic>,
}

impl Diagnostics {
    /// Whether there is no error.
    pub fn is_empty(&self) -> bool {
        self.errors.is_empty()
    }

    /// Number of errors.
    pub fn len(&self) -> usize {
        self.errors.len()
    }

    /// Adds an error.
    pub fn push(&mut self, d: Diagnostic) {
        self.errors.push(d);
    }

    /// Sorts by position and removes duplicates (a component instantiated
    /// twice reports its own mistakes once).
    pub fn finish(&mut self) {
        self.errors
            .sort_by(|a, b| (&a.span, &a.message).cmp(&(&b.span, &b.message)));
        self.errors.dedup_by(|a, b| a.span == b.span && a.message == b.message);
    }

    /// Every error rendered, one block per error, then a summary line.
    pub fn render(&self) -> String {
        let mut s = String::new();
        for e in &self.errors {
            s.push_str(&e.render());
            s.push('\n');
        }
        let n = self.errors.len();
        s.push_str(&format!("{n} error{}\n", if n == 1 { "" } else { "s" }));
        s
    }

    /// The files mentioned by the errors.
    pub fn files(&self) -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = self.errors.iter().map(|e| e.span.file.to_path_buf()).collect();
        v.sort();
        v.dedup();
        v
    }
}

impl fmt::Display for Diagnostics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render())
    }
}

impl std::error::Error for Diagnostics {}
