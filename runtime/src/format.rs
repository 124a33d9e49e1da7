//! The rig's compiled binary form: a small header with what the runtime adds
//! to a program (name, frame rate, joints with parent indices, skin clusters)
//! followed by the program's own bytes (`sinew_core::Program::to_bytes`).
//!
//! ```text
//! "SINEWRIG" | version u32 | name | fps f64 | joint count u32 | (name, parent i32)* |
//! skin count u32 | name* | program length u64 | program bytes (own header and checksum)
//! ```
//!
//! Strings are a u32 length and UTF-8 bytes; integers little-endian. Every
//! length is checked against the bytes left, so corrupt input gives an error.

use std::sync::Arc;

use sinew_core::{Program, Registry};

use crate::rig::{Joint, Rig};
use crate::{ErrorKind, Result, RuntimeError};

/// The first eight bytes of a compiled rig.
pub(crate) const MAGIC: &[u8; 8] = b"SINEWRIG";
/// The format version written by this build.
pub(crate) const VERSION: u32 = 1;

pub(crate) fn encode_rig(rig: &Rig) -> Vec<u8> {
    let inner = &rig.inner;
    let mut out = Vec::new();
    let str_ = |out: &mut Vec<u8>, s: &str| {
        out.extend_from_slice(&(s.len() as u32).to_le_bytes());
        out.extend_from_slice(s.as_bytes());
    };
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    str_(&mut out, &inner.name);
    out.extend_from_slice(&inner.fps.to_le_bytes());
    out.extend_from_slice(&(inner.joints.len() as u32).to_le_bytes());
    for (j, &p) in inner.joints.iter().zip(&inner.parents) {
        str_(&mut out, &j.name);
        out.extend_from_slice(&p.to_le_bytes());
    }
    out.extend_from_slice(&(inner.skins.len() as u32).to_le_bytes());
    for s in &inner.skins {
        str_(&mut out, &s.name);
    }
    let program = inner.program.to_bytes();
    out.extend_from_slice(&(program.len() as u64).to_le_bytes());
    out.extend_from_slice(&program);
    out
}

struct Reader<'a> {
    buf: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8]> {
        if self.buf.len() - self.pos < n {
            return Err(corrupt(format!("unexpected end while reading {what}")));
        }
        let s = &self.buf[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }
    fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N]> {
        let mut a = [0u8; N];
        a.copy_from_slice(self.take(N, what)?);
        Ok(a)
    }
    fn u32(&mut self, what: &str) -> Result<u32> {
        Ok(u32::from_le_bytes(self.array(what)?))
    }
    fn str(&mut self, what: &str) -> Result<String> {
        let n = self.u32(what)? as usize;
        let b = self.take(n, what)?;
        String::from_utf8(b.to_vec()).map_err(|_| corrupt(format!("{what} is not UTF-8")))
    }
}

fn corrupt(msg: String) -> RuntimeError {
    RuntimeError::new(ErrorKind::Format, format!("compiled rig: {msg}"))
}

pub(crate) fn decode_rig(bytes: &[u8], registry: &Registry) -> Result<Rig> {
    if bytes.len() < 8 || &bytes[..8] != MAGIC {
        return Err(corrupt(
            "not a sinew compiled rig (missing the SINEWRIG header); write it with Rig::to_bytes".into(),
        ));
    }
    let mut r = Reader { buf: bytes, pos: 8 };
    let version = r.u32("version")?;
    if version != VERSION {
        return Err(corrupt(format!(
            "format version {version}, but this build reads version {VERSION}; recompile the rig with this version"
        )));
    }
    let name = r.str("rig name")?;
    let fps = f64::from_le_bytes(r.array("fps")?);
    let n = r.u32("joint count")? as usize;
    // Each joint takes at least 8 bytes: refuse absurd counts before allocating.
    if n > (bytes.len() - r.pos) / 8 {
        return Err(corrupt(format!("joint count {n} exceeds the data")));
    }
    let mut joints = Vec::with_capacity(n);
    for i in 0..n {
        let jname = r.str("joint name")?;
        let parent = i32::from_le_bytes(r.array("joint parent")?);
        let parent = match parent {
            -1 => None,
            p if p >= 0 && (p as usize) < i => Some(p as usize),
            p => {
                return Err(corrupt(format!(
                    "joint {i} has parent {p}, which does not come before it"
                )))
            }
        };
        joints.push(Joint { name: jname, parent });
    }
    let n = r.u32("skin count")? as usize;
    if n > (bytes.len() - r.pos) / 4 {
        return Err(corrupt(format!("skin count {n} exceeds the data")));
    }
    let mut skins = Vec::with_capacity(n);
    for _ in 0..n {
        skins.push(r.str("skin name")?);
    }
    let len = u64::from_le_bytes(r.array("program length")?);
    if len != (bytes.len() - r.pos) as u64 {
        return Err(corrupt(format!(
            "the program is announced as {len} bytes but {} follow (truncated or padded)",
            bytes.len() - r.pos
        )));
    }
    let program = Program::from_bytes(&bytes[r.pos..], registry).map_err(|e| corrupt(e.to_string()))?;
    Rig::assemble(name, fps, Arc::new(program), joints, skins)
}
