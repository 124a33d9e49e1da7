//! `attrs: { .. }` on a node in a rig file: custom attribute declarations (Maya's
//! `addAttr`), read into [`AttrSpec`]s with positioned errors and written back in
//! canonical form.
//!
//! ```ron
//! "foot_ctrl_L": transform(translate: (0.1, 0, 0.05), attrs: {
//!     "footRoll": float(default: 0, min: -10, max: 10, keyable: true),
//!     "ikFk": enum(names: ["fk", "ik"], default: ik),
//!     "stretch": bool(true),
//! }),
//! ```

use super::diag::{Diagnostic, Diagnostics, Span};
use super::parse::{Ast, Item, Node};
use super::typed::{read_value, synth, write_value};
use crate::error::nearest;
use crate::spec::{AttrSpec, Direction, MirrorRole};
use crate::value::{AttrType, Value};

/// Type names of declarations, and their value types.
const TYPES: [(&str, AttrType); 8] = [
    ("float", AttrType::Float),
    ("int", AttrType::Int),
    ("bool", AttrType::Bool),
    ("enum", AttrType::Enum),
    ("vec3", AttrType::Vec3),
    ("matrix", AttrType::Matrix),
    ("string", AttrType::String),
    ("floatArray", AttrType::FloatArray),
];

/// Mirror roles a custom vec3 may declare (`mirror: world`).
const MIRRORS: [(&str, MirrorRole); 4] = [
    ("none", MirrorRole::None),
    ("translate", MirrorRole::Translate),
    ("world", MirrorRole::WorldVector),
    ("local", MirrorRole::LocalVector),
];

const COMMON: [&str; 6] = ["default", "short", "doc", "keyable", "multi", "output"];
const RANGE: [&str; 4] = ["min", "max", "softMin", "softMax"];

fn fields_of(ty: AttrType) -> Vec<&'static str> {
    let mut f = COMMON.to_vec();
    match ty {
        AttrType::Float | AttrType::Int => f.extend(RANGE),
        AttrType::Enum => f.push("names"),
        AttrType::Vec3 => f.extend(["children", "mirror"]),
        _ => {}
    }
    f
}

/// The zero a declaration's default is when not written (an enum's first choice).
fn zero(ty: AttrType) -> Value {
    match ty {
        AttrType::Enum => Value::Enum(0),
        AttrType::Matrix => Value::Matrix(glam::DMat4::IDENTITY),
        t => t.zero(),
    }
}

struct Reader<'d> {
    diags: &'d mut Diagnostics,
}

impl Reader<'_> {
    fn err(&mut self, span: &Span, msg: impl Into<String>, hint: impl Into<String>) {
        self.diags.push(Diagnostic::new(span.clone(), msg).hint(hint));
    }

    fn boolean(&mut self, v: &Node, what: &str) -> Option<bool> {
        match v.kind {
            Ast::Bool(b) => Some(b),
            ref other => {
                self.err(
                    &v.span,
                    format!("{what} must be true or false, found {}", other.describe()),
                    format!("e.g. {what}: true"),
                );
                None
            }
        }
    }

    fn number(&mut self, v: &Node, what: &str) -> Option<f64> {
        match v.kind.as_f64() {
            Some(x) if x.is_finite() => Some(x),
            _ => {
                self.err(
                    &v.span,
                    format!("{what} must be a number, found {}", v.kind.describe()),
                    format!("e.g. {what}: 1.0"),
                );
                None
            }
        }
    }

    fn string(&mut self, v: &Node, what: &str) -> Option<String> {
        match &v.kind {
            Ast::Str { value, .. } => Some(value.clone()),
            other => {
                self.err(
                    &v.span,
                    format!("{what} must be a string, found {}", other.describe()),
                    format!("write it in double quotes, e.g. {what}: \"text\""),
                );
                None
            }
        }
    }

    fn strings(&mut self, v: &Node, what: &str) -> Option<Vec<String>> {
        let Ast::List(items) = &v.kind else {
            self.err(
                &v.span,
                format!("{what} must be a list of strings, found {}", v.kind.describe()),
                "e.g. [\"fk\", \"ik\"]",
            );
            return None;
        };
        items.iter().map(|n| self.string(n, what)).collect()
    }

    /// One declaration: `type(positional?, field: value, ..)`.
    fn decl(&mut self, name: &str, v: &Node) -> Option<AttrSpec> {
        let example = "e.g. float(default: 0, min: -10, max: 10, keyable: true)";
        let Ast::Group {
            name: Some(tname),
            items,
        } = &v.kind
        else {
            self.err(
                &v.span,
                format!("custom attribute `{name}` needs a type, found {}", v.kind.describe()),
                example,
            );
            return None;
        };
        let Some(&(_, ty)) = TYPES.iter().find(|(t, _)| t == tname) else {
            let types: Vec<&str> = TYPES.iter().map(|t| t.0).collect();
            let hint = match nearest(tname, types.iter().copied()) {
                Some(s) => format!("did you mean `{s}`? custom attributes are {}", types.join(", ")),
                None => format!("custom attributes are {}", types.join(", ")),
            };
            self.err(&v.span, format!("unknown attribute type `{tname}`"), hint);
            return None;
        };
        let allowed = fields_of(ty);
        let mut spec = AttrSpec::custom(name, zero(ty));
        let mut default: Option<&Node> = None;
        let mut ok = true;
        for (k, it) in items.iter().enumerate() {
            let Some((key, kspan)) = &it.key else {
                // A lone positional item (RON allows no mix of named and positional ones)
                // is the default, or an enum's names: `bool(true)`, `enum(["fk", "ik"])`.
                if k != 0 {
                    self.err(
                        &it.value.span,
                        "a declaration takes one positional value at most",
                        example,
                    );
                    ok = false;
                } else if ty == AttrType::Enum {
                    spec.enum_names = self.strings(&it.value, "enum names").unwrap_or_default();
                } else {
                    default = Some(&it.value);
                }
                continue;
            };
            if !allowed.contains(&key.as_str()) {
                let hint = match nearest(key, allowed.iter().copied()) {
                    Some(s) => format!("did you mean `{s}`? a {tname} declaration takes {}", allowed.join(", ")),
                    None => format!("a {tname} declaration takes {}", allowed.join(", ")),
                };
                self.err(kspan, format!("unknown field `{key}` in a {tname} declaration"), hint);
                ok = false;
                continue;
            }
            let v = &it.value;
            match key.as_str() {
                "default" => default = Some(v),
                "short" => spec.short_name = self.string(v, "short"),
                "doc" => spec.doc = self.string(v, "doc").unwrap_or_default(),
                "keyable" => spec.keyable = self.boolean(v, "keyable").unwrap_or(false),
                "multi" => spec.multi = self.boolean(v, "multi").unwrap_or(false),
                "output" if self.boolean(v, "output") == Some(true) => spec.direction = Direction::Output,
                "min" => spec.min = self.number(v, "min"),
                "max" => spec.max = self.number(v, "max"),
                "softMin" => spec.soft_min = self.number(v, "softMin"),
                "softMax" => spec.soft_max = self.number(v, "softMax"),
                "names" => spec.enum_names = self.strings(v, "names").unwrap_or_default(),
                "children" => match self.strings(v, "children").as_deref() {
                    Some([a, b, c]) => spec.children = Some([a.clone(), b.clone(), c.clone()]),
                    Some(_) => {
                        self.err(
                            &v.span,
                            "a vec3 has three children",
                            "children: [\"aX\", \"aY\", \"aZ\"]",
                        );
                        ok = false;
                    }
                    None => ok = false,
                },
                "mirror" => match v.kind.as_str().and_then(|s| MIRRORS.iter().find(|m| m.0 == s)) {
                    Some(&(_, role)) => spec.mirror = role,
                    None => {
                        let names: Vec<&str> = MIRRORS.iter().map(|m| m.0).collect();
                        self.err(
                            &v.span,
                            format!("mirror must be one of {}, found {}", names.join(", "), v.kind.describe()),
                            "world: a world-space vector (reflected); local: a local axis (negated); translate: a position",
                        );
                        ok = false;
                    }
                },
                _ => {}
            }
        }
        if let Some(d) = default {
            match read_value(d, ty, Some(&spec), &format!("the default of `{name}`")) {
                Ok(v) => spec.default = v,
                Err(e) => {
                    self.diags.push(e);
                    return None;
                }
            }
        }
        if !ok {
            return None;
        }
        if let Err(reason) = spec.validate_custom() {
            let (at, hint) = match default {
                Some(d) if reason.contains("default") => (&d.span, "give a default the declaration allows"),
                _ => (&v.span, example),
            };
            self.err(at, format!("custom attribute {reason}"), hint);
            return None;
        }
        Some(spec)
    }
}

/// Reads `attrs: { "name": type(..), .. }`, adding every problem to `diags`; returns the
/// valid declarations with the position of each.
pub(super) fn read_attrs(n: &Node, diags: &mut Diagnostics) -> Vec<(AttrSpec, Span)> {
    let mut r = Reader { diags };
    let Ast::Map(entries) = &n.kind else {
        r.err(
            &n.span,
            format!("`attrs` must be a map, found {}", n.kind.describe()),
            "write custom attributes as attrs: { \"footRoll\": float(default: 0), .. }",
        );
        return Vec::new();
    };
    let mut out: Vec<(AttrSpec, Span)> = Vec::new();
    for (k, v) in entries {
        let Some(name) = k.kind.as_str() else {
            r.err(
                &k.span,
                format!("a custom attribute name must be a string, found {}", k.kind.describe()),
                "write \"footRoll\": float(..)",
            );
            continue;
        };
        if let Some((_, first)) = out.iter().find(|(a, _)| a.name == name) {
            let first = first.clone();
            r.diags.push(
                Diagnostic::new(k.span.clone(), format!("custom attribute `{name}` is declared twice"))
                    .hint("keep one of them")
                    .note(first, "first declared here"),
            );
            continue;
        }
        if let Some(spec) = r.decl(name, v) {
            out.push((spec, k.span.clone()));
        }
    }
    out
}

fn item(key: &str, value: Ast) -> Item {
    Item {
        key: Some((key.to_string(), synth(Ast::Int(0)).span)),
        value: synth(value),
    }
}

fn opt_num(items: &mut Vec<Item>, key: &str, x: Option<f64>, int: bool) {
    match x {
        Some(x) if int && x.fract() == 0.0 && x.abs() < 9.0e15 => items.push(item(key, Ast::Int(x as i64))),
        Some(x) => items.push(item(key, Ast::Float(x))),
        None => {}
    }
}

/// One declaration in canonical form (named fields only): enum `names` first, then `default` (when not the
/// type's zero), short name, limits, flags, children, mirror, doc.
fn decl_ast(a: &AttrSpec) -> Ast {
    let tname = TYPES.iter().find(|t| t.1 == a.ty).map_or("float", |t| t.0);
    let s = |x: &str| Ast::Str {
        value: x.to_string(),
        exact: false,
    };
    let mut items = Vec::new();
    if a.ty == AttrType::Enum {
        items.push(item(
            "names",
            Ast::List(a.enum_names.iter().map(|n| synth(s(n))).collect()),
        ));
    }
    if !a.default.same_bits(&zero(a.ty)) {
        items.push(item("default", write_value(&a.default, Some(a))));
    }
    if let Some(short) = &a.short_name {
        items.push(item("short", s(short)));
    }
    let int = a.ty == AttrType::Int;
    opt_num(&mut items, "min", a.min, int);
    opt_num(&mut items, "max", a.max, int);
    opt_num(&mut items, "softMin", a.soft_min, int);
    opt_num(&mut items, "softMax", a.soft_max, int);
    for (key, on) in [("keyable", a.keyable), ("multi", a.multi), ("output", !a.is_input())] {
        if on {
            items.push(item(key, Ast::Bool(true)));
        }
    }
    let default_children = ["X", "Y", "Z"].map(|c| format!("{}{c}", a.name));
    if let Some(ch) = a.children.as_ref().filter(|ch| **ch != default_children) {
        items.push(item("children", Ast::List(ch.iter().map(|c| synth(s(c))).collect())));
    }
    if let Some((m, _)) = MIRRORS.iter().find(|m| m.1 == a.mirror && m.1 != MirrorRole::None) {
        items.push(item("mirror", Ast::Ident(m.to_string())));
    }
    if !a.doc.is_empty() {
        items.push(item("doc", s(&a.doc)));
    }
    Ast::Group {
        name: Some(tname.to_string()),
        items,
    }
}

/// `attrs: { .. }` for a node's custom attributes, in declaration order.
pub(super) fn write_attrs(attrs: &[AttrSpec]) -> Ast {
    Ast::Map(
        attrs
            .iter()
            .map(|a| {
                let key = Ast::Str {
                    value: a.name.clone(),
                    exact: false,
                };
                (synth(key), synth(decl_ast(a)))
            })
            .collect(),
    )
}
