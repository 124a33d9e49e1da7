//! Rust helpers that build constraints in a graph the way Maya's constraint
//! commands do: [`constrain`] creates and wires a constraint node,
//! [`maintain_offset`] stores the offsets that keep the constrained node
//! where it is.

use glam::{DMat4, DQuat, DVec3};
use sinew_core::{Error, Graph, NodeId, Plug, Value};

use super::common::{deg, local_rotation, rad};
use crate::transform::math::{euler_to_quat, quat_to_euler, to_translate_rotate_scale, RotateOrder};

/// The constraint node types, for [`constrain`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ConstraintKind {
    /// `parentConstraint` (translate + rotate).
    Parent,
    /// `pointConstraint` (translate).
    Point,
    /// `orientConstraint` (rotate).
    Orient,
    /// `aimConstraint` (rotate).
    Aim,
    /// `scaleConstraint` (scale).
    Scale,
    /// `poleVectorConstraint` (an ikHandle's poleVector).
    PoleVector,
}

impl ConstraintKind {
    /// Every kind.
    pub const ALL: [ConstraintKind; 6] = [
        ConstraintKind::Parent,
        ConstraintKind::Point,
        ConstraintKind::Orient,
        ConstraintKind::Aim,
        ConstraintKind::Scale,
        ConstraintKind::PoleVector,
    ];

    /// The node type name (`parentConstraint`...).
    pub fn type_name(self) -> &'static str {
        match self {
            ConstraintKind::Parent => "parentConstraint",
            ConstraintKind::Point => "pointConstraint",
            ConstraintKind::Orient => "orientConstraint",
            ConstraintKind::Aim => "aimConstraint",
            ConstraintKind::Scale => "scaleConstraint",
            ConstraintKind::PoleVector => "poleVectorConstraint",
        }
    }

    /// The kind whose node type is `name`.
    pub fn from_type_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.type_name() == name)
    }

    /// `(constraint output, constrained node input)` pairs [`constrain`] connects.
    pub fn outputs(self) -> &'static [(&'static str, &'static str)] {
        match self {
            ConstraintKind::Parent => &[("constraintTranslate", "translate"), ("constraintRotate", "rotate")],
            ConstraintKind::Point => &[("constraintTranslate", "translate")],
            ConstraintKind::Orient | ConstraintKind::Aim => &[("constraintRotate", "rotate")],
            ConstraintKind::Scale => &[("constraintScale", "scale")],
            ConstraintKind::PoleVector => &[("constraintTranslate", "poleVector")],
        }
    }
}

fn matrix(v: Value) -> DMat4 {
    match v {
        Value::Matrix(m) => m,
        _ => DMat4::IDENTITY,
    }
}

fn vec3(v: Value) -> DVec3 {
    match v {
        Value::Vec3(m) => m,
        _ => DVec3::ZERO,
    }
}

/// `node.attr` (or `node.attr[0]` for a multi attribute) when `node` has `attr`.
fn attr_path(graph: &Graph, node: NodeId, attr: &str) -> Option<String> {
    let spec = graph.node_spec(node)?;
    let (id, _) = spec.find(attr)?;
    let name = graph.node_name(node)?;
    Some(if spec.attr(id).multi {
        format!("{name}.{attr}[0]")
    } else {
        format!("{name}.{attr}")
    })
}

/// The whole plug of `node.attr` (element indices are added by the caller),
/// or an `UnknownAttribute` error.
fn plug_of(graph: &Graph, node: NodeId, attr: &str) -> Result<Plug, Error> {
    let spec = graph.node_spec(node).ok_or_else(|| Error::Stale {
        what: "constraint node id".into(),
    })?;
    match spec.find(attr) {
        Some((id, None)) => Ok(Plug::new(node, id)),
        _ => Err(Error::UnknownAttribute {
            node: graph.node_name(node).unwrap_or_default().to_string(),
            node_type: spec.name.clone(),
            attr: attr.to_string(),
            suggestion: None,
        }),
    }
}

/// Stores offsets that keep the constrained node at `child_world` (its
/// current world matrix) given the targets' current world matrices.
///
/// * `parentConstraint`, `pointConstraint`, `orientConstraint`,
///   `scaleConstraint`: for each existing target `i`, reads
///   `targetWorldMatrix[i]` (`T_i`, evaluating it through its connection) and
///   sets `targetOffset[i] = T_i⁻¹ · child_world` (glam column vectors; in
///   Maya's row-vector notation `childWorld · targetWorld⁻¹`), so
///   `T_i · targetOffset[i] = child_world` now and the offset follows the
///   target afterwards. Every target then asks for the node's current world
///   transform, so any weights keep it in place. Translation is matched at
///   the node's origin: exact for nodes whose rotatePivot and
///   rotatePivotTranslate are zero (joints, most controls).
/// * `aimConstraint`: sets `offset` (degrees, xyz) to the rotation between
///   the pure aim and the node's current orientation, `offset = aim⁻¹ ·
///   current` in the node's frame; reads `constraintRotate` with `offset` 0.
/// * `poleVectorConstraint`: has no maintain-offset (a pole vector is a
///   direction, not a transform); returns an error.
///
/// Fails if the node is not a constraint, or a target's world matrix is
/// singular (scaled to 0), leaving offsets already set in place.
pub fn maintain_offset(graph: &mut Graph, constraint: NodeId, child_world: DMat4) -> Result<(), Error> {
    let type_name = graph.node_type(constraint).unwrap_or_default().to_string();
    let name = graph.node_name(constraint).unwrap_or_default().to_string();
    match ConstraintKind::from_type_name(&type_name) {
        None => Err(Error::Program(format!(
            "maintain_offset: {name:?} is a {type_name}, not a constraint node"
        ))),
        Some(ConstraintKind::PoleVector) => Err(Error::Program(format!(
            "maintain_offset: {name:?} is a poleVectorConstraint, which has no maintain-offset; set its offset instead"
        ))),
        Some(ConstraintKind::Aim) => {
            let offset = plug_of(graph, constraint, "offset")?;
            graph.set(offset, Value::Vec3(DVec3::ZERO))?;
            let r = vec3(graph.get(plug_of(graph, constraint, "constraintRotate")?)?);
            let order = match graph.get(plug_of(graph, constraint, "constraintRotateOrder")?)? {
                Value::Enum(i) | Value::Int(i) => RotateOrder::from_index(i).unwrap_or_default(),
                _ => RotateOrder::Xyz,
            };
            let jo = vec3(graph.get(plug_of(graph, constraint, "constraintJointOrient")?)?);
            let ra = vec3(graph.get(plug_of(graph, constraint, "constraintRotateAxis")?)?);
            let pim = matrix(graph.get(plug_of(graph, constraint, "constraintParentInverseMatrix")?)?);
            // the parent-space rotation the pure aim gives: JO * R * RA
            let aim = euler_to_quat(rad(jo), RotateOrder::Xyz)
                * euler_to_quat(rad(r), order)
                * euler_to_quat(rad(ra), RotateOrder::Xyz);
            let (_, cur_world, _) = to_translate_rotate_scale(child_world);
            let current = local_rotation(pim, cur_world);
            let off: DQuat = aim.normalize().conjugate() * current;
            let e = quat_to_euler(off, RotateOrder::Xyz);
            graph.set(offset, Value::Vec3(deg(e)))
        }
        Some(_) => {
            let world = plug_of(graph, constraint, "targetWorldMatrix")?;
            let off = plug_of(graph, constraint, "targetOffset")?;
            for i in graph.elements(constraint, world.attr) {
                let t = matrix(graph.get(world.at(i))?);
                let det = t.determinant();
                let inv = t.inverse();
                if !(det.is_finite() && det != 0.0 && inv.is_finite()) {
                    return Err(Error::Program(format!(
                        "maintain_offset: {name}.targetWorldMatrix[{i}] is singular (a target scaled to 0?)"
                    )));
                }
                let o = inv * child_world;
                if !o.is_finite() {
                    return Err(Error::Program(format!(
                        "maintain_offset: offset of {name}.targetWorldMatrix[{i}] is not finite"
                    )));
                }
                graph.set(off.at(i), Value::Matrix(o))?;
            }
            Ok(())
        }
    }
}

/// Creates a `kind` constraint named `{child}_{typeName}N` on the node
/// `child` with the given target nodes, as Maya's constraint commands do,
/// and returns it.
///
/// Connects `target.worldMatrix → targetWorldMatrix[i]` (weights 1), and
/// from the child, when it has the attribute: `parentInverseMatrix →
/// constraintParentInverseMatrix`; `rotateOrder`, `jointOrient`, `rotateAxis`
/// (parent, orient, aim); `rotatePivot`, `rotatePivotTranslate` (parent,
/// point, aim); `translate → constraintTranslate` (aim);
/// `segmentScaleCompensate`, `inverseScale` (scale). The rest values
/// (`restTranslate`/`restRotate`/`restScale`) are set to the child's current
/// translate/rotate/scale (poleVector: its poleVector), so skipped axes keep
/// their value. With `maintain_offset`, [`maintain_offset`] runs with the
/// child's current `worldMatrix` (poleVector: ignored). Finally the outputs
/// are connected into the child ([`ConstraintKind::outputs`]).
///
/// For `poleVectorConstraint` the child is the IK handle; connect the start
/// joint's `parentMatrix → pivotSpace` and `translate →
/// constraintRotatePivot` yourself (the handle does not name its start
/// joint here).
///
/// On any error the new node is removed again, so the graph is as before.
pub fn constrain(
    graph: &mut Graph,
    kind: ConstraintKind,
    targets: &[&str],
    child: &str,
    maintain_offset: bool,
) -> Result<NodeId, Error> {
    let child_id = graph.node_id(child)?;
    for t in targets {
        graph.node_id(t)?;
    }
    let base = format!("{child}_{}", kind.type_name());
    let name = (1u32..)
        .map(|n| format!("{base}{n}"))
        .find(|n| graph.find_node(n).is_none())
        .unwrap_or(base);
    let c = graph.add_node(kind.type_name(), &name)?;
    match wire(graph, kind, targets, child_id, c, &name, maintain_offset) {
        Ok(()) => Ok(c),
        Err(e) => {
            let _ = graph.remove_node(c);
            Err(e)
        }
    }
}

fn wire(
    graph: &mut Graph,
    kind: ConstraintKind,
    targets: &[&str],
    child: NodeId,
    c: NodeId,
    name: &str,
    maintain: bool,
) -> Result<(), Error> {
    for (i, t) in targets.iter().enumerate() {
        let t_id = graph.node_id(t)?;
        let src = attr_path(graph, t_id, "worldMatrix").ok_or_else(|| {
            Error::Program(format!(
                "constrain: target {t:?} has no worldMatrix; targets must be transform-like nodes"
            ))
        })?;
        graph.connect_path(&src, &format!("{name}.targetWorldMatrix[{i}]"))?;
    }
    use ConstraintKind::*;
    let mut inputs: Vec<(&str, &str)> = vec![("parentInverseMatrix", "constraintParentInverseMatrix")];
    if matches!(kind, Parent | Orient | Aim) {
        inputs.extend([
            ("rotateOrder", "constraintRotateOrder"),
            ("jointOrient", "constraintJointOrient"),
            ("rotateAxis", "constraintRotateAxis"),
        ]);
    }
    if matches!(kind, Parent | Point | Aim) {
        inputs.extend([
            ("rotatePivot", "constraintRotatePivot"),
            ("rotatePivotTranslate", "constraintRotateTranslate"),
        ]);
    }
    if kind == Aim {
        inputs.push(("translate", "constraintTranslate"));
    }
    if kind == Scale {
        inputs.extend([
            ("segmentScaleCompensate", "constraintSegmentScaleCompensate"),
            ("inverseScale", "constraintInverseScale"),
        ]);
    }
    for (src, dst) in inputs {
        if let Some(src) = attr_path(graph, child, src) {
            graph.connect_path(&src, &format!("{name}.{dst}"))?;
        }
    }
    let rests: &[(&str, &str)] = match kind {
        Parent => &[("translate", "restTranslate"), ("rotate", "restRotate")],
        Point => &[("translate", "restTranslate")],
        Orient | Aim => &[("rotate", "restRotate")],
        Scale => &[("scale", "restScale")],
        PoleVector => &[("poleVector", "restTranslate")],
    };
    for (src, dst) in rests {
        if let Some(src) = attr_path(graph, child, src) {
            let v = graph.get_path(&src)?;
            if matches!(v, Value::Vec3(_)) {
                graph.set_path(&format!("{name}.{dst}"), v)?;
            }
        }
    }
    if maintain && kind != PoleVector {
        let wm = attr_path(graph, child, "worldMatrix")
            .ok_or_else(|| Error::Program("constrain: maintain offset needs the child's worldMatrix".to_string()))?;
        let child_world = matrix(graph.get_path(&wm)?);
        maintain_offset(graph, c, child_world)?;
    }
    let child_name = graph.node_name(child).unwrap_or_default().to_string();
    for (out, dst) in kind.outputs() {
        graph.connect_path(&format!("{name}.{out}"), &format!("{child_name}.{dst}"))?;
    }
    Ok(())
}
