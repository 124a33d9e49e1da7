//! `sinew nodes`: lists the registered node types and their attributes.

use std::fmt::Write as _;

use serde_json::json;
use sinew_core::{AttrSpec, Direction, NodeSpec, Registry};

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
