//! `geometryConstraint`, `normalConstraint` and `tangentConstraint`: the constrained node
//! sticks to, or turns with the normal or tangent of, the closest point of target geometry.

use glam::{DMat3, DMat4, DVec3};
use sinew_core::{ComputeContext, ComputeError, Input, NodeSpec, NodeType, Output, SpecBuilder, SpecError, Unit};

use super::common::{declare_parent_inverse, ids, parent_world, Channel, ChildPivot, ChildRotation};
use super::geometry_targets::{weighted, GeometryTargets, Hit, Kinds};
use super::orient::{world_up, WORLD_UP_TYPES};
use super::rotation_path::local_rotation_mat3;
use crate::transform::orient::aim_matrix;

/// `geometryConstraint`: moves the constrained node's rotate pivot onto the closest point of
/// its targets (meshes, NURBS surfaces, curves; see `geometry_targets`).
///
/// Maya's node writes `constraintGeometry` into the transform's hidden `geometry` plug and the
/// transform projects its own position; sinew has no such plug, so the node takes the
/// unconstrained position and writes a translate: `restTranslate` is the node's translate
/// before the constraint (author it, or connect a `pointConstraint`'s `constraintTranslate`;
/// not the node's own translate, which would be a cycle). Its world position
/// `p = P · (restTranslate + constraintRotatePivot + constraintRotateTranslate)` (`P` the
/// inverse of `constraintParentInverseMatrix`) is projected onto each target; the weighted
/// average `c` of the closest points is written back as `constraintTranslate = PI · c −
/// pivots`. No target with positive weight: `restTranslate`.
pub struct GeometryConstraint {
    spec: NodeSpec,
    targets: GeometryTargets,
    parent_inverse: Input<DMat4>,
    pivot: ChildPivot,
    translate: Channel,
    out_translate: Output<DVec3>,
}

impl GeometryConstraint {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("geometryConstraint");
        b.maya_names(&[
            ("targetWeight", "tw"),
            ("constraintParentInverseMatrix", "cpim"),
            ("constraintRotatePivot", "crp"),
            ("constraintRotateTranslate", "crt"),
            ("restTranslate", "rst"),
            ("constraintTranslate", "ct"),
        ]);
        b.doc("move the constrained node onto the closest point of its target geometry");
        let all = Kinds {
            mesh: true,
            surface: true,
            curve: true,
        };
        let targets = GeometryTargets::declare(&mut b, all);
        let parent_inverse = declare_parent_inverse(&mut b);
        let pivot = ChildPivot::declare(&mut b);
        let translate = Channel::declare(&mut b, "Translate", DVec3::ZERO, Unit::Distance);
        b.attr_doc(
            translate.rest,
            "the unconstrained translate (projected onto the targets)",
        );
        let out_translate = b.output("constraintTranslate", DVec3::ZERO);
        b.attr_doc(out_translate, "connect to the constrained node's translate");
        b.affects(
            &ids(&[
                &targets.query_ids(),
                &[parent_inverse.id()],
                &pivot.ids(),
                &translate.ids(),
            ]),
            &[out_translate.id()],
        );
        Ok(GeometryConstraint {
            spec: b.build()?,
            targets,
            parent_inverse,
            pivot,
            translate,
            out_translate,
        })
    }
}

impl NodeType for GeometryConstraint {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if self.targets.compute(ctx, "geometryConstraint")? {
            return Ok(());
        }
        let pim = ctx.get(self.parent_inverse);
        let pivots = self.pivot.sum(ctx);
        let p = parent_world(pim).transform_point3(self.translate.rest(ctx) + pivots);
        let hits = self.targets.closest(ctx, p);
        let t = weighted(&hits, |h| h.position).map(|c| pim.transform_point3(c) - pivots);
        let t = self.translate.apply(ctx, t);
        ctx.set(self.out_translate, t);
        Ok(())
    }
}

/// What an [`AimAtGeometry`] aims along.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Along {
    Normal,
    Tangent,
}

/// `normalConstraint` and `tangentConstraint`: turn the constrained node so its `aimVector`
/// follows the surface normal (meshes, NURBS surfaces) or the curve tangent at the closest
/// point of the targets to the node's rotate pivot.
///
/// As `aimConstraint` (which these share their attributes with): the query point is the
/// world position of `constraintTranslate + constraintRotatePivot +
/// constraintRotateTranslate` (connect the node's translate to `constraintTranslate`, an
/// input here); the direction is the weighted average of the targets' unit normals
/// (tangents); `upVector` follows the world up of `worldUpType` (`scene` +Y, `object`
/// towards `worldUpMatrix`'s translation, `objectRotation` `worldUpVector` turned by
/// `worldUpMatrix`, `vector` `worldUpVector`, `none` no twist); the result is written back
/// through `constraintParentInverseMatrix` as `constraintRotate` (degrees,
/// `constraintRotateOrder`, compensating jointOrient and rotateAxis). A zero average
/// direction (opposite normals) leaves the aim axis where it is; no target with positive
/// weight: `restRotate`.
pub struct AimAtGeometry {
    spec: NodeSpec,
    along: Along,
    targets: GeometryTargets,
    parent_inverse: Input<DMat4>,
    rotation: ChildRotation,
    pivot: ChildPivot,
    translate: Input<DVec3>,
    aim_vector: Input<DVec3>,
    up_vector: Input<DVec3>,
    world_up_type: Input<i64>,
    world_up_vector: Input<DVec3>,
    world_up_matrix: Input<DMat4>,
    rotate: Channel,
    out_rotate: Output<DVec3>,
}

fn declare_vec(
    b: &mut SpecBuilder,
    name: &str,
    default: DVec3,
    role: sinew_core::MirrorRole,
    doc: &str,
) -> Input<DVec3> {
    let h = b.input(name, default);
    b.mirror(h, role).attr_doc(h, doc);
    h
}

impl AimAtGeometry {
    fn new(along: Along) -> Result<Self, SpecError> {
        let name = match along {
            Along::Normal => "normalConstraint",
            Along::Tangent => "tangentConstraint",
        };
        let mut b = NodeSpec::builder(name);
        b.maya_names(super::orient::AIM_FAMILY_MAYA_NAMES);
        b.doc(match along {
            Along::Normal => {
                "turn the constrained node's aimVector along the normal of the closest target surface point"
            }
            Along::Tangent => {
                "turn the constrained node's aimVector along the tangent of the closest target curve point"
            }
        });
        let kinds = match along {
            Along::Normal => Kinds {
                mesh: true,
                surface: true,
                curve: false,
            },
            Along::Tangent => Kinds {
                mesh: false,
                surface: false,
                curve: true,
            },
        };
        let targets = GeometryTargets::declare(&mut b, kinds);
        let parent_inverse = declare_parent_inverse(&mut b);
        let rotation = ChildRotation::declare(&mut b);
        let pivot = ChildPivot::declare(&mut b);
        let translate = b.input("constraintTranslate", DVec3::ZERO);
        b.attr_doc(
            translate,
            "translate of the constrained node (connect from it): the query point",
        );
        use sinew_core::MirrorRole::{LocalVector, WorldVector};
        let aim_vector = declare_vec(
            &mut b,
            "aimVector",
            DVec3::X,
            LocalVector,
            "local axis along the normal or tangent",
        );
        let up_vector = declare_vec(
            &mut b,
            "upVector",
            DVec3::Y,
            LocalVector,
            "local axis towards the world up",
        );
        let world_up_type = b.input_enum("worldUpType", &WORLD_UP_TYPES, 3);
        b.attr_doc(world_up_type, "what the up vector follows (as aimConstraint)");
        let world_up_vector = declare_vec(&mut b, "worldUpVector", DVec3::Y, WorldVector, "world up direction");
        let world_up_matrix = b.input("worldUpMatrix", DMat4::IDENTITY);
        b.attr_doc(
            world_up_matrix,
            "world matrix of the up object (object, objectRotation)",
        );
        let rotate = Channel::declare(&mut b, "Rotate", DVec3::ZERO, Unit::Degrees);
        let out_rotate = b.output("constraintRotate", DVec3::ZERO);
        b.unit(out_rotate, Unit::Degrees)
            .attr_doc(out_rotate, "connect to the constrained node's rotate (degrees)");
        let geometry = targets.geometry_ids();
        let query: Vec<_> = b
            .input_ids()
            .into_iter()
            .filter(|id| !geometry.contains(id))
            .chain([targets.cache.id()])
            .collect();
        b.affects(&query, &[out_rotate.id()]);
        Ok(AimAtGeometry {
            spec: b.build()?,
            along,
            targets,
            parent_inverse,
            rotation,
            pivot,
            translate,
            aim_vector,
            up_vector,
            world_up_type,
            world_up_vector,
            world_up_matrix,
            rotate,
            out_rotate,
        })
    }

    /// `normalConstraint`.
    pub fn normal() -> Result<Self, SpecError> {
        Self::new(Along::Normal)
    }

    /// `tangentConstraint`.
    pub fn tangent() -> Result<Self, SpecError> {
        Self::new(Along::Tangent)
    }

    /// The world rotation aiming along `dir` from `from`.
    fn aim(&self, ctx: &ComputeContext<'_>, from: DVec3, dir: DVec3) -> DMat3 {
        let aim = ctx.get(self.aim_vector);
        let up = ctx.get(self.up_vector);
        let world_up = world_up(
            ctx.get(self.world_up_type),
            from,
            ctx.get(self.world_up_vector),
            ctx.get(self.world_up_matrix),
        );
        aim_matrix(DVec3::ZERO, dir, aim, up, world_up)
    }
}

impl NodeType for AimAtGeometry {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if self.targets.compute(ctx, self.spec.name.as_str())? {
            return Ok(());
        }
        let pim = ctx.get(self.parent_inverse);
        let from = parent_world(pim).transform_point3(ctx.get(self.translate) + self.pivot.sum(ctx));
        let hits = self.targets.closest(ctx, from);
        let dir = match self.along {
            Along::Normal => weighted(&hits, |h: &Hit| h.normal),
            Along::Tangent => weighted(&hits, |h: &Hit| h.tangent),
        };
        let rest = self.rotate.rest(ctx);
        let r = dir.map(|d| {
            let world = self.aim(ctx, from, d);
            self.rotation
                .rotate_deg_mat3(ctx, &local_rotation_mat3(&pim, world, DVec3::ZERO), rest)
        });
        let r = self.rotate.apply(ctx, r);
        ctx.set(self.out_rotate, r);
        Ok(())
    }
}
