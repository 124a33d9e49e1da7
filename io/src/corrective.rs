//! Corrective shapes: invert a sculpt made on a posed mesh through the deformers after a
//! `blendShape`, so that it becomes that blendShape's target (Maya's `invertShape` command,
//! Maya 2016.5+, and Chad Vernon's `cvShapeInverter` script it replaced).
//!
//! An artist poses the rig, sculpts the fix on the deformed mesh (an OBJ of
//! `sinew eval --format obj`), and wants it as a target of a blendShape placed *before* the
//! skinning ("pre-deformation", Maya's default order), where deltas live in the rest pose.
//! [`invert_shape`] finds target `i`'s deltas `d` such that, at that pose and with
//! `weight[i] = 1`, the chain's output equals the sculpt.
//!
//! **Method** (cvShapeInverter's): evaluate the chain's output `o₀` with target `i`'s delta
//! at 0, then with every sculpted vertex's delta at the unit offsets `x`, `y` and `z` (all
//! vertices at once: one evaluation per axis). Vertex `v`'s 3×3 Jacobian has the columns
//! `oₖ[v] − o₀[v]`; its delta is `J⁻¹ (sculpt[v] − o₀[v])`. For a chain that is affine in
//! each input point (skinCluster linear blend skinning, cluster, the blendShape's own weight
//! map, envelope and transform-space matrix) this is exact.
//!
//! Then up to [`CorrectiveOptions::max_iterations`] Newton steps
//! `d += J(d)⁻¹ (sculpt − o(d))`, with `J(d)` measured again at the current deltas by offsets
//! of 1e-3 of the mesh's size (four or five evaluations a step). Each vertex keeps its step
//! only if it brings that vertex closer (else its next step is halved) and is done once
//! within 2 `f32` ulps of the mesh's size, so a vertex that cannot be reached does not hold
//! the others back. The steps take per-vertex but non-linear deformers (nonLinear bend,
//! twist, squash..., ffd, softMod, dual quaternion skinning) to the sculpt (a 90° bend:
//! 3.3e-2 off after the first solve, 4e-8 after three steps), and absorb the `f32` rounding
//! of the evaluation. Points a deformer folds (a bend's centre line) may stay out of reach:
//! [`Corrective::max_residual`] and [`Corrective::worst_vertex`] say where. For deformers
//! that mix neighbouring vertices (deltaMush, tension, wrap) the result is an approximation:
//! the sculpted vertices are matched where the steps can (a deltaMush on a sphere: 6.7e-3,
//! then 2e-8 after two steps), but their deltas also move vertices that were not sculpted
//! ([`Corrective::moved_elsewhere`]).
//!
//! Only vertices whose sculpted position differs from `o₀` by more than
//! [`CorrectiveOptions::tolerance`] get a delta (the target is sparse).
//!
//! **The probe is target `i` itself**, not a new target: its `targetIndices[i]` /
//! `targetDeltas[i]` are set to the probe values and `weight[i]` to 1 (a connection driving
//! the weight is removed for the time), so the probes see target `i`'s own
//! `postDeformersMode`, `targetMatrix[i]`, weight map and the envelope. Everything touched
//! (those three plugs, the connection, the graph's time) is restored through the graph's
//! edit API before returning, on success and on error: the graph's authored values and
//! connections are the same bits as before (tested with `graph_eq`).
//!
//! A vertex whose Jacobian is singular (a joint scaled to 0, a weight map or the envelope
//! at 0, a deformer flattening it) cannot be reached by any delta: that is an error naming
//! the vertex, not a silent fallback.

use glam::{DMat3, DVec3, Vec3};
use sinew_core::{Graph, NodeId, Plug, Time, Value};

use crate::bake_morphs::chain_losses;

/// The options of [`invert_shape`].
#[derive(Clone, Debug)]
pub struct CorrectiveOptions {
    /// The blendShape node the corrective goes on.
    pub blend_shape: String,
    /// Target index `i` (driven by `weight[i]`).
    pub target: u32,
    /// The pose: this time, or `None` for the graph's current time and values.
    pub time: Option<Time>,
    /// The plug holding the deformed mesh the sculpt was made on; `None`: the end of the
    /// blendShape's deformer chain (following `outputGeometry → inputGeometry`).
    pub output: Option<String>,
    /// Vertices moved by at most this distance (rig units) get no delta.
    pub tolerance: f64,
    /// Most refinement steps after the first solve.
    pub max_iterations: usize,
}

impl CorrectiveOptions {
    /// Options for target `target` of `blend_shape` at the graph's current pose, tolerance
    /// 1e-4 and up to 8 refinement steps.
    pub fn new(blend_shape: &str, target: u32) -> Self {
        CorrectiveOptions {
            blend_shape: blend_shape.to_string(),
            target,
            time: None,
            output: None,
            tolerance: 1e-4,
            max_iterations: 8,
        }
    }
}

/// A computed corrective target and how well it reproduces the sculpt.
#[derive(Clone, Debug, Default)]
pub struct Corrective {
    /// The vertices with a delta, ascending (what `targetIndices[i]` gets).
    pub indices: Vec<i64>,
    /// Their deltas in the blendShape's space (what `targetDeltas[i]` gets).
    pub deltas: Vec<DVec3>,
    /// The plug whose mesh was matched to the sculpt.
    pub output: String,
    /// Refinement steps that brought at least one vertex closer.
    pub iterations: usize,
    /// Largest distance between the sculpt and the chain's output with the deltas at
    /// weight 1, over the vertices with a delta.
    pub max_residual: f64,
    /// The vertex where that residual is (0 when no vertex has a delta).
    pub worst_vertex: usize,
    /// Largest distance any vertex without a delta moved because of the deltas (0 for
    /// chains of per-vertex deformers; non-local ones such as deltaMush spread them).
    pub moved_elsewhere: f64,
}

/// The state of one plug before the probes, to put back.
struct Saved {
    plug: Plug,
    existed: bool,
    stored: Option<Value>,
    source: Option<Plug>,
}

impl Saved {
    fn take(g: &Graph, plug: Plug) -> Saved {
        let existed = plug.index.is_none_or(|i| g.elements(plug.node, plug.attr).contains(&i));
        Saved {
            plug,
            existed,
            stored: g.stored(plug),
            source: g.source_of(plug),
        }
    }

    fn restore(&self, g: &mut Graph) -> Result<(), String> {
        let name = g.plug_name(self.plug);
        let err = |e: sinew_core::Error| format!("restoring {name}: {e}");
        if let Some(src) = g.source_of(self.plug) {
            g.disconnect(src, self.plug).map_err(err)?;
        }
        match (&self.stored, self.existed) {
            (Some(v), true) => g.set(self.plug, v.clone()).map_err(err)?,
            _ => {
                if let Some(i) = self.plug.index {
                    g.remove_element(self.plug.node, self.plug.attr, i).map_err(err)?;
                }
            }
        }
        if let Some(src) = self.source {
            g.connect(src, self.plug).map_err(err)?;
        }
        Ok(())
    }
}

/// Checks the node is a blendShape and finds the plugs of target `i`.
fn target_plugs(g: &Graph, opts: &CorrectiveOptions) -> Result<(NodeId, [Plug; 3]), String> {
    let bs = &opts.blend_shape;
    let node = g.node_id(bs).map_err(|e| e.to_string())?;
    let ty = g.node_type(node).unwrap_or("?");
    if ty != "blendShape" {
        return Err(format!(
            "`{bs}` is a {ty}, not a blendShape; name the blendShape the corrective target goes on"
        ));
    }
    let max = sinew_nodes::deform::blend_shape_node::MAX_TARGETS;
    if opts.target > max {
        return Err(format!(
            "target index {} is above {max}; give a target index from 0 to {max}",
            opts.target
        ));
    }
    let i = opts.target;
    let plug = |a: &str| g.plug(&format!("{bs}.{a}[{i}]")).map_err(|e| e.to_string());
    let plugs = [plug("weight")?, plug("targetIndices")?, plug("targetDeltas")?];
    for p in &plugs[1..] {
        if let Some(src) = g.source_of(*p) {
            return Err(format!(
                "{} is driven by {}; a corrective writes the target's deltas, so disconnect it first",
                g.plug_name(*p),
                g.plug_name(src)
            ));
        }
    }
    Ok((node, plugs))
}

/// The mesh plug the sculpt is matched to.
fn output_plug(g: &Graph, node: NodeId, opts: &CorrectiveOptions) -> Result<Plug, String> {
    match &opts.output {
        Some(p) => {
            let plug = g.plug(p).map_err(|e| e.to_string())?;
            if g.plug_type(plug).map_err(|e| e.to_string())? != sinew_core::AttrType::Mesh {
                return Err(format!(
                    "{p} is not a mesh plug; name the deformed mesh's plug (e.g. skin.outputGeometry)"
                ));
            }
            Ok(plug)
        }
        None => chain_losses(g, node)
            .1
            .ok_or_else(|| format!("{}: no outputGeometry to follow", opts.blend_shape)),
    }
}

/// The positions of the mesh on `plug`, all finite.
fn positions(g: &mut Graph, plug: Plug) -> Result<Vec<DVec3>, String> {
    let name = g.plug_name(plug);
    let mesh = match g.get(plug).map_err(|e| format!("evaluating {name}: {e}"))? {
        Value::Mesh(m) => m,
        other => return Err(format!("{name} is not a mesh ({other})")),
    };
    let p: Vec<DVec3> = mesh.positions.iter().map(|v| v.as_dvec3()).collect();
    if let Some(v) = p.iter().position(|x| !x.is_finite()) {
        return Err(format!(
            "{name}: vertex {v} is not finite at this pose; fix the rig before sculpting on it"
        ));
    }
    Ok(p)
}

/// Sets target `i`'s probe values: `indices` with `deltas`.
fn set_probe(g: &mut Graph, plugs: &[Plug; 3], indices: &[i64], deltas: Vec<DVec3>) -> Result<(), String> {
    g.set(plugs[1], Value::IntArray(indices.to_vec().into()))
        .and_then(|()| g.set(plugs[2], Value::Vec3Array(deltas.into())))
        .map_err(|e| e.to_string())
}

/// Computes target `opts.target` of blendShape `opts.blend_shape` so that at the pose, with
/// `weight[i] = 1`, the chain's output equals `sculpt` (see the module docs). The graph is
/// left as it was. Errors name the node, plug or vertex and the fix.
pub fn invert_shape(g: &mut Graph, sculpt: &[Vec3], opts: &CorrectiveOptions) -> Result<Corrective, String> {
    if let Some(v) = sculpt.iter().position(|p| !p.is_finite()) {
        return Err(format!(
            "sculpt vertex {v} is {} (not finite); export the sculpt again",
            sculpt[v]
        ));
    }
    if !(opts.tolerance.is_finite() && opts.tolerance >= 0.0) {
        return Err(format!("tolerance {} must be a non-negative number", opts.tolerance));
    }
    let (node, plugs) = target_plugs(g, opts)?;
    let out = output_plug(g, node, opts)?;
    let saved: Vec<Saved> = plugs.iter().map(|&p| Saved::take(g, p)).collect();
    let time = g.time();
    let result = (|| {
        if let Some(t) = opts.time {
            g.set_time(t);
        }
        if let Some(src) = saved[0].source {
            g.disconnect(src, plugs[0]).map_err(|e| e.to_string())?;
        }
        g.set(plugs[0], Value::Float(1.0)).map_err(|e| e.to_string())?;
        solve(g, &plugs, out, sculpt, opts)
    })();
    // Put everything back in reverse order, whatever happened.
    let mut restored = Ok(());
    for s in saved.iter().rev() {
        restored = restored.and(s.restore(g));
    }
    g.set_time(time);
    restored.map_err(|e| format!("internal error: {e}"))?;
    result
}

/// Target `i`'s plugs and the sculpted vertices, for the probe evaluations.
struct Probe<'a> {
    plugs: &'a [Plug; 3],
    out: Plug,
    indices: &'a [i64],
    moved: &'a [usize],
}

impl Probe<'_> {
    /// The chain's output with the sculpted vertices' deltas at `deltas`.
    fn eval(&self, g: &mut Graph, deltas: Vec<DVec3>) -> Result<Vec<DVec3>, String> {
        set_probe(g, self.plugs, self.indices, deltas)?;
        positions(g, self.out)
    }

    /// Each sculpted vertex's inverse Jacobian at `at` (whose output is `o_at`), measured
    /// by offsetting every vertex by `h` along x, y and z (one evaluation per axis); `None`
    /// where it is singular.
    fn inverse_jacobians(
        &self,
        g: &mut Graph,
        at: &[DVec3],
        o_at: &[DVec3],
        h: f64,
    ) -> Result<Vec<Option<DMat3>>, String> {
        let mut cols = Vec::with_capacity(3);
        for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
            let o = self.eval(g, at.iter().map(|d| *d + axis * h).collect())?;
            cols.push(self.moved.iter().map(|&v| (o[v] - o_at[v]) / h).collect::<Vec<_>>());
        }
        Ok((0..self.moved.len())
            .map(|k| {
                let j = DMat3::from_cols(cols[0][k], cols[1][k], cols[2][k]);
                let scale = cols.iter().map(|c| c[k].length()).fold(0.0, f64::max);
                let det = j.determinant();
                (det.is_finite() && scale > 0.0 && det.abs() > 1e-9 * scale.powi(3)).then(|| j.inverse())
            })
            .collect())
    }
}

/// The probes, the per-vertex solve and the refinement (the graph is posed and `weight[i]`
/// is 1).
fn solve(
    g: &mut Graph,
    plugs: &[Plug; 3],
    out: Plug,
    sculpt: &[Vec3],
    opts: &CorrectiveOptions,
) -> Result<Corrective, String> {
    let out_name = g.plug_name(out);
    set_probe(g, plugs, &[], Vec::new())?;
    let o0 = positions(g, out)?;
    if o0.len() != sculpt.len() {
        return Err(format!(
            "the sculpt has {} vertices but {out_name} has {}; sculpt on the posed mesh without adding or removing vertices (same count and order)",
            sculpt.len(),
            o0.len()
        ));
    }
    let target: Vec<DVec3> = sculpt.iter().map(|p| p.as_dvec3()).collect();
    let moved: Vec<usize> = (0..o0.len())
        .filter(|&v| (target[v] - o0[v]).length() > opts.tolerance)
        .collect();
    let mut c = Corrective {
        output: out_name.clone(),
        ..Default::default()
    };
    if moved.is_empty() {
        return Ok(c);
    }
    c.indices = moved.iter().map(|&v| v as i64).collect();
    let probe = Probe {
        plugs,
        out,
        indices: &c.indices,
        moved: &moved,
    };
    // cvShapeInverter's unit offsets from the posed mesh: exact for affine chains.
    let zero = vec![DVec3::ZERO; moved.len()];
    let inverses = probe.inverse_jacobians(g, &zero, &o0, 1.0)?;
    if let Some(k) = inverses.iter().position(Option::is_none) {
        return Err(format!(
            "vertex {}: the deformers after `{}` do not move it freely at this pose (its 3x3 Jacobian is singular: a joint scaled to 0, a weight map or the envelope at 0, or a deformer flattening it), so no delta reaches the sculpt; leave that vertex unsculpted or change the pose",
            moved[k], opts.blend_shape
        ));
    }
    let dist = |o: &[DVec3], k: usize| (target[moved[k]] - o[moved[k]]).length();
    let mut deltas: Vec<DVec3> = (0..moved.len())
        .map(|k| inverses[k].unwrap_or(DMat3::ZERO) * (target[moved[k]] - o0[moved[k]]))
        .collect();
    let mut o = probe.eval(g, deltas.clone())?;
    // Newton steps with Jacobians re-measured at the current deltas by small offsets
    // (1e-3 of the mesh's size: f32 rounding stays 1e-4 of the step). Each vertex keeps its
    // step only when it brings it closer (else its next step is halved), and is done once
    // within the f32 rounding of the mesh's coordinates (2 ulps of its size).
    let size = o0.iter().map(|p| p.abs().max_element()).fold(0.0, f64::max);
    let size = if size > 0.0 { size } else { 1.0 };
    let (h, rounding) = (1e-3 * size, 2.0 * f64::from(f32::EPSILON) * size);
    let mut length = vec![1.0f64; moved.len()];
    for _ in 0..opts.max_iterations {
        let res: Vec<f64> = (0..moved.len()).map(|k| dist(&o, k)).collect();
        let open: Vec<usize> = (0..moved.len()).filter(|&k| res[k] > rounding).collect();
        if open.is_empty() {
            break;
        }
        let inverses = probe.inverse_jacobians(g, &deltas, &o, h)?;
        let mut next = deltas.clone();
        for &k in &open {
            if let Some(inv) = inverses[k] {
                next[k] += inv * (target[moved[k]] - o[moved[k]]) * length[k];
            }
        }
        let o_next = probe.eval(g, next.clone())?;
        let mut kept = 0;
        for &k in &open {
            if dist(&o_next, k) < res[k] {
                deltas[k] = next[k];
                kept += 1;
            } else {
                length[k] *= 0.5;
            }
        }
        if kept == 0 {
            continue;
        }
        c.iterations += 1;
        o = if kept == open.len() {
            o_next
        } else {
            probe.eval(g, deltas.clone())?
        };
    }
    let (worst, res) = (0..moved.len())
        .map(|k| (k, dist(&o, k)))
        .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
    c.worst_vertex = moved[worst];
    let sculpted: std::collections::HashSet<usize> = moved.iter().copied().collect();
    c.moved_elsewhere = (0..o.len())
        .filter(|v| !sculpted.contains(v))
        .map(|v| (o[v] - o0[v]).length())
        .fold(0.0, f64::max);
    c.max_residual = res;
    c.deltas = deltas;
    Ok(c)
}

/// Writes `c` as target `target` of blendShape `blend_shape` (`targetIndices[target]` and
/// `targetDeltas[target]`); the weight is left as it is (drive it, e.g. with a
/// `poseReader`, to turn the corrective on at its pose). Nothing changes on error.
pub fn set_target(g: &mut Graph, blend_shape: &str, target: u32, c: &Corrective) -> Result<(), String> {
    let opts = CorrectiveOptions::new(blend_shape, target);
    let (_, plugs) = target_plugs(g, &opts)?;
    let before = Saved::take(g, plugs[1]);
    set_probe(g, &plugs, &c.indices, c.deltas.clone()).inspect_err(|_| {
        let _ = before.restore(g);
    })
}
