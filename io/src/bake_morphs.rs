//! Morph targets that keep a bake exact where glTF's linear morph weights seem not enough.
//!
//! - **blendShape in-betweens and weight maps.** sinew blends a target's keys (the base at
//!   weight 0, each in-between at its own weight, the full target at 1) piecewise linearly in
//!   the driving weight `x`: the delta at `x` is `Σₖ hₖ(x)·Dₖ`, where `hₖ` is key `k`'s hat
//!   function (1 at its weight, 0 at the other keys, linear between, extended linearly past
//!   the end keys). So each key becomes one glTF morph target (`Dₖ` times the target's
//!   per-vertex weight map, which is constant and so folds into the target exactly), and the
//!   baked glTF weight of that morph at a frame is `envelope · hₖ(x)`, computed by
//!   [`Target::bracket`], the very function the blendShape node evaluates with.
//! - **Deformers glTF cannot express** (cluster, nonLinear, ffd, deltaMush, wire, wrap, ...
//!   anywhere in a mesh's chain): [`chain_losses`] finds them. Without
//!   `--bake-deformers-as-morphs` the bake warns which are lost; with it, that mesh is baked
//!   as its deformed output per frame: the first frame's mesh as the base and one morph target
//!   per frame (its difference from the base), whose weight is 1 at its own frame and 0 at the
//!   others, so the glTF equals sinew's result at every baked frame (and interpolates linearly
//!   between frames). Such a mesh is not skinned in the glTF (its skin's motion is in the
//!   morphs).

use std::sync::Arc;

use glam::Vec3;
use sinew_core::{Graph, Instance, NodeId, Plug, Value};
use sinew_nodes::deform::blend_shape::{Key, Target};
use sinew_nodes::deform::blend_shape_node::BlendShapeCache;

use super::scene::{MorphTarget, Primitive};

/// A blendShape's targets as glTF morph targets (see the module docs).
#[derive(Clone, Debug)]
pub struct BlendMorphs {
    /// The blendShape node.
    pub node: NodeId,
    /// The node's parsed targets (its `targetCache`).
    pub targets: Vec<Target>,
    /// Per glTF morph target: the blendShape target index and the key.
    pub keys: Vec<(usize, Key)>,
    /// The glTF morph targets (dense deltas, weight maps applied), parallel to `keys`.
    pub morphs: Vec<MorphTarget>,
    /// The existing `weight[i]` elements (their handles are sampled per frame).
    pub weight_indices: Vec<u32>,
    /// The node's `supportNegativeWeights` (read once, at bake start): off, a weight below 0
    /// counts as 0, as the node computes.
    pub negative_weights: bool,
}

fn name(g: &Graph, n: NodeId) -> String {
    g.node_name(n).unwrap_or("?").to_string()
}

/// Reads blendShape `bs` (its `targetCache`) for a base of `vc` vertices.
pub fn blend_morphs(g: &mut Graph, bs: NodeId, vc: usize, warnings: &mut Vec<String>) -> Result<BlendMorphs, String> {
    let bname = name(g, bs);
    let targets = match g.get_path(&format!("{bname}.targetCache")).map_err(|e| e.to_string())? {
        Value::Object(o) => {
            let c = o
                .downcast::<BlendShapeCache>()
                .ok_or_else(|| format!("{bname}.targetCache is not a blendShape cache"))?;
            if let Some(t) = &c.tangent {
                let ids: Vec<String> = (0..t.targets.len())
                    .filter(|&i| t.targets[i] != Default::default())
                    .map(|i| i.to_string())
                    .collect();
                warnings.push(format!(
                    "{bname}: glTF cannot express tangent-space targets (postDeformersMode, target {}); their deformation is lost",
                    ids.join(", ")
                ));
            }
            if let Some(t) = &c.transform {
                let ids: Vec<String> = t.targets.iter().map(|t| t.index.to_string()).collect();
                warnings.push(format!(
                    "{bname}: glTF cannot express transform-space targets (postDeformersMode, target {}); their deformation is lost",
                    ids.join(", ")
                ));
            }
            c.targets.clone()
        }
        other => return Err(format!("{bname}.targetCache is not an object ({other})")),
    };
    let mut keys = Vec::new();
    let mut morphs = Vec::new();
    for (t, target) in targets.iter().enumerate() {
        if let Err(e) = target.validate(t, vc) {
            warnings.push(format!("{bname}: {e} (skipped as the blendShape skips it)"));
        }
        let mut ks: Vec<(f32, Key)> = target.keys().filter(|k| k.1 != Key::Base).collect();
        ks.sort_by(|a, b| a.0.total_cmp(&b.0));
        if target.delta.indices.is_empty() && target.in_betweens.is_empty() {
            continue;
        }
        for (_, k) in ks {
            let mut pos = vec![Vec3::ZERO; vc];
            if let Some(d) = target.key_delta(k) {
                for (&i, &delta) in d.indices.iter().zip(&d.deltas) {
                    let m = target.vertex_weights.get(i as usize).copied().unwrap_or(1.0);
                    if let Some(p) = pos.get_mut(i as usize) {
                        *p += delta * m;
                    }
                }
            }
            keys.push((t, k));
            morphs.push(MorphTarget {
                positions: pos,
                normals: Vec::new(),
            });
        }
    }
    let weight_attr = g
        .node_spec(bs)
        .and_then(|s| s.find("weight"))
        .ok_or("blendShape without weight")?
        .0;
    let weight_indices = g.elements(bs, weight_attr);
    let negative_weights = matches!(
        g.get_path(&format!("{bname}.supportNegativeWeights")),
        Ok(Value::Bool(true))
    );
    Ok(BlendMorphs {
        node: bs,
        targets,
        keys,
        morphs,
        weight_indices,
        negative_weights,
    })
}

impl BlendMorphs {
    /// The glTF morph weights for the blendShape's `weight[i]` values (`weights`, parallel to
    /// `weight_indices`) and `envelope`, appended to `out`: what the blendShape node
    /// computes, key by key.
    pub fn morph_weights(&self, weights: &[f32], envelope: f32, out: &mut Vec<f32>) {
        let start = out.len();
        out.resize(start + self.keys.len(), 0.0);
        if !envelope.is_finite() || envelope == 0.0 {
            return;
        }
        for (&i, &x) in self.weight_indices.iter().zip(weights) {
            let Some(target) = self.targets.get(i as usize) else {
                continue;
            };
            let x = if self.negative_weights { x } else { x.max(0.0) };
            if !x.is_finite() || x == 0.0 {
                continue;
            }
            let ((_, lo), (_, hi), t) = target.bracket(x);
            let mut add = |k: Key, w: f32| {
                if let Some(m) = self.keys.iter().position(|&(ti, kk)| ti == i as usize && kk == k) {
                    out[start + m] += w;
                }
            };
            if lo != Key::Base && t != 1.0 {
                add(lo, envelope * (1.0 - t));
            }
            if hi != Key::Base && t != 0.0 {
                add(hi, envelope * t);
            }
        }
    }
}

/// Deformer node types the glTF export reproduces (skin, blend shapes) or that only carry
/// geometry (mesh sources).
fn expressible(ty: &str) -> bool {
    matches!(ty, "skinCluster" | "blendShape" | "mesh") || ty.starts_with("poly")
}

/// The deformers in the geometry chain through `node` (upstream along `inputGeometry` /
/// `inMesh`, downstream along `outputGeometry` / `outMesh`) that glTF cannot express, as
/// "name (type)", and the plug holding the chain's final mesh.
pub fn chain_losses(g: &Graph, node: NodeId) -> (Vec<String>, Option<Plug>) {
    let conns = g.connections();
    let attr_of = |p: Plug| {
        let full = g.plug_name(p);
        full.rsplit_once('.').map(|(_, a)| a.to_string()).unwrap_or_default()
    };
    let mut lost = Vec::new();
    let mut note = |n: NodeId| {
        let ty = g.node_type(n).unwrap_or("?");
        if !expressible(ty) {
            lost.push(format!("{} ({ty})", name(g, n)));
        }
    };
    // Upstream.
    let mut cur = node;
    let mut seen = vec![node];
    loop {
        let up = conns
            .iter()
            .find(|(_, d)| d.node == cur && matches!(attr_of(*d).as_str(), "inputGeometry" | "inMesh"))
            .map(|(s, _)| s.node);
        match up {
            Some(n) if !seen.contains(&n) => {
                note(n);
                seen.push(n);
                cur = n;
            }
            _ => break,
        }
    }
    // Downstream.
    let mut cur = node;
    let mut last = None;
    loop {
        let out = conns.iter().find(|(s, d)| {
            s.node == cur
                && matches!(attr_of(*s).as_str(), "outputGeometry" | "outMesh")
                && matches!(attr_of(*d).as_str(), "inputGeometry" | "inMesh")
        });
        match out {
            Some((s, d)) if !seen.contains(&d.node) => {
                last = Some(*s);
                note(d.node);
                seen.push(d.node);
                cur = d.node;
            }
            _ => break,
        }
    }
    let fin = ["outputGeometry", "outMesh"]
        .iter()
        .find_map(|a| g.plug(&format!("{}.{a}", name(g, cur))).ok())
        .or(last);
    (lost, fin)
}

/// What drives a baked mesh's morph weights.
pub enum MorphDrive {
    /// A blendShape: its keys' hat-function weights.
    Blend {
        /// The blendShape's morphs.
        morphs: BlendMorphs,
        /// Handles of its `weight[i]` (parallel to `weight_indices`).
        weights: Vec<sinew_core::PlugHandle>,
        /// Handle of its `envelope`.
        envelope: sinew_core::PlugHandle,
    },
    /// The chain's final mesh, one morph target per frame.
    Frames {
        /// Handle of the chain's final mesh.
        final_h: sinew_core::PlugHandle,
        /// The final mesh of each sampled frame.
        meshes: Vec<Arc<sinew_core::Mesh>>,
    },
}

impl MorphDrive {
    /// Samples the current frame (blend weights into `out`, or the final mesh).
    pub fn sample(&mut self, inst: &Instance, out: &mut Vec<f32>) {
        match self {
            MorphDrive::Blend {
                morphs,
                weights,
                envelope,
            } => {
                let ws: Vec<f32> = weights
                    .iter()
                    .map(|h| inst.get(h).as_f64().unwrap_or(0.0) as f32)
                    .collect();
                let env = inst.get(envelope).as_f64().unwrap_or(0.0) as f32;
                morphs.morph_weights(&ws, env, out);
            }
            MorphDrive::Frames { final_h, meshes } => {
                if let Value::Mesh(m) = inst.get(final_h) {
                    meshes.push(m);
                }
            }
        }
    }

    /// Completes the primitive (per-frame targets) and the weights; returns the number of
    /// weights per frame.
    pub fn finish(self, frames: usize, prim: &mut Primitive, weights: &mut Vec<f32>) -> usize {
        match self {
            MorphDrive::Blend { morphs, .. } => morphs.keys.len(),
            MorphDrive::Frames { meshes, .. } => {
                let Some(first) = meshes.first() else {
                    return 0;
                };
                prim.mesh = (**first).clone();
                prim.targets = meshes
                    .iter()
                    .map(|m| MorphTarget {
                        positions: m.positions.iter().zip(&first.positions).map(|(a, b)| *a - *b).collect(),
                        normals: Vec::new(),
                    })
                    .collect();
                weights.clear();
                for f in 0..frames {
                    weights.extend((0..meshes.len()).map(|k| if k == f { 1.0 } else { 0.0 }));
                }
                meshes.len()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sinew_nodes::deform::blend_shape::{InBetween, SparseDelta};

    fn target() -> Target {
        let one = |d: Vec3| SparseDelta {
            indices: vec![0],
            deltas: vec![d],
        };
        Target {
            delta: one(Vec3::X * 4.0),
            in_betweens: vec![InBetween {
                weight: 0.5,
                delta: one(Vec3::Y * 8.0),
            }],
            vertex_weights: vec![0.5],
        }
    }

    #[test]
    fn hat_weights_reproduce_the_in_between_blend() {
        let t = target();
        let bm = BlendMorphs {
            node: NodeId::default(),
            targets: vec![t.clone()],
            keys: vec![(0, Key::Between(0)), (0, Key::Full)],
            morphs: Vec::new(),
            weight_indices: vec![0],
            negative_weights: true,
        };
        for (x, want) in [
            (0.25, [0.5, 0.0]),
            (0.5, [1.0, 0.0]),
            (0.75, [0.5, 0.5]),
            (1.0, [0.0, 1.0]),
            (1.5, [-1.0, 2.0]),
        ] {
            let mut out = Vec::new();
            bm.morph_weights(&[x], 1.0, &mut out);
            assert_eq!(out, want, "x = {x}");
        }
        let mut out = Vec::new();
        bm.morph_weights(&[0.75], 0.5, &mut out);
        assert_eq!(out, [0.25, 0.25]);
        // Below 0: extrapolated along the first segment with negative weights supported
        // (−0.25 is half the in-between's distance on the other side), 0 without.
        let mut out = Vec::new();
        bm.morph_weights(&[-0.25], 1.0, &mut out);
        assert_eq!(out, [-0.5, 0.0]);
        let bm = BlendMorphs {
            negative_weights: false,
            ..bm
        };
        let mut out = Vec::new();
        bm.morph_weights(&[-0.25], 1.0, &mut out);
        assert_eq!(out, [0.0, 0.0]);
    }
}
