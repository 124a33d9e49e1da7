//! The byte codec under [`crate::program_bin`]: value and shared-data tags, the
//! little-endian `Writer` and the bounds-checked `Reader` (every read names what it was
//! reading, so corrupt bytes give a precise error).

use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3, Vec2, Vec3};

use crate::data::{Curve, CurveForm, Mesh, Surface, Weights};
use crate::error::{Error, Result};
use crate::program::Binding;
use crate::value::{ObjectRef, Value};

// Value tags. Small constants get their own tag so a typical rig's slots are mostly one byte.
/// An error about the compiled program's bytes.
pub(crate) fn err(msg: impl Into<String>) -> Error {
    Error::Program(format!("compiled program: {}", msg.into()))
}

pub(crate) const V_FALSE: u8 = 0;
pub(crate) const V_TRUE: u8 = 1;
pub(crate) const V_INT: u8 = 2;
pub(crate) const V_FLOAT: u8 = 3;
pub(crate) const V_FLOAT_ZERO: u8 = 4;
pub(crate) const V_FLOAT_ONE: u8 = 5;
pub(crate) const V_VEC3: u8 = 6;
pub(crate) const V_VEC3_ZERO: u8 = 7;
pub(crate) const V_VEC3_ONE: u8 = 8;
pub(crate) const V_QUAT: u8 = 9;
pub(crate) const V_QUAT_IDENTITY: u8 = 10;
pub(crate) const V_MATRIX: u8 = 11;
pub(crate) const V_MATRIX_IDENTITY: u8 = 12;
pub(crate) const V_ENUM: u8 = 13;
pub(crate) const V_OBJECT: u8 = 14;
pub(crate) const V_SHARED: u8 = 15;

// Shared (heavy) data tags.
pub(crate) const S_STRING: u8 = 0;
pub(crate) const S_MESH: u8 = 1;
pub(crate) const S_CURVE: u8 = 2;
pub(crate) const S_WEIGHTS: u8 = 3;
pub(crate) const S_FLOATS: u8 = 4;
pub(crate) const S_INTS: u8 = 5;
pub(crate) const S_VEC3S: u8 = 6;
pub(crate) const S_MATRICES: u8 = 7;
pub(crate) const S_SURFACE: u8 = 8;

#[derive(Default)]
pub(crate) struct Writer {
    pub(crate) buf: Vec<u8>,
}

impl Writer {
    pub(crate) fn u8(&mut self, x: u8) {
        self.buf.push(x);
    }
    pub(crate) fn u32(&mut self, x: u32) {
        self.buf.extend_from_slice(&x.to_le_bytes());
    }
    pub(crate) fn f32(&mut self, x: f32) {
        self.buf.extend_from_slice(&x.to_bits().to_le_bytes());
    }
    pub(crate) fn f64(&mut self, x: f64) {
        self.buf.extend_from_slice(&x.to_bits().to_le_bytes());
    }
    pub(crate) fn varint(&mut self, mut x: u64) {
        loop {
            let b = (x & 0x7f) as u8;
            x >>= 7;
            if x == 0 {
                self.buf.push(b);
                return;
            }
            self.buf.push(b | 0x80);
        }
    }
    pub(crate) fn zigzag(&mut self, x: i64) {
        self.varint(((x << 1) ^ (x >> 63)) as u64);
    }
    pub(crate) fn str(&mut self, s: &str) {
        self.varint(s.len() as u64);
        self.buf.extend_from_slice(s.as_bytes());
    }
    pub(crate) fn f64s(&mut self, xs: &[f64]) {
        for &x in xs {
            self.f64(x);
        }
    }
    pub(crate) fn binding(&mut self, b: Binding) {
        match b {
            Binding::Slot(s) => {
                self.u8(0);
                self.varint(s as u64);
            }
            Binding::Component(s, k) => {
                self.u8(1);
                self.varint(s as u64);
                self.u8(k);
            }
            Binding::Assemble(a) => {
                self.u8(2);
                self.varint(a as u64);
            }
        }
    }

    /// A small (not heavy) value: a tag byte, then its bits.
    pub(crate) fn small(&mut self, v: &Value) {
        let id = DMat4::IDENTITY.to_cols_array();
        match v {
            Value::Bool(b) => self.u8(if *b { V_TRUE } else { V_FALSE }),
            Value::Int(i) => {
                self.u8(V_INT);
                self.zigzag(*i);
            }
            Value::Enum(i) => {
                self.u8(V_ENUM);
                self.zigzag(*i);
            }
            Value::Float(x) if x.to_bits() == 0 => self.u8(V_FLOAT_ZERO),
            Value::Float(x) if x.to_bits() == 1f64.to_bits() => self.u8(V_FLOAT_ONE),
            Value::Float(x) => {
                self.u8(V_FLOAT);
                self.f64(*x);
            }
            Value::Vec3(v) if same_f64s(&v.to_array(), &[0.0; 3]) => self.u8(V_VEC3_ZERO),
            Value::Vec3(v) if same_f64s(&v.to_array(), &[1.0; 3]) => self.u8(V_VEC3_ONE),
            Value::Vec3(v) => {
                self.u8(V_VEC3);
                self.f64s(&v.to_array());
            }
            Value::Quat(q) if same_f64s(&q.to_array(), &DQuat::IDENTITY.to_array()) => self.u8(V_QUAT_IDENTITY),
            Value::Quat(q) => {
                self.u8(V_QUAT);
                self.f64s(&q.to_array());
            }
            Value::Matrix(m) if same_f64s(&m.to_cols_array(), &id) => self.u8(V_MATRIX_IDENTITY),
            Value::Matrix(m) => {
                self.u8(V_MATRIX);
                self.f64s(&m.to_cols_array());
            }
            // Heavy values go through the shared table (`V_SHARED`); objects are caches.
            _ => self.u8(V_OBJECT),
        }
    }
    pub(crate) fn bits(&mut self, bits: &[bool]) {
        self.varint(bits.len() as u64);
        for chunk in bits.chunks(8) {
            self.u8(chunk
                .iter()
                .enumerate()
                .fold(0u8, |acc, (i, &b)| acc | ((b as u8) << i)));
        }
    }
    pub(crate) fn shared(&mut self, v: &Value) {
        match v {
            Value::String(s) => {
                self.u8(S_STRING);
                self.str(s);
            }
            Value::Mesh(m) => {
                self.u8(S_MESH);
                self.varint(m.positions.len() as u64);
                for p in &m.positions {
                    p.to_array().iter().for_each(|&x| self.f32(x));
                }
                self.varint(m.normals.len() as u64);
                for p in &m.normals {
                    p.to_array().iter().for_each(|&x| self.f32(x));
                }
                self.varint(m.uvs.len() as u64);
                for p in &m.uvs {
                    p.to_array().iter().for_each(|&x| self.f32(x));
                }
                self.varint(m.triangles.len() as u64);
                for t in &m.triangles {
                    t.iter().for_each(|&i| self.u32(i));
                }
            }
            Value::Curve(c) => {
                self.u8(S_CURVE);
                self.varint(c.degree as u64);
                self.u8(matches!(c.form, CurveForm::Periodic) as u8);
                self.varint(c.points.len() as u64);
                for p in &c.points {
                    self.f64s(&p.to_array());
                }
                self.varint(c.knots.len() as u64);
                self.f64s(&c.knots);
            }
            Value::Surface(c) => {
                self.u8(S_SURFACE);
                self.varint(c.degree_u as u64);
                self.varint(c.degree_v as u64);
                self.u8(matches!(c.form_u, CurveForm::Periodic) as u8);
                self.u8(matches!(c.form_v, CurveForm::Periodic) as u8);
                self.varint(c.count_u as u64);
                self.varint(c.count_v as u64);
                self.varint(c.points.len() as u64);
                for p in &c.points {
                    self.f64s(&p.to_array());
                }
                self.varint(c.knots_u.len() as u64);
                self.f64s(&c.knots_u);
                self.varint(c.knots_v.len() as u64);
                self.f64s(&c.knots_v);
            }
            Value::Weights(w) => {
                self.u8(S_WEIGHTS);
                self.varint(w.offsets.len() as u64);
                w.offsets.iter().for_each(|&x| self.u32(x));
                self.varint(w.joints.len() as u64);
                w.joints.iter().for_each(|&x| self.u32(x));
                self.varint(w.weights.len() as u64);
                w.weights.iter().for_each(|&x| self.f32(x));
            }
            Value::FloatArray(a) => {
                self.u8(S_FLOATS);
                self.varint(a.len() as u64);
                self.f64s(a);
            }
            Value::IntArray(a) => {
                self.u8(S_INTS);
                self.varint(a.len() as u64);
                a.iter().for_each(|&x| self.zigzag(x));
            }
            Value::Vec3Array(a) => {
                self.u8(S_VEC3S);
                self.varint(a.len() as u64);
                for p in a.iter() {
                    self.f64s(&p.to_array());
                }
            }
            Value::MatrixArray(a) => {
                self.u8(S_MATRICES);
                self.varint(a.len() as u64);
                for m in a.iter() {
                    self.f64s(&m.to_cols_array());
                }
            }
            // Not heavy: `value` never routes these here.
            _ => self.u8(u8::MAX),
        }
    }
}

pub(crate) fn same_f64s(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

pub(crate) struct Reader<'a> {
    pub(crate) buf: &'a [u8],
    pub(crate) pos: usize,
}

impl<'a> Reader<'a> {
    pub(crate) fn fail(&self, what: &str) -> Error {
        err(format!("corrupt data at payload byte {}: {what}", self.pos))
    }
    pub(crate) fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8]> {
        if self.buf.len() - self.pos < n {
            return Err(self.fail(&format!("unexpected end while reading {what}")));
        }
        let s = &self.buf[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }
    pub(crate) fn u8(&mut self, what: &str) -> Result<u8> {
        Ok(self.take(1, what)?[0])
    }
    pub(crate) fn u32(&mut self, what: &str) -> Result<u32> {
        let b = self.take(4, what)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    pub(crate) fn u64(&mut self, what: &str) -> Result<u64> {
        let b = self.take(8, what)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Ok(u64::from_le_bytes(a))
    }
    pub(crate) fn f32(&mut self, what: &str) -> Result<f32> {
        Ok(f32::from_bits(self.u32(what)?))
    }
    pub(crate) fn f64(&mut self, what: &str) -> Result<f64> {
        Ok(f64::from_bits(self.u64(what)?))
    }
    pub(crate) fn f64s<const N: usize>(&mut self, what: &str) -> Result<[f64; N]> {
        let mut a = [0.0; N];
        for x in &mut a {
            *x = self.f64(what)?;
        }
        Ok(a)
    }
    pub(crate) fn f32s<const N: usize>(&mut self, what: &str) -> Result<[f32; N]> {
        let mut a = [0.0; N];
        for x in &mut a {
            *x = self.f32(what)?;
        }
        Ok(a)
    }
    pub(crate) fn varint(&mut self, what: &str) -> Result<u64> {
        let mut x: u64 = 0;
        for i in 0..10 {
            let b = self.u8(what)?;
            let bits = (b & 0x7f) as u64;
            if i == 9 && bits > 1 {
                return Err(self.fail(&format!("{what}: integer overflows 64 bits")));
            }
            x |= bits << (7 * i);
            if b & 0x80 == 0 {
                return Ok(x);
            }
        }
        Err(self.fail(&format!("{what}: integer longer than 10 bytes")))
    }
    pub(crate) fn u32v(&mut self, what: &str) -> Result<u32> {
        let x = self.varint(what)?;
        u32::try_from(x).map_err(|_| self.fail(&format!("{what}: {x} does not fit 32 bits")))
    }
    pub(crate) fn zigzag(&mut self, what: &str) -> Result<i64> {
        let x = self.varint(what)?;
        Ok(((x >> 1) as i64) ^ -((x & 1) as i64))
    }
    /// A count of items that each take at least `min_bytes`, checked against the bytes left.
    pub(crate) fn count(&mut self, min_bytes: usize, what: &str) -> Result<usize> {
        let n = self.varint(what)?;
        let left = (self.buf.len() - self.pos) as u64;
        if n.saturating_mul(min_bytes.max(1) as u64) > left {
            return Err(self.fail(&format!("{what}: count {n} exceeds the remaining {left} bytes")));
        }
        Ok(n as usize)
    }
    pub(crate) fn str(&mut self, what: &str) -> Result<&'a str> {
        let n = self.count(1, what)?;
        let b = self.take(n, what)?;
        std::str::from_utf8(b).map_err(|_| self.fail(&format!("{what}: not UTF-8")))
    }
    pub(crate) fn binding(&mut self) -> Result<Binding> {
        Ok(match self.u8("binding")? {
            0 => Binding::Slot(self.u32v("slot")?),
            1 => Binding::Component(self.u32v("slot")?, self.u8("lane")?),
            2 => Binding::Assemble(self.u32v("assembly")?),
            t => return Err(self.fail(&format!("unknown binding tag {t}"))),
        })
    }
    pub(crate) fn bits(&mut self, what: &str) -> Result<Vec<bool>> {
        let n = self.varint(what)?;
        let bytes = n.div_ceil(8);
        if bytes > (self.buf.len() - self.pos) as u64 {
            return Err(self.fail(&format!("{what}: {n} bits exceed the remaining bytes")));
        }
        let raw = self.take(bytes as usize, what)?;
        Ok((0..n as usize).map(|i| raw[i / 8] & (1 << (i % 8)) != 0).collect())
    }
    pub(crate) fn shared(&mut self) -> Result<Value> {
        Ok(match self.u8("shared data tag")? {
            S_STRING => Value::String(Arc::from(self.str("string")?)),
            S_MESH => {
                let n = self.count(12, "mesh positions")?;
                let positions = (0..n)
                    .map(|_| self.f32s::<3>("position").map(Vec3::from_array))
                    .collect::<Result<Vec<_>>>()?;
                let n = self.count(12, "mesh normals")?;
                let normals = (0..n)
                    .map(|_| self.f32s::<3>("normal").map(Vec3::from_array))
                    .collect::<Result<Vec<_>>>()?;
                let n = self.count(8, "mesh uvs")?;
                let uvs = (0..n)
                    .map(|_| self.f32s::<2>("uv").map(Vec2::from_array))
                    .collect::<Result<Vec<_>>>()?;
                let n = self.count(12, "mesh triangles")?;
                let triangles = (0..n)
                    .map(|_| Ok([self.u32("index")?, self.u32("index")?, self.u32("index")?]))
                    .collect::<Result<Vec<_>>>()?;
                let mesh = Mesh {
                    positions,
                    normals,
                    uvs,
                    triangles,
                };
                mesh.validate().map_err(|m| self.fail(&format!("invalid mesh: {m}")))?;
                Value::Mesh(Arc::new(mesh))
            }
            S_CURVE => {
                let degree = self.u32v("curve degree")?;
                if !(1..=7).contains(&degree) {
                    return Err(self.fail(&format!("curve degree {degree} is not from 1 to 7")));
                }
                let form = match self.u8("curve form")? {
                    0 => CurveForm::Open,
                    1 => CurveForm::Periodic,
                    t => return Err(self.fail(&format!("unknown curve form {t}"))),
                };
                let n = self.count(24, "curve points")?;
                let points = (0..n)
                    .map(|_| self.f64s::<3>("point").map(DVec3::from_array))
                    .collect::<Result<Vec<_>>>()?;
                let n = self.count(8, "curve knots")?;
                let knots = (0..n).map(|_| self.f64("knot")).collect::<Result<Vec<_>>>()?;
                Value::Curve(Arc::new(Curve {
                    degree,
                    points,
                    knots,
                    form,
                }))
            }
            S_SURFACE => {
                let degree_u = self.u32v("surface degree u")?;
                let degree_v = self.u32v("surface degree v")?;
                let mut form = |what: &str| -> Result<CurveForm> {
                    match self.u8(what)? {
                        0 => Ok(CurveForm::Open),
                        1 => Ok(CurveForm::Periodic),
                        t => Err(self.fail(&format!("unknown {what} {t}"))),
                    }
                };
                let form_u = form("surface form u")?;
                let form_v = form("surface form v")?;
                let count_u = self.u32v("surface count u")?;
                let count_v = self.u32v("surface count v")?;
                let n = self.count(24, "surface points")?;
                let points = (0..n)
                    .map(|_| self.f64s::<3>("point").map(DVec3::from_array))
                    .collect::<Result<Vec<_>>>()?;
                let n = self.count(8, "surface knots u")?;
                let knots_u = (0..n).map(|_| self.f64("knot")).collect::<Result<Vec<_>>>()?;
                let n = self.count(8, "surface knots v")?;
                let knots_v = (0..n).map(|_| self.f64("knot")).collect::<Result<Vec<_>>>()?;
                let surface = Surface {
                    degree_u,
                    degree_v,
                    form_u,
                    form_v,
                    count_u,
                    count_v,
                    points,
                    knots_u,
                    knots_v,
                };
                surface
                    .validate()
                    .map_err(|m| self.fail(&format!("invalid surface: {m}")))?;
                Value::Surface(Arc::new(surface))
            }
            S_WEIGHTS => {
                let n = self.count(4, "weight offsets")?;
                let offsets = (0..n).map(|_| self.u32("offset")).collect::<Result<Vec<_>>>()?;
                let n = self.count(4, "weight joints")?;
                let joints = (0..n).map(|_| self.u32("joint")).collect::<Result<Vec<_>>>()?;
                let n = self.count(4, "weights")?;
                let weights = (0..n).map(|_| self.f32("weight")).collect::<Result<Vec<_>>>()?;
                let w = Weights {
                    offsets,
                    joints,
                    weights,
                };
                w.validate().map_err(|m| self.fail(&format!("invalid weights: {m}")))?;
                Value::Weights(Arc::new(w))
            }
            S_FLOATS => {
                let n = self.count(8, "float array")?;
                Value::FloatArray(Arc::new((0..n).map(|_| self.f64("float")).collect::<Result<_>>()?))
            }
            S_INTS => {
                let n = self.count(1, "int array")?;
                Value::IntArray(Arc::new((0..n).map(|_| self.zigzag("int")).collect::<Result<_>>()?))
            }
            S_VEC3S => {
                let n = self.count(24, "vec3 array")?;
                Value::Vec3Array(Arc::new(
                    (0..n)
                        .map(|_| self.f64s::<3>("vec3").map(DVec3::from_array))
                        .collect::<Result<_>>()?,
                ))
            }
            S_MATRICES => {
                let n = self.count(128, "matrix array")?;
                Value::MatrixArray(Arc::new(
                    (0..n)
                        .map(|_| self.f64s::<16>("matrix").map(|a| DMat4::from_cols_array(&a)))
                        .collect::<Result<_>>()?,
                ))
            }
            t => return Err(self.fail(&format!("unknown shared data tag {t}"))),
        })
    }
    pub(crate) fn value(&mut self, shared: &[Value]) -> Result<Value> {
        Ok(match self.u8("value tag")? {
            V_FALSE => Value::Bool(false),
            V_TRUE => Value::Bool(true),
            V_INT => Value::Int(self.zigzag("int")?),
            V_ENUM => Value::Enum(self.zigzag("enum")?),
            V_FLOAT => Value::Float(self.f64("float")?),
            V_FLOAT_ZERO => Value::Float(0.0),
            V_FLOAT_ONE => Value::Float(1.0),
            V_VEC3 => Value::Vec3(DVec3::from_array(self.f64s::<3>("vec3")?)),
            V_VEC3_ZERO => Value::Vec3(DVec3::ZERO),
            V_VEC3_ONE => Value::Vec3(DVec3::ONE),
            V_QUAT => Value::Quat(DQuat::from_array(self.f64s::<4>("quat")?)),
            V_QUAT_IDENTITY => Value::Quat(DQuat::IDENTITY),
            V_MATRIX => Value::Matrix(DMat4::from_cols_array(&self.f64s::<16>("matrix")?)),
            V_MATRIX_IDENTITY => Value::Matrix(DMat4::IDENTITY),
            V_OBJECT => Value::Object(ObjectRef::default()),
            V_SHARED => {
                let i = self.u32v("shared data index")? as usize;
                shared
                    .get(i)
                    .cloned()
                    .ok_or_else(|| self.fail(&format!("shared data index {i} out of range")))?
            }
            t => return Err(self.fail(&format!("unknown value tag {t}"))),
        })
    }
}
