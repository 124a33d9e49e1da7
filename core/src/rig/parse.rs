//! A small RON parser that keeps the position of every value.
//!
//! It reads the RON subset rig files use: numbers, `true`/`false`, strings
//! (with escapes and raw strings), identifiers, tuples and structs
//! (`(1, 2)`, `(a: 1)`, `Name(a: 1)`), lists `[..]` and maps `{k: v}`, with
//! `//` and `/* */` comments and trailing commas. Every value carries its
//! [`Span`], so later stages can point at the exact line and column. Nesting
//! is limited (no stack overflow on hostile input) and parsing never panics.

use std::path::Path;
use std::sync::Arc;

use super::diag::{Diagnostic, Span};

/// Deepest nesting accepted.
pub const MAX_DEPTH: usize = 96;

/// A parsed value and where it starts.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// Where the value starts.
    pub span: Span,
    /// The value.
    pub kind: Ast,
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

    /// The positional items of an unnamed tuple.
    pub fn tuple_items(&self) -> Option<Vec<&Node>> {
        match self {
            Ast::Group { name: None, items } if items.iter().all(|i| i.key.is_none()) => {
                Some(items.iter().map(|i| &i.value).collect())
            }
            _ => None,
        }
    }
}

/// Parses a whole file: one value, then only whitespace and comments.
pub fn parse(text: &str, file: &Arc<Path>) -> Result<Node, Diagnostic> {
    let mut p = Parser {
        src: text.as_bytes(),
        text,
        pos: 0,
        line: 1,
        col: 1,
        file: file.clone(),
        depth: 0,
    };
    p.skip_ws()?;
    // RON's optional `#![enable(...)]` header.
    while p.peek() == Some(b'#') {
        while let Some(c) = p.peek() {
            p.bump();
            if c == b'\n' {
                break;
            }
        }
        p.skip_ws()?;
    }
    if p.peek().is_none() {
        return Err(Diagnostic::new(p.span(), "the file is empty")
            .hint("a rig file holds one `Rig(name: \"..\", nodes: {..})` value"));
    }
    let v = p.value()?;
    p.skip_ws()?;
    if p.peek().is_some() {
        return Err(Diagnostic::new(
            p.span(),
            format!("unexpected {} after the end of the rig", p.describe_here()),
        )
        .hint("a rig file holds exactly one value; check for an extra closing bracket"));
    }
    Ok(v)
}

struct Parser<'a> {
    src: &'a [u8],
    text: &'a str,
    pos: usize,
    line: u32,
    col: u32,
    file: Arc<Path>,
    depth: usize,
}

type PResult<T> = Result<T, Diagnostic>;

fn is_ident_start(c: u8) -> bool {
    c.is_ascii_alphabetic() || c == b'_'
}

fn is_ident_char(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

impl<'a> Parser<'a> {
    fn span(&self) -> Span {
        Span::new(&self.file, self.line, self.col)
    }

    fn peek(&self) -> Option<u8> {
        self.src.get(self.pos).copied()
    }

    fn peek_at(&self, k: usize) -> Option<u8> {
        self.src.get(self.pos + k).copied()
    }

    fn bump(&mut self) {
        if let Some(&c) = self.src.get(self.pos) {
            self.pos += 1;
            if c == b'\n' {
                self.line += 1;
                self.col = 1;
            } else if c & 0xC0 != 0x80 {
                self.col += 1;
            }
        }
    }

    fn describe_here(&self) -> String {
        match self.text.get(self.pos..).and_then(|s| s.chars().next()) {
            None => "end of file".into(),
            Some(c) => format!("`{c}`"),
        }
    }

    fn err<T>(&self, message: impl Into<String>, hint: &str) -> PResult<T> {
        Err(Diagnostic::new(self.span(), message).hint(hint))
    }

    fn skip_ws(&mut self) -> PResult<()> {
        loop {
            match self.peek() {
                Some(c) if c.is_ascii_whitespace() => self.bump(),
                Some(b'/') if self.peek_at(1) == Some(b'/') => {
                    while let Some(c) = self.peek() {
                        if c == b'\n' {
                            break;
                        }
                        self.bump();
                    }
                }
                Some(b'/') if self.peek_at(1) == Some(b'*') => {
                    let start = self.span();
                    self.bump();
                    self.bump();
                    let mut depth = 1usize;
                    loop {
                        match (self.peek(), self.peek_at(1)) {
                            (None, _) => {
                                return Err(Diagnostic::new(start, "unterminated block comment")
                                    .hint("close the comment with `*/`"))
                            }
                            (Some(b'*'), Some(b'/')) => {
                                self.bump();
                                self.bump();
                                depth -= 1;
                                if depth == 0 {
                                    break;
                                }
                            }
                            (Some(b'/'), Some(b'*')) => {
                                self.bump();
                                self.bump();
                                depth += 1;
                            }
                            _ => self.bump(),
                        }
                    }
                }
                _ => return Ok(()),
            }
        }
    }

    fn value(&mut self) -> PResult<Node> {
        self.skip_ws()?;
        let span = self.span();
        let Some(c) = self.peek() else {
            return self.err(
                "unexpected end of file, expected a value",
                "close every `(`, `[` and `{`",
            );
        };
        let kind = match c {
            b'(' => self.group(None)?,
            b'[' => self.list()?,
            b'{' => self.map()?,
            b'"' => self.string()?,
            b'r' if matches!(self.peek_at(1), Some(b'"') | Some(b'#')) => self.raw_string()?,
            b'-' | b'+' | b'0'..=b'9' | b'.' => self.number()?,
            c if is_ident_start(c) => {
                let name = self.ident();
                let save = (self.pos, self.line, self.col);
                self.skip_ws()?;
                if self.peek() == Some(b'(') {
                    self.group(Some(name))?
                } else {
                    (self.pos, self.line, self.col) = save;
                    match name.as_str() {
                        "true" => Ast::Bool(true),
                        "false" => Ast::Bool(false),
                        _ => Ast::Ident(name),
                    }
                }
            }
            b'\'' => {
                return self.err(
                    "character literals are not used in rig files",
                    "write text in double quotes: \"name\"",
                )
            }
            _ => {
                return self.err(
                    format!("expected a value, found {}", self.describe_here()),
                    "values are numbers, \"strings\", names, (tuples), [lists] or {maps}",
                )
            }
        };
        Ok(Node { span, kind })
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

    fn ident(&mut self) -> String {
        let start = self.pos;
        while self.peek().is_some_and(is_ident_char) {
            self.bump();
        }
        self.text[start..self.pos].to_string()
    }

    /// After a value in a sequence: `,` continues, `close` ends; returns whether it ended.
    fn sep(&mut self, close: u8, what: &str) -> PResult<bool> {
        self.skip_ws()?;
        match self.peek() {
            Some(b',') => {
                self.bump();
                self.skip_ws()?;
                if self.peek() == Some(close) {
                    self.bump();
                    return Ok(true);
                }
                Ok(false)
            }
            Some(c) if c == close => {
                self.bump();
                Ok(true)
            }
            None => self.err(
                format!("unexpected end of file inside {what}"),
                &format!("close it with `{}`", close as char),
            ),
            _ => self.err(
                format!(
                    "expected `,` or `{}` in {what}, found {}",
                    close as char,
                    self.describe_here()
                ),
                "separate entries with commas",
            ),
        }
    }

    fn group(&mut self, name: Option<String>) -> PResult<Ast> {
        self.enter()?;
        self.bump(); // (
        let mut items = Vec::new();
        self.skip_ws()?;
        if self.peek() == Some(b')') {
            self.bump();
            self.depth -= 1;
            return Ok(Ast::Group { name, items });
        }
        loop {
            self.skip_ws()?;
            // `name:` (but not `name::`) makes a named field.
            let mut key = None;
            if self.peek().is_some_and(is_ident_start) {
                let save = (self.pos, self.line, self.col);
                let kspan = self.span();
                let k = self.ident();
                self.skip_ws()?;
                if self.peek() == Some(b':') && self.peek_at(1) != Some(b':') {
                    self.bump();
                    key = Some((k, kspan));
                } else {
                    (self.pos, self.line, self.col) = save;
                }
            }
            let value = self.value()?;
            items.push(Item { key, value });
            if self.sep(b')', "a `( .. )` group")? {
                break;
            }
        }
        let named = items.iter().filter(|i| i.key.is_some()).count();
        if named != 0 && named != items.len() {
            let bad = items.iter().find(|i| i.key.is_none()).map(|i| i.value.span.clone());
            return Err(Diagnostic::new(
                bad.unwrap_or_else(|| self.span()),
                "this entry has no field name, but the others do",
            )
            .hint("write every entry of a struct as `name: value`"));
        }
        self.depth -= 1;
        Ok(Ast::Group { name, items })
    }

    fn list(&mut self) -> PResult<Ast> {
        self.enter()?;
        self.bump();
        let mut v = Vec::new();
        self.skip_ws()?;
        if self.peek() == Some(b']') {
            self.bump();
        } else {
            loop {
                v.push(self.value()?);
                if self.sep(b']', "a `[ .. ]` list")? {
                    break;
                }
            }
        }
        self.depth -= 1;
        Ok(Ast::List(v))
    }

    fn map(&mut self) -> PResult<Ast> {
        self.enter()?;
        self.bump();
        let mut v = Vec::new();
        self.skip_ws()?;
        if self.peek() == Some(b'}') {
            self.bump();
        } else {
            loop {
                let k = self.value()?;
                self.skip_ws()?;
                if self.peek() != Some(b':') {
                    return self.err(
                        format!("expected `:` after a map key, found {}", self.describe_here()),
                        "write map entries as `key: value`",
                    );
                }
                self.bump();
                let val = self.value()?;
                v.push((k, val));
                if self.sep(b'}', "a `{ .. }` map")? {
                    break;
                }
            }
        }
        self.depth -= 1;
        Ok(Ast::Map(v))
    }

    fn string(&mut self) -> PResult<Ast> {
        let start = self.span();
        self.bump();
        let mut s = String::new();
        let mut exact = true;
        loop {
            let Some(c) = self.peek() else {
                return Err(Diagnostic::new(start, "unterminated string").hint("close the string with `\"`"));
            };
            match c {
                b'"' => {
                    self.bump();
                    break;
                }
                b'\\' => {
                    exact = false;
                    self.bump();
                    let esc = self.peek();
                    self.bump();
                    match esc {
                        Some(b'n') => s.push('\n'),
                        Some(b't') => s.push('\t'),
                        Some(b'r') => s.push('\r'),
                        Some(b'0') => s.push('\0'),
                        Some(b'\\') => s.push('\\'),
                        Some(b'"') => s.push('"'),
                        Some(b'\'') => s.push('\''),
                        Some(b'u') if self.peek() == Some(b'{') => {
                            self.bump();
                            let st = self.pos;
                            while self.peek().is_some_and(|c| c.is_ascii_hexdigit()) {
                                self.bump();
                            }
                            let hex = &self.text[st..self.pos];
                            if self.peek() != Some(b'}') {
                                return self.err("malformed `\\u{..}` escape", "write a unicode escape as \\u{41}");
                            }
                            self.bump();
                            match u32::from_str_radix(hex, 16).ok().and_then(char::from_u32) {
                                Some(ch) => s.push(ch),
                                None => return self.err("invalid unicode escape", "write a unicode escape as \\u{41}"),
                            }
                        }
                        _ => return self.err("unknown escape in string", "escapes are \\n \\t \\\\ \\\" \\u{..}"),
                    }
                }
                _ => {
                    let st = self.pos;
                    self.bump();
                    while self.peek().is_some_and(|c| c & 0xC0 == 0x80) {
                        self.bump();
                    }
                    if c == b'\n' {
                        exact = false;
                    }
                    s.push_str(&self.text[st..self.pos]);
                }
            }
        }
        Ok(Ast::Str { value: s, exact })
    }

    fn raw_string(&mut self) -> PResult<Ast> {
        let start = self.span();
        self.bump(); // r
        let mut hashes = 0;
        while self.peek() == Some(b'#') {
            hashes += 1;
            self.bump();
        }
        if self.peek() != Some(b'"') {
            return self.err("malformed raw string", "write raw strings as r\"..\" or r#\"..\"#");
        }
        self.bump();
        let st = self.pos;
        loop {
            match self.peek() {
                None => return Err(Diagnostic::new(start, "unterminated raw string").hint("close it with `\"`")),
                Some(b'"') if (1..=hashes).all(|k| self.peek_at(k) == Some(b'#')) => {
                    let s = self.text[st..self.pos].to_string();
                    for _ in 0..=hashes {
                        self.bump();
                    }
                    let exact = !s.contains('\n');
                    return Ok(Ast::Str { value: s, exact });
                }
                _ => self.bump(),
            }
        }
    }

    fn number(&mut self) -> PResult<Ast> {
        let st = self.pos;
        if matches!(self.peek(), Some(b'-') | Some(b'+')) {
            self.bump();
        }
        if self.peek().is_some_and(is_ident_start) {
            let word = self.ident();
            return match word.as_str() {
                "inf" | "NaN" | "nan" | "infinity" => self.err("numbers must be finite", "give a finite number"),
                _ => self.err(
                    format!("expected a number after the sign, found `{word}`"),
                    "write numbers like -1.5",
                ),
            };
        }
        let mut is_float = false;
        let digits = |p: &mut Self| {
            let s = p.pos;
            while p.peek().is_some_and(|c| c.is_ascii_digit() || c == b'_') {
                p.bump();
            }
            p.pos > s
        };
        let int_digits = digits(self);
        if self.peek() == Some(b'.') && self.peek_at(1).is_some_and(|c| c.is_ascii_digit())
            || (self.peek() == Some(b'.') && int_digits)
        {
            is_float = true;
            self.bump();
            digits(self);
        } else if !int_digits {
            return self.err("expected a number", "write numbers like 1, -0.5 or 2.5e-3");
        }
        if matches!(self.peek(), Some(b'e') | Some(b'E')) {
            is_float = true;
            self.bump();
            if matches!(self.peek(), Some(b'-') | Some(b'+')) {
                self.bump();
            }
            if !digits(self) {
                return self.err("malformed exponent", "write exponents like 2.5e-3");
            }
        }
        if self.peek().is_some_and(is_ident_char) {
            return self.err(
                format!("unexpected {} in a number", self.describe_here()),
                "write numbers like 1, -0.5 or 2.5e-3 (no suffixes)",
            );
        }
        let text: String = self.text[st..self.pos].chars().filter(|&c| c != '_').collect();
        let text = text.strip_prefix('+').unwrap_or(&text).to_string();
        if !is_float {
            if let Ok(i) = text.parse::<i64>() {
                return Ok(Ast::Int(i));
            }
        }
        match text.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(Ast::Float(x)),
            _ => Err(Diagnostic::new(
                Span::new(&self.file, self.line, self.col),
                format!("`{text}` is not a finite number"),
            )
            .hint("give a number within the range of f64")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(s: &str) -> Result<Node, Diagnostic> {
        parse(s, &Arc::from(Path::new("t.ron")))
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
