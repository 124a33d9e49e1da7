//! Attribute values in rig files, read and written by the attribute's
//! declared type: `(x, y, z)` for vec3, `(x, y, z, w)` for quat, 16 numbers
//! for a matrix (glam's `to_cols_array` order, which is the order Maya
//! prints a matrix row by row: translation is elements 12..15), enum names,
//! lists for arrays, and small structs for curves and meshes.

use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3, Vec2, Vec3};

use super::diag::{Diagnostic, Span};
use super::parse::{Ast, Item, Node};
use super::typed_surface::{degree, form, knots, points, read_surface, write_surface};
use crate::data::{Curve, CurveForm, Mesh, Weights};
use crate::spec::AttrSpec;
use crate::value::{AttrType, Value};

/// An example value of each type, for hints.
pub fn example(ty: AttrType, attr: Option<&AttrSpec>) -> String {
    match ty {
        AttrType::Bool => "true".into(),
        AttrType::Int => "3".into(),
        AttrType::Float => "1.5".into(),
        AttrType::Vec3 => "(0.0, 1.5, 0.0)".into(),
        AttrType::Quat => "(0.0, 0.0, 0.0, 1.0) (x, y, z, w)".into(),
        AttrType::Matrix => {
            "(1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  tx, ty, tz, 1) (16 numbers, row by row as Maya prints it)".into()
        }
        AttrType::Enum => match attr {
            Some(a) if !a.enum_names.is_empty() => format!("one of {}", a.enum_names.join(", ")),
            _ => "an enum index such as 0".into(),
        },
        AttrType::String => "\"text\"".into(),
        AttrType::FloatArray => "[0.0, 0.5, 1.0]".into(),
        AttrType::IntArray => "[0, 1, 2]".into(),
        AttrType::Vec3Array => "[(0, 0, 0), (1, 0, 0)]".into(),
        AttrType::MatrixArray => "[(16 numbers), (16 numbers)]".into(),
        AttrType::Curve => "(degree: 3, points: [(0, 0, 0), (1, 0, 0), (2, 1, 0), (3, 1, 0)])".into(),
        AttrType::Surface => {
            "(degreeU: 1, degreeV: 1, points: [[(0, 0, 0), (0, 0, 1)], [(1, 0, 0), (1, 0, 1)]])".into()
        }
        AttrType::Mesh => "(positions: [(0, 0, 0), (1, 0, 0), (0, 1, 0)], triangles: [(0, 1, 2)])".into(),
        AttrType::Weights => "[[(0, 1.0)], [(0, 0.5), (1, 0.5)]] (per vertex: (joint, weight) pairs)".into(),
        AttrType::Object => "nothing: object attributes are computed, not written".into(),
    }
}

fn wrong(n: &Node, what: &str, ty: AttrType, attr: Option<&AttrSpec>) -> Diagnostic {
    Diagnostic::new(
        n.span.clone(),
        format!("{what} expects {ty}, found {}", n.kind.describe()),
    )
    .hint(format!("write {ty} like {}", example(ty, attr)))
}

/// The error for a non-finite number written as a name (`NaN`, `inf`, ...), which RON
/// reads as a number and sinew refuses on purpose.
fn non_finite(n: &Node, what: &str) -> Option<Diagnostic> {
    let Ast::Ident(s) = &n.kind else { return None };
    let lower = s.to_ascii_lowercase();
    let word = lower.trim_end_matches("f32").trim_end_matches("f64");
    matches!(word, "nan" | "inf" | "infinity").then(|| {
        Diagnostic::new(n.span.clone(), format!("{what}: `{s}` is not a finite number"))
            .hint("sinew refuses non-finite numbers (NaN, inf): give a finite number")
    })
}

pub(super) fn number(n: &Node, what: &str) -> Result<f64, Diagnostic> {
    n.kind
        .as_f64()
        .ok_or_else(|| non_finite(n, what).unwrap_or_else(|| wrong(n, what, AttrType::Float, None)))
}

pub(super) fn numbers<const N: usize>(n: &Node, what: &str, ty: AttrType) -> Result<[f64; N], Diagnostic> {
    let items = n.kind.tuple().ok_or_else(|| wrong(n, what, ty, None))?;
    if items.len() != N {
        return Err(Diagnostic::new(
            n.span.clone(),
            format!("{what} expects {ty} ({N} numbers), found {} numbers", items.len()),
        )
        .hint(format!("write {ty} like {}", example(ty, None))));
    }
    let mut out = [0.0; N];
    for (k, (o, it)) in out.iter_mut().zip(items.iter().map(|i| &i.value)).enumerate() {
        *o = it.kind.as_f64().ok_or_else(|| {
            non_finite(it, what).unwrap_or_else(|| {
                Diagnostic::new(
                    it.span.clone(),
                    format!(
                        "{what} expects {ty} ({N} numbers); number {} is {}",
                        k + 1,
                        it.kind.describe()
                    ),
                )
                .hint(format!("write {ty} like {}", example(ty, None)))
            })
        })?;
    }
    Ok(out)
}

/// An integer literal, or `-0` (which the parser reads as the float -0.0, as RON reads
/// it into a float).
pub(super) fn int_of(a: &Ast) -> Option<i64> {
    match *a {
        Ast::Int(i) => Some(i),
        Ast::Float(x) if x == 0.0 && x.is_sign_negative() => Some(0),
        _ => None,
    }
}

pub(super) fn list<'a>(n: &'a Node, what: &str, ty: AttrType) -> Result<&'a [Node], Diagnostic> {
    match &n.kind {
        Ast::List(v) => Ok(v),
        _ => Err(wrong(n, what, ty, None)),
    }
}

pub(super) fn fields<'a>(
    n: &'a Node,
    what: &str,
    ty: AttrType,
    allowed: &[&str],
) -> Result<Vec<(&'a str, &'a Node)>, Diagnostic> {
    let Ast::Group { name: None, items } = &n.kind else {
        return Err(wrong(n, what, ty, None));
    };
    let mut out = Vec::new();
    for Item { key, value } in items {
        let Some((k, ks)) = key else {
            return Err(wrong(n, what, ty, None));
        };
        if !allowed.contains(&k.as_str()) {
            return Err(
                Diagnostic::new(ks.clone(), format!("unknown field `{k}` in {ty} value"))
                    .hint(format!("{ty} fields are: {}", allowed.join(", "))),
            );
        }
        out.push((k.as_str(), value));
    }
    Ok(out)
}

fn matrix(n: &Node, what: &str) -> Result<DMat4, Diagnostic> {
    // 16 numbers, or 4 rows of 4.
    if let Some(items) = n.kind.tuple_items() {
        if items.len() == 4 && items.iter().all(|i| i.kind.tuple_items().is_some()) {
            let mut a = [0.0; 16];
            for (r, row) in items.iter().enumerate() {
                let v: [f64; 4] = numbers(row, what, AttrType::Matrix)?;
                a[r * 4..r * 4 + 4].copy_from_slice(&v);
            }
            return Ok(DMat4::from_cols_array(&a));
        }
    }
    Ok(DMat4::from_cols_array(&numbers::<16>(n, what, AttrType::Matrix)?))
}

fn f32_of(x: f64) -> f32 {
    x as f32
}

/// Reads one value of type `ty` (one element, for multi attributes).
pub fn read_value(n: &Node, ty: AttrType, attr: Option<&AttrSpec>, what: &str) -> Result<Value, Diagnostic> {
    let v = match ty {
        AttrType::Bool => match n.kind {
            Ast::Bool(b) => Value::Bool(b),
            _ => return Err(wrong(n, what, ty, attr)),
        },
        AttrType::Int => match int_of(&n.kind) {
            Some(i) => Value::Int(i),
            None => return Err(wrong(n, what, ty, attr)),
        },
        AttrType::Float => Value::Float(number(n, what)?),
        AttrType::Vec3 => Value::Vec3(DVec3::from_array(numbers::<3>(n, what, ty)?)),
        AttrType::Quat => Value::Quat(DQuat::from_array(numbers::<4>(n, what, ty)?)),
        AttrType::Matrix => Value::Matrix(matrix(n, what)?),
        AttrType::Enum => {
            let names: &[String] = attr.map(|a| a.enum_names.as_slice()).unwrap_or(&[]);
            match (&n.kind, int_of(&n.kind)) {
                (_, Some(i)) if names.is_empty() || (i >= 0 && (i as usize) < names.len()) => Value::Enum(i),
                (_, Some(i)) => {
                    return Err(Diagnostic::new(
                        n.span.clone(),
                        format!("{what}: enum index {i} is out of range (0..{})", names.len()),
                    )
                    .hint(format!("write {}", example(ty, attr))))
                }
                (Ast::Ident(s) | Ast::Str { value: s, .. }, _) => match attr.and_then(|a| a.enum_index(s)) {
                    Some(i) => Value::Enum(i),
                    None => {
                        let hint = match crate::error::nearest(s, names.iter().map(|s| s.as_str())) {
                            Some(x) => format!("did you mean `{x}`? choices: {}", names.join(", ")),
                            None => format!("write {}", example(ty, attr)),
                        };
                        return Err(Diagnostic::new(
                            n.span.clone(),
                            format!("{what}: `{s}` is not one of its choices"),
                        )
                        .hint(hint));
                    }
                },
                _ => return Err(wrong(n, what, ty, attr)),
            }
        }
        AttrType::String => match &n.kind {
            Ast::Str { value, .. } => Value::String(Arc::from(value.as_str())),
            _ => return Err(wrong(n, what, ty, attr)),
        },
        AttrType::FloatArray => Value::FloatArray(Arc::new(
            list(n, what, ty)?
                .iter()
                .map(|x| number(x, what))
                .collect::<Result<_, _>>()?,
        )),
        AttrType::IntArray => Value::IntArray(Arc::new(
            list(n, what, ty)?
                .iter()
                .map(|x| int_of(&x.kind).ok_or_else(|| wrong(x, what, AttrType::Int, None)))
                .collect::<Result<_, _>>()?,
        )),
        AttrType::Vec3Array => Value::Vec3Array(Arc::new(
            list(n, what, ty)?
                .iter()
                .map(|x| numbers::<3>(x, what, AttrType::Vec3).map(DVec3::from_array))
                .collect::<Result<_, _>>()?,
        )),
        AttrType::MatrixArray => Value::MatrixArray(Arc::new(
            list(n, what, ty)?
                .iter()
                .map(|x| matrix(x, what))
                .collect::<Result<_, _>>()?,
        )),
        AttrType::Curve => {
            let mut c = Curve::default();
            for (k, v) in fields(n, what, ty, &["degree", "points", "knots", "form"])? {
                match k {
                    "degree" => c.degree = degree(v, "curve")?,
                    "points" => c.points = points(v, what)?,
                    "knots" => c.knots = knots(v, what)?,
                    _ => c.form = form(v, "curve")?,
                }
            }
            Value::Curve(Arc::new(c))
        }
        AttrType::Surface => read_surface(n, what)?,
        AttrType::Mesh => {
            let mut m = Mesh::default();
            let v3 = |x: &Node| {
                numbers::<3>(x, what, AttrType::Vec3).map(|a| Vec3::new(f32_of(a[0]), f32_of(a[1]), f32_of(a[2])))
            };
            for (k, v) in fields(n, what, ty, &["positions", "normals", "uvs", "triangles"])? {
                let items = list(v, what, ty)?;
                match k {
                    "positions" => m.positions = items.iter().map(v3).collect::<Result<_, _>>()?,
                    "normals" => m.normals = items.iter().map(v3).collect::<Result<_, _>>()?,
                    "uvs" => {
                        m.uvs = items
                            .iter()
                            .map(|x| numbers::<2>(x, what, ty).map(|a| Vec2::new(f32_of(a[0]), f32_of(a[1]))))
                            .collect::<Result<_, _>>()?
                    }
                    _ => {
                        m.triangles = items
                            .iter()
                            .map(|x| {
                                let a = numbers::<3>(x, what, ty)?;
                                if a.iter().all(|&i| i >= 0.0 && i.fract() == 0.0 && i <= u32::MAX as f64) {
                                    Ok([a[0] as u32, a[1] as u32, a[2] as u32])
                                } else {
                                    Err(Diagnostic::new(
                                        x.span.clone(),
                                        "triangle indices must be non-negative integers",
                                    )
                                    .hint("e.g. (0, 1, 2)"))
                                }
                            })
                            .collect::<Result<_, _>>()?
                    }
                }
            }
            m.validate()
                .map_err(|e| Diagnostic::new(n.span.clone(), format!("{what}: {e}")).hint("fix the mesh data"))?;
            Value::Mesh(Arc::new(m))
        }
        AttrType::Weights => {
            let mut per_vertex = Vec::new();
            for vtx in list(n, what, ty)? {
                let mut infl = Vec::new();
                for pair in list(vtx, what, ty)? {
                    let [j, w] = numbers::<2>(pair, what, ty)?;
                    if j < 0.0 || j.fract() != 0.0 || j > u32::MAX as f64 {
                        return Err(
                            Diagnostic::new(pair.span.clone(), "a joint index must be a non-negative integer")
                                .hint("write (joint, weight) pairs like (0, 0.5)"),
                        );
                    }
                    infl.push((j as u32, w as f32));
                }
                per_vertex.push(infl);
            }
            let w = Weights::from_lists(per_vertex);
            w.validate()
                .map_err(|e| Diagnostic::new(n.span.clone(), format!("{what}: {e}")).hint("fix the weights"))?;
            Value::Weights(Arc::new(w))
        }
        AttrType::Object => {
            return Err(Diagnostic::new(
                n.span.clone(),
                format!("{what} holds computed plugin data and cannot be written"),
            )
            .hint("remove it; object attributes are filled by their node"))
        }
    };
    if !v.is_finite() {
        return Err(Diagnostic::new(n.span.clone(), format!("{what}: value is not finite")).hint("give finite numbers"));
    }
    Ok(v)
}

/// A node for `kind` with an empty, synthetic position (for written-out values).
pub(super) fn synth(kind: Ast) -> Node {
    Node::new(
        Span {
            file: Arc::new(std::path::PathBuf::new()),
            line: 0,
            col: 0,
        },
        kind,
    )
}

pub(super) fn fl(x: f64) -> Node {
    synth(Ast::Float(x))
}

fn f32n(x: f32) -> Node {
    // Shortest f32 text, read back as the nearest f64, prints the same short text.
    fl(format!("{x:?}").parse::<f64>().unwrap_or(x as f64))
}

pub(super) fn tuple(items: Vec<Node>) -> Ast {
    Ast::Group {
        name: None,
        items: items.into_iter().map(|value| Item { key: None, value }).collect(),
    }
}

pub(super) fn strukt(items: Vec<(&str, Ast)>) -> Ast {
    let span = synth(Ast::Int(0)).span;
    Ast::Group {
        name: None,
        items: items
            .into_iter()
            .map(|(k, v)| Item {
                key: Some((k.to_string(), span.clone())),
                value: synth(v),
            })
            .collect(),
    }
}

fn is_ident(s: &str) -> bool {
    let mut c = s.chars();
    matches!(c.next(), Some(ch) if ch.is_ascii_alphabetic() || ch == '_')
        && c.all(|ch| ch.is_ascii_alphanumeric() || ch == '_')
        && !matches!(s, "true" | "false")
}

fn mat(m: &DMat4) -> Ast {
    tuple(m.to_cols_array().iter().map(|&x| fl(x)).collect())
}

/// Writes a value as rig-file text (the inverse of [`read_value`]).
pub fn write_value(v: &Value, attr: Option<&AttrSpec>) -> Ast {
    match v {
        Value::Bool(b) => Ast::Bool(*b),
        Value::Int(i) => Ast::Int(*i),
        Value::Float(x) => Ast::Float(*x),
        Value::Vec3(v) => tuple(v.to_array().iter().map(|&x| fl(x)).collect()),
        Value::Quat(q) => tuple(q.to_array().iter().map(|&x| fl(x)).collect()),
        Value::Matrix(m) => mat(m),
        Value::Enum(i) => {
            let name = attr.and_then(|a| usize::try_from(*i).ok().and_then(|k| a.enum_names.get(k)));
            match name {
                Some(n) if is_ident(n) => Ast::Ident(n.clone()),
                Some(n) => Ast::Str {
                    value: n.clone(),
                    exact: true,
                },
                None => Ast::Int(*i),
            }
        }
        Value::String(s) => Ast::Str {
            value: s.to_string(),
            exact: true,
        },
        Value::FloatArray(a) => Ast::List(a.iter().map(|&x| fl(x)).collect()),
        Value::IntArray(a) => Ast::List(a.iter().map(|&x| synth(Ast::Int(x))).collect()),
        Value::Vec3Array(a) => Ast::List(
            a.iter()
                .map(|v| synth(tuple(v.to_array().iter().map(|&x| fl(x)).collect())))
                .collect(),
        ),
        Value::MatrixArray(a) => Ast::List(a.iter().map(|m| synth(mat(m))).collect()),
        Value::Curve(c) => {
            let mut f = vec![
                ("degree", Ast::Int(c.degree as i64)),
                (
                    "points",
                    Ast::List(
                        c.points
                            .iter()
                            .map(|v| synth(tuple(v.to_array().iter().map(|&x| fl(x)).collect())))
                            .collect(),
                    ),
                ),
            ];
            if !c.knots.is_empty() {
                f.push(("knots", Ast::List(c.knots.iter().map(|&x| fl(x)).collect())));
            }
            if c.form == CurveForm::Periodic {
                f.push(("form", Ast::Ident("periodic".into())));
            }
            strukt(f)
        }
        Value::Surface(c) => write_surface(c),
        Value::Mesh(m) => {
            let v3s = |vs: &[Vec3]| {
                Ast::List(
                    vs.iter()
                        .map(|v| synth(tuple(v.to_array().iter().map(|&x| f32n(x)).collect())))
                        .collect(),
                )
            };
            let mut f = vec![("positions", v3s(&m.positions))];
            if !m.normals.is_empty() {
                f.push(("normals", v3s(&m.normals)));
            }
            if !m.uvs.is_empty() {
                f.push((
                    "uvs",
                    Ast::List(
                        m.uvs
                            .iter()
                            .map(|v| synth(tuple(v.to_array().iter().map(|&x| f32n(x)).collect())))
                            .collect(),
                    ),
                ));
            }
            f.push((
                "triangles",
                Ast::List(
                    m.triangles
                        .iter()
                        .map(|t| synth(tuple(t.iter().map(|&i| synth(Ast::Int(i as i64))).collect())))
                        .collect(),
                ),
            ));
            strukt(f)
        }
        Value::Weights(w) => Ast::List(
            (0..w.vertex_count())
                .map(|v| {
                    let (js, ws) = w.influences(v);
                    synth(Ast::List(
                        js.iter()
                            .zip(ws)
                            .map(|(&j, &x)| synth(tuple(vec![synth(Ast::Int(j as i64)), f32n(x)])))
                            .collect(),
                    ))
                })
                .collect(),
        ),
        Value::Object(_) => Ast::Ident("None".into()),
    }
}

/// Parses `text` (RON syntax, as in rig files: `1.5`, `(1, 2, 3)`, `true`, an enum name)
/// as a value for `plug` of `graph`, by the plug's declared type. Used by
/// `sinew eval --set` and the viewer's attribute fields.
pub fn parse_plug_value(graph: &crate::graph::Graph, plug: crate::graph::Plug, text: &str) -> Result<Value, String> {
    let ty = graph.plug_type(plug).map_err(|e| e.to_string())?;
    let spec = graph.node_spec(plug.node).ok_or("stale node")?;
    let attr = (plug.component.is_none()).then(|| spec.attr(plug.attr));
    let file = Arc::new(std::path::PathBuf::from("<value>"));
    let node = super::parse::parse(text, &file).map_err(|d| format!("cannot parse {text:?}: {}", d.message))?;
    read_value(&node, ty, attr, &graph.plug_name(plug)).map_err(|d| match d.hint {
        Some(h) => format!("{} ({h})", d.message),
        None => d.message,
    })
}
