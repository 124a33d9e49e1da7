//! glTF reader tests: the real assets, spec sampling with hand-computed answers, and
//! small documents built here to hit each feature and each error path.

use glam::{Mat4, Quat, Vec3};
use serde_json::{json, Value};

use super::assets_dir;
use crate::gltf_read::{read_gltf, read_gltf_slice};
use crate::scene::*;

/// Builds a `.gltf` JSON document with one embedded buffer, accessor by accessor.
#[derive(Default)]
pub(super) struct DocBuilder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

pub(super) fn f32_bytes(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

pub(super) fn u16_bytes(v: &[u16]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

impl DocBuilder {
    /// Adds a bufferView over `bytes` and an accessor on it; `extra` is merged into the accessor.
    pub(super) fn accessor(&mut self, bytes: &[u8], component: u32, count: usize, ty: &str, extra: Value) -> usize {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()}));
        self.bin.extend_from_slice(bytes);
        let mut a = json!({"bufferView": self.views.len() - 1, "componentType": component, "count": count, "type": ty});
        if let (Some(a), Value::Object(e)) = (a.as_object_mut(), extra) {
            a.extend(e);
        }
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    /// A float VEC3 POSITION accessor with the required min/max.
    pub(super) fn positions(&mut self, p: &[[f32; 3]]) -> usize {
        let min: Vec<f32> = (0..3)
            .map(|c| p.iter().map(|v| v[c]).fold(f32::INFINITY, f32::min))
            .collect();
        let max: Vec<f32> = (0..3)
            .map(|c| p.iter().map(|v| v[c]).fold(f32::NEG_INFINITY, f32::max))
            .collect();
        let flat: Vec<f32> = p.iter().flatten().copied().collect();
        self.accessor(
            &f32_bytes(&flat),
            5126,
            p.len(),
            "VEC3",
            json!({"min": min, "max": max}),
        )
    }

    /// The finished document; `buffer_len` overrides the declared byteLength.
    pub(super) fn finish(self, mut rest: Value, buffer_len: Option<usize>) -> Vec<u8> {
        use base64::Engine as _;
        let data = base64::engine::general_purpose::STANDARD.encode(&self.bin);
        rest["asset"] = json!({"version": "2.0"});
        rest["buffers"] = json!([{"byteLength": buffer_len.unwrap_or(self.bin.len()),
            "uri": format!("data:application/octet-stream;base64,{data}")}]);
        rest["bufferViews"] = json!(self.views);
        rest["accessors"] = json!(self.accessors);
        serde_json::to_vec(&rest).unwrap()
    }
}

const TRI: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

/// One triangle with the given index data (u16) on a node.
fn triangle_doc(indices: &[u16]) -> Vec<u8> {
    let mut d = DocBuilder::default();
    let pos = d.positions(&TRI);
    let idx = d.accessor(&u16_bytes(indices), 5123, indices.len(), "SCALAR", json!({}));
    d.finish(
        json!({"nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": pos}, "indices": idx}]}]}),
        None,
    )
}

/// Node transforms and weights are the JSON's numbers as `f64` (the `gltf` crate parses
/// them as `f32`: 0.1 would become 0.10000000149011612).
#[test]
fn node_values_keep_the_json_f64_numbers() {
    let mut d = DocBuilder::default();
    let pos = d.positions(&TRI);
    let t1 = d.positions(&[[0.0, 0.0, 1.0]; 3]);
    let t2 = d.positions(&[[0.0, 1.0, 0.0]; 3]);
    let mut doc: Value = serde_json::from_slice(&d.finish(
        json!({"meshes": [{"primitives": [{"attributes": {"POSITION": pos}, "targets": [{"POSITION": t1}, {"POSITION": t2}]}],
            "weights": [0.1, 0.2]}]}),
        None,
    ))
    .unwrap();
    doc["nodes"] = json!("NODES");
    // The numbers exactly as written (serde_json would print 0.1 the same, but be explicit).
    let text = serde_json::to_string(&doc).unwrap().replace(
        r#""NODES""#,
        r#"[{"translation": [0.1, 1e-9, 123456.789], "rotation": [0.0, 0.0, 0.3826834323650898, 0.9238795325112867],
             "scale": [1.1, 1, 1], "mesh": 0, "weights": [0.3, 0.7]},
            {"matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.1, 0.2, 0.3, 1]}]"#,
    );
    let s = read_gltf_slice(text.as_bytes(), None).unwrap();
    assert_eq!(s.meshes[0].weights, [0.1, 0.2]);
    let n = &s.nodes[0];
    assert_eq!(n.translation, glam::DVec3::new(0.1, 1e-9, 123456.789));
    assert_eq!(
        n.rotation.to_array(),
        [0.0, 0.0, 0.3826834323650898, 0.9238795325112867]
    );
    assert_eq!(n.scale.x, 1.1);
    assert_eq!(n.weights, [0.3, 0.7]);
    let m = s.nodes[1].matrix.unwrap();
    assert_eq!(m.w_axis.truncate(), glam::DVec3::new(0.1, 0.2, 0.3));
    assert_eq!(s.nodes[1].translation, glam::DVec3::new(0.1, 0.2, 0.3));
}

fn err_of(bytes: &[u8]) -> String {
    match read_gltf_slice(bytes, None) {
        Ok(_) => panic!("expected an error"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn fox_asset() {
    let Some(dir) = assets_dir() else { return };
    let s = read_gltf(dir.join("gltf/Fox.glb")).unwrap();
    assert_eq!(s.skins.len(), 1);
    assert_eq!(s.skins[0].joints.len(), 24);
    assert_eq!(s.skins[0].inverse_bind_matrices.len(), 24);
    let node = s.nodes.iter().find(|n| n.mesh.is_some()).unwrap();
    assert_eq!(node.skin, Some(0));
    let prim = &s.meshes[node.mesh.unwrap()].primitives[0];
    assert_eq!(prim.mesh.vertex_count(), 1728);
    assert_eq!(prim.mesh.uvs.len(), 1728);
    let w = prim.skin_weights.as_ref().unwrap();
    assert_eq!(w.vertex_count(), 1728);
    assert!(w.joints.iter().all(|&j| j < 24));
    let names: Vec<_> = s.animations.iter().map(|a| a.name.clone().unwrap()).collect();
    assert_eq!(names, ["Survey", "Walk", "Run"]);
    // Every joint is a descendant of the skeleton root, and IBM * bind world = identity
    // for the rest pose Fox was exported in.
    let world = s.world_matrices();
    for (j, ibm) in s.skins[0].joints.iter().zip(&s.skins[0].inverse_bind_matrices) {
        let m = world[*j] * *ibm;
        assert!(m.abs_diff_eq(Mat4::IDENTITY, 1e-3), "joint {j}: {m:?}");
    }
}

#[test]
fn simple_skin_asset() {
    let Some(dir) = assets_dir() else { return };
    let s = read_gltf(dir.join("gltf/SimpleSkin.gltf")).unwrap();
    assert_eq!(s.skins[0].joints, [1, 2]);
    assert_eq!(s.nodes[2].parent, Some(1));
    assert_eq!(s.animations.len(), 1);
    let c = &s.animations[0].channels[0];
    assert_eq!(
        (c.node, c.path, c.interpolation),
        (2, AnimPath::Rotation, Interpolation::Linear)
    );
    assert_eq!(c.times.len(), 12);
    // Zero-weight padding entries are dropped; every vertex keeps weights summing to 1.
    let w = s.meshes[0].primitives[0].skin_weights.as_ref().unwrap();
    for v in 0..w.vertex_count() {
        let sum: f32 = w.influences(v).1.iter().sum();
        assert!((sum - 1.0).abs() < 1e-6);
        assert!(w.influences(v).1.iter().all(|&x| x > 0.0));
    }
}

#[test]
fn morph_stress_asset() {
    let Some(dir) = assets_dir() else { return };
    let s = read_gltf(dir.join("gltf/MorphStressTest.gltf")).unwrap();
    let m = &s.meshes[0];
    assert!(m.primitives.iter().all(|p| p.targets.len() == 8));
    assert_eq!(m.target_names.len(), 8);
    assert_eq!(s.animations.len(), 3);
    for a in &s.animations {
        let c = &a.channels[0];
        assert_eq!((c.path, c.width), (AnimPath::Weights, 8));
        match c.sample(a.duration() * 0.37) {
            Sample::Weights(w) => assert_eq!(w.len(), 8),
            other => panic!("{other:?}"),
        }
    }
}

fn channel(
    path: AnimPath,
    interpolation: Interpolation,
    times: &[f32],
    width: usize,
    values: &[f32],
) -> AnimationChannel {
    AnimationChannel {
        node: 0,
        path,
        interpolation,
        times: times.to_vec(),
        width,
        values: values.to_vec(),
    }
}

#[test]
fn sampling_follows_the_spec() {
    let lin = channel(
        AnimPath::Translation,
        Interpolation::Linear,
        &[0.0, 1.0],
        3,
        &[0.0, 0.0, 0.0, 2.0, 4.0, 6.0],
    );
    assert_eq!(lin.sample(0.25), Sample::Translation(Vec3::new(0.5, 1.0, 1.5)));
    assert_eq!(
        lin.sample(-1.0),
        Sample::Translation(Vec3::ZERO),
        "clamps before the first key"
    );
    assert_eq!(
        lin.sample(5.0),
        Sample::Translation(Vec3::new(2.0, 4.0, 6.0)),
        "clamps after the last key"
    );
    let step = channel(
        AnimPath::Scale,
        Interpolation::Step,
        &[0.0, 1.0],
        3,
        &[1.0, 1.0, 1.0, 2.0, 2.0, 2.0],
    );
    assert_eq!(step.sample(0.99), Sample::Scale(Vec3::ONE));
    assert_eq!(step.sample(1.0), Sample::Scale(Vec3::splat(2.0)));
    // Slerp takes the short way even when the next key is stored negated.
    let q90 = -Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
    let rot = channel(
        AnimPath::Rotation,
        Interpolation::Linear,
        &[0.0, 2.0],
        4,
        &[0.0, 0.0, 0.0, 1.0, q90.x, q90.y, q90.z, q90.w],
    );
    let Sample::Rotation(q) = rot.sample(1.0) else { panic!() };
    let want = Quat::from_rotation_z(std::f32::consts::FRAC_PI_4);
    assert!(q.dot(want).abs() > 1.0 - 1e-6, "{q:?}");
    // Cubic Hermite: p(0)=0, p'(0)=1/s, p(2)=1, p'(2)=0 is p(t) = t - t^2/4, so p(1) = 0.75.
    // Tangents are per second; the spec scales them by the 2 s interval.
    let cubic = channel(
        AnimPath::Translation,
        Interpolation::CubicSpline,
        &[0.0, 2.0],
        3,
        &[
            0.0, 0.0, 0.0, /* v0 */ 0.0, 0.0, 0.0, /* b0 */ 1.0, 0.0, 0.0, /* a1 */ 0.0, 0.0, 0.0,
            /* v1 */ 1.0, 0.0, 0.0, 0.0, 0.0, 0.0,
        ],
    );
    let Sample::Translation(p) = cubic.sample(1.0) else {
        panic!()
    };
    assert!((p.x - 0.75).abs() < 1e-7, "{p:?}");
    assert_eq!(
        cubic.sample(2.0),
        Sample::Translation(Vec3::X),
        "a key time returns the key as-is"
    );
    let weights = channel(
        AnimPath::Weights,
        Interpolation::Linear,
        &[0.0, 1.0],
        2,
        &[0.0, 1.0, 1.0, 0.0],
    );
    assert_eq!(weights.sample(0.5), Sample::Weights(vec![0.5, 0.5]));
}

#[test]
fn features_of_hand_built_documents() {
    let mut d = DocBuilder::default();
    let pos = d.positions(&TRI);
    // Six influences per vertex over two sets; normalized u8 weights in set 1.
    let j0 = d.accessor(&u16_bytes(&[0, 1, 2, 3].repeat(3)), 5123, 3, "VEC4", json!({}));
    let w0 = d.accessor(&f32_bytes(&[0.3, 0.2, 0.1, 0.1].repeat(3)), 5126, 3, "VEC4", json!({}));
    let j1 = d.accessor(&[4u8, 5, 0, 0].repeat(3), 5121, 3, "VEC4", json!({}));
    let w1 = d.accessor(
        &[51u8, 51, 0, 0].repeat(3),
        5121,
        3,
        "VEC4",
        json!({"normalized": true}),
    );
    // Sparse morph target without a bufferView: zeros, with vertex 2 replaced.
    let si = d.accessor(&u16_bytes(&[2, 0]), 5123, 1, "SCALAR", json!({}));
    let sv = d.accessor(&f32_bytes(&[0.0, 0.0, 1.0]), 5126, 1, "VEC3", json!({}));
    d.accessors.push(
        json!({"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 1],
        "sparse": {"count": 1, "indices": {"bufferView": d.accessors[si]["bufferView"], "componentType": 5123},
                   "values": {"bufferView": d.accessors[sv]["bufferView"]}}}),
    );
    let target = d.accessors.len() - 1;
    let cubic_t = d.accessor(
        &f32_bytes(&[0.0, 1.0]),
        5126,
        2,
        "SCALAR",
        json!({"min": [0.0], "max": [1.0]}),
    );
    let cubic_v = d.accessor(&f32_bytes(&[0.0; 18]), 5126, 6, "VEC3", json!({}));
    let bytes = d.finish(json!({
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0, "skin": 0},
            {"name": "root", "children": [2], "matrix": [2,0,0,0, 0,2,0,0, 0,0,2,0, 1,2,3,1]},
            {"name": "j", "children": [3, 4, 5, 6, 7]},
            {}, {}, {}, {}, {}
        ],
        "skins": [{"joints": [2, 3, 4, 5, 6, 7]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos, "JOINTS_0": j0, "WEIGHTS_0": w0, "JOINTS_1": j1, "WEIGHTS_1": w1},
            "targets": [{"POSITION": target}]}]}],
        "animations": [{"channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}}],
            "samplers": [{"input": cubic_t, "output": cubic_v, "interpolation": "CUBICSPLINE"}]}]
    }), None);
    let s = read_gltf_slice(&bytes, None).unwrap();

    let w = s.meshes[0].primitives[0].skin_weights.as_ref().unwrap();
    let (js, ws) = w.influences(1);
    assert_eq!(js, [0, 1, 2, 3, 4, 5]);
    assert!((ws[4] - 0.2).abs() < 1e-7 && (ws[5] - 0.2).abs() < 1e-7);
    assert_eq!(
        s.meshes[0].primitives[0].mesh.triangles,
        [[0, 1, 2]],
        "indices generated when absent"
    );
    let t = &s.meshes[0].primitives[0].targets[0];
    assert_eq!(t.positions, [Vec3::ZERO, Vec3::ZERO, Vec3::Z]);
    assert_eq!(
        s.skins[0].inverse_bind_matrices,
        vec![Mat4::IDENTITY; 6],
        "identity IBMs when absent"
    );
    let root = &s.nodes[1];
    assert!(root.matrix.is_some());
    assert_eq!(
        (root.translation, root.scale),
        (glam::DVec3::new(1.0, 2.0, 3.0), glam::DVec3::splat(2.0))
    );
    assert_eq!(s.nodes[3].parent, Some(2));
    assert_eq!(s.roots, [0, 1]);
    assert_eq!(s.animations[0].channels[0].interpolation, Interpolation::CubicSpline);
    assert_eq!(s.animations[0].channels[0].values.len(), 18);
}

#[test]
fn malformed_documents_give_clear_errors() {
    assert!(read_gltf_slice(&triangle_doc(&[0, 1, 2]), None).is_ok());
    let e = err_of(&triangle_doc(&[0, 1, 7]));
    assert!(
        e.contains("indices") && e.contains("vertex 7") && e.contains("3 vertices"),
        "{e}"
    );

    // Buffer shorter than declared.
    let mut d = DocBuilder::default();
    let pos = d.positions(&TRI);
    let bytes = d.finish(
        json!({"meshes": [{"primitives": [{"attributes": {"POSITION": pos}}]}]}),
        Some(1000),
    );
    let e = err_of(&bytes);
    assert!(e.contains("declares 1000 bytes"), "{e}");

    // POSITION declared as VEC2.
    let mut d = DocBuilder::default();
    let p = d.accessor(
        &f32_bytes(&[0.0; 6]),
        5126,
        3,
        "VEC2",
        json!({"min": [0, 0], "max": [0, 0]}),
    );
    let bytes = d.finish(
        json!({"meshes": [{"primitives": [{"attributes": {"POSITION": p}}]}]}),
        None,
    );
    let e = read_gltf_slice(&bytes, None).unwrap_err().to_string();
    assert!(e.contains("POSITION") || e.contains("Vec2"), "{e}");

    // NaN in positions.
    let mut d = DocBuilder::default();
    let p = d.accessor(
        &f32_bytes(&[0.0, 0.0, f32::NAN, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]),
        5126,
        3,
        "VEC3",
        json!({"min": [0, 0, 0], "max": [1, 1, 0]}),
    );
    let bytes = d.finish(
        json!({"meshes": [{"primitives": [{"attributes": {"POSITION": p}}]}]}),
        None,
    );
    let e = err_of(&bytes);
    assert!(e.contains("NaN") && e.contains("POSITION"), "{e}");

    // Accessor reaching past its buffer view.
    let mut d = DocBuilder::default();
    let p = d.positions(&TRI);
    d.accessors[p]["count"] = json!(300);
    let bytes = d.finish(
        json!({"meshes": [{"primitives": [{"attributes": {"POSITION": p}}]}]}),
        None,
    );
    let e = err_of(&bytes);
    assert!(e.contains("needs") && e.contains("buffer view"), "{e}");

    // A node with two parents, and a missing external buffer.
    let bytes = serde_json::to_vec(&json!({"asset": {"version": "2.0"},
        "nodes": [{"children": [2]}, {"children": [2]}, {}]}))
    .unwrap();
    assert!(err_of(&bytes).contains("child of both"));
    let bytes = serde_json::to_vec(&json!({"asset": {"version": "2.0"},
        "buffers": [{"byteLength": 4, "uri": "missing.bin"}]}))
    .unwrap();
    let e = read_gltf_slice(&bytes, Some(std::path::Path::new("/nonexistent")))
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing.bin"), "{e}");
    assert!(err_of(&bytes).contains("no base directory"));
    let e = read_gltf("/nonexistent/file.glb").unwrap_err().to_string();
    assert!(e.contains("/nonexistent/file.glb"), "{e}");
    // Animation keys out of order.
    let mut d = DocBuilder::default();
    let t = d.accessor(
        &f32_bytes(&[1.0, 0.5]),
        5126,
        2,
        "SCALAR",
        json!({"min": [0.5], "max": [1.0]}),
    );
    let v = d.accessor(&f32_bytes(&[0.0; 6]), 5126, 2, "VEC3", json!({}));
    let bytes = d.finish(json!({"nodes": [{}], "animations": [{"channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}],
        "samplers": [{"input": t, "output": v}]}]}), None);
    assert!(err_of(&bytes).contains("strictly increase"));
    // Required extensions that change the byte layout are refused by name.
    let bytes = serde_json::to_vec(&json!({"asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_draco_mesh_compression"], "extensionsRequired": ["KHR_draco_mesh_compression"]}))
    .unwrap();
    assert!(err_of(&bytes).contains("requires extension KHR_draco_mesh_compression"));
    // Animation targeting a node or path that does not exist (gltf-json does not check these).
    for target in [
        json!({"node": 5, "path": "translation"}),
        json!({"node": 0, "path": "translatio"}),
    ] {
        let mut d = DocBuilder::default();
        let t = d.accessor(
            &f32_bytes(&[0.0]),
            5126,
            1,
            "SCALAR",
            json!({"min": [0.0], "max": [0.0]}),
        );
        let v = d.accessor(&f32_bytes(&[0.0; 3]), 5126, 1, "VEC3", json!({}));
        let bytes = d.finish(
            json!({"nodes": [{}], "animations": [{"channels": [{"sampler": 0, "target": target}],
            "samplers": [{"input": t, "output": v}]}]}),
            None,
        );
        assert!(
            err_of(&bytes).contains("animations[0].channels[0].target"),
            "{}",
            err_of(&bytes)
        );
    }
}

#[test]
fn corrupt_glb_bytes_never_panic() {
    let Some(dir) = assets_dir() else { return };
    let fox = std::fs::read(dir.join("gltf/Fox.glb")).unwrap();
    for cut in [0, 3, 11, 12, 19, 20, 100, 1000, fox.len() / 2, fox.len() - 1] {
        let e = read_gltf_slice(&fox[..cut], None);
        assert!(e.is_err(), "truncated at {cut} must fail");
    }
    let e = read_gltf_slice(&fox[..fox.len() / 2], None).unwrap_err().to_string();
    assert!(e.contains("GLB") && e.contains("truncated"), "{e}");
    // Random edits: half the runs change digits inside the JSON chunk (indices, counts,
    // offsets, strides), half flip bytes anywhere. Errors or success, never a panic.
    let json_len = u32::from_le_bytes([fox[12], fox[13], fox[14], fox[15]]) as usize;
    let mut state = 0x2545_f491_u32;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state as usize
    };
    for run in 0..600 {
        let mut bytes = fox.clone();
        for _ in 0..3 {
            if run % 2 == 0 {
                let at = 20 + next() % json_len;
                if bytes[at].is_ascii_digit() {
                    bytes[at] = b'0' + (next() % 10) as u8;
                }
            } else {
                let at = next() % bytes.len();
                bytes[at] = next() as u8;
            }
        }
        let _ = read_gltf_slice(&bytes, None);
    }
    // A header claiming a length shorter than the header itself.
    let mut bytes = fox.clone();
    bytes[8..12].copy_from_slice(&4u32.to_le_bytes());
    assert!(read_gltf_slice(&bytes, None).is_err());
}

#[test]
fn external_bin_file() {
    let dir = std::env::temp_dir().join(format!("sinew-io-extbin-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut d = DocBuilder::default();
    let pos = d.positions(&TRI);
    std::fs::write(dir.join("my data.bin"), &d.bin).unwrap();
    let mut doc: Value = serde_json::from_slice(&d.finish(
        json!({"nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": pos}}]}]}),
        None,
    ))
    .unwrap();
    doc["buffers"][0]["uri"] = json!("my%20data.bin");
    std::fs::write(dir.join("tri.gltf"), serde_json::to_vec(&doc).unwrap()).unwrap();
    let s = read_gltf(dir.join("tri.gltf")).unwrap();
    assert_eq!(s.meshes[0].primitives[0].mesh.positions[1], Vec3::X);
    let _ = std::fs::remove_dir_all(&dir);
}
