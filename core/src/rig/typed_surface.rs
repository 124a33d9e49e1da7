//! NURBS surfaces and the parts they share with curves in rig files: a surface is
//! `(degreeU: 3, degreeV: 1, formU: open, formV: open, points: [[row u = 0], [row u = 1], ..],
//! knotsU: [..], knotsV: [..])`, each row listing the control points along `v`.

use std::sync::Arc;

use glam::DVec3;

use super::diag::Diagnostic;
use super::parse::{Ast, Node};
use super::typed::{fields, fl, int_of, list, number, numbers, strukt, synth, tuple};
use crate::data::{CurveForm, Surface};
use crate::value::{AttrType, Value};

/// A degree field of a curve or surface: an integer from 1 to 7.
pub(super) fn degree(v: &Node, what: &str) -> Result<u32, Diagnostic> {
    match int_of(&v.kind) {
        Some(d) if (1..=7).contains(&d) => Ok(d as u32),
        _ => Err(
            Diagnostic::new(v.span.clone(), format!("{what} degree must be an integer from 1 to 7"))
                .hint("e.g. degree: 3"),
        ),
    }
}

/// A form field of a curve or surface: `open` or `periodic`.
pub(super) fn form(v: &Node, what: &str) -> Result<CurveForm, Diagnostic> {
    match v.kind.as_str() {
        Some("open") => Ok(CurveForm::Open),
        Some("periodic") => Ok(CurveForm::Periodic),
        _ => Err(
            Diagnostic::new(v.span.clone(), format!("{what} form must be `open` or `periodic`"))
                .hint("e.g. form: periodic"),
        ),
    }
}

/// A list of finite numbers (knots).
pub(super) fn knots(v: &Node, what: &str) -> Result<Vec<f64>, Diagnostic> {
    list(v, what, AttrType::FloatArray)?
        .iter()
        .map(|x| number(x, what))
        .collect()
}

/// A list of points.
pub(super) fn points(v: &Node, what: &str) -> Result<Vec<DVec3>, Diagnostic> {
    list(v, what, AttrType::Vec3Array)?
        .iter()
        .map(|x| numbers::<3>(x, what, AttrType::Vec3).map(DVec3::from_array))
        .collect()
}

/// Reads a surface value (see the module docs).
pub(super) fn read_surface(n: &Node, what: &str) -> Result<Value, Diagnostic> {
    let ty = AttrType::Surface;
    let mut s = Surface::default();
    let allowed = ["degreeU", "degreeV", "formU", "formV", "points", "knotsU", "knotsV"];
    for (k, v) in fields(n, what, ty, &allowed)? {
        match k {
            "degreeU" => s.degree_u = degree(v, "surface")?,
            "degreeV" => s.degree_v = degree(v, "surface")?,
            "formU" => s.form_u = form(v, "surface")?,
            "formV" => s.form_v = form(v, "surface")?,
            "knotsU" => s.knots_u = knots(v, what)?,
            "knotsV" => s.knots_v = knots(v, what)?,
            _ => {
                let rows = list(v, what, ty)?;
                s.points.clear();
                for row in rows {
                    let pts = points(row, what)?;
                    if s.count_u > 0 && pts.len() != s.count_v as usize {
                        return Err(Diagnostic::new(
                            row.span.clone(),
                            format!(
                                "surface row {} has {} points but row 0 has {}",
                                s.count_u,
                                pts.len(),
                                s.count_v
                            ),
                        )
                        .hint("every row (one per u) lists the same number of points along v"));
                    }
                    s.count_v = pts.len() as u32;
                    s.count_u += 1;
                    s.points.extend(pts);
                }
            }
        }
    }
    Ok(Value::Surface(Arc::new(s)))
}

/// Writes a surface (the inverse of [`read_surface`]; uniform knots and the open form, the
/// defaults, are left out, degrees are always written).
pub(super) fn write_surface(s: &Surface) -> Ast {
    let pt = |v: &DVec3| synth(tuple(v.to_array().iter().map(|&x| fl(x)).collect()));
    let cv = s.count_v.max(1) as usize;
    let rows = s
        .points
        .chunks(cv)
        .map(|row| synth(Ast::List(row.iter().map(pt).collect())));
    let mut f = vec![
        ("degreeU", Ast::Int(s.degree_u as i64)),
        ("degreeV", Ast::Int(s.degree_v as i64)),
    ];
    for (name, form) in [("formU", s.form_u), ("formV", s.form_v)] {
        if form == CurveForm::Periodic {
            f.push((name, Ast::Ident("periodic".into())));
        }
    }
    f.push(("points", Ast::List(rows.collect())));
    for (name, k) in [("knotsU", &s.knots_u), ("knotsV", &s.knots_v)] {
        if !k.is_empty() {
            f.push((name, Ast::List(k.iter().map(|&x| fl(x)).collect())));
        }
    }
    strukt(f)
}

#[cfg(test)]
mod tests {

    use super::super::parse::parse;
    use super::super::typed::{read_value, write_value};
    use super::*;

    fn read(text: &str) -> Result<Value, Diagnostic> {
        let n = parse(text, &Arc::new(std::path::PathBuf::from("mem.ron"))).expect("parses");
        read_value(&n, AttrType::Surface, None, "s.create")
    }

    #[test]
    fn surfaces_read_and_write_back() {
        let v = read(
            "(degreeU: 2, degreeV: 1, formU: periodic, points: [[(0, 0, 0), (0, 0, 1)], [(1, 0, 0), (1, 0, 1)], \
             [(2, 1, 0), (2, 1, 1)]], knotsV: [0, 0, 1, 1])",
        )
        .unwrap();
        let Value::Surface(s) = &v else { panic!("{v:?}") };
        assert_eq!((s.degree_u, s.degree_v, s.count_u, s.count_v), (2, 1, 3, 2));
        assert_eq!(s.form_u, CurveForm::Periodic);
        assert_eq!(s.points[5], DVec3::new(2.0, 1.0, 1.0));
        assert_eq!(s.knots_v, [0.0, 0.0, 1.0, 1.0]);
        let back = read_value(&synth(write_value(&v, None)), AttrType::Surface, None, "s").unwrap();
        assert!(back.same_bits(&v));
    }

    #[test]
    fn surface_errors_point_at_the_value() {
        let e = read("(points: [[(0, 0, 0), (0, 0, 1)], [(1, 0, 0)]])").unwrap_err();
        assert!(
            e.message.contains("row 1 has 1 points but row 0 has 2"),
            "{}",
            e.message
        );
        assert_eq!((e.span.line, e.span.col), (1, 35), "the second row");
        let e = read("(degreeU: 9)").unwrap_err();
        assert!(e.message.contains("from 1 to 7"), "{}", e.message);
        let e = read("(formV: closed)").unwrap_err();
        assert!(e.message.contains("`open` or `periodic`"));
        let e = read("(pointz: [])").unwrap_err();
        assert!(e.message.contains("unknown field `pointz`"));
    }
}
