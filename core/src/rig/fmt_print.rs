//! Printing a rig's syntax tree in canonical layout, with its comments.
//!
//! Layout by role: the `Rig( .. )`, its sections (`components`, `uses`, `nodes`,
//! `connections`, `set`) and component bodies are one entry per line; a node is one line
//! when it fits in [`LINE`] characters (or has one field), else one field per line;
//! values are one line. Comments break that: a value with comments inside is printed
//! over lines, scalars filling lines (a line ends after each trailing comment, so a
//! matrix with a comment per row keeps its rows) and other entries one per line.
//! Leading comments go on their own lines before their entry, trailing ones after it
//! on its line; a blank line before an entry or comment is kept (one, however many
//! there were), except right after an opening bracket.

use super::doc_print::print_ast;
use super::parse::{Ast, Comment, Node};

/// The width a node line may take before its fields go one per line.
pub(super) const LINE: usize = 120;

/// What a container is in a rig file, which decides its layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Role {
    /// `Rig( .. )`.
    Root,
    /// `components: { .. }`.
    Components,
    /// A component body `( nodes: .., .. )`.
    Body,
    /// `uses: [ .. ]`.
    Uses,
    /// `nodes: { .. }`.
    Nodes,
    /// One node, `type( .. )`.
    NodeDecl,
    /// `connections: [ .. ]`.
    Conns,
    /// `set: { .. }`.
    Sets,
    /// Any value.
    Value,
}

impl Role {
    /// The role of the entry `key` of a container of this role.
    pub(super) fn child(self, key: Option<&str>) -> Role {
        match self {
            Role::Root | Role::Body => match key {
                Some("components") if self == Role::Root => Role::Components,
                Some("uses") => Role::Uses,
                Some("nodes") => Role::Nodes,
                Some("connections") => Role::Conns,
                Some("set") => Role::Sets,
                _ => Role::Value,
            },
            Role::Components => Role::Body,
            Role::Nodes => Role::NodeDecl,
            _ => Role::Value,
        }
    }

    fn vertical(self) -> bool {
        !matches!(self, Role::NodeDecl | Role::Value)
    }
}

/// The entries of a container: the key as printed (`name: ` or `"k": `) and the value.
pub(super) fn entries(n: &Node) -> Option<Vec<(Option<String>, &Node)>> {
    match &n.kind {
        Ast::List(v) => Some(v.iter().map(|x| (None, x)).collect()),
        Ast::Map(v) => Some(
            v.iter()
                .map(|(k, x)| {
                    let mut s = String::new();
                    print_ast(&mut s, &k.kind);
                    (Some(s), x)
                })
                .collect(),
        ),
        Ast::Group { items, .. } => Some(
            items
                .iter()
                .map(|i| (i.key.as_ref().map(|k| k.0.clone()), &i.value))
                .collect(),
        ),
        _ => None,
    }
}

fn brackets(n: &Node) -> (String, char) {
    match &n.kind {
        Ast::List(_) => ("[".into(), ']'),
        Ast::Map(_) => ("{".into(), '}'),
        Ast::Group { name, .. } => (format!("{}(", name.as_deref().unwrap_or("")), ')'),
        _ => (String::new(), ' '),
    }
}

/// Whether comments are attached to entries inside `n` (not to `n` itself as an entry).
fn comments_inside(n: &Node) -> bool {
    n.trivia.as_ref().is_some_and(|t| !t.inner_end.is_empty()) || n.kind.children().any(Node::has_comments)
}

fn column(out: &str) -> usize {
    out.len() - out.rfind('\n').map_or(0, |i| i + 1)
}

fn indent(out: &mut String, ind: usize) {
    out.extend(std::iter::repeat_n(' ', ind));
}

fn blank_line(out: &mut String) {
    if !out.ends_with("\n\n") && !out.ends_with("(\n") && !out.ends_with("[\n") && !out.ends_with("{\n") {
        out.push('\n');
    }
}

/// Comments on their own lines at `ind`, keeping one blank line where there was one.
fn own_lines(out: &mut String, comments: &[Comment], ind: usize) {
    for c in comments {
        if c.blank_before {
            blank_line(out);
        }
        indent(out, ind);
        out.push_str(&c.text);
        out.push('\n');
    }
}

fn trailing(out: &mut String, comments: &[Comment]) {
    for c in comments {
        out.push(' ');
        out.push_str(&c.text);
    }
}

/// Prints a whole file: header comments, the root, end-of-file comments.
pub(super) fn print_file(root: &Node) -> String {
    let mut out = String::new();
    let t = root.trivia.as_deref();
    own_lines(&mut out, t.map_or(&[][..], |t| &t.leading), 0);
    print_value(&mut out, root, Role::Root, 0);
    let after = t.map_or(&[][..], |t| &t.trailing);
    let same_line = after.iter().take_while(|c| !c.own_line).count();
    trailing(&mut out, &after[..same_line]);
    out.push('\n');
    own_lines(&mut out, &after[same_line..], 0);
    out
}

/// Prints a value whose first character goes at the end of `out` (indentation `ind`
/// for its lines).
pub(super) fn print_value(out: &mut String, n: &Node, role: Role, ind: usize) {
    let Some(items) = entries(n) else {
        print_ast(out, &n.kind);
        return;
    };
    let inside = comments_inside(n);
    let vertical = match role {
        Role::NodeDecl => {
            let mut one = String::new();
            print_ast(&mut one, &n.kind);
            // `,` follows a node; one field stays on its line however long.
            inside || (column(out) + one.chars().count() + 1 > LINE && items.len() > 1)
        }
        Role::Value => inside,
        _ => true,
    };
    if !vertical {
        print_ast(out, &n.kind);
        return;
    }
    let (open, close) = brackets(n);
    out.push_str(&open);
    let inner_end = n.trivia.as_ref().map_or(&[][..], |t| &t.inner_end[..]);
    if items.is_empty() && inner_end.is_empty() && !role.vertical() {
        out.push(close);
        return;
    }
    let fill = role == Role::Value && items.iter().all(|(_, v)| entries(v).is_none());
    let inner = ind + 4;
    // A comment on the opening bracket's line stays there.
    let first_leading = items
        .first()
        .and_then(|(_, v)| v.trivia.as_ref())
        .map_or(&[][..], |t| &t.leading[..]);
    let on_open = first_leading.iter().take_while(|c| !c.own_line).count();
    trailing(out, &first_leading[..on_open]);
    out.push('\n');
    let mut line_open = false; // fill mode: a line of scalars is being written
    for (i, (key, v)) in items.iter().enumerate() {
        let t = v.trivia.as_deref();
        let leading = t.map_or(&[][..], |t| &t.leading[..]);
        let leading = if i == 0 { &leading[on_open..] } else { leading };
        let blank = t.is_some_and(|t| t.blank_before) && i > 0;
        let mut text = String::new();
        if let Some(k) = key {
            text.push_str(k);
            text.push_str(": ");
        }
        if fill && leading.is_empty() && !blank {
            print_ast(&mut text, &v.kind);
            text.push(',');
            if line_open && column(out) + 1 + text.chars().count() <= LINE {
                out.push(' ');
            } else {
                if line_open {
                    out.push('\n');
                }
                indent(out, inner);
            }
            out.push_str(&text);
            line_open = true;
        } else {
            if line_open {
                out.push('\n');
            }
            if leading.first().is_some_and(|c| c.blank_before) && i > 0 {
                blank_line(out);
            }
            let mut lead = leading.to_vec();
            if let Some(c) = lead.first_mut() {
                c.blank_before = false;
            }
            own_lines(out, &lead, inner);
            if blank {
                blank_line(out);
            }
            indent(out, inner);
            out.push_str(&text);
            print_value(out, v, role.child(key.as_deref()), inner);
            out.push(',');
            line_open = fill;
        }
        let tr = t.map_or(&[][..], |t| &t.trailing[..]);
        if !tr.is_empty() {
            trailing(out, tr);
            line_open = false;
            out.push('\n');
        } else if !fill {
            out.push('\n');
        }
    }
    if line_open {
        out.push('\n');
    }
    own_lines(out, inner_end, inner);
    indent(out, ind);
    out.push(close);
}
