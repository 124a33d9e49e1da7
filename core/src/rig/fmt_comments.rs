//! Carrying the comments of a rig file over to its canonical text.
//!
//! `sinew fmt` prints a rig from its graph and document ([`super::save`]), which holds
//! no comments; this module moves the comments of the file as written (its syntax
//! tree, kept by the loader) onto the syntax tree of the canonical text, entry by
//! entry, and [`super::fmt_print`] prints the result. It works on the syntax tree
//! alone, so every construct of the format keeps its comments without code of its own.
//!
//! Entries are matched by what they are: struct fields and map entries by key (node
//! fields through [`Ids::field`], so a Maya short name or a vec3 child written in the
//! file finds its canonical field; `set` keys through [`Ids::set_path`]), connections
//! by their two plugs ([`Ids::conn`]), `Use`s by position (by text when some were
//! expanded), and the entries of a value by position when the value has the same shape
//! as written. A value that changed shape (a matrix written as 4 rows of 4 is printed
//! as 16 numbers) keeps each comment next to the same number: a comment before an
//! entry goes before the first number of that entry, a comment after an entry after
//! its last number. A comment whose entry is gone from the canonical text (a value
//! equal to its default, a field now driven by a connection, an expanded `Use`) moves
//! to the next entry of the same container that remains, or to the container's end.

use super::fmt_print::{entries, Role};
use super::parse::{Ast, Comment, Node, Trivia};

/// How entries of the file as written are named in the canonical text.
pub(super) trait Ids {
    /// The canonical field name of node field `field` of a node of type `node_type`, and
    /// the attribute it belongs to (for a vec3 child written alone, printed as the whole
    /// vec3).
    fn field(&self, node_type: &str, field: &str) -> (String, Option<String>);
    /// A connection in canonical plug names.
    fn conn(&self, src: &str, dst: &str) -> String;
    /// A `set` key in canonical plug names.
    fn set_path(&self, path: &str) -> String;
}

/// Moves the comments of `orig` (the file as written) onto `new` (its canonical text).
pub(super) fn transfer(orig: &Node, new: &mut Node, ids: &dyn Ids) {
    if let Some(t) = orig.trivia.as_deref() {
        let nt = new.trivia_mut();
        nt.leading = t.leading.clone();
        nt.trailing = t.trailing.clone();
    }
    let left = container(orig, new, Role::Root, ids);
    new.trivia_mut().inner_end.extend(left);
}

/// A comment moved before another entry: on its own line.
fn own(mut c: Comment) -> Comment {
    c.own_line = true;
    c
}

fn all_comments(n: &Node) -> impl Iterator<Item = Comment> + '_ {
    n.comments().into_iter().cloned().map(own)
}

/// The identity of each entry of a container of role `role`.
fn ids_of(n: &Node, role: Role, ids: &dyn Ids) -> Vec<Option<(String, Option<String>)>> {
    let Some(items) = entries(n) else { return Vec::new() };
    let type_name = match &n.kind {
        Ast::Group { name: Some(t), .. } => t.as_str(),
        _ => "",
    };
    items
        .iter()
        .map(|(key, v)| {
            let key = key.as_deref();
            Some(match role {
                Role::NodeDecl => ids.field(type_name, key?),
                Role::Sets => (ids.set_path(&unquote(key?)), None),
                Role::Components | Role::Nodes => (unquote(key?), None),
                Role::Conns => (conn_id(v, ids)?, None),
                _ => (key?.to_string(), None),
            })
        })
        .collect()
}

fn unquote(k: &str) -> String {
    k.strip_prefix('"')
        .and_then(|s| s.strip_suffix('"'))
        .unwrap_or(k)
        .to_string()
}

fn conn_id(v: &Node, ids: &dyn Ids) -> Option<String> {
    match &v.kind {
        Ast::Str { value, .. } => {
            let (s, d) = value.split_once("->")?;
            Some(ids.conn(s.trim(), d.trim()))
        }
        Ast::Group { items, .. } if items.len() == 2 => {
            let s = items[0].value.kind.as_str()?;
            let d = items[1].value.kind.as_str()?;
            Some(ids.conn(s.trim(), d.trim()))
        }
        _ => None,
    }
}

/// Matches the entries of `orig` to those of `new`: for each original entry, the index
/// of its canonical entry.
fn match_entries(orig: &Node, new: &Node, role: Role, ids: &dyn Ids) -> Vec<Option<usize>> {
    let (Some(a), Some(b)) = (entries(orig), entries(new)) else {
        return Vec::new();
    };
    let positional = || (0..a.len()).map(|i| (i < b.len()).then_some(i)).collect();
    match role {
        Role::Uses if a.len() == b.len() => return positional(),
        Role::Value => {
            let keyed = matches!((&orig.kind, &new.kind), (Ast::Map(_), Ast::Map(_)))
                || (a.iter().all(|e| e.0.is_some()) && b.iter().all(|e| e.0.is_some()) && !a.is_empty());
            if !keyed {
                return positional();
            }
        }
        _ => {}
    }
    let (ia, ib) = if role == Role::Uses {
        let text = |n: &Node| {
            entries(n).map(|v| {
                v.iter()
                    .map(|(_, x)| {
                        let mut s = String::new();
                        super::doc_print::print_ast(&mut s, &x.kind);
                        Some((s, None))
                    })
                    .collect::<Vec<_>>()
            })
        };
        (text(orig).unwrap_or_default(), text(new).unwrap_or_default())
    } else {
        (ids_of(orig, role, ids), ids_of(new, role, ids))
    };
    let mut used = vec![false; b.len()];
    let mut out = vec![None; a.len()];
    // Primary names first, then the attribute a field belongs to.
    for pass in 0..2 {
        for (i, id) in ia.iter().enumerate() {
            if out[i].is_some() {
                continue;
            }
            let Some((primary, secondary)) = id else { continue };
            let want = if pass == 0 { Some(primary) } else { secondary.as_ref() };
            let Some(want) = want else { continue };
            let found = ib.iter().enumerate().position(|(k, other)| {
                !used[k]
                    && other.as_ref().is_some_and(|(p, s)| {
                        if pass == 0 {
                            p == want
                        } else {
                            p == want || s.as_ref() == Some(want)
                        }
                    })
            });
            if let Some(k) = found {
                used[k] = true;
                out[i] = Some(k);
            }
        }
    }
    out
}

/// Carries the comments inside container `orig` over to `new` (both of role `role`);
/// returns the comments that found no place inside `new` (the caller keeps them with
/// the entry).
fn container(orig: &Node, new: &mut Node, role: Role, ids: &dyn Ids) -> Vec<Comment> {
    if role == Role::Value && !orig.has_comments() {
        return Vec::new();
    }
    let Some(a) = entries(orig) else {
        // A scalar: nothing inside.
        return Vec::new();
    };
    let Some(b_len) = entries(new).map(|v| v.len()) else {
        // Written as a container, printed as a scalar: its comments stay with the entry.
        let mut left: Vec<Comment> = orig.kind.children().flat_map(all_comments).collect();
        left.extend(
            orig.trivia
                .as_ref()
                .map_or(&[][..], |t| &t.inner_end[..])
                .iter()
                .cloned()
                .map(own),
        );
        return left;
    };
    let same_shape = role != Role::Value
        || (std::mem::discriminant(&orig.kind) == std::mem::discriminant(&new.kind) && a.len() == b_len)
        || matches!((&orig.kind, &new.kind), (Ast::Map(_), Ast::Map(_)));
    if !same_shape {
        return by_leaves(orig, new);
    }
    let matches = match_entries(orig, new, role, ids);
    let mut pending: Vec<Comment> = Vec::new();
    let mut moves: Vec<(usize, Trivia, Vec<Comment>)> = Vec::new();
    for (i, (key, ov)) in a.iter().enumerate() {
        match matches.get(i).copied().flatten() {
            Some(k) => {
                let mut t = ov.trivia.as_deref().cloned().unwrap_or_default();
                t.inner_end.clear();
                let mut lead = std::mem::take(&mut pending);
                lead.append(&mut t.leading);
                t.leading = lead;
                let child_role = role.child(key.as_deref());
                let nv = value_mut(new, k);
                let left = match nv {
                    Some(nv) => container(ov, nv, child_role, ids),
                    None => Vec::new(),
                };
                moves.push((k, t, left));
            }
            None => pending.extend(all_comments(ov)),
        }
    }
    for (k, t, left) in moves {
        if let Some(nv) = value_mut(new, k) {
            let nt = nv.trivia_mut();
            nt.blank_before = t.blank_before;
            nt.leading.extend(t.leading);
            nt.trailing.extend(t.trailing);
            nt.trailing.extend(left.into_iter().map(|mut c| {
                // Kept on the entry's line: a line comment must end it, so it goes last.
                c.own_line = false;
                c
            }));
            nt.trailing.sort_by_key(Comment::is_line);
        }
    }
    let mut end = pending;
    end.extend(
        orig.trivia
            .as_ref()
            .map_or(&[][..], |t| &t.inner_end[..])
            .iter()
            .cloned(),
    );
    new.trivia_mut().inner_end.extend(end);
    Vec::new()
}

/// The value node of entry `k` of a container.
fn value_mut(n: &mut Node, k: usize) -> Option<&mut Node> {
    match &mut n.kind {
        Ast::List(v) => v.get_mut(k),
        Ast::Map(v) => v.get_mut(k).map(|e| &mut e.1),
        Ast::Group { items, .. } => items.get_mut(k).map(|i| &mut i.value),
        _ => None,
    }
}

/// Where a comment sits relative to the scalars ("leaves") of a value.
enum Anchor {
    /// Before leaf i.
    Before(usize),
    /// After leaf i.
    After(usize),
}

/// Leaves of `n` in order; for each node below the root, its first and last leaf.
fn anchors(n: &Node, root: bool, next: &mut usize, out: &mut Vec<(Anchor, Comment)>) {
    let t = n.trivia.as_deref();
    let first = *next;
    if !root {
        out.extend(
            t.iter()
                .flat_map(|t| &t.leading)
                .cloned()
                .map(|c| (Anchor::Before(first), c)),
        );
    }
    let kids: Vec<&Node> = n.kind.children().collect();
    if kids.is_empty() && entries(n).is_none() {
        *next += 1;
    }
    for k in kids {
        anchors(k, false, next, out);
    }
    let last = next.saturating_sub(1).max(first);
    out.extend(
        t.iter()
            .flat_map(|t| &t.inner_end)
            .cloned()
            .map(|c| (Anchor::After(last), c)),
    );
    if !root {
        out.extend(
            t.iter()
                .flat_map(|t| &t.trailing)
                .cloned()
                .map(|c| (Anchor::After(last), c)),
        );
    }
}

/// Places comments on the outermost node below the root that starts (`Before`) or ends
/// (`After`) at the anchored leaf. Returns the comments with no such node.
fn place(n: &mut Node, root: bool, next: &mut usize, todo: &mut Vec<Option<(Anchor, Comment)>>) {
    let first = *next;
    let leaves = count_leaves(n);
    let last = (first + leaves).saturating_sub(1);
    if !root && leaves > 0 {
        for slot in todo.iter_mut() {
            let fits = match slot {
                Some((Anchor::Before(i), _)) => *i == first,
                Some((Anchor::After(i), _)) => *i == last,
                None => false,
            };
            if fits {
                if let Some((a, c)) = slot.take() {
                    match a {
                        Anchor::Before(_) => n.trivia_mut().leading.push(own(c)),
                        Anchor::After(_) => n.trivia_mut().trailing.push(c),
                    }
                }
            }
        }
    }
    match &mut n.kind {
        Ast::List(v) => v.iter_mut().for_each(|k| place(k, false, next, todo)),
        Ast::Map(v) => {
            for (k, x) in v.iter_mut() {
                // A map key prints without comments: the ones anchored at it lead the value.
                let (kf, kn) = (*next, count_leaves(k));
                for slot in todo.iter_mut() {
                    let at_key = match slot {
                        Some((Anchor::Before(i), _)) => *i == kf,
                        Some((Anchor::After(i), _)) => kn > 0 && *i == kf + kn - 1,
                        None => false,
                    };
                    if at_key {
                        if let Some((_, c)) = slot.take() {
                            x.trivia_mut().leading.push(own(c));
                        }
                    }
                }
                *next += kn;
                place(x, false, next, todo);
            }
        }
        Ast::Group { items, .. } => items.iter_mut().for_each(|i| place(&mut i.value, false, next, todo)),
        _ => *next += 1,
    }
    if let Some(t) = n.trivia.as_deref_mut() {
        t.trailing.sort_by_key(Comment::is_line);
    }
}

fn count_leaves(n: &Node) -> usize {
    match entries(n) {
        None => 1,
        Some(_) => n.kind.children().map(count_leaves).sum(),
    }
}

/// Comments of a value whose shape changed, kept next to the same scalars.
fn by_leaves(orig: &Node, new: &mut Node) -> Vec<Comment> {
    let mut found = Vec::new();
    anchors(orig, true, &mut 0, &mut found);
    let total = count_leaves(new);
    let mut todo: Vec<Option<(Anchor, Comment)>> = found
        .into_iter()
        .map(|(a, c)| {
            // Past the new value's end: after its last scalar.
            let a = match a {
                Anchor::Before(i) if i >= total => Anchor::After(total.saturating_sub(1)),
                Anchor::After(i) if i >= total => Anchor::After(total.saturating_sub(1)),
                a => a,
            };
            Some((a, c))
        })
        .collect();
    place(new, true, &mut 0, &mut todo);
    let left: Vec<Comment> = todo.into_iter().flatten().map(|(_, c)| c).collect();
    if !left.is_empty() && entries(new).is_some() {
        new.trivia_mut().inner_end.extend(left.into_iter().map(own));
        return Vec::new();
    }
    left
}
