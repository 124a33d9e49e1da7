//! glTF 2.0 writer: a [`Scene`] to `.glb` bytes or a self-contained `.gltf` string.
//!
//! Output is written to pass the Khronos glTF validator with zero errors: the scene is
//! validated first; nodes carry TRS (unit rotations); every bufferView is 4-byte
//! aligned; vertex attribute views have the ARRAY_BUFFER target and index views
//! ELEMENT_ARRAY_BUFFER, while skin and animation views have none; POSITION (base and
//! morph target) and animation input accessors carry exact `min`/`max`; skin weights
//! are written as `JOINTS_n` (unsigned short) / `WEIGHTS_n` (float) sets of four,
//! strongest first, duplicates merged and sums normalized to 1; indices are unsigned
//! short when every index is below 65535 (the primitive-restart value), else unsigned
//! int. Materials, textures and cameras are not written.

use std::borrow::Cow;
use std::collections::HashMap;

use base64::Engine as _;
use serde_json::{json, Map, Value};

use super::scene::{AnimPath, GltfError, Interpolation, Primitive, Scene};

const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;
const FLOAT: u32 = 5126;

/// Writes `scene` as binary glTF (`.glb`): JSON chunk plus one BIN chunk.
pub fn write_glb(scene: &Scene) -> Result<Vec<u8>, GltfError> {
    let (json, bin) = build(scene, false)?;
    let json = serde_json::to_vec(&json).map_err(|e| GltfError::Json(e.to_string()))?;
    let glb = gltf::binary::Glb {
        header: gltf::binary::Header {
            magic: *b"glTF",
            version: 2,
            length: 0, // computed by `to_vec`
        },
        json: Cow::Owned(json),
        bin: (!bin.is_empty()).then_some(Cow::Owned(bin)),
    };
    glb.to_vec().map_err(|e| GltfError::Glb(e.to_string()))
}

/// Writes `scene` as a single `.gltf` JSON document with the buffer embedded as a
/// base64 `data:` URI (about a third larger than [`write_glb`]'s output).
pub fn write_gltf_embedded(scene: &Scene) -> Result<String, GltfError> {
    let (json, _) = build(scene, true)?;
    serde_json::to_string_pretty(&json).map_err(|e| GltfError::Json(e.to_string()))
}

/// The binary buffer under construction with its views and accessors.
#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
    /// Animation input accessors shared between channels with bit-identical times.
    times: HashMap<Vec<u32>, usize>,
}

impl Builder {
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        let mut v = json!({
            "buffer": 0,
            "byteOffset": self.bin.len(),
            "byteLength": bytes.len(),
        });
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        self.bin.extend_from_slice(bytes);
        self.views.push(v);
        self.views.len() - 1
    }

    /// A FLOAT accessor over `data` with `width` components per element.
    fn floats(&mut self, data: &[f32], ty: &str, width: usize, target: Option<u32>, bounds: bool) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|x| x.to_le_bytes()).collect();
        let view = self.view(&bytes, target);
        let mut a = json!({
            "bufferView": view,
            "componentType": FLOAT,
            "count": data.len() / width.max(1),
            "type": ty,
        });
        if bounds {
            let mut min = vec![f64::INFINITY; width];
            let mut max = vec![f64::NEG_INFINITY; width];
            for chunk in data.chunks_exact(width) {
                for (c, &x) in chunk.iter().enumerate() {
                    // Exact f32 values as f64, so the validator's comparison is exact.
                    min[c] = min[c].min(x as f64);
                    max[c] = max[c].max(x as f64);
                }
            }
            a["min"] = json!(min);
            a["max"] = json!(max);
        }
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    /// An unsigned integer accessor (unsigned short or int) over `data`.
    fn uints(&mut self, data: &[u32], ty: &str, width: usize, target: u32, short: bool) -> usize {
        let bytes: Vec<u8> = if short {
            data.iter().flat_map(|&x| (x as u16).to_le_bytes()).collect()
        } else {
            data.iter().flat_map(|x| x.to_le_bytes()).collect()
        };
        let view = self.view(&bytes, Some(target));
        self.accessors.push(json!({
            "bufferView": view,
            "componentType": if short { UNSIGNED_SHORT } else { UNSIGNED_INT },
            "count": data.len() / width.max(1),
            "type": ty,
        }));
        self.accessors.len() - 1
    }

    fn input(&mut self, times: &[f32]) -> usize {
        let key: Vec<u32> = times.iter().map(|t| t.to_bits()).collect();
        if let Some(&a) = self.times.get(&key) {
            return a;
        }
        let a = self.floats(times, "SCALAR", 1, None, true);
        self.times.insert(key, a);
        a
    }
}

fn flat3(v: &[glam::Vec3]) -> Vec<f32> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

fn named(mut v: Value, name: &Option<String>) -> Value {
    if let Some(n) = name {
        v["name"] = json!(n);
    }
    v
}

fn build(scene: &Scene, embed: bool) -> Result<(Value, Vec<u8>), GltfError> {
    scene
        .validate()
        .map_err(|e| GltfError::Invalid(format!("cannot write scene: {e}")))?;
    let mut b = Builder::default();

    let nodes: Vec<Value> = scene
        .nodes
        .iter()
        .map(|n| {
            let mut v = named(json!({}), &n.name);
            if !n.children.is_empty() {
                v["children"] = json!(n.children);
            }
            if n.translation != glam::DVec3::ZERO {
                v["translation"] = json!(n.translation.to_array());
            }
            let r = n.rotation.normalize();
            if r != glam::DQuat::IDENTITY {
                v["rotation"] = json!(r.to_array());
            }
            if n.scale != glam::DVec3::ONE {
                v["scale"] = json!(n.scale.to_array());
            }
            if let Some(m) = n.mesh {
                v["mesh"] = json!(m);
            }
            if let Some(s) = n.skin {
                v["skin"] = json!(s);
            }
            if !n.weights.is_empty() {
                v["weights"] = json!(n.weights);
            }
            v
        })
        .collect();

    let mut meshes = Vec::new();
    for mesh in &scene.meshes {
        let prims = mesh.primitives.iter().map(|p| primitive(&mut b, p)).collect::<Vec<_>>();
        let mut v = named(json!({ "primitives": prims }), &mesh.name);
        if !mesh.weights.is_empty() {
            v["weights"] = json!(mesh.weights);
        }
        if !mesh.target_names.is_empty() {
            v["extras"] = json!({ "targetNames": mesh.target_names });
        }
        meshes.push(v);
    }

    let mut skins = Vec::new();
    for skin in &scene.skins {
        let ibm: Vec<f32> = skin
            .inverse_bind_matrices
            .iter()
            .flat_map(|m| m.to_cols_array())
            .collect();
        let mut v = named(json!({ "joints": skin.joints }), &skin.name);
        if !ibm.is_empty() {
            v["inverseBindMatrices"] = json!(b.floats(&ibm, "MAT4", 16, None, false));
        }
        if let Some(s) = skin.skeleton {
            v["skeleton"] = json!(s);
        }
        skins.push(v);
    }

    let mut animations = Vec::new();
    for anim in &scene.animations {
        let mut samplers = Vec::new();
        let mut channels = Vec::new();
        for ch in &anim.channels {
            let input = b.input(&ch.times);
            let mut values = ch.values.clone();
            if ch.path == AnimPath::Rotation {
                // Unit quaternions (cubic splines: only the spline vertices, not tangents).
                let cubic = ch.interpolation == Interpolation::CubicSpline;
                for (i, q) in values.chunks_exact_mut(4).enumerate() {
                    if !cubic || i % 3 == 1 {
                        // In f64: a finite f32 quaternion's length cannot overflow there.
                        let q64 = glam::DQuat::from_xyzw(q[0].into(), q[1].into(), q[2].into(), q[3].into());
                        let n = q64.normalize();
                        q.copy_from_slice(&n.to_array().map(|x| x as f32));
                    }
                }
            }
            let ty = match ch.path {
                AnimPath::Translation | AnimPath::Scale => "VEC3",
                AnimPath::Rotation => "VEC4",
                AnimPath::Weights => "SCALAR",
            };
            let width = if ch.path == AnimPath::Weights { 1 } else { ch.width };
            let output = b.floats(&values, ty, width, None, false);
            samplers.push(json!({
                "input": input,
                "output": output,
                "interpolation": match ch.interpolation {
                    Interpolation::Linear => "LINEAR",
                    Interpolation::Step => "STEP",
                    Interpolation::CubicSpline => "CUBICSPLINE",
                },
            }));
            channels.push(json!({
                "sampler": samplers.len() - 1,
                "target": {
                    "node": ch.node,
                    "path": match ch.path {
                        AnimPath::Translation => "translation",
                        AnimPath::Rotation => "rotation",
                        AnimPath::Scale => "scale",
                        AnimPath::Weights => "weights",
                    },
                },
            }));
        }
        animations.push(named(json!({ "channels": channels, "samplers": samplers }), &anim.name));
    }

    while b.bin.len() % 4 != 0 {
        b.bin.push(0);
    }
    let mut root = Map::new();
    root.insert("asset".into(), json!({ "version": "2.0", "generator": "sinew" }));
    let roots: Vec<usize> = if scene.roots.is_empty() {
        (0..scene.nodes.len())
            .filter(|&i| scene.nodes[i].parent.is_none())
            .collect()
    } else {
        scene.roots.clone()
    };
    if !scene.nodes.is_empty() {
        root.insert("scene".into(), json!(0));
        root.insert("scenes".into(), json!([{ "nodes": roots }]));
        root.insert("nodes".into(), json!(nodes));
    }
    let mut put = |key: &str, v: Vec<Value>| {
        if !v.is_empty() {
            root.insert(key.into(), Value::Array(v));
        }
    };
    put("meshes", meshes);
    put("skins", skins);
    put("animations", animations);
    put("accessors", std::mem::take(&mut b.accessors));
    put("bufferViews", std::mem::take(&mut b.views));
    if !b.bin.is_empty() {
        let mut buf = json!({ "byteLength": b.bin.len() });
        if embed {
            let data = base64::engine::general_purpose::STANDARD.encode(&b.bin);
            buf["uri"] = json!(format!("data:application/octet-stream;base64,{data}"));
        }
        root.insert("buffers".into(), json!([buf]));
    }
    Ok((Value::Object(root), b.bin))
}

fn primitive(b: &mut Builder, p: &Primitive) -> Value {
    let m = &p.mesh;
    let vc = m.vertex_count();
    let mut attrs = Map::new();
    let pos = b.floats(&flat3(&m.positions), "VEC3", 3, Some(ARRAY_BUFFER), true);
    attrs.insert("POSITION".into(), json!(pos));
    if !m.normals.is_empty() {
        let normals: Vec<glam::Vec3> = m
            .normals
            .iter()
            .map(|n| n.try_normalize().unwrap_or(glam::Vec3::Y))
            .collect();
        let a = b.floats(&flat3(&normals), "VEC3", 3, Some(ARRAY_BUFFER), false);
        attrs.insert("NORMAL".into(), json!(a));
    }
    if !m.uvs.is_empty() {
        let uv: Vec<f32> = m.uvs.iter().flat_map(|u| u.to_array()).collect();
        let a = b.floats(&uv, "VEC2", 2, Some(ARRAY_BUFFER), false);
        attrs.insert("TEXCOORD_0".into(), json!(a));
    }
    if let Some(w) = &p.skin_weights {
        // Per vertex: merge duplicate joints, drop non-positive weights, strongest
        // first, normalize; vertices with no influence follow joint 0 fully.
        let lists: Vec<Vec<(u32, f32)>> = (0..vc)
            .map(|v| {
                let (js, ws) = w.influences(v);
                let mut l: Vec<(u32, f32)> = Vec::new();
                for (&j, &x) in js.iter().zip(ws) {
                    match l.iter_mut().find(|e| e.0 == j) {
                        Some(e) => e.1 += x,
                        None => l.push((j, x)),
                    }
                }
                l.retain(|e| e.1 > 0.0);
                l.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
                let sum: f32 = l.iter().map(|e| e.1).sum();
                if l.is_empty() || !sum.is_finite() {
                    return vec![(0, 1.0)];
                }
                l.iter_mut().for_each(|e| e.1 /= sum);
                let resid = 1.0 - l.iter().map(|e| e.1).sum::<f32>();
                l[0].1 += resid;
                l
            })
            .collect();
        let sets = lists.iter().map(|l| l.len().div_ceil(4)).max().unwrap_or(1).max(1);
        for set in 0..sets {
            let mut joints = vec![0u32; vc * 4];
            let mut weights = vec![0f32; vc * 4];
            for (v, l) in lists.iter().enumerate() {
                for (k, &(j, x)) in l.iter().skip(set * 4).take(4).enumerate() {
                    joints[v * 4 + k] = j;
                    weights[v * 4 + k] = x;
                }
            }
            let short = joints.iter().all(|&j| j <= u16::MAX as u32);
            let ja = b.uints(&joints, "VEC4", 4, ARRAY_BUFFER, short);
            let wa = b.floats(&weights, "VEC4", 4, Some(ARRAY_BUFFER), false);
            attrs.insert(format!("JOINTS_{set}"), json!(ja));
            attrs.insert(format!("WEIGHTS_{set}"), json!(wa));
        }
    }
    let mut v = json!({ "attributes": attrs });
    if m.triangles.is_empty() {
        v["mode"] = json!(0); // POINTS: nothing to triangulate
    } else {
        let idx: Vec<u32> = m.triangles.iter().flatten().copied().collect();
        let short = idx.iter().all(|&i| i < u16::MAX as u32);
        v["indices"] = json!(b.uints(&idx, "SCALAR", 1, ELEMENT_ARRAY_BUFFER, short));
    }
    if !p.targets.is_empty() {
        let targets: Vec<Value> = p
            .targets
            .iter()
            .map(|t| {
                let mut tv = Map::new();
                if !t.positions.is_empty() || t.normals.is_empty() {
                    let d = if t.positions.is_empty() {
                        vec![0.0; vc * 3]
                    } else {
                        flat3(&t.positions)
                    };
                    tv.insert(
                        "POSITION".into(),
                        json!(b.floats(&d, "VEC3", 3, Some(ARRAY_BUFFER), true)),
                    );
                }
                if !t.normals.is_empty() {
                    let a = b.floats(&flat3(&t.normals), "VEC3", 3, Some(ARRAY_BUFFER), false);
                    tv.insert("NORMAL".into(), json!(a));
                }
                Value::Object(tv)
            })
            .collect();
        v["targets"] = json!(targets);
    }
    v
}
