//! Value files: one heavy value (a float, int, vec3 or matrix array, a mesh, weights, a
//! curve or a string) in binary, exact to the bit, referenced from a rig as
//! `keyValue: File("model.data/hip_rotate.keyValue.bin")`. Importers write large arrays this
//! way (see `sinew::io::rig_builder`), so a 60,000-frame take stays a small rig file plus
//! value files read at memory speed instead of a text file too large to parse.
//!
//! Layout (little-endian): `"SINEWVAL"` | version u32 | payload length u64 | FNV-1a 64 of
//! the payload | payload. The payload is the value in the encoding compiled programs use
//! for their shared data (`program_codec`): a type tag, counts and raw `f32`/`f64`/`u32`
//! bits. Decoding checks every count against the bytes left, validates meshes and
//! weights, and never panics.

use crate::error::{Error, Result};
use crate::program_bin::fnv1a;
use crate::program_codec::{Reader, Writer};
use crate::value::{AttrType, Value};

/// The first eight bytes of every value file.
pub const MAGIC: &[u8; 8] = b"SINEWVAL";
/// The value file version this build writes and reads.
pub const VERSION: u32 = 1;
const HEADER_LEN: usize = 8 + 4 + 8 + 8;

fn bad(msg: impl Into<String>) -> Error {
    Error::Program(format!("value file: {}", msg.into()))
}

/// Whether `bytes` start like a value file.
pub fn is_value_file(bytes: &[u8]) -> bool {
    bytes.starts_with(MAGIC)
}

/// The bytes of a value file holding `v`, or `None` when `v` is not a heavy value that
/// value files hold (small values and plugin objects).
pub fn value_to_bytes(v: &Value) -> Option<Vec<u8>> {
    let t = v.attr_type();
    if !t.is_heavy() || t == AttrType::Object {
        return None;
    }
    let mut w = Writer::default();
    w.shared(v);
    let payload = w.buf;
    let mut out = Vec::with_capacity(HEADER_LEN + payload.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&fnv1a(&payload).to_le_bytes());
    out.extend_from_slice(&payload);
    Some(out)
}

/// Decodes a value file written by [`value_to_bytes`]; corrupt, truncated or foreign
/// bytes give an error naming the problem.
pub fn value_from_bytes(bytes: &[u8]) -> Result<Value> {
    if !is_value_file(bytes) {
        return Err(bad("not a sinew value file (missing the SINEWVAL header)"));
    }
    if bytes.len() < HEADER_LEN {
        return Err(bad(format!("truncated header ({} bytes)", bytes.len())));
    }
    let u32_at = |o: usize| u32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]);
    let u64_at = |o: usize| {
        let mut a = [0u8; 8];
        a.copy_from_slice(&bytes[o..o + 8]);
        u64::from_le_bytes(a)
    };
    let version = u32_at(8);
    if version != VERSION {
        return Err(bad(format!(
            "version {version}, but this build reads version {VERSION}; re-import the file"
        )));
    }
    let payload = &bytes[HEADER_LEN..];
    if payload.len() as u64 != u64_at(12) {
        return Err(bad(format!(
            "the header announces {} payload bytes but {} follow (truncated or padded file)",
            u64_at(12),
            payload.len()
        )));
    }
    if fnv1a(payload) != u64_at(20) {
        return Err(bad("checksum mismatch: the bytes are corrupt"));
    }
    let mut r = Reader { buf: payload, pos: 0 };
    let v = r.shared().map_err(|e| bad(e.to_string()))?;
    if r.pos != payload.len() {
        return Err(bad("trailing bytes after the value"));
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use glam::{DMat4, DVec3, Vec3};

    use super::*;
    use crate::data::{CurveForm, Mesh, Surface, Weights};

    #[test]
    fn heavy_values_round_trip_bit_for_bit() {
        let values = [
            Value::FloatArray(Arc::new(vec![0.1, -0.0, 1e-300, f64::MAX])),
            Value::IntArray(Arc::new(vec![-3, 0, i64::MAX])),
            Value::Vec3Array(Arc::new(vec![DVec3::new(1.0, 2.0, 3.0)])),
            Value::MatrixArray(Arc::new(vec![DMat4::from_translation(DVec3::X)])),
            Value::String(Arc::from("hip")),
            Value::Weights(Arc::new(Weights::from_lists([vec![(0, 0.25), (3, 0.75)]]))),
            Value::Mesh(Arc::new(Mesh {
                positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
                normals: vec![Vec3::Z; 3],
                uvs: Vec::new(),
                triangles: vec![[0, 1, 2]],
            })),
            Value::Surface(Arc::new(Surface {
                degree_u: 2,
                degree_v: 1,
                form_u: CurveForm::Periodic,
                form_v: CurveForm::Open,
                count_u: 3,
                count_v: 2,
                points: (0..6).map(|i| DVec3::new(i as f64, 0.5, -0.0)).collect(),
                knots_u: Vec::new(),
                knots_v: vec![0.0, 0.0, 1.0, 1.0],
            })),
        ];
        for v in values {
            let bytes = value_to_bytes(&v).unwrap();
            let back = value_from_bytes(&bytes).unwrap();
            assert!(back.same_bits(&v), "{v}");
        }
        assert!(value_to_bytes(&Value::Float(1.0)).is_none());
    }

    #[test]
    fn corrupt_bytes_are_refused() {
        let bytes = value_to_bytes(&Value::FloatArray(Arc::new(vec![1.0, 2.0]))).unwrap();
        assert!(value_from_bytes(b"hello").unwrap_err().to_string().contains("SINEWVAL"));
        assert!(value_from_bytes(&bytes[..bytes.len() - 1]).is_err());
        let mut flipped = bytes.clone();
        *flipped.last_mut().unwrap() ^= 1;
        assert!(value_from_bytes(&flipped).unwrap_err().to_string().contains("checksum"));
        // Every truncation and every single-byte change is an error or a value, never a panic.
        for n in 0..bytes.len() {
            let _ = value_from_bytes(&bytes[..n]);
            let mut b = bytes.clone();
            b[n] = b[n].wrapping_add(0x55);
            let _ = value_from_bytes(&b);
        }
    }
}
