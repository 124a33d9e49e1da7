//! Decoding `setAttr` values: plain numbers and booleans, and every `-type` form Maya writes
//! that sinew reads (`double2/3`, `float2/3`, `long2/3`, `matrix` including the `"xform"`
//! form, `string`, `stringArray`, `doubleArray`, `Int32Array`, `pointArray`,
//! `vectorArray`, `componentList`, `polyFaces`, `nurbsCurve`, `attributeAlias`). Other
//! forms (`nurbsSurface`, `dataReferenceEdits`, `dataPolyComponent`, ...) are left as
//! tokens: nothing sinew maps reads them.
//!
//! Every failure names the token it stopped at (a byte offset; the caller reports
//! `file:line:col`).

use glam::{DMat4, DQuat, DVec3};

use super::lex::{Tok, TokKind};
use super::parse::parse_bool;

/// A decoding error at a byte offset.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ValueError {
    /// Byte offset of the token it stopped at.
    pub offset: u32,
    /// What is wrong.
    pub message: String,
}

/// The value tokens of one `setAttr`, with the source they point into.
#[derive(Clone, Copy)]
pub struct Values<'a> {
    src: &'a str,
    toks: &'a [Tok],
    /// Offset reported when the value list is empty.
    at: u32,
}

/// One face of a `polyFaces` value.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PolyFace {
    /// Edge indices of the outer loop; a negative index `-1 - e` means edge `e` reversed.
    pub edges: Vec<i64>,
    /// Holes, each a loop of edge indices.
    pub holes: Vec<Vec<i64>>,
    /// `(uv set, uv indices per face vertex)` from `mu`.
    pub uvs: Vec<(u32, Vec<i64>)>,
}

/// A component range of a `componentList` (`vtx[3]`, `vtx[6:7]`, `vtx[*]`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Component {
    /// Component kind (`vtx`, `f`, `e`, `cv`, `pt`...).
    pub kind: String,
    /// First index, or `None` for `[*]`.
    pub first: Option<u32>,
    /// Last index (inclusive).
    pub last: Option<u32>,
}

/// A NURBS curve value.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NurbsCurve {
    /// Degree.
    pub degree: u32,
    /// Spans.
    pub spans: u32,
    /// Form: 0 open, 1 closed, 2 periodic.
    pub form: u32,
    /// Knots.
    pub knots: Vec<f64>,
    /// Control vertices (internal units).
    pub cvs: Vec<DVec3>,
}

/// Transform components of an `xform` matrix (Maya's `MTransformationMatrix` order).
#[derive(Clone, Debug, PartialEq)]
pub struct XformMatrix {
    /// Scale.
    pub scale: DVec3,
    /// Rotation (radians).
    pub rotate: DVec3,
    /// Rotate order (Maya's enum: xyz, yzx, zxy, xzy, yxz, zyx).
    pub rotate_order: i64,
    /// Translation (internal units).
    pub translate: DVec3,
    /// Shear.
    pub shear: DVec3,
    /// Scale pivot.
    pub scale_pivot: DVec3,
    /// Scale pivot translation.
    pub scale_pivot_translate: DVec3,
    /// Rotate pivot.
    pub rotate_pivot: DVec3,
    /// Rotate pivot translation.
    pub rotate_pivot_translate: DVec3,
    /// Rotate axis as a quaternion.
    pub rotate_axis: DQuat,
    /// Joint orient as a quaternion.
    pub joint_orient: DQuat,
    /// Inverse parent scale.
    pub inverse_parent_scale: DVec3,
    /// Compensate for parent scale.
    pub compensate: bool,
}

impl<'a> Values<'a> {
    /// Wraps tokens; `at` is the statement's offset (reported for missing values).
    pub fn new(src: &'a str, toks: &'a [Tok], at: u32) -> Self {
        Values { src, toks, at }
    }

    /// Number of tokens.
    pub fn len(&self) -> usize {
        self.toks.len()
    }

    /// Whether there are no value tokens.
    pub fn is_empty(&self) -> bool {
        self.toks.is_empty()
    }

    fn fail<T>(&self, i: usize, message: impl Into<String>) -> Result<T, ValueError> {
        Err(ValueError {
            offset: self.toks.get(i).or(self.toks.last()).map_or(self.at, |t| t.start),
            message: message.into(),
        })
    }

    /// Token `i` as a number (MEL booleans count as 1 and 0).
    pub fn num(&self, i: usize) -> Result<f64, ValueError> {
        let Some(t) = self.toks.get(i) else {
            return self.fail(
                i,
                format!("expected a number after {} values, found the end of the statement", i),
            );
        };
        let raw = t.raw(self.src);
        if t.kind == TokKind::Word {
            if let Ok(v) = raw.parse::<f64>() {
                return Ok(v);
            }
            if let Some(b) = parse_bool(raw) {
                return Ok(if b { 1.0 } else { 0.0 });
            }
        }
        self.fail(i, format!("expected a number, found `{raw}`"))
    }

    /// Token `i` as a whole number.
    pub fn int(&self, i: usize) -> Result<i64, ValueError> {
        let v = self.num(i)?;
        if v.fract() == 0.0 && v.abs() < 9.0e15 {
            Ok(v as i64)
        } else {
            self.fail(i, format!("expected a whole number, found {v}"))
        }
    }

    /// Token `i` as a count or index (`>= 0`).
    pub fn count(&self, i: usize) -> Result<usize, ValueError> {
        let v = self.int(i)?;
        usize::try_from(v).or_else(|_| self.fail(i, format!("expected a count >= 0, found {v}")))
    }

    /// Every token as a number.
    pub fn numbers(&self) -> Result<Vec<f64>, ValueError> {
        (0..self.toks.len()).map(|i| self.num(i)).collect()
    }

    /// Exactly `n` numbers.
    pub fn exactly(&self, n: usize) -> Result<Vec<f64>, ValueError> {
        if self.toks.len() != n {
            return self.fail(
                n.min(self.toks.len()),
                format!("expected {n} numbers, found {} values", self.toks.len()),
            );
        }
        self.numbers()
    }

    /// A single boolean (`yes`, `on`, `true`, `1`...).
    pub fn boolean(&self) -> Result<bool, ValueError> {
        Ok(self.num(0)? != 0.0)
    }

    /// A string: one quoted string, or `("a" + "b" ...)` pieces joined.
    pub fn string(&self) -> Result<String, ValueError> {
        let mut out = String::new();
        let mut any = false;
        for (i, t) in self.toks.iter().enumerate() {
            match t.kind {
                TokKind::Str => {
                    out.push_str(&t.text(self.src));
                    any = true;
                }
                TokKind::LParen | TokKind::RParen => {}
                TokKind::Word if t.raw(self.src) == "+" => {}
                _ => return self.fail(i, format!("expected a string, found `{}`", t.raw(self.src))),
            }
        }
        if any {
            Ok(out)
        } else {
            self.fail(0, "expected a string")
        }
    }

    /// `N s1 .. sN` (`stringArray`); no value at all is an empty array.
    pub fn string_array(&self) -> Result<Vec<String>, ValueError> {
        if self.toks.is_empty() {
            return Ok(Vec::new());
        }
        let n = self.count(0)?;
        let mut out = Vec::with_capacity(n.min(self.toks.len()));
        for i in 1..=n {
            match self.toks.get(i) {
                Some(t) if t.kind == TokKind::Str => out.push(t.text(self.src).into_owned()),
                _ => return self.fail(i, format!("expected {n} strings")),
            }
        }
        Ok(out)
    }

    /// `N v1 .. vN` (`doubleArray`, `Int32Array`).
    pub fn number_array(&self) -> Result<Vec<f64>, ValueError> {
        if self.toks.is_empty() {
            return Ok(Vec::new());
        }
        let n = self.count(0)?;
        if self.toks.len() < n + 1 {
            return self.fail(
                self.toks.len(),
                format!("expected {n} numbers after the count, found {}", self.toks.len() - 1),
            );
        }
        (1..=n).map(|i| self.num(i)).collect()
    }

    /// `N` then `N` tuples of `width` numbers, keeping the first three (`pointArray` has
    /// width 4 — x y z w —, `vectorArray` width 3).
    pub fn point_array(&self, width: usize) -> Result<Vec<DVec3>, ValueError> {
        if self.toks.is_empty() {
            return Ok(Vec::new());
        }
        let n = self.count(0)?;
        if self.toks.len() < 1 + n * width {
            return self.fail(self.toks.len(), format!("expected {n} points of {width} numbers"));
        }
        (0..n)
            .map(|k| {
                let b = 1 + k * width;
                Ok(DVec3::new(self.num(b)?, self.num(b + 1)?, self.num(b + 2)?))
            })
            .collect()
    }

    /// `N "vtx[0]" "vtx[6:7]" ...` (`componentList`).
    pub fn component_list(&self) -> Result<Vec<Component>, ValueError> {
        if self.toks.is_empty() {
            return Ok(Vec::new());
        }
        let n = self.count(0)?;
        let mut out = Vec::with_capacity(n.min(self.toks.len()));
        for i in 1..=n {
            let Some(t) = self.toks.get(i).filter(|t| t.kind == TokKind::Str) else {
                return self.fail(i, format!("expected {n} component strings such as \"vtx[0:3]\""));
            };
            let s = t.text(self.src);
            let parsed = (|| {
                let open = s.find('[')?;
                let inner = s.get(open + 1..s.len().checked_sub(1)?)?;
                if !s.ends_with(']') {
                    return None;
                }
                let kind = s[..open].to_string();
                if inner == "*" || inner.is_empty() {
                    return Some(Component {
                        kind,
                        first: None,
                        last: None,
                    });
                }
                let (a, b) = inner.split_once(':').unwrap_or((inner, inner));
                let (a, b) = (a.parse().ok()?, b.parse().ok()?);
                (a <= b).then_some(Component {
                    kind,
                    first: Some(a),
                    last: Some(b),
                })
            })();
            match parsed {
                Some(c) => out.push(c),
                None => return self.fail(i, format!("`{s}` is not a component such as \"vtx[0:3]\"")),
            }
        }
        Ok(out)
    }

    /// A `matrix`: 16 numbers row by row (Maya's row-vector layout, which is glam's column
    /// order, so the numbers go in as they are), or `"xform"` and its components, composed.
    pub fn matrix(&self) -> Result<DMat4, ValueError> {
        if let Some(x) = self.xform()? {
            return Ok(x.matrix());
        }
        let v = self.exactly(16)?;
        let mut a = [0.0; 16];
        a.copy_from_slice(&v);
        Ok(DMat4::from_cols_array(&a))
    }

    /// The components of an `"xform"` matrix, or `None` for a plain one.
    pub fn xform(&self) -> Result<Option<XformMatrix>, ValueError> {
        let Some(first) = self.toks.first() else {
            return self.fail(0, "expected a matrix");
        };
        if first.kind != TokKind::Str || first.text(self.src) != "xform" {
            return Ok(None);
        }
        if self.toks.len() != 38 {
            return self.fail(
                self.toks.len().min(37),
                format!(
                    "an \"xform\" matrix has 37 values after \"xform\", found {}",
                    self.toks.len() - 1
                ),
            );
        }
        let v3 = |i: usize| -> Result<DVec3, ValueError> {
            Ok(DVec3::new(self.num(i)?, self.num(i + 1)?, self.num(i + 2)?))
        };
        let q = |i: usize| -> Result<DQuat, ValueError> {
            Ok(DQuat::from_xyzw(
                self.num(i)?,
                self.num(i + 1)?,
                self.num(i + 2)?,
                self.num(i + 3)?,
            ))
        };
        Ok(Some(XformMatrix {
            scale: v3(1)?,
            rotate: v3(4)?,
            rotate_order: self.int(7)?,
            translate: v3(8)?,
            shear: v3(11)?,
            scale_pivot: v3(14)?,
            scale_pivot_translate: v3(17)?,
            rotate_pivot: v3(20)?,
            rotate_pivot_translate: v3(23)?,
            rotate_axis: q(26)?,
            joint_orient: q(30)?,
            inverse_parent_scale: v3(34)?,
            compensate: self.num(37)? != 0.0,
        }))
    }

    /// `polyFaces`: `f N e…` faces, `h N e…` holes, `mu SET N uv…` UVs; `fc`, `mc` and
    /// `mf` (colours, flags) are read past.
    pub fn poly_faces(&self) -> Result<Vec<PolyFace>, ValueError> {
        let mut faces: Vec<PolyFace> = Vec::new();
        let mut i = 0;
        while i < self.toks.len() {
            let key = self.toks[i].raw(self.src);
            let list = |start: usize| -> Result<(Vec<i64>, usize), ValueError> {
                let n = self.count(start)?;
                let v = (start + 1..start + 1 + n)
                    .map(|k| self.int(k))
                    .collect::<Result<Vec<_>, _>>()?;
                Ok((v, start + 1 + n))
            };
            match key {
                "f" => {
                    let (edges, next) = list(i + 1)?;
                    faces.push(PolyFace {
                        edges,
                        ..Default::default()
                    });
                    i = next;
                }
                "h" => {
                    let (hole, next) = list(i + 1)?;
                    match faces.last_mut() {
                        Some(f) => f.holes.push(hole),
                        None => return self.fail(i, "a hole `h` before any face `f`"),
                    }
                    i = next;
                }
                "mu" => {
                    let set = self.count(i + 1)? as u32;
                    let (uvs, next) = list(i + 2)?;
                    match faces.last_mut() {
                        Some(f) => f.uvs.push((set, uvs)),
                        None => return self.fail(i, "UVs `mu` before any face `f`"),
                    }
                    i = next;
                }
                "mc" => {
                    // mc SET N c1..cN (colour indices per face vertex)
                    let (_, next) = list(i + 2)?;
                    i = next;
                }
                "fc" => {
                    let (_, next) = list(i + 1)?;
                    i = next;
                }
                "mf" => {
                    let (_, next) = list(i + 1)?;
                    i = next;
                }
                other => {
                    return self.fail(
                        i,
                        format!("unexpected `{other}` in polyFaces (expected f, h, mu, mc or fc)"),
                    )
                }
            }
        }
        Ok(faces)
    }

    /// `nurbsCurve`: `degree spans form rational dimension`, `N` knots, `M` control points
    /// of `dimension` (+1 when rational) numbers.
    pub fn nurbs_curve(&self) -> Result<NurbsCurve, ValueError> {
        let degree = self.count(0)? as u32;
        let spans = self.count(1)? as u32;
        let form = self.count(2)? as u32;
        let rational = self.num(3)? != 0.0;
        let dim = self.count(4)?;
        if !(2..=3).contains(&dim) {
            return self.fail(4, format!("curve dimension {dim}; expected 2 or 3"));
        }
        let nk = self.count(5)?;
        let knots = (6..6 + nk).map(|i| self.num(i)).collect::<Result<Vec<_>, _>>()?;
        let at = 6 + nk;
        let ncv = self.count(at)?;
        let width = dim + usize::from(rational);
        let mut cvs = Vec::with_capacity(ncv.min(self.toks.len()));
        for k in 0..ncv {
            let b = at + 1 + k * width;
            let z = if dim == 3 { self.num(b + 2)? } else { 0.0 };
            cvs.push(DVec3::new(self.num(b)?, self.num(b + 1)?, z));
        }
        Ok(NurbsCurve {
            degree,
            spans,
            form,
            knots,
            cvs,
        })
    }

    /// `attributeAlias`: `{"alias", "attr[0]", ...}` as `(alias, attribute)` pairs.
    pub fn attribute_alias(&self) -> Result<Vec<(String, String)>, ValueError> {
        let strings: Vec<String> = self
            .toks
            .iter()
            .filter(|t| t.kind == TokKind::Str)
            .map(|t| t.text(self.src).into_owned())
            .collect();
        if strings.len() % 2 != 0 {
            return self.fail(0, "an attributeAlias lists alias and attribute in pairs");
        }
        Ok(strings.chunks(2).map(|c| (c[0].clone(), c[1].clone())).collect())
    }

    /// Numbers `i..` of an element-range value: `count` elements of `width` numbers each.
    pub fn elements(&self, count: usize, width: usize) -> Result<Vec<f64>, ValueError> {
        let want = count.saturating_mul(width);
        if self.toks.len() != want {
            return self.fail(
                self.toks.len().min(want),
                format!(
                    "expected {count} elements of {width} values ({want} values), found {}",
                    self.toks.len()
                ),
            );
        }
        self.numbers()
    }

    /// Sparse weight lists of an element range such as `.wl[0:5].w`: per element a count
    /// `n` and `n` pairs `(index, value)`.
    pub fn sparse_lists(&self, count: usize) -> Result<Vec<Vec<(u32, f64)>>, ValueError> {
        let mut out = Vec::with_capacity(count.min(self.toks.len()));
        let mut i = 0;
        for _ in 0..count {
            let n = self.count(i)?;
            let mut row = Vec::with_capacity(n.min(64));
            for k in 0..n {
                let idx = self.int(i + 1 + 2 * k)?;
                let idx =
                    u32::try_from(idx).or_else(|_| self.fail(i + 1 + 2 * k, format!("index {idx} out of range")))?;
                row.push((idx, self.num(i + 2 + 2 * k)?));
            }
            out.push(row);
            i += 1 + 2 * n;
        }
        if i != self.toks.len() {
            return self.fail(
                i,
                format!(
                    "{} values left over after {count} weight lists",
                    self.toks.len().saturating_sub(i)
                ),
            );
        }
        Ok(out)
    }
}

impl XformMatrix {
    /// The composed matrix, glam column vectors: Maya's row-vector
    /// `SP⁻¹·S·SH·SP·SPT·RP⁻¹·RA·R·RP·RPT·JO·IS·T` read right to left (the joint terms are the
    /// identity for transforms). Shear composes as Maya's upper-triangular `[1 0 0; xy 1 0;
    /// xz yz 1]` rows.
    pub fn matrix(&self) -> DMat4 {
        use sinew_nodes::transform::euler::{euler_to_quat, RotateOrder};
        let order = RotateOrder::from_index(self.rotate_order).unwrap_or(RotateOrder::Xyz);
        let r = DMat4::from_quat(euler_to_quat(self.rotate, order));
        let t = DMat4::from_translation;
        let s = DMat4::from_scale(self.scale);
        let sh = DMat4::from_cols_array(&[
            1.0,
            0.0,
            0.0,
            0.0,
            self.shear.x,
            1.0,
            0.0,
            0.0,
            self.shear.y,
            self.shear.z,
            1.0,
            0.0,
            0.0,
            0.0,
            0.0,
            1.0,
        ]);
        let is = if self.compensate {
            DMat4::from_scale(self.inverse_parent_scale.recip())
        } else {
            DMat4::IDENTITY
        };
        t(self.translate)
            * is
            * DMat4::from_quat(self.joint_orient)
            * t(self.rotate_pivot_translate)
            * t(self.rotate_pivot)
            * r
            * DMat4::from_quat(self.rotate_axis)
            * t(-self.rotate_pivot)
            * t(self.scale_pivot_translate)
            * t(self.scale_pivot)
            * sh
            * s
            * t(-self.scale_pivot)
    }
}
