//! Test support for comment-keeping formatting: insert comments at every position of a
//! rig file, and list where each comment is attached. Used by the core's tests and the
//! facade's tests over `graphs/` (public for them; not part of the rig API).

use std::path::Path;
use std::sync::Arc;

use super::parse::{parse, Ast, Node};
use super::{format_rig_str, graph_eq, load_rig_str};
use crate::registry::Registry;

/// The byte offsets before and after each token of `text` (strings, numbers and names,
/// brackets, `,` and `:`), where a comment may go; none inside or after a comment.
pub fn gaps(text: &str) -> Vec<usize> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let start = i;
        match c {
            b' ' | b'\t' | b'\n' | b'\r' => {
                i += 1;
                continue;
            }
            b'"' => {
                i += 1;
                while i < b.len() && b[i] != b'"' {
                    i += if b[i] == b'\\' { 2 } else { 1 };
                }
                i += 1;
            }
            // Comments are skipped: no gap inside or right after a line comment.
            b'/' if b.get(i + 1) == Some(&b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
                continue;
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                i += 2;
                while i + 1 < b.len() && !(b[i] == b'*' && b[i + 1] == b'/') {
                    i += 1;
                }
                i += 2;
                continue;
            }
            b'(' | b')' | b'[' | b']' | b'{' | b'}' | b',' | b':' => i += 1,
            _ => {
                while i < b.len() && (b[i].is_ascii_alphanumeric() || matches!(b[i], b'_' | b'.' | b'+' | b'-' | b'#'))
                {
                    i += 1;
                }
                if i == start {
                    i += 1;
                }
            }
        }
        out.push(start);
        out.push(i.min(b.len()));
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// `text` with a block comment `/*cN*/` at every gap between tokens (N counting up).
pub fn with_block_comments(text: &str) -> String {
    let mut out = String::new();
    let mut last = 0;
    for (n, g) in gaps(text).into_iter().enumerate() {
        out.push_str(&text[last..g]);
        out.push_str(&format!("/*c{n}*/"));
        last = g;
    }
    out.push_str(&text[last..]);
    out
}

/// `text` with a block comment `/*cN*/` at every `step`-th gap between tokens, starting
/// with gap `phase`: values with comments next to values without.
pub fn with_some_block_comments(text: &str, step: usize, phase: usize) -> String {
    let mut out = String::new();
    let mut last = 0;
    for (n, g) in gaps(text)
        .into_iter()
        .enumerate()
        .filter(|(n, _)| n % step.max(1) == phase)
    {
        out.push_str(&text[last..g]);
        out.push_str(&format!("/*c{n}*/"));
        last = g;
    }
    out.push_str(&text[last..]);
    out
}

/// `text` with a line comment `// lN` at the end of every line and a comment line
/// `// oN` before every line.
pub fn with_line_comments(text: &str) -> String {
    let mut out = String::new();
    for (n, line) in text.lines().enumerate() {
        let ind = line.len() - line.trim_start().len();
        out.push_str(&format!("{}// o{n}\n{line} // l{n}\n", &line[..ind]));
    }
    out
}

/// Every comment of a parsed file in source order, with the entry it is attached to
/// (a path of keys and positions from the root) and how (`lead`, `trail`, `end`).
pub fn attachments(text: &str) -> Result<Vec<(String, &'static str, String)>, String> {
    let root = parse(text, &Arc::from(Path::new("check.ron"))).map_err(|d| d.render())?;
    let mut out = Vec::new();
    walk(&root, "", &mut out);
    Ok(out)
}

fn walk(n: &Node, path: &str, out: &mut Vec<(String, &'static str, String)>) {
    let t = n.trivia.as_deref();
    for c in t.iter().flat_map(|t| &t.leading) {
        out.push((path.to_string(), "lead", c.text.clone()));
    }
    match &n.kind {
        Ast::List(v) => v
            .iter()
            .enumerate()
            .for_each(|(i, x)| walk(x, &format!("{path}/{i}"), out)),
        Ast::Map(v) => v.iter().for_each(|(k, x)| {
            let mut key = String::new();
            super::doc_print::print_ast(&mut key, &k.kind);
            walk(x, &format!("{path}/{key}"), out)
        }),
        Ast::Group { items, .. } => items.iter().enumerate().for_each(|(i, it)| {
            let key = it.key.as_ref().map_or(i.to_string(), |k| k.0.clone());
            walk(&it.value, &format!("{path}/{key}"), out)
        }),
        _ => {}
    }
    for c in t.iter().flat_map(|t| &t.inner_end) {
        out.push((path.to_string(), "end", c.text.clone()));
    }
    for c in t.iter().flat_map(|t| &t.trailing) {
        out.push((path.to_string(), "trail", c.text.clone()));
    }
}

/// The comment texts of `text` (`/*..*/` and `//..`) in order, by a plain scan.
pub fn comment_texts(text: &str) -> Vec<String> {
    attachments(text)
        .map(|a| a.into_iter().map(|x| x.2).collect())
        .unwrap_or_default()
}

/// Comments inserted at every position of a rig's canonical text are all kept, in
/// order, each attached to the same entry (as the parser attaches it), and the result
/// loads to the same graph and is a fixed point.
pub fn check_canonical_with_comments(text: &str, path: &Path, registry: &Arc<Registry>) {
    let canonical = format_rig_str(text, path, registry).unwrap_or_else(|d| panic!("{}", d.render()));
    let base = load_rig_str(&canonical, path, registry).expect("canonical loads");
    for (kind, commented) in [
        ("block", with_block_comments(&canonical)),
        ("line", with_line_comments(&canonical)),
    ] {
        let out = format_rig_str(&commented, path, registry)
            .unwrap_or_else(|d| panic!("{} ({kind}): {}\n{commented}", path.display(), d.render()));
        let want = attachments(&commented).expect("commented parses");
        let got = attachments(&out).expect("output parses");
        assert!(want.len() > 20, "{}: only {} comments", path.display(), want.len());
        if want != got {
            let k = want
                .iter()
                .zip(&got)
                .position(|(a, b)| a != b)
                .unwrap_or(want.len().min(got.len()));
            panic!(
                "{} ({kind}): comment {k} differs: want {:?}, got {:?}\n{out}",
                path.display(),
                want.get(k),
                got.get(k)
            );
        }
        let again = load_rig_str(&out, path, registry).expect("output loads");
        graph_eq(&base.graph, &again.graph).unwrap_or_else(|e| panic!("{} ({kind}): {e}", path.display()));
        assert_eq!(
            format_rig_str(&out, path, registry).expect("reformat"),
            out,
            "{} ({kind}): not a fixed point",
            path.display()
        );
    }
}

/// Comments inserted everywhere into a rig as written (not canonical: values, order
/// and spelling change) all survive, once each.
pub fn check_written_with_comments(text: &str, path: &Path, registry: &Arc<Registry>) {
    let base = load_rig_str(text, path, registry).unwrap_or_else(|d| panic!("{}", d.render()));
    for commented in [with_block_comments(text), with_line_comments(text)] {
        let out = format_rig_str(&commented, path, registry).unwrap_or_else(|d| panic!("{}", d.render()));
        let mut want = comment_texts(&commented);
        let mut got = comment_texts(&out);
        assert_eq!(
            want.len(),
            got.len(),
            "{}: comments lost or added\n{out}",
            path.display()
        );
        want.sort();
        got.sort();
        assert_eq!(want, got, "{}", path.display());
        let again = load_rig_str(&out, path, registry).expect("output loads");
        graph_eq(&base.graph, &again.graph).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(
            format_rig_str(&out, path, registry).expect("reformat"),
            out,
            "{}: not a fixed point",
            path.display()
        );
    }
}

/// The loader's document takes the values of node fields out of the syntax tree it keeps
/// for `sinew fmt` (see [`super::doc::read_document_taking`]): formatting must give the
/// same text as with the tree as parsed. Checked on `text` as written, with a line
/// comment on every line, and with block comments at every third gap (each phase), so
/// values with and without comments sit side by side. Returns false (checking nothing)
/// when `text` does not load.
pub fn check_fmt_with_taken_values(text: &str, path: &Path, registry: &Arc<Registry>) -> bool {
    if load_rig_str(text, path, registry).is_err() {
        return false;
    }
    let variants = [
        text.to_string(),
        with_line_comments(text),
        with_some_block_comments(text, 3, 0),
        with_some_block_comments(text, 3, 1),
        with_some_block_comments(text, 3, 2),
    ];
    for (k, t) in variants.iter().enumerate() {
        // A comment between `r` and the quote of a raw string breaks it: such a variant
        // does not load and has nothing to compare.
        let Ok(mut rig) = load_rig_str(t, path, registry) else {
            continue;
        };
        let taken = super::save_rig(&rig.graph, &rig.document);
        let file: Arc<Path> = Arc::from(path);
        rig.document.syntax = Some(parse(t, &file).expect("variant parses"));
        let whole = super::save_rig(&rig.graph, &rig.document);
        assert_eq!(
            taken,
            whole,
            "{} (variant {k}): fmt depends on the values taken out of the tree",
            path.display()
        );
    }
    true
}
