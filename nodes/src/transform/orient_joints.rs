//! Maya's Orient Joint (`joint -e -orientJoint xyz -secondaryAxisOrient yup -children`) on a
//! graph: each joint's axes are re-aimed (the aim axis at its first child joint, the up
//! axis as close as it can be to a world axis) and the orientation goes into its
//! `jointOrient`, with `rotate` and `rotateAxis` zeroed; translations are recomputed so
//! every joint stays exactly where it is in the world.
//!
//! Per oriented joint `J` with world position `p` and first child joint at `c`:
//! `aim = (c − p)/|c − p|`, `up = normalize(w − (w·aim) aim)` for the world-up axis `w`, the
//! third axis completing a right-handed frame. The new world rotation has those columns;
//! `jointOrient = euler_xyz(Q_parent⁻¹ · Q_J)` (the parent's world rotation with its scale
//! removed) and `translate = W_parent⁻¹ · p` with the parent's *new* world matrix, joints
//! processed parent first. A joint without a child joint takes its parent's orientation
//! (`jointOrient` 0). When the aim is parallel to the world up, the up axis falls back to
//! the parent's new up axis (then to any perpendicular).
//!
//! Nodes below an oriented joint that are not oriented themselves keep their whole world
//! matrix: a joint through its `translate` and `jointOrient` (its `rotate` and
//! `rotateAxis` kept), anything else through its `offsetParentMatrix`. Joints whose
//! `translate`, `rotate`, `rotateAxis` or `jointOrient` a connection drives are refused
//! (the new frame would change what the driver means). Parents are assumed to have uniform
//! scale (as for Maya's tool).

use std::collections::HashSet;

use glam::{DMat3, DMat4, DQuat, DVec3};
use sinew_core::{Error, Graph, NodeId, Value};

use super::euler::{euler_to_quat, quat_to_euler, RotateOrder};
use super::math::orthonormalize;

/// A world axis with a sign (`-y` is `(0, -1, 0)`).
pub fn axis_vector(axis: &str) -> Option<DVec3> {
    let (neg, a) = match axis.strip_prefix('-') {
        Some(a) => (true, a),
        None => (false, axis.strip_prefix('+').unwrap_or(axis)),
    };
    let v = match a.to_ascii_lowercase().as_str() {
        "x" => DVec3::X,
        "y" => DVec3::Y,
        "z" => DVec3::Z,
        _ => return None,
    };
    Some(if neg { -v } else { v })
}

/// What to orient and how (Maya's `-orientJoint` axes and `-secondaryAxisOrient`).
#[derive(Clone, Debug)]
pub struct OrientJoints {
    /// The local axis (0 = X, 1 = Y, 2 = Z) that points at the child.
    pub aim: usize,
    /// The local axis that points as close as possible to `world_up`.
    pub up: usize,
    /// The world direction for the up axis (unit).
    pub world_up: DVec3,
    /// Joints to orient (`None`: every joint).
    pub joints: Option<Vec<String>>,
    /// With `joints`: orient their descendant joints too (Maya's `-children`).
    pub children: bool,
}

fn err(msg: String) -> Error {
    Error::Program(msg)
}

fn vec3(g: &Graph, node: NodeId, attr: &str) -> DVec3 {
    match g
        .plug(&format!("{}.{attr}", g.node_name(node).unwrap_or("")))
        .ok()
        .and_then(|p| g.stored(p))
    {
        Some(Value::Vec3(v)) => v,
        _ => DVec3::ZERO,
    }
}

fn world(g: &mut Graph, node: NodeId) -> Result<DMat4, Error> {
    let name = g.node_name(node).unwrap_or("").to_string();
    match g.get_path(&format!("{name}.worldMatrix"))? {
        Value::Matrix(m) => Ok(m),
        other => Err(err(format!("{name}.worldMatrix holds {other}"))),
    }
}

/// The rotation of a world matrix with scale (and shear) removed.
fn rotation(m: &DMat4) -> DQuat {
    DQuat::from_mat3(&orthonormalize(DMat3::from_mat4(*m))).normalize()
}

fn set(g: &mut Graph, node: NodeId, attr: &str, v: Value) -> Result<(), Error> {
    let name = g.node_name(node).unwrap_or("").to_string();
    g.set_path(&format!("{name}.{attr}"), v)
}

fn deg(q: DQuat) -> DVec3 {
    let r = quat_to_euler(q, RotateOrder::Xyz);
    DVec3::new(r.x.to_degrees(), r.y.to_degrees(), r.z.to_degrees())
}

fn rad(v: DVec3) -> DVec3 {
    DVec3::new(v.x.to_radians(), v.y.to_radians(), v.z.to_radians())
}

/// Orients the joints (see the module docs); returns the names of the oriented joints, in
/// the order they were processed. Fails, before changing anything, on an unknown joint
/// name, equal aim and up axes, or a driven channel.
pub fn orient_joints(g: &mut Graph, o: &OrientJoints) -> Result<Vec<String>, Error> {
    if o.aim > 2 || o.up > 2 || o.aim == o.up {
        return Err(err("the aim and up axes must be two different axes of x, y, z".into()));
    }
    let is_joint = |g: &Graph, n: NodeId| g.node_type(n) == Some("joint");
    let all: Vec<NodeId> = g.nodes().into_iter().filter(|&n| is_joint(g, n)).collect();
    let mut chosen: HashSet<NodeId> = match &o.joints {
        None => all.iter().copied().collect(),
        Some(names) => names.iter().map(|n| g.node_id(n)).collect::<Result<_, _>>()?,
    };
    if let Some(bad) = chosen.iter().find(|&&n| !is_joint(g, n)) {
        return Err(err(format!("{} is not a joint", g.node_name(*bad).unwrap_or("?"))));
    }
    if o.joints.is_some() && o.children {
        let mut stack: Vec<NodeId> = chosen.iter().copied().collect();
        while let Some(n) = stack.pop() {
            for c in g.children_of(n) {
                if is_joint(g, c) && chosen.insert(c) {
                    stack.push(c);
                }
            }
        }
    }
    // Parent first: by depth, then creation order.
    let depth = |g: &Graph, mut n: NodeId| {
        let mut d = 0;
        while let Some(p) = g.parent_of(n) {
            d += 1;
            n = p;
        }
        d
    };
    let mut order: Vec<NodeId> = g.nodes().into_iter().filter(|n| chosen.contains(n)).collect();
    order.sort_by_key(|&n| depth(g, n));
    for &n in &order {
        for attr in ["translate", "rotate", "rotateAxis", "jointOrient"] {
            let p = g.plug(&format!("{}.{attr}", g.node_name(n).unwrap_or("")))?;
            let driven = g
                .source_of(p)
                .or_else(|| (0..3).find_map(|k| g.source_of(p.component(k))));
            if let Some(src) = driven {
                return Err(err(format!(
                    "{} is driven by {}; orient the skeleton before connecting it (or disconnect it)",
                    g.plug_name(p),
                    g.plug_name(src)
                )));
            }
        }
    }
    // The world matrices before any change: what every node must keep.
    let mut before: std::collections::HashMap<NodeId, DMat4> = std::collections::HashMap::new();
    for n in g.nodes() {
        if g.node_spec(n).is_some_and(|s| s.dag.is_some()) {
            before.insert(n, world(g, n)?);
        }
    }
    let mut done = Vec::with_capacity(order.len());
    for &j in &order {
        let parent_world = match g.parent_of(j) {
            Some(p) => world(g, p)?,
            None => DMat4::IDENTITY,
        };
        let pos = before[&j].w_axis.truncate();
        let child = g.children_of(j).into_iter().find(|&c| is_joint(g, c));
        let q_parent = rotation(&parent_world);
        let q = match child.map(|c| before[&c].w_axis.truncate() - pos) {
            Some(d) if d.length() > 1e-12 => {
                let aim = d.normalize();
                let fallback = q_parent * axis_unit(o.up);
                let up = [o.world_up, fallback, aim.any_orthonormal_vector()]
                    .into_iter()
                    .map(|w| w - w.dot(aim) * aim)
                    .find(|u| u.length() > 1e-9)
                    .unwrap_or(DVec3::ZERO)
                    .normalize();
                frame(o.aim, aim, o.up, up)
            }
            _ => q_parent,
        };
        let local = q_parent.inverse() * q;
        let t = parent_world.inverse().transform_point3(pos);
        set(g, j, "rotate", Value::Vec3(DVec3::ZERO))?;
        set(g, j, "rotateAxis", Value::Vec3(DVec3::ZERO))?;
        set(g, j, "jointOrient", Value::Vec3(deg(local)))?;
        set(g, j, "translate", Value::Vec3(t))?;
        // Children that are not oriented keep their world matrix.
        let new_world = world(g, j)?;
        for c in g.children_of(j) {
            if chosen.contains(&c) || !before.contains_key(&c) {
                continue;
            }
            keep_world(g, c, &new_world, &before[&j], &before[&c])?;
        }
        done.push(g.node_name(j).unwrap_or("").to_string());
    }
    Ok(done)
}

fn axis_unit(k: usize) -> DVec3 {
    [DVec3::X, DVec3::Y, DVec3::Z][k]
}

/// The rotation whose axis `aim_axis` is `aim` and axis `up_axis` is `up` (unit, orthogonal),
/// the third axis completing a right-handed frame.
fn frame(aim_axis: usize, aim: DVec3, up_axis: usize, up: DVec3) -> DQuat {
    let mut cols = [DVec3::ZERO; 3];
    cols[aim_axis] = aim;
    cols[up_axis] = up;
    let third = 3 - aim_axis - up_axis;
    cols[third] = cols[(third + 1) % 3].cross(cols[(third + 2) % 3]);
    DQuat::from_mat3(&DMat3::from_cols(cols[0], cols[1], cols[2])).normalize()
}

/// Gives `c` (a child of a node whose world matrix went from `old_parent` to
/// `new_parent`) its old world matrix `old` again.
fn keep_world(g: &mut Graph, c: NodeId, new_parent: &DMat4, old_parent: &DMat4, old: &DMat4) -> Result<(), Error> {
    let name = g.node_name(c).unwrap_or("").to_string();
    let joint_ok = g.node_type(c) == Some("joint")
        && ["translate", "jointOrient"].iter().all(|a| {
            g.plug(&format!("{name}.{a}"))
                .is_ok_and(|p| g.source_of(p).is_none() && (0..3).all(|k| g.source_of(p.component(k)).is_none()))
        });
    if joint_ok {
        let order = match g.get_path(&format!("{name}.rotateOrder"))? {
            Value::Enum(i) | Value::Int(i) => RotateOrder::from_index(i).unwrap_or_default(),
            _ => RotateOrder::Xyz,
        };
        let r = euler_to_quat(rad(vec3(g, c, "rotate")), order);
        let ra = euler_to_quat(rad(vec3(g, c, "rotateAxis")), RotateOrder::Xyz);
        // Q_local = JO · R · RA  ⇒  JO = Q_local · RA⁻¹ · R⁻¹.
        let local = rotation(new_parent).inverse() * rotation(old);
        let jo = local * ra.inverse() * r.inverse();
        set(g, c, "jointOrient", Value::Vec3(deg(jo)))?;
        let t = new_parent.inverse().transform_point3(old.w_axis.truncate());
        return set(g, c, "translate", Value::Vec3(t));
    }
    // world = parent · offset · local: offset' = parent'⁻¹ · parent · offset.
    let opm = format!("{name}.offsetParentMatrix");
    let Ok(p) = g.plug(&opm) else { return Ok(()) };
    let current = match g.stored(p) {
        Some(Value::Matrix(m)) => m,
        _ => DMat4::IDENTITY,
    };
    g.set(p, Value::Matrix(new_parent.inverse() * *old_parent * current))
}
