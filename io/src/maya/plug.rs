//! Maya plug paths as written in a `.ma` file: `node.attr`, `.attr` (the current node),
//! `node.compound[3].child`, element ranges `.wl[0:11].w`, and DAG paths for the node
//! (`|group|shape.attr`).

use std::fmt;

/// The index part of a path segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Index {
    /// `[7]`
    One(u32),
    /// `[0:11]` (both ends included, as in Maya).
    Range(u32, u32),
    /// `[*]` or `[]` (every element; `-na` connections and component lists).
    All,
}

impl Index {
    /// The first and last element (both included); `None` for [`Index::All`].
    pub fn bounds(self) -> Option<(u32, u32)> {
        match self {
            Index::One(k) => Some((k, k)),
            Index::Range(x, y) => Some((x, y)),
            Index::All => None,
        }
    }
}

/// One `name[index]` segment of an attribute path.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Seg {
    /// Attribute name as written (short or long).
    pub name: String,
    /// Element index, if any.
    pub index: Option<Index>,
}

/// A parsed plug path.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlugPath {
    /// The node part (`None` for `.attr`, the current node).
    pub node: Option<String>,
    /// Attribute segments, outermost first.
    pub segs: Vec<Seg>,
}

fn parse_index(s: &str) -> Result<Index, String> {
    let s = s.trim();
    if s.is_empty() || s == "*" {
        return Ok(Index::All);
    }
    let num = |t: &str| {
        t.trim()
            .parse::<u32>()
            .map_err(|_| format!("`{t}` is not an element index (a whole number >= 0)"))
    };
    match s.split_once(':') {
        Some((a, b)) => {
            let (a, b) = (num(a)?, num(b)?);
            if b < a {
                return Err(format!("element range [{a}:{b}] ends before it starts"));
            }
            Ok(Index::Range(a, b))
        }
        None => Ok(Index::One(num(s)?)),
    }
}

/// Parses the attribute part `attr[1].child` (no leading dot).
pub fn parse_attr_path(s: &str) -> Result<Vec<Seg>, String> {
    if s.is_empty() {
        return Err("empty attribute name".into());
    }
    let mut segs = Vec::new();
    for part in split_dots(s) {
        let (name, index) = match part.find('[') {
            Some(open) => {
                let close = part
                    .rfind(']')
                    .filter(|&c| c > open && c == part.len() - 1)
                    .ok_or_else(|| format!("`{part}` has an unclosed or misplaced `[`"))?;
                (&part[..open], Some(parse_index(&part[open + 1..close])?))
            }
            None => (part, None),
        };
        if name.is_empty() {
            return Err(format!("`{s}` has an empty attribute name"));
        }
        if !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(format!("`{name}` is not an attribute name (letters, digits, `_`)"));
        }
        segs.push(Seg {
            name: name.to_string(),
            index,
        });
    }
    Ok(segs)
}

/// Splits on dots outside brackets.
fn split_dots(s: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut depth = 0i32;
    let mut start = 0;
    for (i, c) in s.char_indices() {
        match c {
            '[' => depth += 1,
            ']' => depth -= 1,
            '.' if depth == 0 => {
                out.push(&s[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&s[start..]);
    out
}

impl PlugPath {
    /// Parses `node.attr...` or `.attr...`.
    pub fn parse(s: &str) -> Result<PlugPath, String> {
        let dot = s
            .find('.')
            .ok_or_else(|| format!("`{s}` is not a plug path: write `node.attribute` or `.attribute`"))?;
        let node = &s[..dot];
        if node.contains('[') {
            return Err(format!("`{s}`: a node name cannot contain `[`"));
        }
        Ok(PlugPath {
            node: (!node.is_empty()).then(|| node.to_string()),
            segs: parse_attr_path(&s[dot + 1..])?,
        })
    }

    /// The attribute part written back (`a[1].b`).
    pub fn attr_text(&self) -> String {
        let mut s = String::new();
        write_segs(&mut s, &self.segs);
        s
    }
}

/// Writes segments as `a[1].b`.
pub fn write_segs(out: &mut String, segs: &[Seg]) {
    use std::fmt::Write as _;
    for (k, seg) in segs.iter().enumerate() {
        if k > 0 {
            out.push('.');
        }
        out.push_str(&seg.name);
        match seg.index {
            Some(Index::One(i)) => {
                let _ = write!(out, "[{i}]");
            }
            Some(Index::Range(a, b)) => {
                let _ = write!(out, "[{a}:{b}]");
            }
            Some(Index::All) => out.push_str("[*]"),
            None => {}
        }
    }
}

impl fmt::Display for PlugPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(n) = &self.node {
            f.write_str(n)?;
        }
        write!(f, ".{}", self.attr_text())
    }
}

/// The last `|`-separated part of a node name (`|a|b` → `b`) with a leading root namespace
/// `:` removed (`:time1` → `time1`).
pub fn short_name(name: &str) -> &str {
    let leaf = name.rsplit('|').next().unwrap_or(name);
    leaf.strip_prefix(':').unwrap_or(leaf)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seg(name: &str, index: Option<Index>) -> Seg {
        Seg {
            name: name.into(),
            index,
        }
    }

    #[test]
    fn paths_parse() {
        let p = PlugPath::parse(".wl[0:11].w").unwrap();
        assert_eq!(p.node, None);
        assert_eq!(p.segs, vec![seg("wl", Some(Index::Range(0, 11))), seg("w", None)]);
        let p = PlugPath::parse("|a|b_Shape.iog.og[2].gid").unwrap();
        assert_eq!(p.node.as_deref(), Some("|a|b_Shape"));
        assert_eq!(p.segs.len(), 3);
        assert_eq!(p.to_string(), "|a|b_Shape.iog.og[2].gid");
        let p = PlugPath::parse("blendShape10.it[0].itg[0].iti[5333].igt").unwrap();
        assert_eq!(p.segs[2], seg("iti", Some(Index::One(5333))));
        assert_eq!(PlugPath::parse("x.dsm[]").unwrap().segs[0].index, Some(Index::All));
        assert_eq!(PlugPath::parse("._f").unwrap().segs[0].name, "_f");
    }

    #[test]
    fn bad_paths_fail_with_a_reason() {
        for bad in [
            "noDot", ".", ".a[", ".a[1", ".a[x]", ".a[3:1]", ".a..b", "n[0].a", ".a]b", ".a b",
        ] {
            assert!(PlugPath::parse(bad).is_err(), "{bad} should fail");
        }
    }

    #[test]
    fn short_names() {
        assert_eq!(short_name("|a|b"), "b");
        assert_eq!(short_name(":time1"), "time1");
        assert_eq!(short_name("ns:x"), "ns:x");
    }
}
