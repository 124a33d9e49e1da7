//! Type checking and compilation of a parsed expression to a flat bytecode,
//! and the interpreter that runs it: a fixed-size value stack and local
//! registers on the Rust stack, so a run allocates nothing.
//!
//! Every value is a `DVec3`; numbers live in `x`. Types are checked at
//! compile time (number or vector), so each instruction knows what it holds.

use glam::DVec3;
use sinew_core::{AttrId, AttrType, Direction, NodeSpec};

use super::parse::{BinOp, Expr, ExprError, Node, Port, Pos, Program, Stmt, Target, MAX_PORTS};
use crate::math::arith::{safe_div, safe_pow};
use crate::math::vector::{length, unit};
use crate::math::{finite, finite3};

/// Deepest value stack a compiled expression may need.
pub const MAX_STACK: usize = 32;
/// Most local variables an expression may use.
pub const MAX_LOCALS: usize = 64;

/// The static type of a value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ty {
    /// A number.
    Num,
    /// A 3-vector.
    Vec,
}

impl Ty {
    fn name(self) -> &'static str {
        match self {
            Ty::Num => "a number",
            Ty::Vec => "a vector",
        }
    }
}

/// A built-in function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Func {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Atan2,
    Sqrt,
    Exp,
    Log,
    Log10,
    Abs,
    Floor,
    Ceil,
    Trunc,
    Round,
    Sign,
    DegToRad,
    RadToDeg,
    Pow,
    Min,
    Max,
    Clamp,
    Smoothstep,
    Linstep,
    Lerp,
    LerpVec,
    Noise,
    NoiseVec,
    Mag,
    Unit,
    Dot,
    Cross,
    Angle,
}

/// The functions: name, argument types, result type, the function.
const FUNCS: &[(&str, &[Ty], Ty, Func)] = &[
    ("sin", &[Ty::Num], Ty::Num, Func::Sin),
    ("cos", &[Ty::Num], Ty::Num, Func::Cos),
    ("tan", &[Ty::Num], Ty::Num, Func::Tan),
    ("asin", &[Ty::Num], Ty::Num, Func::Asin),
    ("acos", &[Ty::Num], Ty::Num, Func::Acos),
    ("atan", &[Ty::Num], Ty::Num, Func::Atan),
    ("atan2", &[Ty::Num, Ty::Num], Ty::Num, Func::Atan2),
    ("sqrt", &[Ty::Num], Ty::Num, Func::Sqrt),
    ("exp", &[Ty::Num], Ty::Num, Func::Exp),
    ("log", &[Ty::Num], Ty::Num, Func::Log),
    ("log10", &[Ty::Num], Ty::Num, Func::Log10),
    ("abs", &[Ty::Num], Ty::Num, Func::Abs),
    ("floor", &[Ty::Num], Ty::Num, Func::Floor),
    ("ceil", &[Ty::Num], Ty::Num, Func::Ceil),
    ("trunc", &[Ty::Num], Ty::Num, Func::Trunc),
    ("round", &[Ty::Num], Ty::Num, Func::Round),
    ("sign", &[Ty::Num], Ty::Num, Func::Sign),
    ("deg_to_rad", &[Ty::Num], Ty::Num, Func::DegToRad),
    ("rad_to_deg", &[Ty::Num], Ty::Num, Func::RadToDeg),
    ("pow", &[Ty::Num, Ty::Num], Ty::Num, Func::Pow),
    ("min", &[Ty::Num, Ty::Num], Ty::Num, Func::Min),
    ("max", &[Ty::Num, Ty::Num], Ty::Num, Func::Max),
    ("clamp", &[Ty::Num, Ty::Num, Ty::Num], Ty::Num, Func::Clamp),
    ("smoothstep", &[Ty::Num, Ty::Num, Ty::Num], Ty::Num, Func::Smoothstep),
    ("linstep", &[Ty::Num, Ty::Num, Ty::Num], Ty::Num, Func::Linstep),
    ("lerp", &[Ty::Num, Ty::Num, Ty::Num], Ty::Num, Func::Lerp),
    ("lerp", &[Ty::Vec, Ty::Vec, Ty::Num], Ty::Vec, Func::LerpVec),
    ("noise", &[Ty::Num], Ty::Num, Func::Noise),
    ("noise", &[Ty::Vec], Ty::Num, Func::NoiseVec),
    ("mag", &[Ty::Vec], Ty::Num, Func::Mag),
    ("length", &[Ty::Vec], Ty::Num, Func::Mag),
    ("unit", &[Ty::Vec], Ty::Vec, Func::Unit),
    ("normalize", &[Ty::Vec], Ty::Vec, Func::Unit),
    ("dot", &[Ty::Vec, Ty::Vec], Ty::Num, Func::Dot),
    ("cross", &[Ty::Vec, Ty::Vec], Ty::Vec, Func::Cross),
    ("angle", &[Ty::Vec, Ty::Vec], Ty::Num, Func::Angle),
];

/// Whether `name` is a built-in function.
pub fn is_function(name: &str) -> bool {
    FUNCS.iter().any(|f| f.0 == name)
}

/// The candidate closest to `name` (edit distance at most 2), for "did you mean".
pub fn nearest<'a>(name: &str, candidates: impl Iterator<Item = &'a str>) -> Option<&'a str> {
    fn dist(a: &str, b: &str) -> usize {
        let b: Vec<char> = b.chars().collect();
        let mut row: Vec<usize> = (0..=b.len()).collect();
        for (i, ca) in a.chars().enumerate() {
            let mut prev = row[0];
            row[0] = i + 1;
            for (j, cb) in b.iter().enumerate() {
                let cur = row[j + 1];
                row[j + 1] = (prev + usize::from(ca != *cb)).min(row[j] + 1).min(cur + 1);
                prev = cur;
            }
        }
        row[b.len()]
    }
    candidates
        .map(|c| (dist(name, c), c))
        .filter(|(d, _)| *d <= 2)
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

/// One bytecode instruction.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Const(DVec3),
    Input(u8),
    Local(u8),
    SetLocal(u8),
    SetOutput(u8),
    Time,
    Frame,
    Neg,
    Not,
    Bin(BinOp),
    VAdd,
    VSub,
    VNeg,
    VScale,
    ScaleV,
    VDiv,
    VDot,
    VCross,
    VEq(bool),
    MakeVec,
    Comp(u8),
    Call(Func),
    /// Jump to the target when the popped number is 0.
    JumpIfZero(u32),
    Jump(u32),
}

/// Where a compiled expression reads a value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// `input[k]`.
    Element(u32),
    /// A custom float input of the node.
    Attr(AttrId),
}

/// Where a compiled expression writes a value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sink {
    /// `output[k]`.
    Element(u32),
    /// A custom float output of the node.
    Attr(AttrId),
}

/// A compiled expression: bytecode over fixed-size registers, and the plugs it
/// reads (`sources`, by slot) and writes (`sinks`, by slot).
#[derive(Clone, Debug, PartialEq)]
pub struct Compiled {
    code: Vec<Op>,
    /// The values a run reads, by slot (the node fills them).
    pub sources: Vec<Source>,
    /// The values a run writes, by slot.
    pub sinks: Vec<Sink>,
}

impl Compiled {
    /// Whether the expression reads or writes a custom attribute (it then writes no
    /// `output[k]`).
    pub fn uses_attrs(&self) -> bool {
        self.sources.iter().any(|s| matches!(s, Source::Attr(_)))
            || self.sinks.iter().any(|s| matches!(s, Sink::Attr(_)))
    }
}

struct Compiler<'a> {
    code: Vec<Op>,
    /// Declared `in` names: a bare declared name reads its input.
    inputs: Vec<String>,
    /// The node's spec (custom attributes by name), if any.
    spec: Option<&'a NodeSpec>,
    locals: Vec<(String, Ty)>,
    depth: usize,
    max_depth: usize,
    sources: Vec<Source>,
    sinks: Vec<Sink>,
    /// The first `output[k]` written and the first custom attribute used, for the rule
    /// that an expression does not mix them.
    element_sink: Option<Pos>,
    attr_port: Option<Pos>,
}

/// Parses and compiles `text` with no custom attributes (the plugs are `input[k]`,
/// `output[k]` and the declared names).
pub fn compile(text: &str) -> Result<Compiled, ExprError> {
    compile_for(text, None)
}

/// Parses and compiles `text` for a node with `spec`: `in.name`/`out.name` (and bare
/// names) that are not declared with `in`/`out` are the node's custom float attributes.
pub fn compile_for(text: &str, spec: Option<&NodeSpec>) -> Result<Compiled, ExprError> {
    let prog: Program = super::parse::parse(text)?;
    let mut c = Compiler {
        code: Vec::new(),
        inputs: prog.inputs.clone(),
        spec,
        locals: Vec::new(),
        depth: 0,
        max_depth: 0,
        sources: Vec::new(),
        sinks: Vec::new(),
        element_sink: None,
        attr_port: None,
    };
    c.stmts(&prog.stmts)?;
    if let (Some(e), Some(_)) = (c.element_sink, c.attr_port) {
        return Err(ExprError::new(
            e,
            "an expression that uses custom attributes writes custom outputs only",
        )
        .hint("write `out.name` with `name` a custom output (attrs: {\"name\": float(output: true)})"));
    }
    Ok(Compiled {
        code: c.code,
        sources: c.sources,
        sinks: c.sinks,
    })
}

impl Compiler<'_> {
    /// A custom float attribute of the node named `name`, in direction `dir`.
    fn custom_attr(&self, name: &str, pos: Pos, dir: Direction) -> Result<AttrId, ExprError> {
        let (word, decl) = match dir {
            Direction::Input => ("in", "float(0)"),
            Direction::Output => ("out", "float(output: true)"),
        };
        let customs = || {
            self.spec
                .into_iter()
                .flat_map(|s| s.custom_attrs().iter().map(|a| a.name.as_str()))
        };
        let Some((spec, (id, comp))) = self.spec.and_then(|s| s.find(name).map(|f| (s, f))) else {
            let declared = if dir == Direction::Input {
                self.inputs.clone()
            } else {
                Vec::new()
            };
            let hint = match nearest(name, customs().chain(declared.iter().map(|s| s.as_str()))) {
                Some(s) => format!("did you mean `{word}.{s}`?"),
                None => format!("declare it in the text (`{word} {name}`, an element of {word}put[]) or give the node a custom attribute: attrs: {{\"{name}\": {decl}}}"),
            };
            return Err(ExprError::new(pos, format!("`{word}.{name}` is not declared")).hint(hint));
        };
        let a = spec.attr(id);
        if comp.is_some() || !spec.is_custom(id) || a.ty != AttrType::Float || a.multi || a.direction != dir {
            let want = if dir == Direction::Input { "input" } else { "output" };
            return Err(
                ExprError::new(pos, format!("`{name}` is not a custom float {want} of this node")).hint(format!(
                    "expressions read and write the node's custom float attributes: attrs: {{\"{name}\": {decl}}}"
                )),
            );
        }
        Ok(id)
    }

    fn source_slot(&mut self, src: Source) -> Result<u8, ExprError> {
        let slot = match self.sources.iter().position(|s| *s == src) {
            Some(k) => k,
            None => {
                self.sources.push(src);
                self.sources.len() - 1
            }
        };
        Ok(slot as u8)
    }

    fn sink_slot(&mut self, dst: Sink) -> u8 {
        let slot = match self.sinks.iter().position(|s| *s == dst) {
            Some(k) => k,
            None => {
                self.sinks.push(dst);
                self.sinks.len() - 1
            }
        };
        slot as u8
    }

    fn read_port(&mut self, port: &Port, pos: Pos) -> Result<(), ExprError> {
        let src = match port {
            Port::Element(k) => Source::Element(*k as u32),
            Port::Attr(name, at) => {
                self.attr_port.get_or_insert(*at);
                Source::Attr(self.custom_attr(name, *at, Direction::Input)?)
            }
        };
        if self.sources.len() >= MAX_PORTS && !self.sources.contains(&src) {
            return Err(ExprError::new(pos, format!("more than {MAX_PORTS} inputs read")));
        }
        let slot = self.source_slot(src)?;
        self.push(Op::Input(slot), 1, pos)
    }

    fn push(&mut self, op: Op, delta: isize, pos: Pos) -> Result<(), ExprError> {
        self.code.push(op);
        self.depth = (self.depth as isize + delta).max(0) as usize;
        self.max_depth = self.max_depth.max(self.depth);
        if self.max_depth > MAX_STACK {
            return Err(ExprError::new(pos, "the expression is nested too deeply")
                .hint("split it into local names: `a = ...; b = a * ...`"));
        }
        Ok(())
    }

    fn stmts(&mut self, stmts: &[Stmt]) -> Result<(), ExprError> {
        for s in stmts {
            match s {
                Stmt::Assign(target, value, pos) => {
                    let ty = self.expr(value)?;
                    match target {
                        Target::Output(port) => {
                            if ty != Ty::Num {
                                return Err(ExprError::new(value.pos, "outputs are numbers, this is a vector")
                                    .hint("write one component, e.g. `out.x = v.x`"));
                            }
                            let dst = match port {
                                Port::Element(k) => {
                                    self.element_sink.get_or_insert(*pos);
                                    Sink::Element(*k as u32)
                                }
                                Port::Attr(name, at) => {
                                    self.attr_port.get_or_insert(*at);
                                    Sink::Attr(self.custom_attr(name, *at, Direction::Output)?)
                                }
                            };
                            if self.sinks.len() >= MAX_PORTS && !self.sinks.contains(&dst) {
                                return Err(ExprError::new(*pos, format!("more than {MAX_PORTS} outputs written")));
                            }
                            let slot = self.sink_slot(dst);
                            self.push(Op::SetOutput(slot), -1, *pos)?;
                        }
                        Target::Local(name)
                            if self.inputs.contains(name)
                                || self
                                    .spec
                                    .is_some_and(|s| s.find(name).is_some_and(|(id, _)| s.is_custom(id))) =>
                        {
                            return Err(ExprError::new(
                                *pos,
                                format!(
                                    "`{name}` is an input or a custom attribute; assign outputs as `out.{name} = ...`"
                                ),
                            )
                            .hint("assign to a new local name or to an output"));
                        }
                        Target::Local(name) => {
                            let slot = match self.locals.iter().position(|(n, _)| n == name) {
                                Some(i) if self.locals[i].1 == ty => i,
                                Some(i) => {
                                    return Err(ExprError::new(
                                        value.pos,
                                        format!("`{name}` holds {}, this is {}", self.locals[i].1.name(), ty.name()),
                                    )
                                    .hint("a local name keeps the type of its first assignment"))
                                }
                                None => {
                                    if self.locals.len() >= MAX_LOCALS {
                                        return Err(ExprError::new(
                                            *pos,
                                            format!("more than {MAX_LOCALS} local names"),
                                        ));
                                    }
                                    self.locals.push((name.clone(), ty));
                                    self.locals.len() - 1
                                }
                            };
                            self.push(Op::SetLocal(slot as u8), -1, *pos)?;
                        }
                    }
                }
                Stmt::If(cond, then, els) => {
                    if self.expr(cond)? != Ty::Num {
                        return Err(ExprError::new(cond.pos, "a condition must be a number (0 is false)"));
                    }
                    let jz = self.code.len();
                    self.push(Op::JumpIfZero(0), -1, cond.pos)?;
                    self.stmts(then)?;
                    if els.is_empty() {
                        self.code[jz] = Op::JumpIfZero(self.code.len() as u32);
                    } else {
                        let jmp = self.code.len();
                        self.push(Op::Jump(0), 0, cond.pos)?;
                        self.code[jz] = Op::JumpIfZero(self.code.len() as u32);
                        self.stmts(els)?;
                        self.code[jmp] = Op::Jump(self.code.len() as u32);
                    }
                }
            }
        }
        Ok(())
    }

    fn expr(&mut self, n: &Node) -> Result<Ty, ExprError> {
        let pos = n.pos;
        match &n.expr {
            Expr::Num(v) => {
                self.push(Op::Const(DVec3::new(*v, 0.0, 0.0)), 1, pos)?;
                Ok(Ty::Num)
            }
            Expr::Time(frame) => {
                self.push(if *frame { Op::Frame } else { Op::Time }, 1, pos)?;
                Ok(Ty::Num)
            }
            Expr::Input(port) => {
                self.read_port(port, pos)?;
                Ok(Ty::Num)
            }
            Expr::Local(name) => match self.locals.iter().position(|(l, _)| l == name) {
                Some(i) => {
                    let ty = self.locals[i].1;
                    self.push(Op::Local(i as u8), 1, pos)?;
                    Ok(ty)
                }
                None if self.inputs.contains(name) => {
                    let k = self.inputs.iter().position(|n| n == name).unwrap_or(0);
                    self.read_port(&Port::Element(k), pos)?;
                    Ok(Ty::Num)
                }
                None if self
                    .spec
                    .is_some_and(|s| s.find(name).is_some_and(|(id, _)| s.is_custom(id))) =>
                {
                    self.read_port(&Port::Attr(name.clone(), pos), pos)?;
                    Ok(Ty::Num)
                }
                None => {
                    let customs = self
                        .spec
                        .into_iter()
                        .flat_map(|s| s.custom_attrs().iter().map(|a| a.name.as_str()));
                    let names = self
                        .locals
                        .iter()
                        .map(|(l, _)| l.as_str())
                        .chain(self.inputs.iter().map(|s| s.as_str()))
                        .chain(customs);
                    let hint = match nearest(name, names) {
                        Some(s) => format!("did you mean `{s}`?"),
                        None => "assign it first (`name = ...`), read an input as `in.name` or `input[k]`".into(),
                    };
                    Err(ExprError::new(pos, format!("unknown name `{name}`")).hint(hint))
                }
            },
            Expr::Neg(e) => match self.expr(e)? {
                Ty::Num => self.push(Op::Neg, 0, pos).map(|_| Ty::Num),
                Ty::Vec => self.push(Op::VNeg, 0, pos).map(|_| Ty::Vec),
            },
            Expr::Not(e) => {
                self.num(e, "`!`")?;
                self.push(Op::Not, 0, pos)?;
                Ok(Ty::Num)
            }
            Expr::Bin(op, a, b) => {
                let (ta, tb) = (self.expr(a)?, self.expr(b)?);
                let (code, ty) = match (op, ta, tb) {
                    (_, Ty::Num, Ty::Num) => (Op::Bin(*op), Ty::Num),
                    (BinOp::Add, Ty::Vec, Ty::Vec) => (Op::VAdd, Ty::Vec),
                    (BinOp::Sub, Ty::Vec, Ty::Vec) => (Op::VSub, Ty::Vec),
                    (BinOp::Mul, Ty::Vec, Ty::Vec) => (Op::VDot, Ty::Num),
                    (BinOp::Pow, Ty::Vec, Ty::Vec) => (Op::VCross, Ty::Vec),
                    (BinOp::Eq, Ty::Vec, Ty::Vec) => (Op::VEq(true), Ty::Num),
                    (BinOp::Ne, Ty::Vec, Ty::Vec) => (Op::VEq(false), Ty::Num),
                    (BinOp::Mul, Ty::Vec, Ty::Num) => (Op::VScale, Ty::Vec),
                    (BinOp::Mul, Ty::Num, Ty::Vec) => (Op::ScaleV, Ty::Vec),
                    (BinOp::Div, Ty::Vec, Ty::Num) => (Op::VDiv, Ty::Vec),
                    _ => {
                        return Err(ExprError::new(
                            pos,
                            format!("this operator does not apply to {} and {}", ta.name(), tb.name()),
                        )
                        .hint("vectors take + - (vectors), * / (by a number), * (dot) and ^ (cross)"))
                    }
                };
                self.push(code, -1, pos)?;
                Ok(ty)
            }
            Expr::Cond(c, a, b) => {
                self.num(c, "a condition")?;
                let jz = self.code.len();
                self.push(Op::JumpIfZero(0), -1, pos)?;
                let ta = self.expr(a)?;
                let jmp = self.code.len();
                self.push(Op::Jump(0), -1, pos)?;
                self.code[jz] = Op::JumpIfZero(self.code.len() as u32);
                let tb = self.expr(b)?;
                self.code[jmp] = Op::Jump(self.code.len() as u32);
                if ta != tb {
                    return Err(ExprError::new(b.pos, format!("both branches must be {}", ta.name())));
                }
                Ok(ta)
            }
            Expr::Vector(parts) => {
                for p in parts.iter() {
                    self.num(p, "a vector component")?;
                }
                self.push(Op::MakeVec, -2, pos)?;
                Ok(Ty::Vec)
            }
            Expr::Comp(e, k) => {
                if self.expr(e)? != Ty::Vec {
                    return Err(ExprError::new(pos, "only vectors have components .x .y .z"));
                }
                self.push(Op::Comp(*k), 0, pos)?;
                Ok(Ty::Num)
            }
            Expr::Call(name, args) => {
                let tys = args.iter().map(|a| self.expr(a)).collect::<Result<Vec<_>, _>>()?;
                let f = FUNCS.iter().find(|f| f.0 == name && f.1 == tys.as_slice());
                let Some(&(_, params, ret, func)) = f else {
                    if is_function(name) {
                        let sigs: Vec<String> = FUNCS
                            .iter()
                            .filter(|f| f.0 == name)
                            .map(|f| {
                                format!(
                                    "{}({})",
                                    name,
                                    f.1.iter().map(|t| t.name()).collect::<Vec<_>>().join(", ")
                                )
                            })
                            .collect();
                        return Err(ExprError::new(pos, format!("wrong arguments for `{name}`"))
                            .hint(format!("it takes {}", sigs.join(" or "))));
                    }
                    let hint = match nearest(name, FUNCS.iter().map(|f| f.0)) {
                        Some(s) => format!("did you mean `{s}`?"),
                        None => "see docs/expression.md for the functions".to_string(),
                    };
                    return Err(ExprError::new(pos, format!("unknown function `{name}`")).hint(hint));
                };
                self.push(Op::Call(func), 1 - params.len() as isize, pos)?;
                Ok(ret)
            }
        }
    }

    fn num(&mut self, e: &Node, what: &str) -> Result<(), ExprError> {
        match self.expr(e)? {
            Ty::Num => Ok(()),
            Ty::Vec => Err(ExprError::new(
                e.pos,
                format!("{what} must be a number, this is a vector"),
            )),
        }
    }
}

/// What an expression run reads: its sources' values by slot and the time.
pub struct Env<'a> {
    /// The value of each source slot (`Compiled::sources`; 0 where absent).
    pub inputs: &'a [f64],
    /// Seconds.
    pub time: f64,
    /// The frame number.
    pub frame: f64,
}

impl Compiled {
    /// Runs the expression; writes the value of each sink slot (`Compiled::sinks`) into
    /// `outputs` (sinks not assigned on this run are 0). Allocates nothing.
    pub fn run(&self, env: &Env<'_>, outputs: &mut [f64]) {
        let mut stack = [DVec3::ZERO; MAX_STACK + 1];
        let mut locals = [DVec3::ZERO; MAX_LOCALS];
        outputs.iter_mut().for_each(|o| *o = 0.0);
        let mut sp = 0usize;
        let mut pc = 0usize;
        macro_rules! pop {
            () => {{
                sp = sp.saturating_sub(1);
                stack[sp]
            }};
        }
        macro_rules! push {
            ($v:expr) => {{
                let v = $v;
                if sp < stack.len() {
                    stack[sp] = v;
                    sp += 1;
                }
            }};
        }
        while let Some(&op) = self.code.get(pc) {
            pc += 1;
            match op {
                Op::Const(v) => push!(v),
                Op::Input(k) => push!(DVec3::new(env.inputs.get(k as usize).copied().unwrap_or(0.0), 0.0, 0.0)),
                Op::Local(k) => push!(locals[k as usize % MAX_LOCALS]),
                Op::SetLocal(k) => locals[k as usize % MAX_LOCALS] = pop!(),
                Op::SetOutput(k) => {
                    let v = pop!().x;
                    if let Some(o) = outputs.get_mut(k as usize) {
                        *o = finite(v);
                    }
                }
                Op::Time => push!(DVec3::new(env.time, 0.0, 0.0)),
                Op::Frame => push!(DVec3::new(env.frame, 0.0, 0.0)),
                Op::Neg => {
                    let a = pop!();
                    push!(DVec3::new(-a.x, 0.0, 0.0))
                }
                Op::Not => {
                    let a = pop!();
                    push!(DVec3::new(if a.x == 0.0 { 1.0 } else { 0.0 }, 0.0, 0.0))
                }
                Op::Bin(b) => {
                    let (y, x) = (pop!().x, pop!().x);
                    push!(DVec3::new(binary(b, x, y), 0.0, 0.0))
                }
                Op::VAdd => {
                    let (b, a) = (pop!(), pop!());
                    push!(finite3(a + b))
                }
                Op::VSub => {
                    let (b, a) = (pop!(), pop!());
                    push!(finite3(a - b))
                }
                Op::VNeg => {
                    let a = pop!();
                    push!(-a)
                }
                Op::VScale => {
                    let (s, v) = (pop!().x, pop!());
                    push!(finite3(v * s))
                }
                Op::ScaleV => {
                    let (v, s) = (pop!(), pop!().x);
                    push!(finite3(v * s))
                }
                Op::VDiv => {
                    let (s, v) = (pop!().x, pop!());
                    push!(DVec3::new(safe_div(v.x, s), safe_div(v.y, s), safe_div(v.z, s)))
                }
                Op::VDot => {
                    let (b, a) = (pop!(), pop!());
                    push!(DVec3::new(finite(a.dot(b)), 0.0, 0.0))
                }
                Op::VCross => {
                    let (b, a) = (pop!(), pop!());
                    push!(finite3(a.cross(b)))
                }
                Op::VEq(eq) => {
                    let (b, a) = (pop!(), pop!());
                    push!(DVec3::new(if (a == b) == eq { 1.0 } else { 0.0 }, 0.0, 0.0))
                }
                Op::MakeVec => {
                    let (z, y, x) = (pop!().x, pop!().x, pop!().x);
                    push!(DVec3::new(x, y, z))
                }
                Op::Comp(k) => {
                    let v = pop!();
                    push!(DVec3::new(v[k as usize % 3], 0.0, 0.0))
                }
                Op::Call(f) => {
                    let v = call(f, &mut stack, &mut sp);
                    push!(v)
                }
                Op::JumpIfZero(t) => {
                    if pop!().x == 0.0 {
                        pc = t as usize;
                    }
                }
                Op::Jump(t) => pc = t as usize,
            }
        }
    }
}

fn truth(b: bool) -> f64 {
    if b {
        1.0
    } else {
        0.0
    }
}

/// A binary operator on numbers (total: x/0 = 0, x % 0 = 0, no real power = 0).
fn binary(op: BinOp, x: f64, y: f64) -> f64 {
    match op {
        BinOp::Add => finite(x + y),
        BinOp::Sub => finite(x - y),
        BinOp::Mul => finite(x * y),
        BinOp::Div => safe_div(x, y),
        BinOp::Mod => crate::mathnodes::scalar::modulo(x, y),
        BinOp::Pow => safe_pow(x, y),
        BinOp::Lt => truth(x < y),
        BinOp::Le => truth(x <= y),
        BinOp::Gt => truth(x > y),
        BinOp::Ge => truth(x >= y),
        BinOp::Eq => truth(x == y),
        BinOp::Ne => truth(x != y),
        BinOp::And => truth(x != 0.0 && y != 0.0),
        BinOp::Or => truth(x != 0.0 || y != 0.0),
    }
}

/// Pops a call's arguments (the compiler checked their count and types) and applies it.
fn call(f: Func, stack: &mut [DVec3], sp: &mut usize) -> DVec3 {
    let n = match f {
        Func::Atan2 | Func::Pow | Func::Min | Func::Max | Func::Dot | Func::Cross | Func::Angle => 2,
        Func::Clamp | Func::Smoothstep | Func::Linstep | Func::Lerp | Func::LerpVec => 3,
        _ => 1,
    };
    let start = sp.saturating_sub(n);
    let a = |k: usize| stack.get(start + k).copied().unwrap_or(DVec3::ZERO);
    let (x, y, z) = (a(0).x, a(1).x, a(2).x);
    let num = |v: f64| DVec3::new(finite(v), 0.0, 0.0);
    let r = match f {
        Func::Sin => num(x.sin()),
        Func::Cos => num(x.cos()),
        Func::Tan => num(x.tan()),
        Func::Asin => num(finite(x).clamp(-1.0, 1.0).asin()),
        Func::Acos => num(finite(x).clamp(-1.0, 1.0).acos()),
        Func::Atan => num(x.atan()),
        Func::Atan2 => num(finite(x).atan2(finite(y))),
        Func::Sqrt => num(if x > 0.0 { x.sqrt() } else { 0.0 }),
        Func::Exp => num(x.exp()),
        Func::Log => num(if x > 0.0 { x.ln() } else { 0.0 }),
        Func::Log10 => num(if x > 0.0 { x.log10() } else { 0.0 }),
        Func::Abs => num(x.abs()),
        Func::Floor => num(x.floor()),
        Func::Ceil => num(x.ceil()),
        Func::Trunc => num(x.trunc()),
        Func::Round => num(crate::mathnodes::scalar::round_half_up(x)),
        Func::Sign => num(if x > 0.0 {
            1.0
        } else if x < 0.0 {
            -1.0
        } else {
            0.0
        }),
        Func::DegToRad => num(x.to_radians()),
        Func::RadToDeg => num(x.to_degrees()),
        Func::Pow => num(safe_pow(x, y)),
        Func::Min => num(x.min(y)),
        Func::Max => num(x.max(y)),
        // Maya's argument order: clamp(min, max, value), smoothstep(start, end, value).
        Func::Clamp => num(crate::mathnodes::scalar::clamp_range(z, x, y)),
        Func::Smoothstep => num(crate::mathnodes::scalar::smooth_step(z, x, y)),
        Func::Linstep => num(if y > x {
            ((z - x) / (y - x)).clamp(0.0, 1.0)
        } else {
            truth(z >= x)
        }),
        Func::Lerp => num(crate::mathnodes::scalar::lerp(x, y, z)),
        Func::LerpVec => finite3(a(0) * (1.0 - a(2).x) + a(1) * a(2).x),
        Func::Noise => num(super::noise::noise3(DVec3::new(x, 0.0, 0.0))),
        Func::NoiseVec => num(super::noise::noise3(a(0))),
        Func::Mag => num(length(a(0))),
        Func::Unit => unit(a(0)),
        Func::Dot => num(a(0).dot(a(1))),
        Func::Cross => finite3(a(0).cross(a(1))),
        Func::Angle => {
            let (u, v) = (unit(a(0)), unit(a(1)));
            num(length(u.cross(v)).atan2(u.dot(v)))
        }
    };
    *sp = start;
    r
}

/// The element count `input[]`/`output[]` may address.
pub const PORTS: usize = MAX_PORTS;
