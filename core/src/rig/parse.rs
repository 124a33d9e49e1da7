//! A small RON parser that keeps the position of every value, and its comments.
//!
//! It reads RON as the `ron` crate 0.12 does (see [`super::lex`] for the lexical rules):
//! numbers in every form, `true`/`false`, strings (escapes, raw strings), identifiers
//! (raw ones too), tuples and structs (`(1, 2)`, `(a: 1)`, `Name(a: 1)`), lists `[..]`
//! and maps `{k: v}`, `//` and nested `/* */` comments, trailing commas and
//! `#![enable(..)]` headers. Every value carries its [`Span`], so later stages can
//! point at the exact line and column, and its [`Trivia`]: the comments and blank
//! lines around it, so `sinew fmt` can keep them. Nesting is limited (no stack
//! overflow on hostile input) and parsing never panics.
//!
//! Where comments go: a comment before an entry of a `( )`, `[ ]` or `{ }` (or between
//! its key and its value) leads that entry; one on the same line after an entry (before
//! or after its comma) trails it; one after the last entry, before the closing bracket,
//! is the container's `inner_end`. Comments before the root value (and `#![..]`
//! attributes) lead the root; comments after it trail it. Entry trivia is stored on the
//! entry's value node (for a map entry, on the value, not the key).

use std::path::PathBuf;
use std::sync::Arc;

use super::diag::{Diagnostic, Span};
use super::lex;

/// Deepest nesting accepted.
pub const MAX_DEPTH: usize = 96;

/// A comment, verbatim (`// text` without the line break, or `/* text */`), or a
/// `#![..]` attribute line of the header.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Comment {
    /// The text as written (line comments without trailing spaces).
    pub text: String,
    /// Whether it started its line (nothing but whitespace before it on that line).
    pub own_line: bool,
    /// Whether a blank line precedes it.
    pub blank_before: bool,
}

impl Comment {
    /// Whether it is a `//` comment (which must end its line when printed).
    pub fn is_line(&self) -> bool {
        self.text.starts_with("//")
    }
}

/// Comments and blank lines attached to a value (see the module docs for the rules).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Trivia {
    /// A blank line separates this entry from what precedes it (the previous entry or
    /// its own leading comments).
    pub blank_before: bool,
    /// Comments before the entry.
    pub leading: Vec<Comment>,
    /// Comments after the entry on its last line.
    pub trailing: Vec<Comment>,
    /// Comments after a container's last entry, before its closing bracket.
    pub inner_end: Vec<Comment>,
}

impl Trivia {
    /// Whether it holds no comment (a blank line alone counts as empty).
    pub fn has_comments(&self) -> bool {
        !(self.leading.is_empty() && self.trailing.is_empty() && self.inner_end.is_empty())
    }
}

/// A parsed value, where it starts, and its comments.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// Where the value starts.
    pub span: Span,
    /// The value.
    pub kind: Ast,
    /// Comments and blank lines around it (`None` when there are none).
    pub trivia: Option<Box<Trivia>>,
}

impl Node {
    /// A node without trivia.
    pub fn new(span: Span, kind: Ast) -> Node {
        Node {
            span,
            kind,
            trivia: None,
        }
    }

    /// Its trivia, created empty if absent.
    pub fn trivia_mut(&mut self) -> &mut Trivia {
        self.trivia.get_or_insert_with(Default::default)
    }

    /// Whether this node or any node inside it has comments.
    pub fn has_comments(&self) -> bool {
        // Walks the containers directly (`children` boxes an iterator per container).
        self.trivia.as_ref().is_some_and(|t| t.has_comments())
            || match &self.kind {
                Ast::List(v) => v.iter().any(Node::has_comments),
                Ast::Map(v) => v.iter().any(|(k, v)| k.has_comments() || v.has_comments()),
                Ast::Group { items, .. } => items.iter().any(|i| i.value.has_comments()),
                _ => false,
            }
    }

    /// Every comment of this node and the nodes inside it, in source order.
    pub fn comments(&self) -> Vec<&Comment> {
        let mut out = Vec::new();
        self.collect_comments(&mut out);
        out
    }

    fn collect_comments<'a>(&'a self, out: &mut Vec<&'a Comment>) {
        let t = self.trivia.as_deref();
        out.extend(t.iter().flat_map(|t| &t.leading));
        for c in self.kind.children() {
            c.collect_comments(out);
        }
        out.extend(t.iter().flat_map(|t| &t.inner_end));
        out.extend(t.iter().flat_map(|t| &t.trailing));
    }
}
/// One entry of a `( .. )` group: positional (`key == None`) or named.
#[derive(Clone, Debug, PartialEq)]
pub struct Item {
    /// The field name and its position, for `name: value`.
    pub key: Option<(String, Span)>,
    /// The value.
    pub value: Node,
}

/// The value kinds of the RON subset.
#[derive(Clone, Debug, PartialEq)]
pub enum Ast {
    /// `true` / `false`.
    Bool(bool),
    /// An integer literal.
    Int(i64),
    /// A float literal.
    Float(f64),
    /// A string; `exact` is true when the source text between the quotes is
    /// the content itself (no escapes), so columns inside it can be computed.
    Str {
        /// The content.
        value: String,
        /// Whether source columns map one-to-one onto the content.
        exact: bool,
    },
    /// A bare identifier (`xzy`, `YZ`, `None`).
    Ident(String),
    /// `[a, b]`.
    List(Vec<Node>),
    /// `{k: v}`.
    Map(Vec<(Node, Node)>),
    /// `(..)` or `Name(..)`: a tuple (positional items) or struct (named items).
    Group {
        /// The name before `(`, if any.
        name: Option<String>,
        /// The entries.
        items: Vec<Item>,
    },
}

impl Ast {
    /// A short description for "found ..." messages.
    pub fn describe(&self) -> String {
        match self {
            Ast::Bool(b) => format!("`{b}`"),
            Ast::Int(i) => format!("the integer {i}"),
            Ast::Float(x) => format!("the number {x:?}"),
            Ast::Str { value, .. } => format!("the string {value:?}"),
            Ast::Ident(i) => format!("the name `{i}`"),
            Ast::List(v) => format!("a list of {}", v.len()),
            Ast::Map(v) => format!("a map of {}", v.len()),
            Ast::Group { name: Some(n), .. } => format!("`{n}(..)`"),
            Ast::Group { items, .. } if items.iter().any(|i| i.key.is_some()) => "a struct `(name: ..)`".into(),
            Ast::Group { items, .. } => format!("a tuple of {}", items.len()),
        }
    }

    /// The number, for ints and floats.
    pub fn as_f64(&self) -> Option<f64> {
        match *self {
            Ast::Int(i) => Some(i as f64),
            Ast::Float(x) => Some(x),
            _ => None,
        }
    }

    /// The text of a string or identifier.
    pub fn as_str(&self) -> Option<&str> {
        match self {
            Ast::Str { value, .. } => Some(value),
            Ast::Ident(s) => Some(s),
            _ => None,
        }
    }

    /// The nodes directly inside this value, in source order (a map's keys before
    /// their values).
    pub fn children(&self) -> Box<dyn Iterator<Item = &Node> + '_> {
        match self {
            Ast::List(v) => Box::new(v.iter()),
            Ast::Map(v) => Box::new(v.iter().flat_map(|(k, v)| [k, v])),
            Ast::Group { items, .. } => Box::new(items.iter().map(|i| &i.value)),
            _ => Box::new(std::iter::empty()),
        }
    }

    /// The positional items of an unnamed tuple.
    pub fn tuple_items(&self) -> Option<Vec<&Node>> {
        Some(self.tuple()?.iter().map(|i| &i.value).collect())
    }

    /// The items of an unnamed tuple, as written (what [`Ast::tuple_items`] lists, without
    /// collecting them).
    pub fn tuple(&self) -> Option<&[Item]> {
        match self {
            Ast::Group { name: None, items } if items.iter().all(|i| i.key.is_none()) => Some(items),
            _ => None,
        }
    }
}

/// Parses a whole file: optional `#![..]` attributes, one value, then only whitespace
/// and comments.
pub fn parse(text: &str, file: &Arc<PathBuf>) -> Result<Node, Diagnostic> {
    let mut p = Parser {
        text,
        pos: 0,
        line: 1,
        col: 1,
        file: file.clone(),
        depth: 0,
        pending: Vec::new(),
        nl: 0,
        seen_token: false,
    };
    p.skip_ws()?;
    let mut header = Vec::new();
    while p.peek() == Some('#') {
        header.append(&mut p.pending);
        let blank_before = p.nl >= 2;
        let text = p.attribute()?;
        header.push(Comment {
            text,
            own_line: true,
            blank_before,
        });
        p.skip_ws()?;
    }
    if p.peek().is_none() {
        return Err(Diagnostic::new(p.span(), "the file is empty")
            .hint("a rig file holds one `Rig(name: \"..\", nodes: {..})` value"));
    }
    let mut root = p.value()?;
    p.skip_ws()?;
    if p.peek().is_some() {
        return Err(Diagnostic::new(
            p.span(),
            format!("unexpected {} after the end of the rig", p.describe_here()),
        )
        .hint("a rig file holds exactly one value; check for an extra closing bracket"));
    }
    let trailing = std::mem::take(&mut p.pending);
    if !header.is_empty() || !trailing.is_empty() {
        let t = root.trivia_mut();
        header.append(&mut t.leading);
        t.leading = header;
        t.trailing = trailing;
    }
    Ok(root)
}

struct Parser<'a> {
    text: &'a str,
    pos: usize,
    line: u32,
    col: u32,
    file: Arc<PathBuf>,
    depth: usize,
    /// Comments read since they were last taken.
    pending: Vec<Comment>,
    /// Line breaks since the last token or comment.
    nl: u32,
    /// Whether a token was read yet (comments before the first one start their line).
    seen_token: bool,
}

/// A parser position to return to after a look-ahead.
type Mark = (usize, u32, u32, usize, u32);

type PResult<T> = Result<T, Diagnostic>;

/// What follows an entry: the comments trailing it, the comments before the next entry
/// (or the closing bracket), and whether the container ended.
struct AfterEntry {
    trailing: Vec<Comment>,
    carry: Vec<Comment>,
    ended: bool,
}

impl<'a> Parser<'a> {
    fn span(&self) -> Span {
        Span::new(&self.file, self.line, self.col)
    }

    fn rest(&self) -> &'a str {
        &self.text[self.pos..]
    }

    fn peek(&self) -> Option<char> {
        self.rest().chars().next()
    }

    /// Moves over `bytes` bytes of text (counting lines and columns).
    fn advance(&mut self, bytes: usize) {
        let end = (self.pos + bytes).min(self.text.len());
        // Columns count characters: every byte but UTF-8 continuation bytes starts one.
        for &b in &self.text.as_bytes()[self.pos..end] {
            if b == b'\n' {
                self.line += 1;
                self.col = 1;
            } else if b & 0xC0 != 0x80 {
                self.col += 1;
            }
        }
        self.pos = end;
    }

    /// Moves over a token of `bytes` bytes.
    fn token(&mut self, bytes: usize) {
        self.advance(bytes);
        self.nl = 0;
        self.seen_token = true;
    }

    fn mark(&self) -> Mark {
        (self.pos, self.line, self.col, self.pending.len(), self.nl)
    }

    fn reset(&mut self, m: Mark) {
        (self.pos, self.line, self.col) = (m.0, m.1, m.2);
        self.pending.truncate(m.3);
        self.nl = m.4;
    }

    fn describe_here(&self) -> String {
        match self.peek() {
            None => "end of file".into(),
            Some(c) => lex::describe_char(c),
        }
    }

    fn err<T>(&self, message: impl Into<String>, hint: &str) -> PResult<T> {
        Err(Diagnostic::new(self.span(), message).hint(hint))
    }

    /// A lexical error at `at` bytes past the current position.
    fn lex_err<T>(&mut self, e: lex::LexError) -> PResult<T> {
        self.advance(e.at);
        self.err(e.message, e.hint)
    }

    fn push_comment(&mut self, len: usize) {
        let text = self.rest()[..len].trim_end().to_string();
        self.pending.push(Comment {
            text,
            own_line: self.nl > 0 || !self.seen_token,
            blank_before: self.nl >= 2,
        });
        self.advance(len);
        self.nl = 0;
    }

    /// Skips whitespace, collecting comments into `pending`.
    fn skip_ws(&mut self) -> PResult<()> {
        loop {
            // ASCII whitespace byte by byte; the rest of RON's whitespace and comments below.
            while let Some(&b) = self.text.as_bytes().get(self.pos) {
                match b {
                    b'\n' => {
                        self.nl += 1;
                        self.line += 1;
                        self.col = 1;
                    }
                    b' ' | b'\t' | b'\r' | 0x0B | 0x0C => self.col += 1,
                    _ => break,
                }
                self.pos += 1;
            }
            let rest = self.rest();
            match rest.chars().next() {
                Some(c) if lex::is_whitespace(c) => {
                    if c == '\n' {
                        self.nl += 1;
                    }
                    self.advance(c.len_utf8());
                }
                Some('/') if rest.starts_with("//") => self.push_comment(rest.find('\n').unwrap_or(rest.len())),
                Some('/') if rest.starts_with("/*") => {
                    let mut depth = 0usize;
                    let mut i = 0;
                    let len = loop {
                        match rest[i..].find(['/', '*']).map(|k| i + k) {
                            None => {
                                return self.err("unterminated block comment", "close the comment with `*/`");
                            }
                            Some(k) if rest[k..].starts_with("/*") => {
                                depth += 1;
                                i = k + 2;
                            }
                            Some(k) if rest[k..].starts_with("*/") => {
                                depth -= 1;
                                i = k + 2;
                                if depth == 0 {
                                    break i;
                                }
                            }
                            Some(k) => i = k + 1,
                        }
                    };
                    self.push_comment(len);
                }
                _ => return Ok(()),
            }
        }
    }

    /// `#![enable(ext, ..)]` or `#![type = ".."]` / `#![schema = ".."]` (RON's
    /// attributes), returned in canonical spelling.
    fn attribute(&mut self) -> PResult<String> {
        let hint = "RON's header is #![enable(implicit_some, ..)]";
        for c in ['#', '!', '['] {
            self.skip_ws()?;
            if self.peek() != Some(c) {
                return self.err(
                    format!("expected `{c}` in a `#![..]` attribute, found {}", self.describe_here()),
                    hint,
                );
            }
            self.token(1);
        }
        self.skip_ws()?;
        let Some((word, len)) = lex::ident(self.rest()) else {
            return self.err(
                format!(
                    "expected `enable` in a `#![..]` attribute, found {}",
                    self.describe_here()
                ),
                hint,
            );
        };
        let word = word.to_string();
        self.token(len);
        self.skip_ws()?;
        let text = match word.as_str() {
            "enable" => {
                if self.peek() != Some('(') {
                    return self.err("expected `(` after `#![enable`", hint);
                }
                self.token(1);
                let mut exts = Vec::new();
                loop {
                    self.skip_ws()?;
                    let Some((ext, len)) = lex::ident(self.rest()) else {
                        return self.err(
                            format!("expected an extension name, found {}", self.describe_here()),
                            hint,
                        );
                    };
                    const KNOWN: [&str; 4] = [
                        "unwrap_newtypes",
                        "implicit_some",
                        "unwrap_variant_newtypes",
                        "explicit_struct_names",
                    ];
                    if !KNOWN.contains(&ext) {
                        return self.err(
                            format!("unknown RON extension `{ext}`"),
                            "RON's extensions are unwrap_newtypes, implicit_some, unwrap_variant_newtypes, explicit_struct_names",
                        );
                    }
                    exts.push(ext.to_string());
                    self.token(len);
                    self.skip_ws()?;
                    if self.peek() == Some(',') {
                        self.token(1);
                        self.skip_ws()?;
                        if self.rest().starts_with(lex::is_ident_continue) {
                            continue;
                        }
                    }
                    break;
                }
                if self.peek() != Some(')') {
                    return self.err(
                        format!("expected `)` in `#![enable(..)]`, found {}", self.describe_here()),
                        hint,
                    );
                }
                self.token(1);
                format!("#![enable({})]", exts.join(", "))
            }
            "type" | "schema" => {
                if self.peek() != Some('=') {
                    return self.err(format!("expected `=` after `#![{word}`"), "write #![type = \"name\"]");
                }
                self.token(1);
                self.skip_ws()?;
                let (value, _, len) = match lex::string(self.rest()) {
                    Ok(v) if self.peek() == Some('"') => v,
                    Ok(_) => return self.err("expected a string", "write #![type = \"name\"]"),
                    Err(e) => return self.lex_err(e),
                };
                self.token(len);
                let mut q = String::new();
                super::doc_print::quote(&mut q, &value);
                format!("#![{word} = {q}]")
            }
            _ => return self.err(format!("unknown attribute `#![{word}`"), hint),
        };
        self.skip_ws()?;
        if self.peek() != Some(']') {
            return self.err(
                format!("expected `]` to close the attribute, found {}", self.describe_here()),
                hint,
            );
        }
        self.token(1);
        Ok(text)
    }

    fn value(&mut self) -> PResult<Node> {
        self.skip_ws()?;
        let mut leading = std::mem::take(&mut self.pending);
        let blank = self.nl >= 2;
        let span = self.span();
        let rest = self.rest();
        let Some(c) = rest.chars().next() else {
            return self.err(
                "unexpected end of file, expected a value",
                "close every `(`, `[` and `{`",
            );
        };
        let (kind, inner_end) = match c {
            '(' => self.group(None)?,
            '[' => self.list()?,
            '{' => self.map()?,
            '"' => match lex::string(rest) {
                Ok((value, exact, len)) => {
                    self.token(len);
                    (Ast::Str { value, exact }, Vec::new())
                }
                Err(e) => return self.lex_err(e),
            },
            'r' if rest.starts_with("r\"") || rest.starts_with("r#\"") || rest.starts_with("r##") => {
                match lex::raw_string(rest) {
                    Ok((value, len)) => {
                        self.token(len);
                        let exact = !value.contains('\n');
                        (Ast::Str { value, exact }, Vec::new())
                    }
                    Err(e) => return self.lex_err(e),
                }
            }
            '0'..='9' | '+' | '-' | '.' => match lex::number(rest) {
                Ok((n, len)) => {
                    if let Some((w, _)) = lex::ident(&rest[len..]) {
                        self.advance(len);
                        return self.err(
                            format!("unexpected `{w}` after a number"),
                            "write numbers like 1, -0.5, 0x1F, 2.5e-3 or 24i64",
                        );
                    }
                    self.token(len);
                    let kind = match n {
                        lex::Number::Int(i) => Ast::Int(i),
                        lex::Number::Float(x) => Ast::Float(x),
                    };
                    (kind, Vec::new())
                }
                Err(e) => return self.lex_err(e),
            },
            '\'' => {
                return self.err(
                    "character literals are not used in rig files",
                    "write text in double quotes: \"name\"",
                )
            }
            'b' if ["b\"", "b'", "br\"", "br#"].iter().any(|p| rest.starts_with(p)) => {
                return self.err(
                    "byte strings are not used in rig files",
                    "write text in double quotes: \"name\"",
                )
            }
            _ => match lex::ident(rest) {
                Some((name, len)) => {
                    let raw = rest.starts_with("r#");
                    let name = name.to_string();
                    self.token(len);
                    let m = self.mark();
                    self.skip_ws()?;
                    // `true`, `false` and `None` are values of their own in RON, never
                    // the name of a struct; `Some` always takes one value in `( )`.
                    let keyword = !raw && matches!(name.as_str(), "true" | "false" | "None");
                    if self.peek() == Some('(') && !keyword {
                        leading.append(&mut self.pending);
                        let (kind, inner_end) = self.group(Some(name))?;
                        if matches!(&kind, Ast::Group { name: Some(n), items } if !raw && n == "Some"
                            && (items.len() != 1 || items[0].key.is_some()))
                        {
                            return Err(
                                Diagnostic::new(span, "`Some(..)` holds exactly one value").hint("write Some(value)")
                            );
                        }
                        (kind, inner_end)
                    } else if !raw && name == "Some" {
                        return Err(
                            Diagnostic::new(span, "`Some` needs a value in parentheses").hint("write Some(value)")
                        );
                    } else {
                        self.reset(m);
                        let kind = match name.as_str() {
                            "true" if !raw => Ast::Bool(true),
                            "false" if !raw => Ast::Bool(false),
                            _ => Ast::Ident(name),
                        };
                        (kind, Vec::new())
                    }
                }
                None => {
                    return self.err(
                        format!("expected a value, found {}", self.describe_here()),
                        "values are numbers, \"strings\", names, (tuples), [lists] or {maps}",
                    )
                }
            },
        };
        let mut node = Node::new(span, kind);
        if blank || !leading.is_empty() || !inner_end.is_empty() {
            let t = node.trivia_mut();
            t.blank_before = blank;
            t.leading = leading;
            t.inner_end = inner_end;
        }
        Ok(node)
    }

    fn enter(&mut self) -> PResult<()> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return self.err(
                format!("values are nested more than {MAX_DEPTH} levels deep"),
                "rig values need only a few levels of nesting; check for unbalanced brackets",
            );
        }
        Ok(())
    }

    /// Reads the opening bracket; returns the comments before the first entry.
    fn open(&mut self) -> PResult<Vec<Comment>> {
        self.enter()?;
        self.token(1);
        self.skip_ws()?;
        Ok(std::mem::take(&mut self.pending))
    }

    /// Attaches an entry's leading comments (before the ones read with its value),
    /// blank line and trailing comments to its value node.
    fn attach(node: &mut Node, mut leading: Vec<Comment>, blank: bool, trailing: Vec<Comment>) {
        if leading.is_empty() && !blank && trailing.is_empty() {
            return;
        }
        let t = node.trivia_mut();
        leading.append(&mut t.leading);
        t.leading = leading;
        t.blank_before |= blank;
        t.trailing = trailing;
    }

    /// After an entry: `,` continues, `close` ends. Splits the comments read on the way
    /// into those on the entry's line and those before what follows.
    fn after_entry(&mut self, close: char, what: &str) -> PResult<AfterEntry> {
        self.skip_ws()?;
        let mut carry = std::mem::take(&mut self.pending);
        let same_line = carry.iter().position(|c| c.own_line).unwrap_or(carry.len());
        let mut trailing: Vec<Comment> = carry.drain(..same_line).collect();
        match self.peek() {
            Some(',') => {
                self.token(1);
                self.skip_ws()?;
                let mut more = std::mem::take(&mut self.pending);
                if carry.is_empty() {
                    let same_line = more.iter().position(|c| c.own_line).unwrap_or(more.len());
                    trailing.extend(more.drain(..same_line));
                }
                carry.append(&mut more);
                let ended = self.peek() == Some(close);
                if ended {
                    self.token(1);
                }
                Ok(AfterEntry { trailing, carry, ended })
            }
            Some(c) if c == close => {
                self.token(1);
                Ok(AfterEntry {
                    trailing,
                    carry,
                    ended: true,
                })
            }
            None => self.err(
                format!("unexpected end of file inside {what}"),
                &format!("close it with `{close}`"),
            ),
            _ => self.err(
                format!("expected `,` or `{close}` in {what}, found {}", self.describe_here()),
                "separate entries with commas",
            ),
        }
    }

    /// Reads entries until `close`; `entry` reads one and returns it with the node that
    /// holds its trivia. Returns the comments before the closing bracket.
    fn entries<E>(
        &mut self,
        close: char,
        what: &str,
        out: &mut Vec<E>,
        mut entry: impl FnMut(&mut Self) -> PResult<E>,
        holder: fn(&mut E) -> &mut Node,
    ) -> PResult<Vec<Comment>> {
        let mut carry = self.open()?;
        if self.peek() == Some(close) {
            self.token(1);
            self.depth -= 1;
            return Ok(carry);
        }
        loop {
            let blank = self.nl >= 2;
            let mut e = entry(self)?;
            let after = self.after_entry(close, what)?;
            Self::attach(holder(&mut e), carry, blank, after.trailing);
            out.push(e);
            carry = after.carry;
            if after.ended {
                self.depth -= 1;
                // The tree is kept for as long as the document (`sinew fmt` reads its
                // comments): no spare capacity (a 3-tuple would keep room for 4).
                out.shrink_to_fit();
                return Ok(carry);
            }
        }
    }

    fn group(&mut self, name: Option<String>) -> PResult<(Ast, Vec<Comment>)> {
        let mut items = Vec::new();
        let inner_end = self.entries(
            ')',
            "a `( .. )` group",
            &mut items,
            |p| {
                // `name:` (but not `name::`) makes a named field.
                let mut key = None;
                if let Some((k, len)) = lex::ident(p.rest()) {
                    let m = p.mark();
                    let kspan = p.span();
                    let k = k.to_string();
                    p.token(len);
                    p.skip_ws()?;
                    if p.rest().starts_with(':') && !p.rest().starts_with("::") {
                        p.token(1);
                        key = Some((k, kspan));
                    } else {
                        p.reset(m);
                    }
                }
                Ok(Item { key, value: p.value()? })
            },
            |i| &mut i.value,
        )?;
        let named = items.iter().filter(|i| i.key.is_some()).count();
        if named != 0 && named != items.len() {
            let bad = items.iter().find(|i| i.key.is_none()).map(|i| i.value.span.clone());
            return Err(Diagnostic::new(
                bad.unwrap_or_else(|| self.span()),
                "this entry has no field name, but the others do",
            )
            .hint("write every entry of a struct as `name: value`"));
        }
        Ok((Ast::Group { name, items }, inner_end))
    }

    fn list(&mut self) -> PResult<(Ast, Vec<Comment>)> {
        let mut v = Vec::new();
        let inner_end = self.entries(']', "a `[ .. ]` list", &mut v, Self::value, |n| n)?;
        Ok((Ast::List(v), inner_end))
    }

    fn map(&mut self) -> PResult<(Ast, Vec<Comment>)> {
        let mut v = Vec::new();
        let inner_end = self.entries(
            '}',
            "a `{ .. }` map",
            &mut v,
            |p| {
                let mut k = p.value()?;
                p.skip_ws()?;
                if p.peek() != Some(':') {
                    return p.err(
                        format!("expected `:` after a map key, found {}", p.describe_here()),
                        "write map entries as `key: value`",
                    );
                }
                p.token(1);
                let mut val = p.value()?;
                // The key's comments (and the ones before the colon) lead the entry.
                if let Some(kt) = k.trivia.take() {
                    let mut leading = kt.leading;
                    leading.append(&mut val.trivia_mut().leading);
                    val.trivia_mut().leading = leading;
                    val.trivia_mut().blank_before |= kt.blank_before;
                }
                Ok((k, val))
            },
            |e| &mut e.1,
        )?;
        Ok((Ast::Map(v), inner_end))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(s: &str) -> Result<Node, Diagnostic> {
        parse(s, &Arc::new(PathBuf::from("t.ron")))
    }

    #[test]
    fn parses_values_with_positions() {
        let n = p("Rig(\n  a: (1, -2.5e1, \"x\\n\"),\n  b: [true, xzy, {0: r\"q\"}],\n)").unwrap();
        let Ast::Group { name, items } = &n.kind else { panic!() };
        assert_eq!(name.as_deref(), Some("Rig"));
        assert_eq!(items[0].key.as_ref().unwrap().1.line, 2);
        assert_eq!(items[0].value.span.col, 6);
        let t = items[0].value.kind.tuple_items().unwrap();
        assert_eq!(t[1].kind, Ast::Float(-25.0));
        assert_eq!(items[1].value.span.line, 3);
    }

    #[test]
    fn spans_and_nodes_stay_small() {
        // A loaded 100,000-joint chain holds some 18 spans and 10 nodes per joint (syntax
        // tree, document, flat list): a span is a thin file handle and a position.
        assert_eq!(std::mem::size_of::<Span>(), 16);
        assert!(std::mem::size_of::<Node>() <= 80, "{}", std::mem::size_of::<Node>());
        assert!(std::mem::size_of::<Item>() <= 120, "{}", std::mem::size_of::<Item>());
    }

    #[test]
    fn errors_point_at_the_problem() {
        let e = p("(a: 1,\n b: [1 2])").unwrap_err();
        assert_eq!((e.span.line, e.span.col), (2, 8));
        assert!(e.message.contains("expected `,` or `]`"), "{}", e.message);
        let e = p("(a: \"abc").unwrap_err();
        assert_eq!((e.span.line, e.span.col), (1, 5));
        let e = p(&"[".repeat(500)).unwrap_err();
        assert!(e.message.contains("nested"));
        assert!(p("(a: 1) x").is_err());
        assert!(p("(a: 1, 2)").is_err());
        assert!(p("(a: nan)").is_ok()); // an identifier; the typed stage rejects it
        assert!(p("(a: -nan)").is_err());
        assert!(p("1e999").is_err());
    }
}
