//! Plug paths as text: `node.attr`, `node.attrX`, `node.attr[3]`,
//! `node.attr[3].child`. Parsing is separate from lookup so the graph, the
//! compiled program and the rig loader all read paths the same way.

use crate::spec::{AttrId, AttrSpec, NodeSpec};
use crate::value::AttrType;

/// The parts of a plug path, before any lookup.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlugPath<'a> {
    /// Node name.
    pub node: &'a str,
    /// Attribute (or vec3 child) name.
    pub attr: &'a str,
    /// Element index, for multi attributes.
    pub index: Option<u32>,
    /// Child name after the index (`input3D[0].input3Dx`).
    pub child: Option<&'a str>,
}

/// The path of a plug as text: `node.attr`, `node.attr[index]`, and for a component the
/// child's name (`node.translateX`, `node.attr[index].translateX`, or `.x`/`.y`/`.z` for an
/// attribute without named children).
pub fn plug_path_text(node: &str, a: &AttrSpec, index: Option<u32>, component: Option<u8>) -> String {
    let mut s = format!("{node}.{}", a.name);
    if let Some(i) = index {
        s.push_str(&format!("[{i}]"));
    }
    if let Some(k) = component {
        match (&a.children, index) {
            (Some(ch), None) => s = format!("{node}.{}", ch[k as usize % 3]),
            (Some(ch), Some(_)) => s.push_str(&format!(".{}", ch[k as usize % 3])),
            (None, _) => s.push_str(&format!(".{}", ["x", "y", "z"][k as usize % 3])),
        }
    }
    s
}

/// Splits a plug path into its parts; the error says what is malformed.
pub fn parse_plug_path(path: &str) -> Result<PlugPath<'_>, String> {
    let (node, rest) = path
        .split_once('.')
        .ok_or_else(|| "expected node.attribute, e.g. \"hip_L.rotate\"".to_string())?;
    if node.is_empty() {
        return Err("the node name is empty".into());
    }
    parse_attr_path(node, rest)
}

/// The parts of `rest`, what follows `node.` in a plug path (`attr`, `attrX`, `attr[3]`,
/// `attr[3].child`), with `node` as the node name; the error says what is malformed.
pub fn parse_attr_path<'a>(node: &'a str, rest: &'a str) -> Result<PlugPath<'a>, String> {
    let (attr_part, child) = match rest.find(']') {
        Some(close) => {
            let after = &rest[close + 1..];
            match after.strip_prefix('.') {
                Some(c) if !c.is_empty() => (&rest[..=close], Some(c)),
                None if after.is_empty() => (rest, None),
                _ => return Err("unexpected text after ']'".into()),
            }
        }
        None => (rest, None),
    };
    let (attr, index) = match attr_part.find('[') {
        Some(open) => {
            let inner = attr_part[open + 1..]
                .strip_suffix(']')
                .ok_or_else(|| "missing ']' after the element index".to_string())?;
            let i: u32 = inner
                .trim()
                .parse()
                .map_err(|_| "element index must be a non-negative integer".to_string())?;
            (&attr_part[..open], Some(i))
        }
        None => (attr_part, None),
    };
    if attr.is_empty() {
        return Err("the attribute name is empty".into());
    }
    Ok(PlugPath {
        node,
        attr,
        index,
        child,
    })
}

/// Why an attribute lookup failed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum AttrLookupError {
    /// No attribute or child with this name.
    Unknown(String),
    /// The path is well-formed but does not fit the attribute.
    Malformed(String),
}

/// Looks up `attr` (and optional `child`) in a spec, giving the attribute and component.
pub fn resolve_attr(spec: &NodeSpec, attr: &str, child: Option<&str>) -> Result<(AttrId, Option<u8>), AttrLookupError> {
    let (id, component) = spec
        .find(attr)
        .ok_or_else(|| AttrLookupError::Unknown(attr.to_string()))?;
    let Some(c) = child else {
        return Ok((id, component));
    };
    if component.is_some() {
        return Err(AttrLookupError::Malformed("a component cannot have a child".into()));
    }
    let a = spec.attr(id);
    if a.ty != AttrType::Vec3 {
        return Err(AttrLookupError::Malformed(format!(
            "{} is {}; only vec3 attributes have children",
            a.name, a.ty
        )));
    }
    let k = match c {
        "x" | "X" | "r" | "R" => 0,
        "y" | "Y" | "g" | "G" => 1,
        "z" | "Z" | "b" | "B" => 2,
        c => a
            .children
            .iter()
            .chain(&a.child_short_names)
            .find_map(|ch| ch.iter().position(|n| n == c))
            .ok_or_else(|| AttrLookupError::Unknown(c.to_string()))? as u8,
    };
    Ok((id, Some(k)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_all_forms() {
        assert_eq!(
            parse_plug_path("hip_L.rotate").unwrap(),
            PlugPath {
                node: "hip_L",
                attr: "rotate",
                index: None,
                child: None
            }
        );
        assert_eq!(parse_plug_path("b.input[12]").unwrap().index, Some(12));
        let p = parse_plug_path("pma.input3D[0].input3Dx").unwrap();
        assert_eq!((p.attr, p.index, p.child), ("input3D", Some(0), Some("input3Dx")));
    }

    #[test]
    fn rejects_malformed() {
        for bad in ["noattr", ".x", "a.", "a.b[", "a.b[-1]", "a.b[1]x", "a.b[x]"] {
            assert!(parse_plug_path(bad).is_err(), "{bad} should fail");
        }
    }
}
