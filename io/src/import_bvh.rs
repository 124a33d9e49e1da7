//! BVH import: a parsed [`Bvh`] to `joint` nodes driven by sampled curves.
//!
//! - Each BVH joint becomes a `joint` (names made rig-safe: other characters become `_`)
//!   with `translate` = its `OFFSET`; each `End Site` becomes a joint `<parent>_end`.
//! - Rotate order: BVH rotation channels apply in file order as *intrinsic* rotations
//!   (`Zrotation Xrotation Yrotation` → `Rz · Rx · Ry`, column vectors; see
//!   [`super::bvh`]). Maya's `rotateOrder` names the order in which rotations apply about
//!   the parent's axes (`yxz` → `Rz · Rx · Ry`), so a BVH channel order maps to the
//!   **reversed** Maya order: ZXY → `yxz`, ZYX → `xyz`, XYZ → `zyx`, YXZ → `zxy`. Joints
//!   with fewer than three rotation channels get an order with their axes in the same
//!   relative order (the missing angle is 0). A joint that repeats an axis (e.g. `Z X Z`)
//!   cannot be expressed as one Euler triple; it gets a `quatCurve` with the per-frame
//!   quaternions instead.
//! - Motion: frame `f` (0-based) is at `f · FrameTime` seconds, i.e. rig frame `f` at
//!   `fps = 1 / FrameTime`; the rig's `frames` are `(0, Frames - 1)`. Rotations go to a
//!   `vectorCurve` (Euler degrees, linear between frames) → `rotate`; joints with position
//!   channels get a `vectorCurve` of the full translation (the offset with each channel's
//!   axis replaced, as the reader's reference FK does) → `translate`. Key `f` is at
//!   `f / fps` seconds in `f64`, the very operation that turns rig frame `f` into seconds
//!   ([`sinew_core::Time::seconds`]), so every frame lands exactly on its key at the rig's
//!   rate, however long the take.

use std::sync::Arc;

use glam::DVec3;
use sinew_core::Value;

use super::bvh::{Axis, Bvh, Channel};
use super::rig_builder::RigBuilder;

/// The Maya rotate order (enum index) for BVH rotation axes applied intrinsically in
/// `axes` order: the reverse sequence.
pub fn maya_order_for_bvh(axes: [Axis; 3]) -> i64 {
    let idx = |a: Axis| a as usize;
    // Maya order as (first applied, second, third) axes → enum index.
    let reversed = [idx(axes[2]), idx(axes[1]), idx(axes[0])];
    match reversed {
        [0, 1, 2] => 0, // xyz
        [1, 2, 0] => 1, // yzx
        [2, 0, 1] => 2, // zxy
        [0, 2, 1] => 3, // xzy
        [1, 0, 2] => 4, // yxz
        _ => 5,         // zyx
    }
}

/// Rotation axes of a joint in file order.
fn rotation_axes(channels: &[Channel]) -> Vec<Axis> {
    channels
        .iter()
        .filter_map(|c| match c {
            Channel::Rotation(a) => Some(*a),
            Channel::Position(_) => None,
        })
        .collect()
}

/// Completes up to three distinct axes (file order) to a full order, missing axes first
/// (their angle is zero, so where they go does not matter).
fn complete_axes(axes: &[Axis]) -> Option<[Axis; 3]> {
    let mut seen = [false; 3];
    for a in axes {
        if std::mem::replace(&mut seen[*a as usize], true) {
            return None;
        }
    }
    let mut full: Vec<Axis> = [Axis::X, Axis::Y, Axis::Z]
        .into_iter()
        .filter(|a| !seen[*a as usize])
        .collect();
    full.extend_from_slice(axes);
    Some([full[0], full[1], full[2]])
}

/// Options of [`import_bvh`].
#[derive(Clone, Debug)]
pub struct BvhImportOptions {
    /// Rig name.
    pub name: String,
}

/// The imported rig and the rig node name of each BVH joint.
#[derive(Clone, Debug)]
pub struct BvhImport {
    /// The rig.
    pub rig: RigBuilder,
    /// Rig node name of each BVH joint (same order as `Bvh::joints`).
    pub joint_names: Vec<String>,
}

/// Maps a BVH to joints and curves (see the module docs).
pub fn import_bvh(bvh: &Bvh, opts: &BvhImportOptions) -> Result<BvhImport, String> {
    if !(bvh.frame_time.is_finite() && bvh.frame_time > 0.0) {
        return Err(format!("Frame Time {} must be a positive number", bvh.frame_time));
    }
    let fps = 1.0 / bvh.frame_time;
    let mut rig = RigBuilder::new(&opts.name, fps);
    rig.frames = Some((0.0, bvh.frame_count.saturating_sub(1) as f64));
    let names: Vec<String> = bvh
        .joints
        .iter()
        .enumerate()
        .map(|(i, j)| rig.name(&j.name, &format!("joint{i}")))
        .collect();
    let times: Vec<f64> = (0..bvh.frame_count)
        .map(|f| sinew_core::Time::new(f as f64, fps).seconds())
        .collect();
    if times.windows(2).any(|w| w[0] >= w[1]) {
        return Err("frame times collapse (too many frames or a tiny Frame Time)".into());
    }
    let times = Value::FloatArray(Arc::new(times));
    // Each frame's channel values, found once (finding one walks the joints).
    let frames: Vec<&[f64]> = (0..bvh.frame_count).map(|f| bvh.frame(f).unwrap_or(&[])).collect();
    for (i, j) in bvh.joints.iter().enumerate() {
        let name = names[i].clone();
        let k = rig.add(&name, "joint", j.parent.map(|p| names[p].as_str()), false);
        rig.set(k, "translate", Value::Vec3(j.offset));
        let axes = rotation_axes(&j.channels);
        let order = complete_axes(&axes);
        if let Some(o) = order {
            let m = maya_order_for_bvh(o);
            if m != 0 {
                rig.set(k, "rotateOrder", Value::Enum(m));
            }
        }
        if bvh.frame_count == 0 {
            continue;
        }
        let has_pos = j.channels.iter().any(|c| matches!(c, Channel::Position(_)));
        if has_pos {
            let mut vals = Vec::with_capacity(bvh.frame_count * 3);
            for values in &frames {
                let (t, _) = bvh.local_transform_in(i, values).ok_or("frame out of range")?;
                vals.extend_from_slice(&t.to_array());
            }
            let crv = rig.name(&format!("{name}_translate_crv"), "crv");
            let c = rig.add(&crv, "vectorCurve", None, true);
            rig.set(c, "keyTime", times.clone());
            rig.set(c, "keyValue", Value::FloatArray(Arc::new(vals)));
            rig.connect(format!("{crv}.output"), format!("{name}.translate"));
        }
        if axes.is_empty() {
            continue;
        }
        let values = |f: usize| frames[f];
        if order.is_some() {
            let mut vals = Vec::with_capacity(bvh.frame_count * 3);
            for f in 0..bvh.frame_count {
                let fv = values(f);
                let mut r = DVec3::ZERO;
                for (c, ch) in j.channels.iter().enumerate() {
                    if let Channel::Rotation(a) = ch {
                        r[*a as usize] = fv.get(j.first_channel + c).copied().unwrap_or(0.0);
                    }
                }
                vals.extend_from_slice(&r.to_array());
            }
            let crv = rig.name(&format!("{name}_rotate_crv"), "crv");
            let c = rig.add(&crv, "vectorCurve", None, true);
            rig.set(c, "keyTime", times.clone());
            rig.set(c, "keyValue", Value::FloatArray(Arc::new(vals)));
            rig.connect(format!("{crv}.output"), format!("{name}.rotate"));
        } else {
            let mut vals = Vec::with_capacity(bvh.frame_count * 4);
            for values in &frames {
                let (_, q) = bvh.local_transform_in(i, values).ok_or("frame out of range")?;
                vals.extend_from_slice(&q.to_array());
            }
            let crv = rig.name(&format!("{name}_rotate_crv"), "crv");
            let c = rig.add(&crv, "quatCurve", None, true);
            rig.set(c, "keyTime", times.clone());
            rig.set(c, "keyValue", Value::FloatArray(Arc::new(vals)));
            rig.connect(format!("{crv}.outputRotate"), format!("{name}.rotate"));
        }
    }
    for (i, j) in bvh.joints.iter().enumerate() {
        if let Some(e) = j.end_site {
            let end = rig.name(&format!("{}_end", names[i]), "end");
            let k = rig.add(&end, "joint", Some(&names[i]), false);
            rig.set(k, "translate", Value::Vec3(e));
        }
    }
    Ok(BvhImport {
        rig,
        joint_names: names,
    })
}
