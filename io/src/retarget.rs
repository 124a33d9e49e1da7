//! Retargeting: drive a rig's skeleton from motion capture with different proportions and
//! rest orientations. Implemented as an *importer*: it computes, per mocap frame, the
//! rotate (and root translate) values of the target joints and adds `quatCurve` /
//! `vectorCurve` nodes that drive them, so the result is an ordinary rig that evaluates,
//! edits and bakes like any other.
//!
//! # Method
//! - **Joint map**: source joint → target DAG node, from a map file (RON
//!   `{ "Hips": "pelvis", "LeftUpLeg": "thigh_L", .. }`) or by default by canonical humanoid
//!   names ([`canonical`]: `Hips/Spine/LeftUpLeg…`, `mixamorig:*`, `pelvis/thigh_l/calf_l`
//!   style, `L_`/`_L` sides), matched after dropping namespaces, case, `_`, `-`, `.`, spaces.
//! - **Rest-pose alignment**: each mapped joint receives its source joint's *world-space
//!   rotation delta from the source rest pose*, applied on top of its own rest world
//!   rotation: `Wt = (Ws · Ws_rest⁻¹) · Wt_rest`. Local axes and joint orients may differ
//!   freely; the two rest poses should be the same *pose* (e.g. both T-poses), as with every
//!   delta-based retargeter. Unmapped target joints keep their rest local rotation. The
//!   BVH rest pose is all channels zero.
//! - **Joint channels**: the local rotation `Q = Pt⁻¹ · Wt` is written to `rotate` through
//!   the node's own parts: a joint's rotation is `JO · R · RA` (column vectors), so
//!   `R = JO⁻¹ · Q · RA⁻¹`, in the node's `rotateOrder`.
//! - **Root motion**: the target root (the node mapped from the source root) moves by the
//!   source root's world displacement from rest times `leg ratio` = target leg length /
//!   source leg length (hip→knee→ankle, left side; the target leg is the one mapped from
//!   the source's, else found by name; falling back to the ratio of root heights above the
//!   lowest joint, then 1). World up (+Y) and facing are assumed shared.
//!   Heights are measured from the ground: each skeleton's rest pose stands on its lowest
//!   rest joint, and the clip's ground is its lowest joint over all frames, so the
//!   vertical displacement is `(root height above the clip's ground) − (rest root height
//!   above the lowest rest joint)`. Motion capture stores absolute root positions while
//!   the BVH rest pose puts the root at its offset; measuring from the ground keeps the
//!   target's feet on its own floor.
//!   The root's own parent may be animated by the rig: its world matrix is evaluated per
//!   frame, so the root lands exactly where the scaled source motion puts it.
//! - **Drivers**: curves replace whatever drove a retargeted `rotate` / root `translate`
//!   before (e.g. the biped's leg IK and ankle orient constraints); each replacement is
//!   reported as a warning (when the new connection fails, the old drivers are restored).
//! - **Foot planting** (optional, [`RetargetOptions::plant_feet`], `--plant-feet`): the
//!   leg ratio keeps feet roughly in place but not exactly, so feet slide. With planting,
//!   source foot contacts are detected from ankle (and toe) height and speed, each target
//!   ankle is held at one point per contact with blends in and out, and the hip, knee and
//!   ankle keys come from a two-bone IK; see [`super::retarget_feet`].

use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3};
use sinew_core::{Graph, NodeId, Plug, Time, Value};
use sinew_nodes::transform::dag_nodes::deg_to_rad;
use sinew_nodes::transform::euler::euler_to_quat;

use super::bake::dag_order;
use super::bvh::Bvh;
use super::retarget_feet::{plant_feet, PlantInput};
pub use super::retarget_feet::{FootContacts, RetargetOptions};
pub use super::retarget_map::{canonical, canonical_among, default_map, parse_map};

/// What [`retarget_with`] did.
#[derive(Clone, Debug, Default)]
pub struct RetargetReport {
    /// `(source joint, target node)` pairs used.
    pub pairs: Vec<(String, String)>,
    /// Root motion scale (leg length ratio).
    pub scale: f64,
    /// Frames per second of the motion (the rig plays frame `f` at `f / fps` seconds).
    pub fps: f64,
    /// Frame range of the motion.
    pub frames: (i64, i64),
    /// Notes (skipped joints, replaced drivers, feet not planted).
    pub warnings: Vec<String>,
    /// With foot planting: the planted contacts per foot (empty without).
    pub feet: Vec<FootContacts>,
}

fn rot(m: &DMat4) -> DQuat {
    let (_, r, _) = m.to_scale_rotation_translation();
    r.normalize()
}

fn get(g: &mut Graph, node: NodeId, attr: &str) -> Option<Value> {
    let name = g.node_name(node)?.to_string();
    g.get_path(&format!("{name}.{attr}")).ok()
}

fn vec3(v: Option<Value>) -> DVec3 {
    match v {
        Some(Value::Vec3(x)) => x,
        _ => DVec3::ZERO,
    }
}

/// World matrices of the target's DAG nodes in the rest pose (drivers from non-DAG nodes
/// disconnected while evaluating, then restored).
fn rest_worlds(g: &mut Graph, dag: &[NodeId]) -> Result<Vec<DMat4>, String> {
    let set: HashSet<NodeId> = dag.iter().copied().collect();
    let drivers: Vec<(Plug, Plug)> = g
        .connections()
        .into_iter()
        .filter(|(s, d)| set.contains(&d.node) && !set.contains(&s.node))
        .collect();
    for (s, d) in &drivers {
        g.disconnect(*s, *d).map_err(|e| e.to_string())?;
    }
    let w: Vec<DMat4> = dag
        .iter()
        .map(|&n| match get(g, n, "worldMatrix") {
            Some(Value::Matrix(m)) => m,
            _ => DMat4::IDENTITY,
        })
        .collect();
    for (s, d) in &drivers {
        g.connect(*s, *d).map_err(|e| e.to_string())?;
    }
    Ok(w)
}

/// Connects `src` to `dst`, replacing any drivers of `dst` (and of its components).
fn drive(g: &mut Graph, src: &str, dst: &str, warnings: &mut Vec<String>) {
    let plugs = g.plug(src).and_then(|s| Ok((s, g.plug(dst)?)));
    let Ok((s, d)) = plugs else {
        warnings.push(format!("{dst} is not retargeted: no such plug"));
        return;
    };
    let old: Vec<(Plug, Plug)> = g
        .connections()
        .into_iter()
        .filter(|(_, o)| o.node == d.node && o.attr == d.attr && o.index == d.index)
        .collect();
    let old: Vec<(Plug, Plug)> = old.into_iter().filter(|(a, b)| g.disconnect(*a, *b).is_ok()).collect();
    match g.connect(s, d) {
        Ok(()) => {
            for (a, b) in &old {
                warnings.push(format!("{} no longer drives {}", g.plug_name(*a), g.plug_name(*b)));
            }
        }
        Err(e) => {
            warnings.push(format!("{dst} is not retargeted: {e}"));
            for (a, b) in old {
                let _ = g.connect(a, b);
            }
        }
    }
}

/// [`retarget_with`] with the default options (no foot planting).
pub fn retarget_bvh(bvh: &Bvh, target: &mut Graph, map: Option<&[(String, String)]>) -> Result<RetargetReport, String> {
    retarget_with(bvh, target, map, &RetargetOptions::default())
}

/// Adds curves to `target` that make its skeleton follow `bvh` (see the module docs).
/// `map` is `(source joint, target node)`; `None` uses [`default_map`].
pub fn retarget_with(
    bvh: &Bvh,
    target: &mut Graph,
    map: Option<&[(String, String)]>,
    opts: &RetargetOptions,
) -> Result<RetargetReport, String> {
    if !(bvh.frame_time.is_finite() && bvh.frame_time > 0.0) || bvh.frame_count == 0 {
        return Err("the BVH has no frames or a non-positive Frame Time".into());
    }
    let dag = dag_order(target);
    let tnames: Vec<String> = dag
        .iter()
        .map(|&n| target.node_name(n).unwrap_or("").to_string())
        .collect();
    let snames: Vec<String> = bvh.joints.iter().map(|j| j.name.clone()).collect();
    let pairs = match map {
        Some(m) => m.to_vec(),
        None => default_map(&snames, &tnames),
    };
    let mut report = RetargetReport {
        fps: 1.0 / bvh.frame_time,
        frames: (0, bvh.frame_count as i64 - 1),
        ..Default::default()
    };
    let tindex: HashMap<&str, usize> = tnames.iter().enumerate().map(|(i, n)| (n.as_str(), i)).collect();
    // target dag index -> source joint index
    let mut src_of: HashMap<usize, usize> = HashMap::new();
    for (s, t) in &pairs {
        let si = bvh
            .joint_index(s)
            .ok_or_else(|| format!("map: the BVH has no joint {s:?}"))?;
        let ti = *tindex
            .get(t.as_str())
            .ok_or_else(|| format!("map: the rig has no joint or transform {t:?}"))?;
        src_of.insert(ti, si);
        report.pairs.push((s.clone(), t.clone()));
    }
    if src_of.is_empty() {
        return Err("no joints matched between the BVH and the rig; give --map MAP.ron".into());
    }
    let index: HashMap<NodeId, usize> = dag.iter().enumerate().map(|(i, &n)| (n, i)).collect();
    let parent: Vec<Option<usize>> = dag
        .iter()
        .map(|&n| target.parent_of(n).and_then(|p| index.get(&p).copied()))
        .collect();
    let rest = rest_worlds(target, &dag)?;
    let rest_local: Vec<DQuat> = (0..dag.len())
        .map(|i| rot(&(parent[i].map_or(DMat4::IDENTITY, |p| rest[p]).inverse() * rest[i])))
        .collect();
    // Source rest pose: all channels zero → identity rotations, positions from offsets.
    let mut src_rest_pos = vec![DVec3::ZERO; bvh.joints.len()];
    for (i, j) in bvh.joints.iter().enumerate() {
        src_rest_pos[i] = j.parent.map_or(DVec3::ZERO, |p| src_rest_pos[p]) + j.offset;
    }
    // Leg ratio.
    let leg = |pos: &dyn Fn(&str) -> Option<DVec3>| -> Option<f64> {
        let (a, b, c) = (pos("leftupleg")?, pos("leftleg")?, pos("leftfoot")?);
        let l = (b - a).length() + (c - b).length();
        (l > 1e-9).then_some(l)
    };
    let src_pos = |c: &str| {
        snames
            .iter()
            .position(|n| canonical(n).as_deref() == Some(c))
            .map(|i| src_rest_pos[i])
    };
    // Target leg joints: those mapped from the source's leg joints, else by their own names.
    let tgt_pos = |c: &str| {
        let mapped = (0..dag.len()).find(|t| {
            src_of
                .get(t)
                .is_some_and(|&s| canonical(&snames[s]).as_deref() == Some(c))
        });
        mapped
            .or_else(|| tnames.iter().position(|n| canonical(n).as_deref() == Some(c)))
            .map(|i| rest[i].w_axis.truncate())
    };
    let root_t = (0..dag.len())
        .filter(|t| src_of.contains_key(t))
        .min_by_key(|t| {
            let mut d = 0;
            let mut p = parent[*t];
            while let Some(q) = p {
                d += 1;
                p = parent[q];
            }
            d
        })
        .ok_or("no mapped target joint")?;
    let root_s = src_of[&root_t];
    report.scale = match (leg(&src_pos), leg(&tgt_pos)) {
        (Some(s), Some(t)) => t / s,
        _ => {
            let low_s = src_rest_pos.iter().map(|p| p.y).fold(f64::MAX, f64::min);
            let low_t = rest.iter().map(|m| m.w_axis.y).fold(f64::MAX, f64::min);
            let hs = src_rest_pos[root_s].y - low_s;
            let ht = rest[root_t].w_axis.y - low_t;
            if hs > 1e-9 && ht > 1e-9 {
                ht / hs
            } else {
                1.0
            }
        }
    };
    // Per-frame keys.
    let n = dag.len();
    let mut rot_keys: Vec<Vec<f64>> = vec![Vec::with_capacity(bvh.frame_count * 4); n];
    let mut root_keys = Vec::with_capacity(bvh.frame_count * 3);
    let jo: Vec<DQuat> = dag
        .iter()
        .map(|&d| euler_to_quat(deg_to_rad(vec3(get(target, d, "jointOrient"))), Default::default()))
        .collect();
    let ra: Vec<DQuat> = dag
        .iter()
        .map(|&d| euler_to_quat(deg_to_rad(vec3(get(target, d, "rotateAxis"))), Default::default()))
        .collect();
    // Source forward kinematics, once for the whole clip (ground, keys and foot planting).
    let src_world: Vec<Vec<DMat4>> = (0..bvh.frame_count).map(|f| bvh.world_matrices(f)).collect();
    // Ground of the clip and rest heights above each skeleton's lowest rest joint.
    let src_ground = src_world
        .iter()
        .flatten()
        .map(|m| m.w_axis.y)
        .fold(f64::INFINITY, f64::min);
    let src_rest_low = src_rest_pos.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
    let src_rest_height = src_rest_pos[root_s].y - src_rest_low;
    let time = target.time();
    for (f, sw) in src_world.iter().enumerate() {
        // The root's parent as the rig animates it (rest when it has no parent).
        let root_parent_world = match parent[root_t] {
            Some(p) => {
                target.set_time(Time::new(f as f64, report.fps));
                match get(target, dag[p], "worldMatrix") {
                    Some(Value::Matrix(m)) => m,
                    _ => rest[p],
                }
            }
            None => DMat4::IDENTITY,
        };
        let mut world_rot = vec![DQuat::IDENTITY; n];
        for i in 0..n {
            let prot = match parent[i] {
                Some(_) if i == root_t => rot(&root_parent_world),
                Some(p) => world_rot[p],
                None => DQuat::IDENTITY,
            };
            world_rot[i] = match src_of.get(&i) {
                Some(&s) => (rot(&sw[s]) * rot(&rest[i])).normalize(),
                None => (prot * rest_local[i]).normalize(),
            };
            if src_of.contains_key(&i) {
                let q = (prot.inverse() * world_rot[i]).normalize();
                let mut r = jo[i].inverse() * q * ra[i].inverse();
                if let Some(prev) = rot_keys[i].rchunks(4).next() {
                    if DQuat::from_slice(prev).dot(r) < 0.0 {
                        r = -r;
                    }
                }
                rot_keys[i].extend_from_slice(&r.to_array());
            }
        }
        let mut disp = sw[root_s].w_axis.truncate() - src_rest_pos[root_s];
        if src_ground.is_finite() {
            disp.y = (sw[root_s].w_axis.y - src_ground) - src_rest_height;
        }
        let disp = disp * report.scale;
        let world_pos = rest[root_t].w_axis.truncate() + disp;
        root_keys.extend_from_slice(&root_parent_world.inverse().transform_point3(world_pos).to_array());
    }
    target.set_time(time);
    let times = Arc::new(
        (0..bvh.frame_count)
            // Key `f` at the very seconds rig frame `f` plays at, so frames land on keys.
            .map(|f| Time::new(f as f64, report.fps).seconds())
            .collect::<Vec<f64>>(),
    );
    let mut curves: HashMap<usize, String> = HashMap::new();
    for (i, keys) in rot_keys.iter().enumerate() {
        if keys.is_empty() {
            continue;
        }
        let node = tnames[i].clone();
        let crv = unique(target, &format!("{node}_retarget_rotate"));
        target.add_node("quatCurve", &crv).map_err(|e| e.to_string())?;
        target
            .set_path(&format!("{crv}.keyTime"), Value::FloatArray(times.clone()))
            .map_err(|e| e.to_string())?;
        target
            .set_path(&format!("{crv}.keyValue"), Value::FloatArray(Arc::new(keys.clone())))
            .map_err(|e| e.to_string())?;
        let order = get(target, dag[i], "rotateOrder")
            .and_then(|v| v.as_f64())
            .unwrap_or(0.0) as i64;
        target
            .set_path(&format!("{crv}.rotateOrder"), Value::Enum(order))
            .map_err(|e| e.to_string())?;
        drive(
            target,
            &format!("{crv}.outputRotate"),
            &format!("{node}.rotate"),
            &mut report.warnings,
        );
        curves.insert(i, crv);
    }
    let node = tnames[root_t].clone();
    let crv = unique(target, &format!("{node}_retarget_translate"));
    target.add_node("vectorCurve", &crv).map_err(|e| e.to_string())?;
    target
        .set_path(&format!("{crv}.keyTime"), Value::FloatArray(times))
        .map_err(|e| e.to_string())?;
    target
        .set_path(&format!("{crv}.keyValue"), Value::FloatArray(Arc::new(root_keys)))
        .map_err(|e| e.to_string())?;
    drive(
        target,
        &format!("{crv}.output"),
        &format!("{node}.translate"),
        &mut report.warnings,
    );
    if opts.plant_feet {
        let input = PlantInput {
            bvh,
            src_world: &src_world,
            dag: &dag,
            parent: &parent,
            src_of: &src_of,
            jo: &jo,
            ra: &ra,
            fps: report.fps,
        };
        let (feet, changed) = plant_feet(target, &input, &mut rot_keys, opts, &mut report.warnings);
        report.feet = feet;
        for i in changed {
            if let Some(crv) = curves.get(&i) {
                let keys = Value::FloatArray(Arc::new(std::mem::take(&mut rot_keys[i])));
                target
                    .set_path(&format!("{crv}.keyValue"), keys)
                    .map_err(|e| e.to_string())?;
            }
        }
    }
    Ok(report)
}

fn unique(g: &Graph, base: &str) -> String {
    let mut name = base.to_string();
    let mut k = 1;
    while g.find_node(&name).is_some() {
        name = format!("{base}_{k}");
        k += 1;
    }
    name
}
