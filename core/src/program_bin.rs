//! The compiled binary form of a [`Program`]: `Program::to_bytes` and
//! `Program::from_bytes`, so an engine loads a rig's schedule in microseconds
//! instead of parsing and compiling RON.
//!
//! Layout (all integers little-endian; `varint` = unsigned LEB128):
//!
//! ```text
//! header   "SINEWPRG" | format version u32 | flags u32 (0) | payload length u64 | FNV-1a 64 of payload
//! payload  node types   name, attribute count, group count, spec fingerprint (u64)
//!          nodes        name, type index, attribute base
//!          attributes   first element, element count   (head binding and group are derived)
//!          elements     index, binding, driven flag (connected as a whole)
//!          assemblies   own slot, three optional component sources
//!          shared data  heavy values (strings, meshes, weights, curves, arrays), each stored once
//!          slots        initial values (small values inline, common constants as one byte, heavy by index)
//!          dynamic / own-input / pruned slot bitsets, steps (node, group), frame steps
//!          guarded schedule  0, or 1 | its frame steps | guards (binding, small value)
//! ```
//!
//! Node types are stored by name and resolved through the [`Registry`] given
//! to `from_bytes`; a type whose attributes changed since the program was
//! written (different fingerprint) is refused with a message saying to
//! recompile. Floats are stored as their exact bits, so a loaded program
//! evaluates bit-identically to the one that was saved. `Object` values
//! (plugin caches) are stored empty: they are outputs that the first
//! evaluation of an instance (always a full one) recomputes.
//!
//! Decoding never panics: every length is checked against the bytes left
//! before allocating, every index is range-checked and every slot's value is
//! type-checked against the attributes bound to it, so corrupt or foreign bytes
//! give an [`Error::Program`] naming the problem.

use std::collections::HashMap;
use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3, Vec2, Vec3};

use crate::data::{Curve, CurveForm, Mesh, Weights};
use crate::error::{Error, Result};
use crate::inactive::Guard;
use crate::program::{
    frame_schedule, Assembly, AttrBinding, Binding, CompiledTables, ElemBinding, GuardedSchedule, NodeEntry, Program,
    Step,
};
use crate::registry::Registry;
use crate::spec::{AttrId, Direction, NodeSpec};
use crate::value::{AttrType, ObjectRef, Value};

/// The first eight bytes of every compiled program.
pub const MAGIC: &[u8; 8] = b"SINEWPRG";
/// The format version written by this build; other versions are refused.
pub const FORMAT_VERSION: u32 = 3;
const HEADER_LEN: usize = 8 + 4 + 4 + 8 + 8;

/// FNV-1a, 64 bit: the payload checksum and the spec fingerprint (stable across builds).
pub(crate) fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// A fingerprint of what a compiled program relies on in a node type's spec:
/// its name, attributes (name, type, direction, multi) in order and group count.
fn spec_fingerprint(spec: &NodeSpec) -> u64 {
    let mut w = Writer::default();
    w.str(&spec.name);
    w.varint(spec.attrs.len() as u64);
    for a in &spec.attrs {
        w.str(&a.name);
        w.str(a.ty.name());
        w.u8(matches!(a.direction, Direction::Output) as u8);
        w.u8(a.multi as u8);
    }
    w.varint(spec.groups().len() as u64);
    fnv1a(&w.buf)
}

// Value tags. Small constants get their own tag so a typical rig's slots are mostly one byte.
const V_FALSE: u8 = 0;
const V_TRUE: u8 = 1;
const V_INT: u8 = 2;
const V_FLOAT: u8 = 3;
const V_FLOAT_ZERO: u8 = 4;
const V_FLOAT_ONE: u8 = 5;
const V_VEC3: u8 = 6;
const V_VEC3_ZERO: u8 = 7;
const V_VEC3_ONE: u8 = 8;
const V_QUAT: u8 = 9;
const V_QUAT_IDENTITY: u8 = 10;
const V_MATRIX: u8 = 11;
const V_MATRIX_IDENTITY: u8 = 12;
const V_ENUM: u8 = 13;
const V_OBJECT: u8 = 14;
const V_SHARED: u8 = 15;

// Shared (heavy) data tags.
const S_STRING: u8 = 0;
const S_MESH: u8 = 1;
const S_CURVE: u8 = 2;
const S_WEIGHTS: u8 = 3;
const S_FLOATS: u8 = 4;
const S_INTS: u8 = 5;
const S_VEC3S: u8 = 6;
const S_MATRICES: u8 = 7;

#[derive(Default)]
struct Writer {
    buf: Vec<u8>,
}

impl Writer {
    fn u8(&mut self, x: u8) {
        self.buf.push(x);
    }
    fn u32(&mut self, x: u32) {
        self.buf.extend_from_slice(&x.to_le_bytes());
    }
    fn f32(&mut self, x: f32) {
        self.buf.extend_from_slice(&x.to_bits().to_le_bytes());
    }
    fn f64(&mut self, x: f64) {
        self.buf.extend_from_slice(&x.to_bits().to_le_bytes());
    }
    fn varint(&mut self, mut x: u64) {
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
    fn zigzag(&mut self, x: i64) {
        self.varint(((x << 1) ^ (x >> 63)) as u64);
    }
    fn str(&mut self, s: &str) {
        self.varint(s.len() as u64);
        self.buf.extend_from_slice(s.as_bytes());
    }
    fn f64s(&mut self, xs: &[f64]) {
        for &x in xs {
            self.f64(x);
        }
    }
    fn binding(&mut self, b: Binding) {
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
    fn small(&mut self, v: &Value) {
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
    fn bits(&mut self, bits: &[bool]) {
        self.varint(bits.len() as u64);
        for chunk in bits.chunks(8) {
            self.u8(chunk
                .iter()
                .enumerate()
                .fold(0u8, |acc, (i, &b)| acc | ((b as u8) << i)));
        }
    }
    fn shared(&mut self, v: &Value) {
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

fn same_f64s(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// The address of the `Arc` behind a heavy value (its identity, for sharing).
fn heavy_ptr(v: &Value) -> Option<usize> {
    Some(match v {
        Value::String(a) => Arc::as_ptr(a) as *const u8 as usize,
        Value::Mesh(a) => Arc::as_ptr(a) as usize,
        Value::Curve(a) => Arc::as_ptr(a) as usize,
        Value::Weights(a) => Arc::as_ptr(a) as usize,
        Value::FloatArray(a) => Arc::as_ptr(a) as usize,
        Value::IntArray(a) => Arc::as_ptr(a) as usize,
        Value::Vec3Array(a) => Arc::as_ptr(a) as usize,
        Value::MatrixArray(a) => Arc::as_ptr(a) as usize,
        _ => return None,
    })
}

impl Program {
    /// Serializes the compiled program (see the [module docs](crate::program_bin)
    /// for the layout). Load it back with [`Program::from_bytes`].
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut w = Writer::default();
        // Node types, each once.
        let mut type_index: HashMap<&str, u32> = HashMap::new();
        let mut types: Vec<&NodeSpec> = Vec::new();
        for n in &self.nodes {
            let spec = n.kind.spec();
            type_index.entry(spec.name.as_str()).or_insert_with(|| {
                types.push(spec);
                (types.len() - 1) as u32
            });
        }
        w.varint(types.len() as u64);
        for spec in &types {
            w.str(&spec.name);
            w.varint(spec.attrs.len() as u64);
            w.varint(spec.groups().len() as u64);
            w.buf.extend_from_slice(&spec_fingerprint(spec).to_le_bytes());
        }
        w.varint(self.nodes.len() as u64);
        for n in &self.nodes {
            w.str(&n.name);
            w.varint(type_index.get(n.kind.spec().name.as_str()).copied().unwrap_or(0) as u64);
            w.varint(n.attr_base as u64);
        }
        w.varint(self.attr_bindings.len() as u64);
        for ab in &self.attr_bindings {
            w.varint(ab.first as u64);
            w.varint(ab.len as u64);
        }
        w.varint(self.tables.elems.len() as u64);
        for e in &self.tables.elems {
            w.varint(e.index as u64);
            w.binding(e.binding);
            w.u8(e.driven as u8);
        }
        w.varint(self.tables.assemblies.len() as u64);
        for a in &self.tables.assemblies {
            w.varint(a.own as u64);
            for c in &a.comps {
                match c {
                    None => w.u8(0),
                    Some((s, None)) => {
                        w.u8(1);
                        w.varint(*s as u64);
                    }
                    Some((s, Some(k))) => {
                        w.u8(2);
                        w.varint(*s as u64);
                        w.u8(*k);
                    }
                }
            }
        }
        // Heavy data, each allocation once (instances and slots share it after loading too).
        let mut shared_index: HashMap<usize, u32> = HashMap::new();
        let mut shared: Vec<&Value> = Vec::new();
        let slot_shared: Vec<Option<u32>> = self
            .initial
            .iter()
            .map(|v| {
                heavy_ptr(v).map(|p| {
                    *shared_index.entry(p).or_insert_with(|| {
                        shared.push(v);
                        (shared.len() - 1) as u32
                    })
                })
            })
            .collect();
        w.varint(shared.len() as u64);
        for v in &shared {
            w.shared(v);
        }
        w.varint(self.initial.len() as u64);
        for (v, sh) in self.initial.iter().zip(&slot_shared) {
            if let Some(i) = sh {
                w.u8(V_SHARED);
                w.varint(*i as u64);
                continue;
            }
            w.small(v);
        }
        w.bits(&self.dynamic_slot);
        w.bits(&self.own_input_slot);
        w.bits(&self.pruned_slot);
        w.varint(self.steps.len() as u64);
        for s in &self.steps {
            w.varint(s.node as u64);
            w.varint(s.group as u64);
        }
        w.varint(self.frame_steps.len() as u64);
        for &f in &self.frame_steps {
            w.varint(f as u64);
        }
        match &self.guarded {
            None => w.u8(0),
            Some(g) => {
                w.u8(1);
                w.varint(g.frame_steps.len() as u64);
                for &f in &g.frame_steps {
                    w.varint(f as u64);
                }
                w.varint(g.guards.len() as u64);
                for guard in &g.guards {
                    w.binding(guard.binding);
                    w.small(&guard.value);
                }
            }
        }
        let payload = w.buf;
        let mut out = Vec::with_capacity(HEADER_LEN + payload.len());
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        out.extend_from_slice(&0u32.to_le_bytes());
        out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
        out.extend_from_slice(&fnv1a(&payload).to_le_bytes());
        out.extend_from_slice(&payload);
        out
    }

    /// Loads a program written by [`Program::to_bytes`], resolving node types
    /// by name in `registry`. Corrupt, truncated or foreign bytes, an unknown
    /// node type or one whose attributes changed give an error (never a panic).
    pub fn from_bytes(bytes: &[u8], registry: &Registry) -> Result<Program> {
        let payload = check_header(bytes)?;
        decode_payload(payload, registry)
    }
}

fn err(msg: impl Into<String>) -> Error {
    Error::Program(format!("compiled program: {}", msg.into()))
}

fn check_header(bytes: &[u8]) -> Result<&[u8]> {
    if bytes.len() < 8 || &bytes[..8] != MAGIC {
        return Err(err(
            "not a sinew compiled program (missing the SINEWPRG header); write it with Program::to_bytes",
        ));
    }
    if bytes.len() < HEADER_LEN {
        return Err(err(format!("truncated header ({} bytes)", bytes.len())));
    }
    let u32_at = |o: usize| u32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]);
    let u64_at = |o: usize| {
        let mut a = [0u8; 8];
        a.copy_from_slice(&bytes[o..o + 8]);
        u64::from_le_bytes(a)
    };
    let version = u32_at(8);
    if version != FORMAT_VERSION {
        return Err(err(format!(
            "format version {version}, but this build reads version {FORMAT_VERSION}; recompile the rig with this version"
        )));
    }
    if u32_at(12) != 0 {
        return Err(err("unknown flags in the header"));
    }
    let len = u64_at(16);
    let payload = &bytes[HEADER_LEN..];
    if payload.len() as u64 != len {
        return Err(err(format!(
            "the header announces {len} payload bytes but {} follow (truncated or padded file)",
            payload.len()
        )));
    }
    if fnv1a(payload) != u64_at(24) {
        return Err(err("checksum mismatch: the bytes are corrupt"));
    }
    Ok(payload)
}

struct Reader<'a> {
    buf: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    fn fail(&self, what: &str) -> Error {
        err(format!("corrupt data at payload byte {}: {what}", self.pos))
    }
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8]> {
        if self.buf.len() - self.pos < n {
            return Err(self.fail(&format!("unexpected end while reading {what}")));
        }
        let s = &self.buf[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }
    fn u8(&mut self, what: &str) -> Result<u8> {
        Ok(self.take(1, what)?[0])
    }
    fn u32(&mut self, what: &str) -> Result<u32> {
        let b = self.take(4, what)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    fn u64(&mut self, what: &str) -> Result<u64> {
        let b = self.take(8, what)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Ok(u64::from_le_bytes(a))
    }
    fn f32(&mut self, what: &str) -> Result<f32> {
        Ok(f32::from_bits(self.u32(what)?))
    }
    fn f64(&mut self, what: &str) -> Result<f64> {
        Ok(f64::from_bits(self.u64(what)?))
    }
    fn f64s<const N: usize>(&mut self, what: &str) -> Result<[f64; N]> {
        let mut a = [0.0; N];
        for x in &mut a {
            *x = self.f64(what)?;
        }
        Ok(a)
    }
    fn f32s<const N: usize>(&mut self, what: &str) -> Result<[f32; N]> {
        let mut a = [0.0; N];
        for x in &mut a {
            *x = self.f32(what)?;
        }
        Ok(a)
    }
    fn varint(&mut self, what: &str) -> Result<u64> {
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
    fn u32v(&mut self, what: &str) -> Result<u32> {
        let x = self.varint(what)?;
        u32::try_from(x).map_err(|_| self.fail(&format!("{what}: {x} does not fit 32 bits")))
    }
    fn zigzag(&mut self, what: &str) -> Result<i64> {
        let x = self.varint(what)?;
        Ok(((x >> 1) as i64) ^ -((x & 1) as i64))
    }
    /// A count of items that each take at least `min_bytes`, checked against the bytes left.
    fn count(&mut self, min_bytes: usize, what: &str) -> Result<usize> {
        let n = self.varint(what)?;
        let left = (self.buf.len() - self.pos) as u64;
        if n.saturating_mul(min_bytes.max(1) as u64) > left {
            return Err(self.fail(&format!("{what}: count {n} exceeds the remaining {left} bytes")));
        }
        Ok(n as usize)
    }
    fn str(&mut self, what: &str) -> Result<&'a str> {
        let n = self.count(1, what)?;
        let b = self.take(n, what)?;
        std::str::from_utf8(b).map_err(|_| self.fail(&format!("{what}: not UTF-8")))
    }
    fn binding(&mut self) -> Result<Binding> {
        Ok(match self.u8("binding")? {
            0 => Binding::Slot(self.u32v("slot")?),
            1 => Binding::Component(self.u32v("slot")?, self.u8("lane")?),
            2 => Binding::Assemble(self.u32v("assembly")?),
            t => return Err(self.fail(&format!("unknown binding tag {t}"))),
        })
    }
    fn bits(&mut self, what: &str) -> Result<Vec<bool>> {
        let n = self.varint(what)?;
        let bytes = n.div_ceil(8);
        if bytes > (self.buf.len() - self.pos) as u64 {
            return Err(self.fail(&format!("{what}: {n} bits exceed the remaining bytes")));
        }
        let raw = self.take(bytes as usize, what)?;
        Ok((0..n as usize).map(|i| raw[i / 8] & (1 << (i % 8)) != 0).collect())
    }
    fn shared(&mut self) -> Result<Value> {
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
    fn value(&mut self, shared: &[Value]) -> Result<Value> {
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

fn decode_payload(payload: &[u8], registry: &Registry) -> Result<Program> {
    let mut r = Reader { buf: payload, pos: 0 };
    // Node types.
    let n = r.count(11, "node types")?;
    let mut types = Vec::with_capacity(n);
    for _ in 0..n {
        let name = r.str("node type name")?;
        let attr_count = r.varint("attribute count")?;
        let group_count = r.varint("group count")?;
        let fingerprint = r.u64("spec fingerprint")?;
        let kind = registry.get(name).ok_or_else(|| {
            err(format!(
                "node type `{name}` is not registered{}; register the plugin that provides it before loading",
                registry
                    .suggest(name)
                    .map(|s| format!(" (did you mean `{s}`?)"))
                    .unwrap_or_default()
            ))
        })?;
        let spec = kind.spec();
        if spec.attrs.len() as u64 != attr_count
            || spec.groups().len() as u64 != group_count
            || spec_fingerprint(spec) != fingerprint
        {
            return Err(err(format!(
                "node type `{name}` changed since the program was compiled (its attributes or compute groups differ); recompile the rig"
            )));
        }
        types.push(kind.clone());
    }
    // Nodes.
    let n = r.count(3, "nodes")?;
    let mut nodes = Vec::with_capacity(n);
    let mut node_index = HashMap::with_capacity(n);
    for i in 0..n {
        let name = r.str("node name")?;
        let t = r.u32v("node type index")? as usize;
        let kind = types
            .get(t)
            .cloned()
            .ok_or_else(|| r.fail(&format!("node type index {t} out of range")))?;
        let attr_base = r.u32v("attribute base")?;
        if node_index.insert(name.to_string(), i as u32).is_some() {
            return Err(r.fail(&format!("node name `{name}` appears twice")));
        }
        nodes.push(NodeEntry {
            name: name.to_string(),
            kind,
            attr_base,
        });
    }
    // Attribute bindings (head and group are filled in once elements are known).
    let n = r.count(2, "attributes")?;
    let mut attr_bindings = Vec::with_capacity(n);
    for _ in 0..n {
        let first = r.u32v("first element")?;
        let len = r.u32v("element count")?;
        attr_bindings.push(AttrBinding {
            first,
            len,
            ..AttrBinding::default()
        });
    }
    let n = r.count(4, "elements")?;
    let mut elems = Vec::with_capacity(n);
    for _ in 0..n {
        let index = r.u32v("element index")?;
        let binding = r.binding()?;
        let driven = match r.u8("element driven flag")? {
            0 => false,
            1 => true,
            t => return Err(r.fail(&format!("bad element driven flag {t}"))),
        };
        elems.push(ElemBinding { index, binding, driven });
    }
    let n = r.count(4, "assemblies")?;
    let mut assemblies = Vec::with_capacity(n);
    for _ in 0..n {
        let own = r.u32v("assembly slot")?;
        let mut comps = [None; 3];
        for c in &mut comps {
            *c = match r.u8("assembly component")? {
                0 => None,
                1 => Some((r.u32v("component slot")?, None)),
                2 => Some((r.u32v("component slot")?, Some(r.u8("component lane")?))),
                t => return Err(r.fail(&format!("unknown assembly component tag {t}"))),
            };
        }
        assemblies.push(Assembly { own, comps });
    }
    let n = r.count(2, "shared data")?;
    let mut shared = Vec::with_capacity(n);
    for _ in 0..n {
        shared.push(r.shared()?);
    }
    let n = r.count(1, "slots")?;
    let mut initial = Vec::with_capacity(n);
    for _ in 0..n {
        initial.push(r.value(&shared)?);
    }
    let dynamic_slot = r.bits("dynamic slots")?;
    let own_input_slot = r.bits("own input slots")?;
    let pruned_slot = r.bits("pruned slots")?;
    let n = r.count(2, "steps")?;
    let mut step_keys = Vec::with_capacity(n);
    for _ in 0..n {
        let node = r.u32v("step node")?;
        let group = r.u32v("step group")?;
        step_keys.push((node, group));
    }
    let n = r.count(1, "frame steps")?;
    let mut frame_steps = Vec::with_capacity(n);
    for _ in 0..n {
        frame_steps.push(r.u32v("frame step")?);
    }
    let guarded = match r.u8("guarded schedule flag")? {
        0 => None,
        1 => {
            let n = r.count(1, "guarded frame steps")?;
            let mut steps = Vec::with_capacity(n);
            for _ in 0..n {
                steps.push(r.u32v("guarded frame step")?);
            }
            let n = r.count(3, "guards")?;
            let mut guards = Vec::with_capacity(n);
            for _ in 0..n {
                let binding = r.binding()?;
                let value = r.value(&[])?;
                guards.push(Guard { binding, value });
            }
            Some((steps, guards))
        }
        t => return Err(r.fail(&format!("bad guarded schedule flag {t}"))),
    };
    if r.pos != payload.len() {
        return Err(r.fail("trailing bytes after the program"));
    }

    // Validation: everything evaluation and `handle` index must be in range and well typed.
    let slots = initial.len();
    if dynamic_slot.len() != slots || own_input_slot.len() != slots || pruned_slot.len() != slots {
        return Err(err("slot flag tables do not match the slot count"));
    }
    let tables = CompiledTables { elems, assemblies };
    let slot_ok = |s: u32| (s as usize) < slots;
    let slot_ty = |s: u32| initial.get(s as usize).map(|v| v.attr_type());
    for (i, a) in tables.assemblies.iter().enumerate() {
        let bad_comp = a.comps.iter().flatten().any(|&(s, k)| match k {
            None => !matches!(
                slot_ty(s),
                Some(AttrType::Float | AttrType::Int | AttrType::Enum | AttrType::Bool)
            ),
            Some(k) => k >= 3 || slot_ty(s) != Some(AttrType::Vec3),
        });
        if slot_ty(a.own) != Some(AttrType::Vec3) || bad_comp {
            return Err(err(format!("assembly {i} refers to a missing or mistyped slot")));
        }
    }
    let mut expected_base = 0u64;
    for node in &nodes {
        let spec = node.kind.spec();
        if node.attr_base as u64 != expected_base {
            return Err(err(format!("node `{}` has a wrong attribute base", node.name)));
        }
        expected_base += spec.attrs.len() as u64;
        for (a, aspec) in spec.attrs.iter().enumerate() {
            let Some(ab) = attr_bindings.get_mut(node.attr_base as usize + a) else {
                return Err(err("attribute table shorter than the nodes need"));
            };
            let end = ab.first as u64 + ab.len as u64;
            if end > tables.elems.len() as u64 || (!aspec.multi && ab.len > 1) {
                return Err(err(format!("`{}.{}` has a bad element range", node.name, aspec.name)));
            }
            let group = spec.group_of(AttrId(a as u16)).unwrap_or(u16::MAX);
            if (aspec.direction == Direction::Output) != (group != u16::MAX) {
                return Err(err(format!("`{}.{}` has no compute group", node.name, aspec.name)));
            }
            ab.group = group;
            for e in &tables.elems[ab.first as usize..end as usize] {
                let ok = match e.binding {
                    Binding::Slot(s) => slot_ty(s).is_some_and(|t| t == aspec.ty || t.connects_to(aspec.ty)),
                    Binding::Component(s, k) => {
                        k < 3 && slot_ty(s) == Some(AttrType::Vec3) && aspec.ty == AttrType::Float
                    }
                    Binding::Assemble(x) => (x as usize) < tables.assemblies.len() && aspec.ty == AttrType::Vec3,
                };
                if !ok {
                    return Err(err(format!(
                        "`{}.{}[{}]` is bound to a missing or mistyped slot",
                        node.name, aspec.name, e.index
                    )));
                }
                if aspec.direction == Direction::Output && !matches!(e.binding, Binding::Slot(s) if slot_ok(s)) {
                    return Err(err(format!(
                        "output `{}.{}` is not bound to a slot",
                        node.name, aspec.name
                    )));
                }
            }
            ab.set_head(
                tables
                    .elems
                    .get(ab.first as usize)
                    .filter(|_| ab.len > 0)
                    .map(|e| e.binding),
            );
        }
    }
    if expected_base != attr_bindings.len() as u64 {
        return Err(err("attribute table does not match the nodes"));
    }
    let mut steps = Vec::with_capacity(step_keys.len());
    for (node, group) in step_keys {
        let Some(entry) = nodes.get(node as usize) else {
            return Err(err(format!("step refers to node {node}, out of range")));
        };
        let spec = entry.kind.spec();
        if group as usize >= spec.groups().len() {
            return Err(err(format!(
                "step of `{}` refers to group {group}, out of range",
                entry.name
            )));
        }
        steps.push(Step::new(
            entry.kind.clone(),
            node,
            entry.attr_base,
            group as u16,
            &attr_bindings,
        ));
    }
    if let Some(&f) = frame_steps.iter().find(|&&f| f as usize >= steps.len()) {
        return Err(err(format!("frame step {f} out of range")));
    }
    let guarded = match guarded {
        None => None,
        Some((guarded_steps, guards)) => {
            if let Some(&f) = guarded_steps.iter().find(|&&f| f as usize >= steps.len()) {
                return Err(err(format!("guarded frame step {f} out of range")));
            }
            for g in &guards {
                let reads = match g.binding {
                    Binding::Slot(s) => slot_ty(s),
                    Binding::Component(s, k) => {
                        (k < 3 && slot_ty(s) == Some(AttrType::Vec3)).then_some(AttrType::Float)
                    }
                    Binding::Assemble(x) => ((x as usize) < tables.assemblies.len()).then_some(AttrType::Vec3),
                };
                if reads != Some(g.value.attr_type()) {
                    return Err(err("a guard refers to a missing or mistyped slot"));
                }
            }
            Some(GuardedSchedule::new(&steps, guarded_steps, guards))
        }
    };
    Ok(Program {
        guarded,
        frame_schedule: frame_schedule(&steps, &frame_steps),
        steps,
        frame_steps,
        attr_bindings,
        tables,
        initial,
        dynamic_slot,
        own_input_slot,
        pruned_slot,
        nodes,
        node_index,
    })
}
