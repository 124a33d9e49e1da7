//! `sinew nodes`: lists the registered node types and their attributes, or one node of a
//! rig with its custom attributes (`--rig`).

use std::fmt::Write as _;

use serde_json::json;
use sinew_core::{AttrSpec, AttrType, Direction, Graph, NodeSpec, Registry, Unit, Value};

/// Human-readable listing of one node type.
fn describe(spec: &NodeSpec, out: &mut String) {
    let _ = writeln!(
        out,
        "{}{}",
        spec.name,
        if spec.doc.is_empty() {
            String::new()
        } else {
            format!(" — {}", spec.doc)
        }
    );
    for a in &spec.attrs {
        let _ = writeln!(out, "    {}", attr_line(a));
    }
}

/// The attributes of node `name` of a loaded rig: its type's, then its custom ones (marked
/// `custom`), as text or JSON.
pub fn render_node(graph: &Graph, name: &str, as_json: bool) -> Result<String, String> {
    let id = graph.node_id(name).map_err(|e| e.to_string())?;
    let spec = graph.node_spec(id).ok_or("stale node")?;
    let custom = |a: &AttrSpec| spec.find(&a.name).is_some_and(|(id, _)| spec.is_custom(id));
    if as_json {
        let attrs: Vec<_> = spec
            .attrs
            .iter()
            .map(|a| {
                let mut v = attr_json(a);
                v["custom"] = json!(custom(a));
                v
            })
            .collect();
        let v = json!({ "name": name, "type": spec.name, "attributes": attrs });
        return serde_json::to_string_pretty(&v).map_err(|e| e.to_string());
    }
    let mut out = format!("{name} ({})\n", spec.name);
    for a in &spec.attrs {
        let mark = if custom(a) { "  [custom]" } else { "" };
        let _ = writeln!(out, "    {}{mark}", attr_line(a));
    }
    Ok(out)
}

fn attr_line(a: &AttrSpec) -> String {
    let dir = match a.direction {
        Direction::Input => "in ",
        Direction::Output => "out",
    };
    let short = a.short_name.as_ref().map(|s| format!(" ({s})")).unwrap_or_default();
    let mut s = format!("{dir} {}{}{short}: {}", a.name, if a.multi { "[]" } else { "" }, a.ty);
    if !a.enum_names.is_empty() {
        s.push_str(&format!(" ({})", a.enum_names.join("|")));
    }
    if a.direction == Direction::Input {
        s.push_str(&format!(" = {}", a.default));
    }
    if a.unit == sinew_core::Unit::Degrees {
        s.push_str(" (degrees)");
    }
    let limit = |x: Option<f64>| x.map_or(String::new(), |x| x.to_string());
    if a.min.is_some() || a.max.is_some() {
        s.push_str(&format!(" [{}, {}]", limit(a.min), limit(a.max)));
    }
    if a.soft_min.is_some() || a.soft_max.is_some() {
        s.push_str(&format!(" soft [{}, {}]", limit(a.soft_min), limit(a.soft_max)));
    }
    if !a.doc.is_empty() {
        s.push_str(&format!("  // {}", a.doc));
    }
    s
}

fn attr_json(a: &AttrSpec) -> serde_json::Value {
    json!({
        "name": a.name,
        "shortName": a.short_name,
        "type": a.ty.name(),
        "direction": if a.direction == Direction::Input { "input" } else { "output" },
        "multi": a.multi,
        "keyable": a.keyable,
        "default": a.default.to_string(),
        "children": a.children.as_ref().map(|c| c.to_vec()),
        "childShortNames": a.child_short_names.as_ref().map(|c| c.to_vec()),
        "enum": if a.enum_names.is_empty() { None } else { Some(a.enum_names.clone()) },
        "unit": format!("{:?}", a.unit).to_lowercase(),
        "min": a.min,
        "max": a.max,
        "softMin": a.soft_min,
        "softMax": a.soft_max,
        "doc": a.doc,
    })
}

/// Renders the listing of `only` (or all types) as text or JSON.
pub fn render(registry: &Registry, only: Option<&str>, as_json: bool) -> Result<String, String> {
    let specs: Vec<&NodeSpec> = match only {
        Some(name) => vec![registry.spec(name).ok_or_else(|| match registry.suggest(name) {
            Some(s) => format!("unknown node type {name:?} (did you mean {s:?}?)"),
            None => format!("unknown node type {name:?}; run `sinew nodes` to list them"),
        })?],
        None => registry.specs().collect(),
    };
    if as_json {
        let v: Vec<_> = specs
            .iter()
            .map(|s| {
                json!({
                    "name": s.name,
                    "doc": s.doc,
                    "timeDependent": s.time_dependent,
                    "attributes": s.attrs.iter().map(attr_json).collect::<Vec<_>>(),
                })
            })
            .collect();
        return serde_json::to_string_pretty(&v).map_err(|e| e.to_string());
    }
    let mut out = String::new();
    for s in specs {
        describe(s, &mut out);
    }
    Ok(out)
}

/// The command that regenerates `docs/nodes.md` (named in its header and in the
/// test that fails when the file is stale).
pub const MARKDOWN_COMMAND: &str = "cargo run -- nodes --markdown > docs/nodes.md";

/// Every node type of `registry` as Markdown, in name order: per type its doc
/// line and a table of attributes (direction, type, unit, default, children or
/// enum choices, doc). `docs/nodes.md` is this text.
pub fn markdown(registry: &Registry) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "# Node types\n");
    let _ = writeln!(
        out,
        "Generated from the registered node specs by `sinew nodes --markdown`; do not edit by hand. \
         A test fails when this file is stale: regenerate it with `{MARKDOWN_COMMAND}`.\n"
    );
    let _ = writeln!(
        out,
        "{} node types. Angles are degrees; `[]` marks a multi (array) attribute, `name[i]` in rig files; \
         Maya's short names are in parentheses.\n",
        registry.len()
    );
    for spec in registry.specs() {
        let _ = writeln!(out, "## `{}`\n", spec.name);
        if !spec.doc.is_empty() {
            let _ = writeln!(out, "{}\n", md_escape(&spec.doc));
        }
        if spec.time_dependent {
            let _ = writeln!(out, "Reads the time.\n");
        }
        let _ = writeln!(
            out,
            "| attribute | dir | type | unit | default | children / choices | doc |"
        );
        let _ = writeln!(out, "|---|---|---|---|---|---|---|");
        for a in &spec.attrs {
            let _ = writeln!(out, "{}", md_attr_row(a));
        }
        out.push('\n');
    }
    out
}

fn md_attr_row(a: &AttrSpec) -> String {
    let dir = match a.direction {
        Direction::Input => "in",
        Direction::Output => "out",
    };
    let short = a.short_name.as_ref().map(|s| format!(" (`{s}`)")).unwrap_or_default();
    let name = format!("`{}{}`{short}", a.name, if a.multi { "[]" } else { "" });
    let unit = match a.unit {
        Unit::None => "",
        Unit::Degrees => "degrees",
        Unit::Distance => "distance",
        Unit::Frames => "frames",
    };
    let default = if let (Value::Enum(i), false) = (&a.default, a.enum_names.is_empty()) {
        let name = usize::try_from(*i).ok().and_then(|i| a.enum_names.get(i));
        name.map_or_else(|| i.to_string(), |n| format!("`{n}`"))
    } else if a.direction == Direction::Input || !a.ty.is_heavy() {
        md_value(&a.default)
    } else {
        String::new()
    };
    let extra = if !a.enum_names.is_empty() {
        a.enum_names
            .iter()
            .enumerate()
            .map(|(i, n)| format!("{i} `{n}`"))
            .collect::<Vec<_>>()
            .join(", ")
    } else if let Some(c) = &a.children {
        let shorts = a.child_short_names.as_ref();
        c.iter()
            .enumerate()
            .map(|(k, n)| match shorts {
                Some(s) => format!("`{n}` (`{}`)", s[k]),
                None => format!("`{n}`"),
            })
            .collect::<Vec<_>>()
            .join(", ")
    } else {
        String::new()
    };
    format!(
        "| {name} | {dir} | {} | {unit} | {default} | {extra} | {} |",
        a.ty,
        md_escape(&a.doc)
    )
}

/// A default as short text: matrices that are the identity say so.
fn md_value(v: &Value) -> String {
    match v {
        Value::Matrix(m) if *m == glam::DMat4::IDENTITY => "identity".to_string(),
        Value::Quat(q) if *q == glam::DQuat::IDENTITY => "identity".to_string(),
        v if v.attr_type() == AttrType::Object => String::new(),
        v => md_escape(&v.to_string()),
    }
}

fn md_escape(s: &str) -> String {
    s.replace('|', "\\|")
}
