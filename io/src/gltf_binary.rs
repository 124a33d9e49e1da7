//! The byte layer of the glTF reader: the GLB container, buffer loading (GLB BIN
//! chunk, base64 `data:` URIs, external files) and accessor decoding (strides, sparse
//! substitution, normalized integers), all with explicit bounds checks so corrupt
//! input gives a [`GltfError`] and never a panic.

use std::path::Path;

use base64::Engine as _;
use gltf::accessor::{DataType, Dimensions};

use super::scene::GltfError;

/// Splits a GLB container into its JSON chunk and optional BIN chunk, checking every
/// length against the data actually present (GLB 2.0, section "Binary glTF Layout").
pub(super) fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), GltfError> {
    let bad = |m: String| GltfError::Glb(m);
    let u32_at = |o: usize| -> Option<usize> {
        let b = bytes.get(o..o + 4)?;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
    };
    let version = u32_at(4).ok_or_else(|| bad("file ends inside the 12-byte header".into()))?;
    if version != 2 {
        return Err(bad(format!("version {version}, only glTF 2 is supported")));
    }
    let total = u32_at(8).ok_or_else(|| bad("file ends inside the 12-byte header".into()))?;
    if total > bytes.len() || total < 20 {
        return Err(bad(format!(
            "header declares {total} bytes but the file has {} (truncated?)",
            bytes.len()
        )));
    }
    let mut chunks = Vec::new();
    let mut at = 12;
    while at < total {
        let (Some(len), Some(ty)) = (u32_at(at), bytes.get(at + 4..at + 8)) else {
            return Err(bad(format!("chunk header at byte {at} is cut off")));
        };
        let start = at + 8;
        let end = start.checked_add(len).filter(|&e| e <= total).ok_or_else(|| {
            bad(format!(
                "chunk at byte {at} declares {len} bytes but only {} remain",
                total.saturating_sub(start)
            ))
        })?;
        chunks.push((ty, &bytes[start..end]));
        at = end;
    }
    match chunks.as_slice() {
        [(b"JSON", json), rest @ ..] => {
            let bin = rest.iter().find(|(t, _)| *t == b"BIN\0").map(|(_, d)| *d);
            Ok((json, bin))
        }
        _ => Err(bad("the first chunk must be the JSON chunk".into())),
    }
}

/// Loads every buffer, checking it holds at least its declared `byteLength`.
pub(super) fn load_buffers(
    doc: &gltf::Document,
    bin: Option<&[u8]>,
    base_dir: Option<&Path>,
) -> Result<Vec<Vec<u8>>, GltfError> {
    let mut out = Vec::new();
    for buffer in doc.buffers() {
        let index = buffer.index();
        let err = |message: String| GltfError::Buffer { index, message };
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => bin
                .ok_or_else(|| err("refers to the GLB BIN chunk but the file has none".into()))?
                .to_vec(),
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                let (_, payload) = uri
                    .split_once(";base64,")
                    .ok_or_else(|| err("data: URI is not base64-encoded".into()))?;
                base64::engine::general_purpose::STANDARD
                    .decode(payload.trim())
                    .map_err(|e| err(format!("bad base64 in data: URI: {e}")))?
            }
            gltf::buffer::Source::Uri(uri) => {
                let dir = base_dir.ok_or_else(|| {
                    err(format!(
                        "refers to external file '{uri}' but no base directory was given"
                    ))
                })?;
                let path = dir.join(percent_decode(uri));
                sinew_core::files::read_file(&path, sinew_core::files::DATA)
                    .map_err(|e| err(format!("cannot read external file {}: {e}", path.display())))?
            }
        };
        if data.len() < buffer.length() {
            return Err(err(format!(
                "declares {} bytes but only {} are present (truncated?)",
                buffer.length(),
                data.len()
            )));
        }
        let mut data = data;
        data.truncate(buffer.length());
        out.push(data);
    }
    Ok(out)
}

/// Decodes `%XX` escapes in a relative URI (glTF URIs are RFC 3986).
fn percent_decode(uri: &str) -> String {
    let b = uri.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let hex = b.get(i + 1..i + 3).and_then(|h| std::str::from_utf8(h).ok());
        match (b[i], hex.and_then(|h| u8::from_str_radix(h, 16).ok())) {
            (b'%', Some(v)) => {
                out.push(v);
                i += 3;
            }
            (c, _) => {
                out.push(c);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// What kind of numbers an accessor may hold for a given use.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Kind {
    /// FLOAT only.
    Float,
    /// FLOAT or normalized unsigned byte/short (UVs, weights).
    FloatOrUnorm,
    /// FLOAT or any normalized integer (animation outputs for rotation and weights).
    FloatOrNorm,
    /// Unsigned integers, not normalized (indices, joints).
    Uint,
}

/// Fewest elements a view-less accessor may always have (see [`Buffers::read`]).
pub(super) const MIN_VIEWLESS_ELEMENTS: usize = 1 << 16;
/// Fewest numbers the accessors of any file may decode to in all (see [`Buffers::new`]).
pub(super) const MIN_DECODE_BUDGET: usize = 1 << 24;

/// Loaded buffer data, indexed like the document's buffers, and what is left of the
/// file's decoding budget.
pub(super) struct Buffers {
    data: Vec<Vec<u8>>,
    /// Largest number of elements an accessor without a buffer view may have.
    viewless_limit: usize,
    /// Numbers the accessors may still decode to.
    budget: std::cell::Cell<usize>,
}

impl Buffers {
    /// Wraps the loaded buffers. Work is bounded by the data the file holds: an accessor
    /// without a buffer view (zeros, plus sparse substitutions) has at most
    /// max([`MIN_VIEWLESS_ELEMENTS`], bytes in the buffers) elements, and all accessor
    /// reads together (an accessor used twice counts twice) decode to at most
    /// max([`MIN_DECODE_BUDGET`], 32 × bytes in the buffers) numbers. A few hundred bytes
    /// of JSON naming huge counts are refused instead of allocating gigabytes.
    pub(super) fn new(data: Vec<Vec<u8>>) -> Self {
        let bytes: usize = data.iter().map(Vec::len).sum();
        Buffers {
            viewless_limit: MIN_VIEWLESS_ELEMENTS.max(bytes),
            budget: std::cell::Cell::new(MIN_DECODE_BUDGET.max(bytes.saturating_mul(32))),
            data,
        }
    }

    /// Reads accessor `acc` as `f64` components, checking type, bounds and finiteness.
    /// Returns the flat values; `dims` lists the accepted element types.
    pub(super) fn read(
        &self,
        acc: &gltf::Accessor,
        dims: &[Dimensions],
        kind: Kind,
        ctx: &str,
    ) -> Result<Vec<f64>, GltfError> {
        let err = |message: String| GltfError::Accessor {
            index: acc.index(),
            context: ctx.to_string(),
            message,
        };
        if !dims.contains(&acc.dimensions()) {
            return Err(err(format!(
                "type is {:?} but {:?} is required",
                acc.dimensions(),
                dims
            )));
        }
        let dt = acc.data_type();
        let ok = match kind {
            Kind::Float => dt == DataType::F32,
            Kind::FloatOrUnorm => {
                dt == DataType::F32 || (acc.normalized() && matches!(dt, DataType::U8 | DataType::U16))
            }
            Kind::FloatOrNorm => dt == DataType::F32 || (acc.normalized() && dt != DataType::U32),
            Kind::Uint => !acc.normalized() && matches!(dt, DataType::U8 | DataType::U16 | DataType::U32),
        };
        if !ok {
            return Err(err(format!(
                "component type {dt:?}{} is not allowed here",
                if acc.normalized() { " (normalized)" } else { "" }
            )));
        }
        let width = acc.dimensions().multiplicity();
        let count = acc.count();
        let csize = dt.size();
        if matches!(acc.dimensions(), Dimensions::Mat2 | Dimensions::Mat3) && csize < 4 {
            return Err(err("padded small-component matrices are not supported".into()));
        }
        if acc.view().is_none() && count > self.viewless_limit {
            return Err(err(format!(
                "count {count} without a buffer view is more than the {} elements the file's data can justify",
                self.viewless_limit
            )));
        }
        let total = count
            .checked_mul(width)
            .filter(|&t| t <= 1 << 28)
            .ok_or_else(|| err(format!("count {count} is unreasonably large")))?;
        let left = self.budget.get();
        if total > left {
            return Err(err(format!(
                "decoding {total} more numbers would exceed the file's budget of \
                 max({MIN_DECODE_BUDGET}, 32 × its buffer bytes) decoded numbers (accessors are read once per use)"
            )));
        }
        // The view must hold every element before anything is sized by the count.
        let viewed = match acc.view() {
            Some(view) => {
                let elem = width * csize;
                let stride = view.stride().unwrap_or(elem);
                if stride < elem {
                    return Err(err(format!(
                        "byteStride {stride} is smaller than the element ({elem} bytes)"
                    )));
                }
                let bytes = self.view_bytes(&view, acc.index(), ctx)?;
                let need = if count == 0 {
                    0
                } else {
                    acc.offset()
                        .saturating_add((count - 1).saturating_mul(stride))
                        .saturating_add(elem)
                };
                let data = bytes
                    .get(acc.offset()..)
                    .filter(|_| need <= bytes.len())
                    .ok_or_else(|| {
                        err(format!(
                            "needs {need} bytes of buffer view {} but it has {}",
                            view.index(),
                            bytes.len()
                        ))
                    })?;
                Some((data, stride))
            }
            None => None,
        };
        self.budget.set(left - total);
        let mut out = vec![0.0f64; total];
        if let Some((data, stride)) = viewed {
            for i in 0..count {
                for c in 0..width {
                    let o = i * stride + c * csize;
                    out[i * width + c] = component(&data[o..o + csize], dt, acc.normalized());
                }
            }
        }
        if let Some(sparse) = acc.sparse() {
            let n = sparse.count();
            let iv = sparse.indices().view();
            let ibytes = self.view_bytes(&iv, acc.index(), ctx)?;
            let isize = match sparse.indices().index_type() {
                gltf::accessor::sparse::IndexType::U8 => 1,
                gltf::accessor::sparse::IndexType::U16 => 2,
                gltf::accessor::sparse::IndexType::U32 => 4,
            };
            let vv = sparse.values().view();
            let vbytes = self.view_bytes(&vv, acc.index(), ctx)?;
            let elem = width * csize;
            let ioff = sparse.indices().offset();
            let voff = sparse.values().offset();
            let short = || err(format!("sparse data for {n} elements does not fit its buffer views"));
            let iend = ioff.saturating_add(n.saturating_mul(isize));
            let vend = voff.saturating_add(n.saturating_mul(elem));
            let idata = ibytes.get(ioff..iend).ok_or_else(short)?;
            let vdata = vbytes.get(voff..vend).ok_or_else(short)?;
            for s in 0..n {
                let ib = &idata[s * isize..(s + 1) * isize];
                let target = ib.iter().rev().fold(0usize, |a, &b| (a << 8) | b as usize);
                if target >= count {
                    return Err(err(format!("sparse index {target} is outside {count} elements")));
                }
                for c in 0..width {
                    let o = s * elem + c * csize;
                    out[target * width + c] = component(&vdata[o..o + csize], dt, acc.normalized());
                }
            }
        }
        if let Some(i) = out.iter().position(|x| !x.is_finite()) {
            return Err(err(format!("element {} holds NaN or infinity", i / width.max(1))));
        }
        Ok(out)
    }

    fn view_bytes(&self, view: &gltf::buffer::View, acc: usize, ctx: &str) -> Result<&[u8], GltfError> {
        let b = self.data.get(view.buffer().index()).map(Vec::as_slice).unwrap_or(&[]);
        b.get(view.offset()..view.offset().saturating_add(view.length()))
            .ok_or_else(|| GltfError::Accessor {
                index: acc,
                context: ctx.to_string(),
                message: format!(
                    "buffer view {} (bytes {}..{}) reaches past the end of buffer {} ({} bytes)",
                    view.index(),
                    view.offset(),
                    view.offset().saturating_add(view.length()),
                    view.buffer().index(),
                    b.len()
                ),
            })
    }
}

/// One component as `f64`, applying the spec's normalized-integer decoding.
fn component(b: &[u8], dt: DataType, normalized: bool) -> f64 {
    let le = |n: usize| b.iter().take(n).rev().fold(0u32, |a, &x| (a << 8) | x as u32);
    match (dt, normalized) {
        (DataType::F32, _) => f32::from_bits(le(4)) as f64,
        (DataType::U8, true) => le(1) as f64 / 255.0,
        (DataType::U16, true) => le(2) as f64 / 65535.0,
        (DataType::I8, true) => (le(1) as u8 as i8 as f64 / 127.0).max(-1.0),
        (DataType::I16, true) => (le(2) as u16 as i16 as f64 / 32767.0).max(-1.0),
        (DataType::I8, false) => le(1) as u8 as i8 as f64,
        (DataType::I16, false) => le(2) as u16 as i16 as f64,
        (DataType::U8 | DataType::U16 | DataType::U32, _) => le(dt.size()) as f64,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A document whose accessor 0 is `count` scalars without a buffer view (zeros, with
    /// one sparse substitution of element 0 by 0.0, as the spec requires of a view-less
    /// accessor) and accessor 1 is `count` scalars in a 4-byte view.
    fn doc(count: usize) -> gltf::Document {
        let json = format!(
            r#"{{"asset":{{"version":"2.0"}},"buffers":[{{"byteLength":4}}],
            "bufferViews":[{{"buffer":0,"byteLength":4}}],
            "accessors":[{{"componentType":5126,"count":{count},"type":"SCALAR",
                           "sparse":{{"count":1,"indices":{{"bufferView":0,"componentType":5125}},
                                      "values":{{"bufferView":0}}}}}},
                         {{"bufferView":0,"componentType":5126,"count":{count},"type":"SCALAR"}}]}}"#
        );
        gltf::Gltf::from_slice(json.as_bytes()).expect("valid glTF").document
    }

    fn read(buffers: &Buffers, doc: &gltf::Document, index: usize) -> Result<Vec<f64>, GltfError> {
        let acc = doc.accessors().nth(index).expect("accessor");
        buffers.read(&acc, &[Dimensions::Scalar], Kind::Float, "test")
    }

    /// With 4 bytes of data the budget is its floor, 2^24 numbers: 256 reads of a
    /// 2^16-element view-less accessor (the most such an accessor may have) use it up
    /// exactly, and the 257th is refused with the budget named. A view-less accessor one
    /// element over its limit is refused on its own.
    #[test]
    fn decoding_stops_at_the_file_budget() {
        let buffers = Buffers::new(vec![vec![0; 4]]);
        let d = doc(MIN_VIEWLESS_ELEMENTS);
        let reads = MIN_DECODE_BUDGET / MIN_VIEWLESS_ELEMENTS;
        assert_eq!(reads, 256);
        for _ in 0..reads {
            let v = read(&buffers, &d, 0).expect("within the budget");
            assert_eq!(v.len(), MIN_VIEWLESS_ELEMENTS);
        }
        let e = read(&buffers, &d, 0).expect_err("over the budget").to_string();
        assert!(e.contains("exceed the file's budget"), "{e}");
        let fresh = Buffers::new(vec![vec![0; 4]]);
        let e = read(&fresh, &doc(MIN_VIEWLESS_ELEMENTS + 1), 0)
            .expect_err("over the view-less limit")
            .to_string();
        assert!(e.contains("without a buffer view"), "{e}");
    }

    /// The budget grows with the data: 32 numbers per buffer byte above the floor.
    #[test]
    fn the_budget_scales_with_the_buffer_bytes() {
        let bytes = MIN_DECODE_BUDGET / 32 + 1000;
        let buffers = Buffers::new(vec![vec![0; bytes]]);
        assert_eq!(buffers.budget.get(), bytes * 32);
        assert_eq!(buffers.viewless_limit, bytes);
    }

    /// A count the view cannot hold is refused before anything is sized by it, and the
    /// refused read costs no budget.
    #[test]
    fn a_view_too_small_for_the_count_is_refused_without_spending_budget() {
        let buffers = Buffers::new(vec![vec![0; 4]]);
        let d = doc(1 << 22);
        let e = read(&buffers, &d, 1).expect_err("view too small").to_string();
        assert!(e.contains("needs 16777216 bytes of buffer view 0 but it has 4"), "{e}");
        assert_eq!(buffers.budget.get(), MIN_DECODE_BUDGET);
        let e = read(&buffers, &doc(1 << 31), 1).expect_err("huge").to_string();
        assert!(e.contains("unreasonably large"), "{e}");
    }
}
