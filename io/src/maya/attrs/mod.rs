//! Maya's own attribute names: long and short name and unit class of the attributes of
//! the node types the importer maps, by type with inheritance (`joint` → `transform` →
//! `dagNode` → `node`). A `.ma` file writes short names (`.t`, `.jo`, `.wl[3].w[2]`);
//! these tables turn them into long names (`translate`, `jointOrient`,
//! `weightList[3].weights[2]`), which are sinew's attribute names wherever sinew has the
//! attribute. Attributes sinew has no counterpart of are listed too, so the import report
//! can name what it skips.
//!
//! Source: the Maya node reference (help.autodesk.com, *Nodes*), one page per type.

mod dag;
mod deform;
mod util;

use std::collections::HashMap;
use std::sync::OnceLock;

use super::units::UnitClass;

/// One Maya attribute.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MayaAttr {
    /// Long name.
    pub long: &'static str,
    /// Short name.
    pub short: &'static str,
    /// Unit class of its values.
    pub class: UnitClass,
}

/// A type's own attributes: `(long, short, class)`.
pub(crate) type Table = &'static [(&'static str, &'static str, UnitClass)];

/// Maya attributes sinew keeps under another long name on its node of the same type:
/// `(Maya type, Maya long name, sinew name)`. (The values may differ too: sinew's tangent
/// types are its own enum; the animation mapper converts them.)
pub const SINEW_RENAMES: &[(&str, &str, &str)] = &[
    ("animCurve", "keyTanInType", "keyInTangentType"),
    ("animCurve", "keyTanOutType", "keyOutTangentType"),
];

/// The types with tables: `(type, parent type, own attributes)`.
fn types() -> Vec<(&'static str, Option<&'static str>, Table)> {
    let mut v = Vec::new();
    v.extend(dag::TYPES.iter().copied());
    v.extend(deform::TYPES.iter().copied());
    v.extend(util::TYPES.iter().copied());
    v
}

struct TypeInfo {
    parent: Option<&'static str>,
    by_name: HashMap<&'static str, MayaAttr>,
}

fn index() -> &'static HashMap<&'static str, TypeInfo> {
    static INDEX: OnceLock<HashMap<&'static str, TypeInfo>> = OnceLock::new();
    INDEX.get_or_init(|| {
        let mut m = HashMap::new();
        for (ty, parent, table) in types() {
            let mut by_name = HashMap::with_capacity(table.len() * 2);
            for &(long, short, class) in table {
                let a = MayaAttr { long, short, class };
                by_name.insert(long, a);
                by_name.entry(short).or_insert(a);
            }
            m.insert(ty, TypeInfo { parent, by_name });
        }
        m
    })
}

/// The parent type of a Maya type with a table (unknown types count as plain DG nodes).
pub fn parent_type(ty: &str) -> Option<&'static str> {
    match index().get(ty) {
        Some(t) => t.parent,
        None if ty == "node" => None,
        None => Some("node"),
    }
}

/// Whether `ty` is `base` or derives from it (by these tables).
pub fn is_a(ty: &str, base: &str) -> bool {
    let mut t = Some(ty);
    let mut guard = 0;
    while let Some(x) = t {
        if x == base {
            return true;
        }
        guard += 1;
        if guard > 16 {
            return false;
        }
        t = parent_type(x);
    }
    false
}

/// Looks up an attribute by long or short name on `ty` and its ancestors.
pub fn find(ty: &str, name: &str) -> Option<MayaAttr> {
    let idx = index();
    let mut t = Some(ty);
    let mut guard = 0;
    while let Some(x) = t {
        if let Some(info) = idx.get(x) {
            if let Some(a) = info.by_name.get(name) {
                return Some(*a);
            }
        }
        guard += 1;
        if guard > 16 {
            return None;
        }
        t = parent_type(x);
    }
    None
}

/// The long name of `name` on `ty` (the name itself when the tables do not know it).
pub fn long_name<'a>(ty: &str, name: &'a str) -> &'a str {
    match find(ty, name) {
        Some(a) => a.long,
        None => name,
    }
}

/// The unit class of attribute `name` (long or short) on `ty`; `None` when unknown.
pub fn class_of(ty: &str, name: &str) -> Option<UnitClass> {
    find(ty, name).map(|a| a.class)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_names_resolve_through_inheritance() {
        assert_eq!(long_name("joint", "jo"), "jointOrient");
        assert_eq!(long_name("joint", "t"), "translate");
        assert_eq!(long_name("joint", "wm"), "worldMatrix");
        assert_eq!(long_name("joint", "msg"), "message");
        assert_eq!(long_name("skinCluster", "wl"), "weightList");
        assert_eq!(long_name("skinCluster", "w"), "weights");
        assert_eq!(long_name("skinCluster", "ma"), "matrix");
        assert_eq!(long_name("skinCluster", "ip"), "input");
        assert_eq!(long_name("parentConstraint", "tg"), "target");
        assert_eq!(long_name("parentConstraint", "t"), "translate");
        assert_eq!(long_name("someUnknownType", "msg"), "message");
        assert_eq!(long_name("someUnknownType", "zz"), "zz");
        assert_eq!(class_of("joint", "rx"), Some(UnitClass::Angle));
        assert_eq!(class_of("transform", "tz"), Some(UnitClass::Linear));
        assert_eq!(class_of("multiplyDivide", "i1x"), Some(UnitClass::None));
        assert!(is_a("joint", "transform"));
        assert!(is_a("parentConstraint", "transform"));
        assert!(!is_a("mesh", "transform"));
        assert!(is_a("mesh", "dagNode"));
    }

    /// Within a type and its ancestors, no short name means two different attributes.
    #[test]
    fn no_short_name_is_ambiguous() {
        for (ty, _, _) in types() {
            let mut seen: HashMap<&str, &str> = HashMap::new();
            let mut t = Some(ty);
            while let Some(x) = t {
                if let Some((_, _, table)) = types().into_iter().find(|(n, _, _)| *n == x) {
                    for &(long, short, _) in table {
                        if let Some(prev) = seen.insert(short, long) {
                            assert_eq!(prev, long, "{ty}: short name {short} is both {prev} and {long}");
                        }
                    }
                }
                t = parent_type(x);
            }
        }
    }
}

#[cfg(test)]
mod agreement {
    use super::*;

    /// Where a sinew node type has Maya's name, its spec's short names (sinew's own
    /// table, from Maya's node reference) and these tables agree: a short name both know
    /// means the same long name.
    #[test]
    fn sinew_short_names_agree_with_these_tables() {
        let registry = sinew_nodes::registry().unwrap();
        let mut checked = 0;
        let mut bad = Vec::new();
        for spec in registry.specs() {
            let ty = spec.name.as_str();
            if !index().contains_key(ty) {
                continue;
            }
            for id in spec.attr_ids() {
                let a = spec.attr(id);
                let pairs = a.short_name.iter().map(|s| (s.clone(), a.name.clone())).chain(
                    a.child_short_names
                        .iter()
                        .zip(a.children.iter())
                        .flat_map(|(s, c)| s.iter().cloned().zip(c.iter().cloned())),
                );
                for (short, long) in pairs {
                    checked += 1;
                    if let Some(m) = find(ty, &short) {
                        let renamed = SINEW_RENAMES
                            .iter()
                            .any(|(t, maya, sinew)| is_a(ty, t) && *maya == m.long && *sinew == long);
                        if m.long != long && !renamed {
                            bad.push(format!("{ty}.{short}: sinew {long}, Maya table {}", m.long));
                        }
                    }
                }
            }
        }
        assert!(checked > 100, "only {checked} short names checked");
        assert!(bad.is_empty(), "{bad:#?}");
    }
}
