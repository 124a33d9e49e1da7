//! Printing rig documents as canonical text (the half of [`super::doc`] that writes):
//! values ([`print_ast`]), nodes, connections, `Use`s and whole documents
//! ([`print_document`]).

use std::fmt::Write as _;

use super::doc::{Body, RigDocument, UseDecl};
use super::parse::Ast;

/// Appends `s` as a RON string literal.
pub fn quote(out: &mut String, s: &str) {
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{{{:x}}}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
}

/// Prints a value on one line.
pub fn print_ast(out: &mut String, a: &Ast) {
    match a {
        Ast::Bool(b) => {
            let _ = write!(out, "{b}");
        }
        Ast::Int(i) => {
            let _ = write!(out, "{i}");
        }
        Ast::Float(x) => {
            let _ = write!(out, "{x:?}");
        }
        Ast::Str { value, .. } => quote(out, value),
        Ast::Ident(s) => out.push_str(s),
        Ast::List(v) => {
            out.push('[');
            for (i, x) in v.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                print_ast(out, &x.kind);
            }
            out.push(']');
        }
        Ast::Map(v) => {
            out.push('{');
            for (i, (k, x)) in v.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                print_ast(out, &k.kind);
                out.push_str(": ");
                print_ast(out, &x.kind);
            }
            out.push('}');
        }
        Ast::Group { name, items } => {
            if let Some(n) = name {
                out.push_str(n);
            }
            out.push('(');
            for (i, it) in items.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                if let Some((k, _)) = &it.key {
                    out.push_str(k);
                    out.push_str(": ");
                }
                print_ast(out, &it.value.kind);
            }
            out.push(')');
        }
    }
}

/// A node ready to print: type, parent and attribute values as values.
pub struct PrintNode<'a> {
    /// Name.
    pub name: &'a str,
    /// Type.
    pub type_name: &'a str,
    /// Parent name.
    pub parent: Option<&'a str>,
    /// Attributes.
    pub fields: Vec<(String, Ast)>,
}

const LINE: usize = 120;

fn print_node(out: &mut String, ind: &str, n: &PrintNode<'_>) {
    let mut parts: Vec<String> = Vec::new();
    if let Some(p) = n.parent {
        let mut s = String::from("parent: ");
        quote(&mut s, p);
        parts.push(s);
    }
    for (k, v) in &n.fields {
        let mut s = format!("{k}: ");
        print_ast(&mut s, v);
        parts.push(s);
    }
    let mut head = String::new();
    quote(&mut head, n.name);
    let one = format!("{ind}{head}: {}({}),", n.type_name, parts.join(", "));
    if one.chars().count() <= LINE || parts.len() <= 1 {
        out.push_str(&one);
        out.push('\n');
    } else {
        let _ = writeln!(out, "{ind}{head}: {}(", n.type_name);
        for p in parts {
            let _ = writeln!(out, "{ind}    {p},");
        }
        let _ = writeln!(out, "{ind}),");
    }
}

fn conn_text(src: &str, dst: &str) -> String {
    let mut s = String::new();
    quote(&mut s, &format!("{src} -> {dst}"));
    s
}

/// Prints the uses list entries.
fn print_use(u: &UseDecl) -> String {
    let mut parts = Vec::new();
    let q = |s: &str| {
        let mut o = String::new();
        quote(&mut o, s);
        o
    };
    if let Some((c, _)) = &u.component {
        parts.push(format!("component: {}", q(c)));
    }
    if let Some((f, _)) = &u.file {
        parts.push(format!("file: {}", q(f)));
    }
    if !u.prefix.is_empty() {
        parts.push(format!("prefix: {}", q(&u.prefix)));
    }
    if let Some(p) = u.mirror {
        parts.push(format!("mirror: {}", p.name()));
    }
    let default_rename = UseDecl {
        rename: None,
        ..u.clone()
    }
    .renames();
    if let Some(r) = &u.rename {
        if *r != default_rename {
            let pairs: Vec<String> = r.iter().map(|(a, b)| format!("({}, {})", q(a), q(b))).collect();
            parts.push(format!("rename: [{}]", pairs.join(", ")));
        }
    }
    if !u.set.is_empty() {
        let entries: Vec<String> = u
            .set
            .iter()
            .map(|s| {
                let mut o = q(&s.path);
                o.push_str(": ");
                print_ast(&mut o, &s.value.kind);
                o
            })
            .collect();
        parts.push(format!("set: {{{}}}", entries.join(", ")));
    }
    format!("Use({})", parts.join(", "))
}

/// The sections of a body, ready to print.
pub struct PrintBody<'a> {
    /// `uses` entries.
    pub uses: Vec<UseDecl>,
    /// Nodes.
    pub nodes: Vec<PrintNode<'a>>,
    /// Connections `(src, dst)`.
    pub connections: Vec<(String, String)>,
    /// Overrides `(path, value)`.
    pub set: Vec<(String, Ast)>,
}

fn print_body(out: &mut String, ind: &str, b: &PrintBody<'_>) {
    let inner = format!("{ind}    ");
    if !b.uses.is_empty() {
        let _ = writeln!(out, "{ind}uses: [");
        for u in &b.uses {
            let _ = writeln!(out, "{inner}{},", print_use(u));
        }
        let _ = writeln!(out, "{ind}],");
    }
    if !b.nodes.is_empty() {
        let _ = writeln!(out, "{ind}nodes: {{");
        for n in &b.nodes {
            print_node(out, &inner, n);
        }
        let _ = writeln!(out, "{ind}}},");
    }
    if !b.connections.is_empty() {
        let _ = writeln!(out, "{ind}connections: [");
        for (s, d) in &b.connections {
            let _ = writeln!(out, "{inner}{},", conn_text(s, d));
        }
        let _ = writeln!(out, "{ind}],");
    }
    if !b.set.is_empty() {
        let _ = writeln!(out, "{ind}set: {{");
        for (p, v) in &b.set {
            let mut s = String::new();
            quote(&mut s, p);
            s.push_str(": ");
            print_ast(&mut s, v);
            let _ = writeln!(out, "{inner}{s},");
        }
        let _ = writeln!(out, "{ind}}},");
    }
}

/// The printable form of a component body (kept as written, canonically spaced).
pub fn component_print_body(b: &Body) -> PrintBody<'_> {
    PrintBody {
        uses: b.uses.clone(),
        nodes: b
            .nodes
            .iter()
            .map(|n| PrintNode {
                name: &n.name,
                type_name: &n.type_name,
                parent: n.parent.as_ref().map(|p| p.0.as_str()),
                fields: n.fields.iter().map(|(k, _, v)| (k.clone(), v.kind.clone())).collect(),
            })
            .collect(),
        connections: b.connections.iter().map(|c| (c.src.clone(), c.dst.clone())).collect(),
        set: b.set.iter().map(|s| (s.path.clone(), s.value.kind.clone())).collect(),
    }
}

fn num(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        format!("{}", x as i64)
    } else {
        format!("{x:?}")
    }
}

/// Prints a whole rig: header, components, then `main`.
pub fn print_document(doc: &RigDocument, main: &PrintBody<'_>) -> String {
    let mut out = String::from("Rig(\n");
    if let Some(n) = &doc.name {
        out.push_str("    name: ");
        quote(&mut out, n);
        out.push_str(",\n");
    }
    if let Some(f) = doc.fps {
        let _ = writeln!(out, "    fps: {f:?},");
    }
    if let Some((a, b)) = doc.frames {
        let _ = writeln!(out, "    frames: ({}, {}),", num(a), num(b));
    }
    if !doc.components.is_empty() {
        out.push_str("    components: {\n");
        for c in &doc.components {
            out.push_str("        ");
            quote(&mut out, &c.name);
            out.push_str(": (\n");
            print_body(&mut out, "            ", &component_print_body(&c.body));
            out.push_str("        ),\n");
        }
        out.push_str("    },\n");
    }
    print_body(&mut out, "    ", main);
    out.push_str(")\n");
    out
}
