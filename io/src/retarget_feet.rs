//! Optional IK foot planting for [`super::retarget`]: contact detection on the source
//! motion, then a two-bone leg IK that holds each target ankle still during contacts.
//!
//! # Contacts (on the source, world up = +Y)
//! A foot touches the ground on a frame when its ankle — and its toe, when the map has one
//! for that side — is each within `contact_height` of the lowest height of that joint kind
//! over both feet and the whole clip, and moves horizontally (XZ) slower than
//! `contact_speed`; both thresholds are in *source leg lengths* (hip→knee→ankle at rest)
//! and leg lengths per second. The speed of a frame is the smaller of its backward and
//! forward differences, so the frame a foot lands on and the frame it leaves from count as
//! still. Gaps up to `max_gap` seconds inside a contact are filled, then contacts shorter
//! than `min_contact` seconds are dropped.
//!
//! # Planting
//! Each contact interval gets one plant point: the mean of the plain-retarget target ankle
//! world positions over the interval (so its height is the retarget's, not snapped to a
//! floor). On every frame of the interval the leg's goal is the plant point; over `blend`
//! seconds before and after (clipped to leave at least one untouched frame between two
//! contacts) the goal moves from the plain ankle to the plant point with a smoothstep weight,
//! so nothing pops. All other frames keep the plain retarget's keys bit for bit.
//!
//! # Leg IK
//! Per planted frame the target hip→knee→ankle chain is solved by
//! [`sinew_nodes::ik::two_bone::solve_two_bone`] (analytic, bone lengths kept): the hip's
//! parent world matrix and the joints' `translate` are read from the graph at that frame
//! (with the plain curves driving it), the plain rotations are the chain's preferred pose and
//! the plain knee sets the pole, so the knee stays in the plain pose's bend plane. A goal out
//! of reach gives a straight leg pointing at it. The ankle keeps its plain *world* rotation.
//! New rotations go to the same `quatCurve` keys as `R = JO⁻¹ · Q · RA⁻¹`.
//!
//! # Fallbacks
//! A side is skipped with a warning when its hip, knee or ankle is not mapped, when the
//! targets are not a parent → child chain, or when the graph's ankle does not match the
//! chain's forward kinematics (scale, pivots or shear on the leg joints, which the IK does
//! not model). An invalid solve (non-finite input) keeps the plain keys of that frame.

use std::collections::HashMap;

use glam::{DMat4, DQuat, DVec3};
use sinew_core::{Graph, NodeId, Time, Value};
use sinew_nodes::ik::chain::{chain_world_matrices, Chain, ChainJoint};
use sinew_nodes::ik::soft::ReachParams;
use sinew_nodes::ik::two_bone::{solve_two_bone, RpParams};

use super::bvh::Bvh;
use super::retarget_map::canonical;

/// Retargeting options; [`Default`] is the plain retarget (no foot planting). A NaN
/// threshold finds no contacts; negative or NaN durations count as 0.
#[derive(Clone, Debug, PartialEq)]
pub struct RetargetOptions {
    /// Hold each target ankle still while the source foot is in contact (default off).
    pub plant_feet: bool,
    /// Contact height: at most this far above the lowest height in the clip, in source leg
    /// lengths (default 0.08, about 7 cm on a human: real takes drift by a few cm).
    pub contact_height: f64,
    /// Contact speed: horizontal speed below this, in source leg lengths per second
    /// (default 0.3, about 25 cm/s on a human).
    pub contact_speed: f64,
    /// Contacts shorter than this are dropped, seconds (default 0.1).
    pub min_contact: f64,
    /// Non-contact gaps up to this long inside a contact are filled, seconds (default 0.05).
    pub max_gap: f64,
    /// Blend in and out over this long before and after each contact, seconds (default 0.1).
    pub blend: f64,
}

impl Default for RetargetOptions {
    fn default() -> Self {
        RetargetOptions {
            plant_feet: false,
            contact_height: 0.08,
            contact_speed: 0.3,
            min_contact: 0.1,
            max_gap: 0.05,
            blend: 0.1,
        }
    }
}

/// The planted contacts of one foot.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FootContacts {
    /// `"left"` or `"right"`.
    pub side: String,
    /// The target ankle node.
    pub ankle: String,
    /// Contact intervals (first and last frame, inclusive): the ankle is planted throughout.
    pub intervals: Vec<(i64, i64)>,
    /// Per interval, the frames whose keys changed (the interval with its blend zones).
    pub affected: Vec<(i64, i64)>,
}

/// What [`plant_feet`] needs from the retargeter.
pub(super) struct PlantInput<'a> {
    /// The motion.
    pub bvh: &'a Bvh,
    /// The motion's world matrices per frame and joint (`Bvh::world_matrices`).
    pub src_world: &'a [Vec<DMat4>],
    /// Target DAG nodes (indices below refer to this).
    pub dag: &'a [NodeId],
    /// DAG parent index per node.
    pub parent: &'a [Option<usize>],
    /// Target index → source joint.
    pub src_of: &'a HashMap<usize, usize>,
    /// jointOrient and rotateAxis quaternions per node.
    pub jo: &'a [DQuat],
    /// See `jo`.
    pub ra: &'a [DQuat],
    /// Frames per second of the motion.
    pub fps: f64,
}

/// A leg: source hip/knee/ankle(/toe) joints and target hip/knee/ankle DAG indices.
struct Leg {
    side: &'static str,
    src: [usize; 3],
    toe: Option<usize>,
    tgt: [usize; 3],
}

/// Finds the legs (see the module docs for when a side is skipped).
fn legs(inp: &PlantInput, warnings: &mut Vec<String>) -> Vec<Leg> {
    let mut out = Vec::new();
    for side in ["left", "right"] {
        let find = |part: &str| {
            let want = format!("{side}{part}");
            let mut m: Vec<(usize, usize)> = inp
                .src_of
                .iter()
                .filter(|(_, &s)| canonical(&inp.bvh.joints[s].name).as_deref() == Some(want.as_str()))
                .map(|(&t, &s)| (t, s))
                .collect();
            m.sort_unstable();
            m.first().copied()
        };
        let (Some(h), Some(k), Some(a)) = (find("upleg"), find("leg"), find("foot")) else {
            warnings.push(format!(
                "foot planting skipped for the {side} foot: its hip, knee and ankle are not all mapped"
            ));
            continue;
        };
        if inp.parent[k.0] != Some(h.0) || inp.parent[a.0] != Some(k.0) {
            warnings.push(format!(
                "foot planting skipped for the {side} foot: the target hip, knee and ankle are not a parent-child chain"
            ));
            continue;
        }
        out.push(Leg {
            side,
            src: [h.1, k.1, a.1],
            toe: find("toebase").map(|t| t.1),
            tgt: [h.0, k.0, a.0],
        });
    }
    out
}

/// Frames where `joint` is low and still (see the module docs).
fn still(pos: &[Vec<DVec3>], joint: usize, ground: f64, height: f64, speed: f64, dt: f64) -> Vec<bool> {
    let n = pos.len();
    let flat = |f: usize| DVec3::new(pos[f][joint].x, 0.0, pos[f][joint].z);
    (0..n)
        .map(|f| {
            let back = (f > 0).then(|| (flat(f) - flat(f - 1)).length() / dt);
            let fwd = (f + 1 < n).then(|| (flat(f + 1) - flat(f)).length() / dt);
            let v = match (back, fwd) {
                (Some(a), Some(b)) => a.min(b),
                (Some(a), None) | (None, Some(a)) => a,
                (None, None) => 0.0,
            };
            pos[f][joint].y - ground <= height && v <= speed
        })
        .collect()
}

/// Runs of `true` as inclusive `(start, end)` frames.
fn runs(flags: &[bool]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (f, &c) in flags.iter().chain([false].iter()).enumerate() {
        match (c, start) {
            (true, None) => start = Some(f),
            (false, Some(s)) => {
                out.push((s, f - 1));
                start = None;
            }
            _ => {}
        }
    }
    out
}

/// Contact intervals from per-frame flags: gaps up to `max_gap` frames filled, then runs
/// shorter than `min_len` frames dropped.
pub fn clean_contacts(flags: &[bool], max_gap: usize, min_len: usize) -> Vec<(usize, usize)> {
    let mut merged: Vec<(usize, usize)> = Vec::new();
    for (s, e) in runs(flags) {
        match merged.last_mut() {
            Some(last) if s - last.1 - 1 <= max_gap => last.1 = e,
            _ => merged.push((s, e)),
        }
    }
    merged.retain(|(s, e)| e - s + 1 >= min_len.max(1));
    merged
}

/// Per frame the planting weight and interval (`None` = untouched): 1 inside intervals,
/// a smoothstep ramp over at most `blend` frames outside them, leaving at least one
/// untouched frame between two intervals.
fn weights(intervals: &[(usize, usize)], frames: usize, blend: usize) -> Vec<Option<(f64, usize)>> {
    let mut w = vec![None; frames];
    for (i, &(s, e)) in intervals.iter().enumerate() {
        for slot in &mut w[s..=e] {
            *slot = Some((1.0, i));
        }
        let before = match i {
            0 => s,
            _ => (s - intervals[i - 1].1 - 2) / 2,
        };
        let after = match intervals.get(i + 1) {
            Some(&(ns, _)) => (ns - e - 2) / 2,
            None => frames - 1 - e,
        };
        let ramp = |k: usize, side: usize| {
            let x = 1.0 - k as f64 / (side as f64 + 1.0);
            x * x * (3.0 - 2.0 * x)
        };
        let b = blend.min(before);
        for k in 1..=b {
            w[s - k] = Some((ramp(k, b), i));
        }
        let b = blend.min(after);
        for k in 1..=b {
            w[e + k] = Some((ramp(k, b), i));
        }
    }
    w
}

fn matrix(v: Option<Value>) -> Option<DMat4> {
    match v {
        Some(Value::Matrix(m)) => Some(m),
        _ => None,
    }
}

fn get(g: &mut Graph, node: NodeId, attr: &str) -> Option<Value> {
    let name = g.node_name(node)?.to_string();
    g.get_path(&format!("{name}.{attr}")).ok()
}

fn key(keys: &[f64], f: usize) -> DQuat {
    keys.get(4 * f..4 * f + 4).map_or(DQuat::IDENTITY, DQuat::from_slice)
}

/// One frame of a leg to solve.
struct Frame {
    f: usize,
    weight: f64,
    interval: usize,
    chain: Chain,
    plain: [DQuat; 3],
    hip: DVec3,
    knee: DVec3,
    ankle: DVec3,
}

/// Detects contacts and plants the feet by rewriting the hip, knee and ankle keys in
/// `rot_keys` (flat `x y z w` per frame, per target DAG index; a new key takes the sign of
/// its predecessor). The graph must be driven by the plain keys. Returns the contacts per
/// planted foot and the DAG indices whose keys changed; the graph's time is restored.
pub(super) fn plant_feet(
    g: &mut Graph,
    inp: &PlantInput,
    rot_keys: &mut [Vec<f64>],
    opts: &RetargetOptions,
    warnings: &mut Vec<String>,
) -> (Vec<FootContacts>, Vec<usize>) {
    let legs = legs(inp, warnings);
    let n = inp.bvh.frame_count;
    let pos: Vec<Vec<DVec3>> = inp
        .src_world
        .iter()
        .map(|w| w.iter().map(|m| m.w_axis.truncate()).collect())
        .collect();
    let lowest = |joints: &[usize]| {
        pos.iter()
            .flat_map(|p| joints.iter().map(|&j| p[j].y))
            .fold(f64::INFINITY, f64::min)
    };
    let ankle_ground = lowest(&legs.iter().map(|l| l.src[2]).collect::<Vec<_>>());
    let toe_ground = lowest(&legs.iter().filter_map(|l| l.toe).collect::<Vec<_>>());
    let frames_of = |secs: f64| (secs.max(0.0) * inp.fps).round().min(n as f64) as usize;
    let dt = 1.0 / inp.fps;
    let time = g.time();
    let mut out = Vec::new();
    let mut changed = Vec::new();
    for leg in legs {
        let rest = |j: usize| inp.bvh.joints[j].offset.length();
        let length = rest(leg.src[1]) + rest(leg.src[2]);
        let (h, v) = (opts.contact_height * length, opts.contact_speed * length);
        let mut flags = still(&pos, leg.src[2], ankle_ground, h, v, dt);
        if let Some(toe) = leg.toe {
            for (c, t) in flags.iter_mut().zip(still(&pos, toe, toe_ground, h, v, dt)) {
                *c &= t;
            }
        }
        let intervals = clean_contacts(&flags, frames_of(opts.max_gap), frames_of(opts.min_contact));
        let w = weights(&intervals, n, frames_of(opts.blend));
        match solve_leg(g, inp, &leg, &w, intervals.len(), rot_keys) {
            Ok(()) => changed.extend(leg.tgt),
            Err(e) => {
                warnings.push(format!("foot planting skipped for the {} foot: {e}", leg.side));
                continue;
            }
        }
        let affected = (0..intervals.len())
            .map(|i| {
                let in_zone = |f: &usize| w[*f].is_some_and(|(_, k)| k == i);
                let first = (0..n).find(in_zone).unwrap_or(0);
                (first as i64, (0..n).rev().find(in_zone).unwrap_or(first) as i64)
            })
            .collect();
        out.push(FootContacts {
            side: leg.side.to_string(),
            ankle: g.node_name(inp.dag[leg.tgt[2]]).unwrap_or("").to_string(),
            intervals: intervals.iter().map(|&(s, e)| (s as i64, e as i64)).collect(),
            affected,
        });
    }
    g.set_time(time);
    (out, changed)
}

/// Plants one leg: reads the plain pose from the graph on every weighted frame, then solves.
fn solve_leg(
    g: &mut Graph,
    inp: &PlantInput,
    leg: &Leg,
    w: &[Option<(f64, usize)>],
    count: usize,
    rot_keys: &mut [Vec<f64>],
) -> Result<(), String> {
    let [h, k, a] = leg.tgt;
    let mut frames = Vec::new();
    for (f, wf) in w.iter().enumerate() {
        let Some((weight, interval)) = *wf else { continue };
        g.set_time(Time::new(f as f64, inp.fps));
        let parent_world = matrix(get(g, inp.dag[h], "parentMatrix")).unwrap_or(DMat4::IDENTITY);
        let plain = [key(&rot_keys[h], f), key(&rot_keys[k], f), key(&rot_keys[a], f)];
        let mut joints = Vec::with_capacity(3);
        for (i, &t) in leg.tgt.iter().enumerate() {
            let translate = match get(g, inp.dag[t], "translate") {
                Some(Value::Vec3(v)) => v,
                _ => DVec3::ZERO,
            };
            joints.push(ChainJoint {
                translate,
                joint_orient: inp.jo[t],
                rotate_axis: inp.ra[t],
                preferred: plain[i],
            });
        }
        let chain = Chain { parent_world, joints };
        let m = chain_world_matrices(&chain, &plain);
        let [hip, knee, ankle] = [0, 1, 2].map(|i| m[i].w_axis.truncate());
        let length = hip.distance(knee) + knee.distance(ankle);
        let graph_ankle = matrix(get(g, inp.dag[a], "worldMatrix")).map(|m| m.w_axis.truncate());
        let follows = graph_ankle.is_some_and(|p| p.distance(ankle) <= 1e-6 * length.max(1e-9));
        if !follows {
            return Err(
                "the rig's ankle does not follow the leg's forward kinematics (scale, pivots or shear \
                 on the hip, knee or ankle?)"
                    .into(),
            );
        }
        frames.push(Frame {
            f,
            weight,
            interval,
            chain,
            plain,
            hip,
            knee,
            ankle,
        });
    }
    let mut sum = vec![(DVec3::ZERO, 0usize); count];
    for fr in frames.iter().filter(|fr| fr.weight >= 1.0) {
        sum[fr.interval].0 += fr.ankle;
        sum[fr.interval].1 += 1;
    }
    let plant: Vec<DVec3> = sum.iter().map(|(p, c)| *p / (*c).max(1) as f64).collect();
    let (jo, ra) = (leg.tgt.map(|t| inp.jo[t]), leg.tgt.map(|t| inp.ra[t]));
    let local = |i: usize, r: DQuat| jo[i] * r * ra[i];
    for fr in &frames {
        let goal = if fr.weight >= 1.0 {
            plant[fr.interval]
        } else {
            fr.ankle.lerp(plant[fr.interval], fr.weight)
        };
        let rp = RpParams {
            pole_vector: fr.knee - fr.hip,
            twist: 0.0,
        };
        let sol = solve_two_bone(&fr.chain, goal, &rp, &ReachParams::default());
        if sol.is_invalid() || sol.rotations.len() != 3 {
            continue;
        }
        let (r0, r1) = (sol.rotations[0], sol.rotations[1]);
        // Keep the ankle's world rotation: K_new · A_new = K_plain · A_plain.
        let k_new = local(0, r0) * local(1, r1);
        let k_plain = local(0, fr.plain[0]) * local(1, fr.plain[1]);
        let a_new = k_new.inverse() * k_plain * local(2, fr.plain[2]);
        let r2 = (jo[2].inverse() * a_new * ra[2].inverse()).normalize();
        for (&t, r) in leg.tgt.iter().zip([r0, r1, r2]) {
            if !r.is_finite() {
                continue;
            }
            // Same hemisphere as the previous key (earlier frames are final); later plain keys stay untouched.
            let mut r = r.normalize();
            if fr.f > 0 && key(&rot_keys[t], fr.f - 1).dot(r) < 0.0 {
                r = -r;
            }
            rot_keys[t][4 * fr.f..4 * fr.f + 4].copy_from_slice(&r.to_array());
        }
    }
    Ok(())
}
