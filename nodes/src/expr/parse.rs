//! The expression language's tokens and syntax tree: a recursive-descent
//! parser that keeps each node's position (1-based line and column inside
//! the expression text) for error messages.

use std::fmt;

/// A position inside the expression text.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Pos {
    /// Byte offset.
    pub offset: usize,
    /// 1-based line.
    pub line: u32,
    /// 1-based column, in characters.
    pub col: u32,
}

/// An error in an expression: where, what, and how to fix it.
#[derive(Clone, Debug, PartialEq)]
pub struct ExprError {
    /// Where the problem is.
    pub pos: Pos,
    /// What is wrong.
    pub message: String,
    /// How to fix it.
    pub hint: Option<String>,
}

impl ExprError {
    pub(crate) fn new(pos: Pos, message: impl Into<String>) -> Self {
        ExprError {
            pos,
            message: message.into(),
            hint: None,
        }
    }

    pub(crate) fn hint(mut self, hint: impl Into<String>) -> Self {
        self.hint = Some(hint.into());
        self
    }
}

impl fmt::Display for ExprError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "expression:{}:{}: {}", self.pos.line, self.pos.col, self.message)?;
        if let Some(h) = &self.hint {
            write!(f, " ({h})")?;
        }
        Ok(())
    }
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Num(f64),
    Ident(String),
    Op(&'static str),
    End,
}

/// The operators, longest first (so `<=` wins over `<`).
const OPS: [&str; 25] = [
    "<<", ">>", "<=", ">=", "==", "!=", "&&", "||", "+", "-", "*", "/", "%", "^", "<", ">", "!", "=", "(", ")", "{",
    "}", ",", ";", ".",
];
pub(crate) const MORE_OPS: [&str; 4] = ["[", "]", "?", ":"];

fn lex(text: &str) -> Result<Vec<(Tok, Pos)>, ExprError> {
    let mut out = Vec::new();
    let (mut i, mut line, mut col) = (0usize, 1u32, 1u32);
    let b = text.as_bytes();
    while i < b.len() {
        let pos = Pos { offset: i, line, col };
        let c = b[i];
        if c == b'\n' {
            i += 1;
            line += 1;
            col = 1;
            continue;
        }
        if c.is_ascii_whitespace() {
            i += 1;
            col += 1;
            continue;
        }
        if c == b'/' && b.get(i + 1) == Some(&b'/') {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        if c.is_ascii_digit() || (c == b'.' && b.get(i + 1).is_some_and(|d| d.is_ascii_digit())) {
            let st = i;
            while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
                i += 1;
            }
            if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
                let mut j = i + 1;
                if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
                    j += 1;
                }
                if j < b.len() && b[j].is_ascii_digit() {
                    i = j;
                    while i < b.len() && b[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            let s = &text[st..i];
            let v: f64 = s.parse().map_err(|_| {
                ExprError::new(pos, format!("malformed number `{s}`")).hint("write numbers as 1, 0.5 or 2e-3")
            })?;
            out.push((Tok::Num(v), pos));
            col += (i - st) as u32;
            continue;
        }
        if c.is_ascii_alphabetic() || c == b'_' {
            let st = i;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            out.push((Tok::Ident(text[st..i].to_string()), pos));
            col += (i - st) as u32;
            continue;
        }
        let op = OPS
            .iter()
            .chain(MORE_OPS.iter())
            .find(|op| text[i..].starts_with(**op))
            .copied();
        match op {
            Some(op) => {
                out.push((Tok::Op(op), pos));
                i += op.len();
                col += op.len() as u32;
            }
            None => {
                let ch = text[i..].chars().next().unwrap_or('?');
                return Err(ExprError::new(pos, format!("unexpected character `{ch}`"))
                    .hint("expressions use numbers, names, + - * / % ^, comparisons, && || ! and ( ) { } < < >>"));
            }
        }
    }
    out.push((
        Tok::End,
        Pos {
            offset: b.len(),
            line,
            col,
        },
    ));
    Ok(out)
}

/// A binary operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `%`
    Mod,
    /// `^` (power; cross product of vectors)
    Pow,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
    /// `==`
    Eq,
    /// `!=`
    Ne,
    /// `&&`
    And,
    /// `||`
    Or,
}

/// A plug an expression reads or writes.
#[derive(Clone, Debug, PartialEq)]
pub enum Port {
    /// `input[k]` / `output[k]` (or a name declared with `in` / `out`).
    Element(usize),
    /// A custom attribute of the node, by name (resolved when compiling).
    Attr(String, Pos),
}

/// An expression node.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    /// A number literal.
    Num(f64),
    /// `time` (seconds) or `frame`.
    Time(bool),
    /// `in.name` or `input[k]`.
    Input(Port),
    /// A local variable by name.
    Local(String),
    /// `-e`
    Neg(Box<Node>),
    /// `!e`
    Not(Box<Node>),
    /// `a op b`
    Bin(BinOp, Box<Node>, Box<Node>),
    /// `c ? a : b`
    Cond(Box<Node>, Box<Node>, Box<Node>),
    /// `name(args)`
    Call(String, Vec<Node>),
    /// `<<x, y, z>>`
    Vector(Box<[Node; 3]>),
    /// `e.x`, `e.y`, `e.z`
    Comp(Box<Node>, u8),
}

/// An expression with its position.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// The expression.
    pub expr: Expr,
    /// Where it starts.
    pub pos: Pos,
}

/// Where an assignment writes.
#[derive(Clone, Debug, PartialEq)]
pub enum Target {
    /// `out.name` or `output[k]`.
    Output(Port),
    /// A local variable.
    Local(String),
}

/// A statement.
#[derive(Clone, Debug, PartialEq)]
pub enum Stmt {
    /// `target = value`
    Assign(Target, Node, Pos),
    /// `if (cond) { .. } else { .. }`
    If(Node, Vec<Stmt>, Vec<Stmt>),
}

/// A parsed expression program: its statements and declared names.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Program {
    /// The statements in order.
    pub stmts: Vec<Stmt>,
    /// `in` names, by input index.
    pub inputs: Vec<String>,
    /// `out` names, by output index.
    pub outputs: Vec<String>,
}

struct Parser {
    toks: Vec<(Tok, Pos)>,
    i: usize,
    prog: Program,
}

/// Most elements `input[k]`/`output[k]` an expression may address (k < this).
pub const MAX_PORTS: usize = 64;

/// Parses an expression program.
pub fn parse(text: &str) -> Result<Program, ExprError> {
    let mut p = Parser {
        toks: lex(text)?,
        i: 0,
        prog: Program::default(),
    };
    let mut stmts = Vec::new();
    while !p.at_end() {
        if p.eat_op(";") {
            continue;
        }
        if let Some(dir) = p.declaration() {
            p.declare(dir)?;
            continue;
        }
        stmts.push(p.stmt()?);
    }
    p.prog.stmts = stmts;
    Ok(p.prog)
}

const KEYWORDS: [&str; 8] = ["in", "out", "input", "output", "if", "else", "time", "frame"];

impl Parser {
    fn peek(&self) -> &Tok {
        &self.toks[self.i.min(self.toks.len() - 1)].0
    }
    fn pos(&self) -> Pos {
        self.toks[self.i.min(self.toks.len() - 1)].1
    }
    fn at_end(&self) -> bool {
        *self.peek() == Tok::End
    }
    fn bump(&mut self) -> Tok {
        let t = self.peek().clone();
        self.i = (self.i + 1).min(self.toks.len() - 1);
        t
    }
    fn eat_op(&mut self, op: &str) -> bool {
        if matches!(self.peek(), Tok::Op(o) if *o == op) {
            self.bump();
            true
        } else {
            false
        }
    }
    fn expect_op(&mut self, op: &str, what: &str) -> Result<(), ExprError> {
        if self.eat_op(op) {
            Ok(())
        } else {
            Err(self.unexpected(&format!("`{op}` {what}")))
        }
    }
    fn unexpected(&self, wanted: &str) -> ExprError {
        let found = match self.peek() {
            Tok::Num(v) => format!("number {v}"),
            Tok::Ident(s) => format!("`{s}`"),
            Tok::Op(o) => format!("`{o}`"),
            Tok::End => "the end of the expression".to_string(),
        };
        ExprError::new(self.pos(), format!("expected {wanted}, found {found}"))
    }
    fn ident(&mut self, what: &str) -> Result<(String, Pos), ExprError> {
        let (pos, at) = (self.pos(), self.i);
        match self.bump() {
            Tok::Ident(s) => Ok((s, pos)),
            _ => {
                self.i = at;
                Err(self.unexpected(what))
            }
        }
    }

    /// `in a, b` / `out x` at the start of a statement: the direction, or `None`.
    fn declaration(&self) -> Option<bool> {
        let next_is_name = matches!(self.toks.get(self.i + 1), Some((Tok::Ident(_), _)));
        match self.peek() {
            Tok::Ident(s) if s == "in" && next_is_name => Some(true),
            Tok::Ident(s) if s == "out" && next_is_name => Some(false),
            _ => None,
        }
    }

    fn declare(&mut self, input: bool) -> Result<(), ExprError> {
        self.bump();
        loop {
            let (name, pos) = self.ident("a name to declare")?;
            if KEYWORDS.contains(&name.as_str()) || super::code::is_function(&name) {
                return Err(ExprError::new(pos, format!("`{name}` is a reserved word")).hint("pick another name"));
            }
            let list = if input {
                &mut self.prog.inputs
            } else {
                &mut self.prog.outputs
            };
            if list.contains(&name) {
                return Err(ExprError::new(pos, format!("`{name}` is declared twice")));
            }
            if list.len() >= MAX_PORTS {
                return Err(ExprError::new(pos, format!("more than {MAX_PORTS} names declared")));
            }
            list.push(name);
            if !self.eat_op(",") {
                return Ok(());
            }
        }
    }

    fn body(&mut self) -> Result<Vec<Stmt>, ExprError> {
        if self.eat_op("{") {
            let mut v = Vec::new();
            while !self.eat_op("}") {
                if self.at_end() {
                    return Err(self.unexpected("`}` to close the block"));
                }
                if self.eat_op(";") {
                    continue;
                }
                v.push(self.stmt()?);
            }
            Ok(v)
        } else {
            Ok(vec![self.stmt()?])
        }
    }

    fn stmt(&mut self) -> Result<Stmt, ExprError> {
        let pos = self.pos();
        if matches!(self.peek(), Tok::Ident(s) if s == "if") {
            self.bump();
            self.expect_op("(", "after `if`")?;
            let cond = self.expr()?;
            self.expect_op(")", "to close the condition")?;
            let then = self.body()?;
            let els = if matches!(self.peek(), Tok::Ident(s) if s == "else") {
                self.bump();
                self.body()?
            } else {
                Vec::new()
            };
            return Ok(Stmt::If(cond, then, els));
        }
        let target = self.target()?;
        self.expect_op("=", "(statements assign: `out.x = ...` or `name = ...`)")?;
        let value = self.expr()?;
        self.eat_op(";");
        Ok(Stmt::Assign(target, value, pos))
    }

    fn port_index(&mut self, input: bool) -> Result<usize, ExprError> {
        self.expect_op("[", "after `input`/`output`")?;
        let pos = self.pos();
        let k = match self.bump() {
            Tok::Num(v) if v >= 0.0 && v.fract() == 0.0 && (v as usize) < MAX_PORTS => v as usize,
            _ => {
                return Err(ExprError::new(pos, "expected an element index").hint(format!(
                    "write {}[k] with k an integer from 0 to {}",
                    if input { "input" } else { "output" },
                    MAX_PORTS - 1
                )))
            }
        };
        self.expect_op("]", "to close the index")?;
        Ok(k)
    }

    /// `.name` after `in`/`out`: a declared element, else a custom attribute by name.
    fn named_port(&mut self, input: bool) -> Result<Port, ExprError> {
        self.expect_op(".", if input { "after `in`" } else { "after `out`" })?;
        let (name, pos) = self.ident("a name")?;
        let list = if input { &self.prog.inputs } else { &self.prog.outputs };
        Ok(match list.iter().position(|n| *n == name) {
            Some(k) => Port::Element(k),
            None => Port::Attr(name, pos),
        })
    }

    fn target(&mut self) -> Result<Target, ExprError> {
        let (name, pos) = self.ident("a statement (`out.name = ...`, `name = ...` or `if`)")?;
        match name.as_str() {
            "out" => Ok(Target::Output(self.named_port(false)?)),
            "output" => Ok(Target::Output(Port::Element(self.port_index(false)?))),
            n if KEYWORDS.contains(&n) || super::code::is_function(n) => {
                Err(ExprError::new(pos, format!("cannot assign to `{n}`"))
                    .hint("assign to `out.name`, `output[k]` or a local name"))
            }
            _ => Ok(Target::Local(name)),
        }
    }

    fn expr(&mut self) -> Result<Node, ExprError> {
        let c = self.binary(0)?;
        if self.eat_op("?") {
            let a = self.expr()?;
            self.expect_op(":", "in `cond ? a : b`")?;
            let b = self.expr()?;
            let pos = c.pos;
            return Ok(Node {
                expr: Expr::Cond(Box::new(c), Box::new(a), Box::new(b)),
                pos,
            });
        }
        Ok(c)
    }

    /// Precedence climbing over the binary operators (`^` is handled in `unary`).
    fn binary(&mut self, level: usize) -> Result<Node, ExprError> {
        const LEVELS: [&[(&str, BinOp)]; 5] = [
            &[("||", BinOp::Or)],
            &[("&&", BinOp::And)],
            &[
                ("<=", BinOp::Le),
                (">=", BinOp::Ge),
                ("==", BinOp::Eq),
                ("!=", BinOp::Ne),
                ("<", BinOp::Lt),
                (">", BinOp::Gt),
            ],
            &[("+", BinOp::Add), ("-", BinOp::Sub)],
            &[("*", BinOp::Mul), ("/", BinOp::Div), ("%", BinOp::Mod)],
        ];
        if level == LEVELS.len() {
            return self.unary();
        }
        let mut lhs = self.binary(level + 1)?;
        loop {
            let op = match self.peek() {
                Tok::Op(o) => LEVELS[level].iter().find(|(s, _)| s == o).map(|&(_, op)| op),
                _ => None,
            };
            let Some(op) = op else { return Ok(lhs) };
            self.bump();
            let rhs = self.binary(level + 1)?;
            let pos = lhs.pos;
            lhs = Node {
                expr: Expr::Bin(op, Box::new(lhs), Box::new(rhs)),
                pos,
            };
        }
    }

    fn unary(&mut self) -> Result<Node, ExprError> {
        let pos = self.pos();
        if self.eat_op("-") {
            let e = self.unary()?;
            return Ok(Node {
                expr: Expr::Neg(Box::new(e)),
                pos,
            });
        }
        if self.eat_op("+") {
            return self.unary();
        }
        if self.eat_op("!") {
            let e = self.unary()?;
            return Ok(Node {
                expr: Expr::Not(Box::new(e)),
                pos,
            });
        }
        let base = self.postfix()?;
        if self.eat_op("^") {
            let exp = self.unary()?;
            return Ok(Node {
                expr: Expr::Bin(BinOp::Pow, Box::new(base), Box::new(exp)),
                pos,
            });
        }
        Ok(base)
    }

    fn postfix(&mut self) -> Result<Node, ExprError> {
        let mut e = self.primary()?;
        while matches!(self.peek(), Tok::Op(".")) {
            self.bump();
            let (c, cpos) = self.ident("`x`, `y` or `z`")?;
            let k = match c.as_str() {
                "x" => 0,
                "y" => 1,
                "z" => 2,
                _ => {
                    return Err(ExprError::new(
                        cpos,
                        format!("vectors have components x, y, z, not `{c}`"),
                    ))
                }
            };
            let pos = e.pos;
            e = Node {
                expr: Expr::Comp(Box::new(e), k),
                pos,
            };
        }
        Ok(e)
    }

    fn primary(&mut self) -> Result<Node, ExprError> {
        let (pos, at) = (self.pos(), self.i);
        let node = |expr| Ok(Node { expr, pos });
        match self.bump() {
            Tok::Num(v) => node(Expr::Num(v)),
            Tok::Op("(") => {
                let e = self.expr()?;
                self.expect_op(")", "to close the parenthesis")?;
                Ok(e)
            }
            Tok::Op("<<") => {
                let x = self.expr()?;
                self.expect_op(",", "between vector components")?;
                let y = self.expr()?;
                self.expect_op(",", "between vector components")?;
                let z = self.expr()?;
                self.expect_op(">>", "to close the vector")?;
                node(Expr::Vector(Box::new([x, y, z])))
            }
            Tok::Ident(name) => match name.as_str() {
                "time" => node(Expr::Time(false)),
                "frame" => node(Expr::Time(true)),
                "in" => {
                    let k = self.named_port(true)?;
                    node(Expr::Input(k))
                }
                "input" => {
                    let k = self.port_index(true)?;
                    node(Expr::Input(Port::Element(k)))
                }
                "out" | "output" | "if" | "else" => Err(ExprError::new(pos, format!("`{name}` cannot be read"))
                    .hint("outputs are written (`out.x = ...`); keep a value in a local name to reuse it")),
                _ if self.eat_op("(") => {
                    let mut args = Vec::new();
                    if !self.eat_op(")") {
                        loop {
                            args.push(self.expr()?);
                            if self.eat_op(")") {
                                break;
                            }
                            self.expect_op(",", "between arguments")?;
                        }
                    }
                    node(Expr::Call(name, args))
                }
                _ => node(Expr::Local(name)),
            },
            _ => {
                self.i = at;
                Err(self.unexpected("a value (a number, a name, `(`, `<<`)"))
            }
        }
    }
}
