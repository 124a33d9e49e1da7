//! Statements of the MEL subset Maya writes, read into a [`MaScene`].
//!
//! A statement is the tokens up to `;` (several may share a line, one may span many).
//! Supported commands (see `docs/maya-import.md`): `requires`, `currentUnit`, `fileInfo`,
//! `createNode`, `rename`, `setAttr`, `addAttr`, `connectAttr`, `parent`, `select -ne`;
//! `relationship`, `lockNode` and `dataStructure` are read and ignored (they do not affect
//! evaluation); `file` (references) and any other command are skipped with a note naming
//! the line. Errors (a truncated file, a statement that cannot mean anything) carry the
//! byte offset of the offending token; [`super::MayaError`] turns it into `file:line:col`.

use std::collections::HashMap;

use super::lex::{lex, Tok, TokKind};
use super::plug::{Index, PlugPath};
use super::scene::{AddAttr, Connection, MaNode, MaScene, Note, SetAttr};
use super::units::{angle_unit, linear_unit, time_unit};

/// A parse error at a byte offset.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseError {
    /// Byte offset of the offending token.
    pub offset: u32,
    /// What is wrong.
    pub message: String,
    /// How to fix it.
    pub hint: String,
}

fn err(at: &Tok, message: impl Into<String>, hint: impl Into<String>) -> ParseError {
    ParseError {
        offset: at.start,
        message: message.into(),
        hint: hint.into(),
    }
}

/// Whether a word is a flag (`-n`, `-type`), not a negative number.
fn is_flag(t: &Tok, src: &str) -> bool {
    let r = t.raw(src).as_bytes();
    t.kind == TokKind::Word && r.len() > 1 && r[0] == b'-' && r[1].is_ascii_alphabetic() && !is_special_number(r)
}

fn is_special_number(r: &[u8]) -> bool {
    let s = &r[1..];
    s.eq_ignore_ascii_case(b"inf") || s.eq_ignore_ascii_case(b"nan") || s.eq_ignore_ascii_case(b"infinity")
}

/// Parses a whole file.
pub fn parse(src: &str) -> Result<MaScene, ParseError> {
    let toks = lex(src).map_err(|e| ParseError {
        offset: e.offset,
        message: e.message,
        hint: "the file looks truncated or damaged; save it again from Maya".into(),
    })?;
    let mut p = Parser {
        src,
        scene: MaScene::default(),
        current: None,
        by_name: HashMap::new(),
        next_free: HashMap::new(),
    };
    let mut start = 0;
    for (i, t) in toks.iter().enumerate() {
        if t.kind == TokKind::Semi {
            if i > start {
                p.statement(&toks[start..i])?;
            }
            start = i + 1;
        }
    }
    if let Some(first) = toks.get(start) {
        return Err(err(
            first,
            format!(
                "the file ends inside a `{}` statement (no `;` after it)",
                first.text(src)
            ),
            "the file is truncated; save it again from Maya",
        ));
    }
    Ok(p.scene)
}

struct Parser<'a> {
    src: &'a str,
    scene: MaScene,
    current: Option<usize>,
    /// Node index by the name as written in `createNode -n` / `select -ne` (last wins).
    by_name: HashMap<String, usize>,
    /// Next free element per `node.attr` multi, for `connectAttr -na`.
    next_free: HashMap<String, u32>,
}

/// Flags of a command: `(name, takes an argument)`. Unknown flags are assumed to take none.
type FlagSpec = &'static [(&'static str, bool)];

const CREATE_FLAGS: FlagSpec = &[
    ("-n", true),
    ("-name", true),
    ("-p", true),
    ("-parent", true),
    ("-s", false),
    ("-shared", false),
    ("-ss", false),
    ("-skipSelect", false),
];
const SETATTR_FLAGS: FlagSpec = &[
    ("-s", true),
    ("-size", true),
    ("-k", true),
    ("-keyable", true),
    ("-l", true),
    ("-lock", true),
    ("-cb", true),
    ("-channelBox", true),
    ("-ch", true),
    ("-capacityHint", true),
    ("-type", true),
    ("-typ", true),
    ("-ca", true),
    ("-caching", true),
    ("-av", false),
    ("-alteredValue", false),
    ("-c", false),
    ("-clamp", false),
];
const ADDATTR_NO_ARG: &[&str] = &[
    "-m",
    "-multi",
    "-uap",
    "-usedAsProxy",
    "-uac",
    "-usedAsColor",
    "-uaf",
    "-usedAsFilename",
    "-xn",
];
const CONNECT_FLAGS: FlagSpec = &[
    ("-na", false),
    ("-nextAvailable", false),
    ("-f", false),
    ("-force", false),
    ("-l", true),
    ("-lock", true),
    ("-rd", true),
    ("-referenceDest", true),
];

/// Splits a statement's arguments into flags (with their argument) and positionals.
struct Args<'t> {
    flags: Vec<(&'t Tok, Option<&'t Tok>)>,
    positional: Vec<&'t Tok>,
}

fn split_args<'t>(src: &str, toks: &'t [Tok], spec: FlagSpec) -> Result<Args<'t>, ParseError> {
    let mut flags = Vec::new();
    let mut positional = Vec::new();
    let mut i = 0;
    while i < toks.len() {
        let t = &toks[i];
        if is_flag(t, src) {
            let takes = spec.iter().find(|(n, _)| *n == t.raw(src)).is_some_and(|(_, a)| *a);
            if takes {
                let arg = toks.get(i + 1).ok_or_else(|| {
                    err(
                        t,
                        format!("flag `{}` needs a value", t.raw(src)),
                        "give the flag its value",
                    )
                })?;
                flags.push((t, Some(arg)));
                i += 2;
            } else {
                flags.push((t, None));
                i += 1;
            }
        } else {
            positional.push(t);
            i += 1;
        }
    }
    Ok(Args { flags, positional })
}

fn flag<'t>(args: &Args<'t>, src: &str, names: &[&str]) -> Option<Option<&'t Tok>> {
    args.flags
        .iter()
        .rev()
        .find(|(f, _)| names.contains(&f.raw(src)))
        .map(|(_, a)| *a)
}

/// A MEL boolean word: `on/off`, `yes/no`, `true/false`, `1/0`.
pub fn parse_bool(s: &str) -> Option<bool> {
    match s {
        "on" | "yes" | "true" | "1" => Some(true),
        "off" | "no" | "false" | "0" => Some(false),
        _ => None,
    }
}

impl Parser<'_> {
    fn note(&mut self, at: &Tok, message: String) {
        self.scene.notes.push(Note { at: at.start, message });
    }

    fn statement(&mut self, toks: &[Tok]) -> Result<(), ParseError> {
        let head = &toks[0];
        if head.kind != TokKind::Word {
            return Err(err(
                head,
                format!("expected a command name, found `{}`", head.raw(self.src)),
                "a statement starts with a command such as `createNode` or `setAttr`",
            ));
        }
        let rest = &toks[1..];
        match head.raw(self.src) {
            "createNode" => self.create_node(head, rest),
            "setAttr" => self.set_attr(head, rest),
            "addAttr" => self.add_attr(head, rest),
            "connectAttr" => self.connect_attr(head, rest),
            "parent" => self.parent(head, rest),
            "select" => self.select(head, rest),
            "rename" => self.rename(head, rest),
            "currentUnit" => self.current_unit(rest),
            "fileInfo" => {
                if let [k, v, ..] = rest {
                    let kv = (k.text(self.src).into_owned(), v.text(self.src).into_owned());
                    self.scene.file_info.push(kv);
                }
                Ok(())
            }
            "requires" => {
                self.requires(rest);
                Ok(())
            }
            "relationship" | "lockNode" | "dataStructure" => {
                self.scene.ignored_statements += 1;
                Ok(())
            }
            "file" => {
                self.note(
                    head,
                    "`file` (a reference to another scene) is skipped: referenced nodes are not imported; import the referenced file on its own".into(),
                );
                Ok(())
            }
            other => {
                let msg = format!("`{other}` is not part of the MEL subset sinew reads; statement skipped");
                self.note(head, msg);
                Ok(())
            }
        }
    }

    fn requires(&mut self, rest: &[Tok]) {
        let mut i = 0;
        let mut pos = Vec::new();
        while i < rest.len() {
            let t = &rest[i];
            if is_flag(t, self.src) {
                let f = t.raw(self.src);
                if let Some(a) = rest.get(i + 1) {
                    if f == "-nodeType" || f == "-nt" {
                        self.scene.plugin_types.push(a.text(self.src).into_owned());
                    }
                }
                i += 2;
            } else {
                pos.push(t.text(self.src).into_owned());
                i += 1;
            }
        }
        if let [plugin, version, ..] = pos.as_slice() {
            self.scene.requires.push((plugin.clone(), version.clone()));
        }
    }

    fn current_unit(&mut self, rest: &[Tok]) -> Result<(), ParseError> {
        let args = split_args(self.src, rest, &[("-l", true), ("-a", true), ("-t", true)])?;
        for (f, a) in &args.flags {
            let Some(a) = a else { continue };
            let v = a.text(self.src).into_owned();
            let u = &mut self.scene.units;
            match f.raw(self.src) {
                "-l" => match linear_unit(&v) {
                    Some(k) => (u.linear, u.cm_per_unit) = (v, k),
                    None => {
                        return Err(err(
                            a,
                            format!("unknown linear unit `{v}`"),
                            "use one of mm, cm, m, km, in, ft, yd, mi",
                        ))
                    }
                },
                "-a" => match angle_unit(&v) {
                    Some(k) => (u.angle, u.rad_per_unit) = (v, k),
                    None => return Err(err(a, format!("unknown angular unit `{v}`"), "use degree or radian")),
                },
                "-t" => match time_unit(&v) {
                    Some(k) => (u.time, u.fps) = (v, k),
                    None => {
                        return Err(err(
                            a,
                            format!("unknown time unit `{v}`"),
                            "use game, film, pal, ntsc, show, palf, ntscf, sec or a rate like 30fps",
                        ))
                    }
                },
                _ => {}
            }
        }
        Ok(())
    }

    fn create_node(&mut self, head: &Tok, rest: &[Tok]) -> Result<(), ParseError> {
        let args = split_args(self.src, rest, CREATE_FLAGS)?;
        let ty = args.positional.first().ok_or_else(|| {
            err(
                head,
                "`createNode` without a node type",
                "write `createNode TYPE -n NAME;`",
            )
        })?;
        let name = match flag(&args, self.src, &["-n", "-name"]) {
            Some(Some(n)) => n.text(self.src).into_owned(),
            _ => format!("{}1", ty.text(self.src)),
        };
        if name.is_empty() {
            return Err(err(
                head,
                "`createNode -n \"\"`: a node needs a name",
                "give the node a name",
            ));
        }
        let parent = match flag(&args, self.src, &["-p", "-parent"]) {
            Some(Some(p)) => Some(p.text(self.src).into_owned()),
            _ => None,
        };
        let idx = self.scene.nodes.len();
        self.scene.nodes.push(MaNode {
            name: name.clone(),
            ty: ty.text(self.src).into_owned(),
            parent,
            parent_index: None,
            shared: flag(&args, self.src, &["-s", "-shared"]).is_some(),
            existing: false,
            uid: None,
            attrs: Vec::new(),
            added: Vec::new(),
            at: head.start,
        });
        self.by_name.insert(name, idx);
        self.current = Some(idx);
        Ok(())
    }

    fn select(&mut self, head: &Tok, rest: &[Tok]) -> Result<(), ParseError> {
        let args = split_args(self.src, rest, &[])?;
        let ne = flag(&args, self.src, &["-ne", "-noExpand"]).is_some();
        let Some(target) = args.positional.first() else {
            self.current = None;
            return Ok(());
        };
        let name = target.text(self.src).into_owned();
        if !ne {
            self.note(head, format!("`select {name}` without -ne: only the node is noted"));
        }
        let key = name.strip_prefix(':').unwrap_or(&name).to_string();
        let idx = match self.by_name.get(&key).or_else(|| self.by_name.get(&name)) {
            Some(&i) => i,
            None => {
                let i = self.scene.nodes.len();
                self.scene.nodes.push(MaNode {
                    name: key.clone(),
                    ty: String::new(),
                    parent: None,
                    parent_index: None,
                    shared: true,
                    existing: true,
                    uid: None,
                    attrs: Vec::new(),
                    added: Vec::new(),
                    at: head.start,
                });
                self.by_name.insert(key, i);
                i
            }
        };
        self.current = Some(idx);
        Ok(())
    }

    fn rename(&mut self, head: &Tok, rest: &[Tok]) -> Result<(), ParseError> {
        let args = split_args(
            self.src,
            rest,
            &[("-uid", true), ("-uuid", true), ("-is", false), ("-ignoreShape", false)],
        )?;
        if let Some(Some(uid)) = flag(&args, self.src, &["-uid", "-uuid"]) {
            if let Some(c) = self.current {
                self.scene.nodes[c].uid = Some(uid.text(self.src).into_owned());
            }
            return Ok(());
        }
        match args.positional.as_slice() {
            [old, new] => {
                let (old, new) = (old.text(self.src).into_owned(), new.text(self.src).into_owned());
                match self.by_name.remove(&old) {
                    Some(i) => {
                        self.scene.nodes[i].name = new.clone();
                        self.by_name.insert(new, i);
                    }
                    None => self.note(head, format!("`rename {old} {new}`: no node {old}; skipped")),
                }
                Ok(())
            }
            [new] => {
                if let Some(c) = self.current {
                    let new = new.text(self.src).into_owned();
                    let old = std::mem::replace(&mut self.scene.nodes[c].name, new.clone());
                    self.by_name.remove(&old);
                    self.by_name.insert(new, c);
                }
                Ok(())
            }
            _ => Err(err(
                head,
                "`rename` needs a new name",
                "write `rename OLD NEW;` or `rename -uid UID;`",
            )),
        }
    }

    fn parent(&mut self, head: &Tok, rest: &[Tok]) -> Result<(), ParseError> {
        let args = split_args(self.src, rest, &[])?;
        let world = flag(&args, self.src, &["-w", "-world"]).is_some();
        let add = flag(&args, self.src, &["-add", "-addObject"]).is_some();
        let names: Vec<String> = args.positional.iter().map(|t| t.text(self.src).into_owned()).collect();
        let (children, parent) = if world {
            (names.as_slice(), None)
        } else {
            match names.split_last() {
                Some((p, c)) if !c.is_empty() => (c, Some(p.clone())),
                _ => {
                    return Err(err(
                        head,
                        "`parent` needs a child and a parent",
                        "write `parent CHILD PARENT;` or `parent -w CHILD;`",
                    ))
                }
            }
        };
        for c in children {
            let key = c.rsplit('|').next().unwrap_or(c);
            let Some(&i) = self.by_name.get(key) else {
                self.note(head, format!("`parent`: no node {c}; skipped"));
                continue;
            };
            if add && self.scene.nodes[i].parent.is_some() {
                self.note(
                    head,
                    format!("`parent -add`: {c} is instanced under a second parent; sinew keeps the first"),
                );
                continue;
            }
            self.scene.nodes[i].parent = parent.clone();
        }
        Ok(())
    }

    fn target(&self, path: &PlugPath, at: &Tok) -> Result<usize, ParseError> {
        match &path.node {
            None => self.current.ok_or_else(|| {
                err(
                    at,
                    format!("`{path}` names no node and no node is current"),
                    "put the statement after a `createNode` or `select -ne`, or write `node.attribute`",
                )
            }),
            Some(n) => {
                let key = n.rsplit('|').next().unwrap_or(n);
                let key = key.strip_prefix(':').unwrap_or(key);
                self.by_name.get(key).copied().ok_or_else(|| {
                    err(
                        at,
                        format!("no node named `{n}` before this statement"),
                        "create the node first",
                    )
                })
            }
        }
    }

    fn set_attr(&mut self, head: &Tok, rest: &[Tok]) -> Result<(), ParseError> {
        // The first string is the path; flags may come before or after it.
        let mut flags: Vec<(&Tok, Option<&Tok>)> = Vec::new();
        let mut path_tok = None;
        let mut values = Vec::new();
        let mut i = 0;
        while i < rest.len() {
            let t = &rest[i];
            if is_flag(t, self.src) {
                let takes = SETATTR_FLAGS
                    .iter()
                    .find(|(n, _)| *n == t.raw(self.src))
                    .is_some_and(|(_, a)| *a);
                if takes {
                    let a = rest.get(i + 1).ok_or_else(|| {
                        err(
                            t,
                            format!("flag `{}` needs a value", t.raw(self.src)),
                            "give the flag its value",
                        )
                    })?;
                    flags.push((t, Some(a)));
                    i += 2;
                } else {
                    flags.push((t, None));
                    i += 1;
                }
                continue;
            }
            if path_tok.is_none() {
                if t.kind != TokKind::Str {
                    return Err(err(
                        t,
                        format!("expected the attribute path as a string, found `{}`", t.raw(self.src)),
                        "write `setAttr \".attribute\" value;`",
                    ));
                }
                path_tok = Some(t);
            } else {
                values.push(*t);
            }
            i += 1;
        }
        let path_tok = path_tok.ok_or_else(|| {
            err(
                head,
                "`setAttr` without an attribute",
                "write `setAttr \".attribute\" value;`",
            )
        })?;
        let path = PlugPath::parse(&path_tok.text(self.src)).map_err(|m| {
            err(
                path_tok,
                m,
                "write a plug path such as \".translate\" or \"node.wl[0:3].w\"",
            )
        })?;
        let node = self.target(&path, path_tok)?;
        let mut sa = SetAttr {
            segs: path.segs,
            ty: None,
            size: None,
            lock: None,
            keyable: None,
            values,
            at: head.start,
        };
        for (f, a) in flags {
            let text = a.map(|a| a.text(self.src).into_owned()).unwrap_or_default();
            match f.raw(self.src) {
                "-type" | "-typ" => sa.ty = Some(text),
                "-s" | "-size" => {
                    let a = a.unwrap_or(f);
                    sa.size = Some(text.parse().map_err(|_| {
                        err(
                            a,
                            format!("`-s {text}`: the size must be a whole number"),
                            "write `-s 4`",
                        )
                    })?);
                }
                "-l" | "-lock" => sa.lock = parse_bool(&text),
                "-k" | "-keyable" => sa.keyable = parse_bool(&text),
                _ => {}
            }
        }
        self.scene.nodes[node].attrs.push(sa);
        Ok(())
    }

    fn add_attr(&mut self, head: &Tok, rest: &[Tok]) -> Result<(), ParseError> {
        let mut a = AddAttr {
            at_offset: head.start,
            ..Default::default()
        };
        let mut i = 0;
        let mut target = None;
        while i < rest.len() {
            let t = &rest[i];
            if !is_flag(t, self.src) {
                target = Some(t.text(self.src).into_owned());
                i += 1;
                continue;
            }
            let f = t.raw(self.src);
            if ADDATTR_NO_ARG.contains(&f) {
                if f == "-m" || f == "-multi" {
                    a.multi = true;
                }
                i += 1;
                continue;
            }
            let v = rest
                .get(i + 1)
                .ok_or_else(|| err(t, format!("flag `{f}` needs a value"), "give the flag its value"))?;
            let text = v.text(self.src).into_owned();
            let num = || text.parse::<f64>().ok();
            match f {
                "-ln" | "-longName" => a.long = text.clone(),
                "-sn" | "-shortName" => a.short = text.clone(),
                "-nn" | "-niceName" => a.nice = Some(text.clone()),
                "-at" | "-attributeType" => a.at = Some(text.clone()),
                "-dt" | "-dataType" => a.dt = Some(text.clone()),
                "-p" | "-parent" => a.parent = Some(text.clone()),
                "-dv" | "-defaultValue" => a.default = num(),
                "-min" | "-minValue" => a.min = num(),
                "-max" | "-maxValue" => a.max = num(),
                "-en" | "-enumName" => a.enum_names = Some(text.clone()),
                "-k" | "-keyable" => a.keyable = parse_bool(&text).unwrap_or(false),
                "-nc" | "-numberOfChildren" => a.children = text.parse().ok(),
                _ => {}
            }
            i += 2;
        }
        if a.long.is_empty() {
            a.long = a.short.clone();
        }
        if a.short.is_empty() {
            a.short = a.long.clone();
        }
        if a.long.is_empty() {
            return Err(err(
                head,
                "`addAttr` without -ln or -sn",
                "name the attribute with -ln NAME",
            ));
        }
        let node = match target {
            Some(n) => self.by_name.get(n.rsplit('|').next().unwrap_or(&n)).copied(),
            None => self.current,
        };
        let Some(node) = node else {
            return Err(err(
                head,
                "`addAttr` with no current node",
                "put it after the node's `createNode`",
            ));
        };
        self.scene.nodes[node].added.push(a);
        Ok(())
    }

    fn connect_attr(&mut self, head: &Tok, rest: &[Tok]) -> Result<(), ParseError> {
        let args = split_args(self.src, rest, CONNECT_FLAGS)?;
        let [s, d, ..] = args.positional.as_slice() else {
            return Err(err(
                head,
                "`connectAttr` needs a source and a destination plug",
                "write `connectAttr \"a.output\" \"b.input\";`",
            ));
        };
        let parse = |t: &Tok| {
            let p = PlugPath::parse(&t.text(self.src))
                .map_err(|m| err(t, m, "write a plug path such as \"node.attribute\""))?;
            if p.node.is_none() {
                return Err(err(t, "a connection end needs a node name", "write \"node.attribute\""));
            }
            Ok(p)
        };
        let src = parse(s)?;
        let mut dst = parse(d)?;
        let na = flag(&args, self.src, &["-na", "-nextAvailable"]).is_some();
        // Maya appends a `-na` connection at the next free element of the destination multi.
        let mut base = dst.clone();
        let last_index = base.segs.last_mut().and_then(|l| l.index.take());
        let next = self.next_free.entry(base.to_string()).or_insert(0);
        match last_index {
            Some(Index::One(i)) => *next = (*next).max(i.saturating_add(1)),
            None | Some(Index::All) if na => {
                if let Some(l) = dst.segs.last_mut() {
                    l.index = Some(Index::One(*next));
                }
                *next += 1;
            }
            _ => {}
        }
        self.scene.connections.push(Connection {
            src,
            dst,
            next_available: na,
            at: head.start,
        });
        Ok(())
    }
}

#[cfg(test)]
#[path = "tests_parse.rs"]
mod tests;
