//! Shared plumbing of the constraint nodes: the target multis, the
//! constrained node's space (parentInverseMatrix, rotate order, jointOrient,
//! pivots), per-axis skip/rest channels and the weighted blends.
//!
//! Everything here is pure: it reads through a [`ComputeContext`] and
//! returns values; the node files decide what to write.

use std::cell::RefCell;

use glam::{DMat3, DMat4, DQuat, DVec3};
use sinew_core::{AttrId, ComputeContext, Input, MultiInput, SpecBuilder, Unit};

use crate::ik::EulerMemo;
use crate::transform::euler::sanitize_quat;
use crate::transform::math::{
    euler_to_quat, is_identity_bits, matrix_rotation_quat, orthonormalize, quat_blend_weighted,
    rotate_for_orientation_quats, slerp_shortest, to_translate_rotate_scale, RotateOrder,
};
use crate::transform::matrix_nodes::inverse_or_identity;

thread_local! {
    /// This thread's memo of the constraints' angle conversions (see [`memo_quat`]).
    static EULER_MEMO: RefCell<EulerMemo> = RefCell::new(EulerMemo::default());
}

/// `euler_to_quat(rad(degrees), order)`, through this thread's [`EulerMemo`].
///
/// A constraint's jointOrient, rotateAxis and offset rarely change from frame to frame; a hit
/// returns the bits the same conversion gave before, so results do not depend on history. (The
/// memo converts with `degrees * (PI / 180)`, which is what `to_radians` computes, bit for bit.)
pub(crate) fn memo_quat(degrees: DVec3, order: RotateOrder) -> DQuat {
    EULER_MEMO.with(|m| match m.try_borrow_mut() {
        Ok(mut m) => m.quat(degrees, order),
        Err(_) => euler_to_quat(rad(degrees), order),
    })
}

/// The `rotate` (degrees, `order`) giving the parent-space rotation `local` to a node with
/// rotateAxis `rotate_axis_deg` and jointOrient `joint_orient_deg` (degrees), the euler triple
/// closest to `near_deg`: `deg(rotate_for_orientation(local, order, rad(rotate_axis_deg),
/// rad(joint_orient_deg), Some(rad(near_deg))))`, with the two constant conversions memoized
/// ([`memo_quat`]).
pub(crate) fn rotate_for_orientation_deg(
    local: DQuat,
    order: RotateOrder,
    rotate_axis_deg: DVec3,
    joint_orient_deg: DVec3,
    near_deg: DVec3,
) -> DVec3 {
    let jo = memo_quat(joint_orient_deg, RotateOrder::Xyz);
    let ra = memo_quat(rotate_axis_deg, RotateOrder::Xyz);
    deg(rotate_for_orientation_quats(local, order, ra, jo, Some(rad(near_deg))))
}

/// Maya's rotate orders, in enum order.
pub const ROTATE_ORDERS: [&str; 6] = ["xyz", "yzx", "zxy", "xzy", "yxz", "zyx"];

/// Maya's `interpType` choices, in enum order (index 1, `average`, is the default).
pub const INTERP_TYPES: [&str; 5] = ["noFlip", "average", "shortest", "longest", "cache"];

/// Degrees to radians, per component.
pub(crate) fn rad(v: DVec3) -> DVec3 {
    DVec3::new(v.x.to_radians(), v.y.to_radians(), v.z.to_radians())
}

/// Radians to degrees, per component.
pub(crate) fn deg(v: DVec3) -> DVec3 {
    DVec3::new(v.x.to_degrees(), v.y.to_degrees(), v.z.to_degrees())
}

/// One target as the constraint sees it: its effective world matrix
/// (`targetWorldMatrix[i] * targetOffset[i]`, glam) and its weight (> 0).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Target {
    /// `targetWorldMatrix[i] * targetOffset[i]` (glam column-vector product).
    pub world: DMat4,
    /// The weight, always positive and finite.
    pub weight: f64,
}

/// The three target multis every constraint has.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Targets {
    pub world: MultiInput<DMat4>,
    pub weight: MultiInput<f64>,
    pub offset: MultiInput<DMat4>,
}

impl Targets {
    /// Declares `targetWorldMatrix`, `targetWeight` and `targetOffset`.
    pub fn declare(b: &mut SpecBuilder) -> Self {
        let world = b.multi_input("targetWorldMatrix", DMat4::IDENTITY);
        b.attr_doc(
            world,
            "target i's world matrix (connect from target.worldMatrix); defines which targets exist",
        );
        let weight = b.multi_input("targetWeight", 1.0);
        b.attr_doc(weight, "weight of target i (default 1; negative counts as 0)");
        let offset = b.multi_input("targetOffset", DMat4::IDENTITY);
        b.attr_doc(
            offset,
            "offset of target i: the constrained node follows targetWorldMatrix[i] * targetOffset[i] (glam)",
        );
        Targets { world, weight, offset }
    }

    /// The attribute ids, for `affects`.
    pub fn ids(&self) -> [AttrId; 3] {
        [self.world.id(), self.weight.id(), self.offset.id()]
    }

    /// The usable targets: every existing `targetWorldMatrix[i]` whose weight
    /// is positive and whose effective matrix is finite.
    ///
    /// An identity `targetOffset[i]` (the default) is not multiplied in.
    pub fn read(&self, ctx: &ComputeContext<'_>) -> SmallList<Target, 4> {
        let n = ctx.multi_len(self.world);
        let mut out = SmallList::new();
        for k in 0..n {
            let Some((i, m)) = ctx.multi_at(self.world, k) else {
                break;
            };
            let w = ctx.get_at(self.weight, i).unwrap_or(1.0);
            if !(w.is_finite() && w > 0.0) {
                continue;
            }
            let world = match ctx.get_at(self.offset, i) {
                Some(o) if !is_identity_bits(&o) => m * o,
                _ => m,
            };
            if world.is_finite() {
                out.push(Target { world, weight: w });
            }
        }
        out
    }
}

/// Sum of the weights, when it is positive and finite.
fn total_weight(ts: &[Target]) -> Option<f64> {
    let total: f64 = ts.iter().map(|t| t.weight).sum();
    (total.is_finite() && total > 0.0).then_some(total)
}

/// Weighted average of the targets' world positions; `None` without weight.
pub(crate) fn weighted_position(ts: &[Target]) -> Option<DVec3> {
    let total = total_weight(ts)?;
    let p = ts.iter().fold(DVec3::ZERO, |acc, t| {
        acc + t.world.w_axis.truncate() * (t.weight / total)
    });
    p.is_finite().then_some(p)
}

/// Weighted average of the targets' world scales (decomposed, shear
/// dropped); `None` without weight.
pub(crate) fn weighted_scale(ts: &[Target]) -> Option<DVec3> {
    let total = total_weight(ts)?;
    let s = ts.iter().fold(DVec3::ZERO, |acc, t| {
        acc + to_translate_rotate_scale(t.world).2 * (t.weight / total)
    });
    s.is_finite().then_some(s)
}

/// Slerp from `a` to `b` along the *longer* arc (Maya's `longest`). When the
/// two are the same rotation the long way is a full turn about no defined
/// axis; then the short way (no motion) is taken.
pub(crate) fn slerp_longest(a: DQuat, b: DQuat, t: f64) -> DQuat {
    let a = sanitize_quat(a);
    let b = sanitize_quat(b);
    let d = a.dot(b);
    // put b in the opposite hemisphere of a: the path through it is the long one
    let (b, d) = if d > 0.0 { (-b, -d) } else { (b, d) };
    if d < -1.0 + 1e-10 {
        return slerp_shortest(a, b, t);
    }
    let theta = d.max(-1.0).acos();
    let s = theta.sin();
    let wa = ((1.0 - t) * theta).sin() / s;
    let wb = (t * theta).sin() / s;
    sanitize_quat(a * wa + b * wb)
}

/// Blends the targets' world orientations by Maya's `interpType` index:
/// `average` (1), `noFlip` (0) and `cache` (4): normalized weighted average in
/// the hemisphere of the first target ([`quat_blend_weighted`]); `shortest` (2)
/// and `longest` (3): successive slerps, `q ← slerp(q, qᵢ, wᵢ / (w₀ + … + wᵢ))`,
/// along the shorter / longer arc. `None` without weight.
pub(crate) fn blend_rotation(ts: &[Target], interp: i64) -> Option<DQuat> {
    total_weight(ts)?;
    let mut items = SmallList::<(DQuat, f64), 4>::new();
    for t in ts {
        items.push((matrix_rotation_quat(&t.world), t.weight));
    }
    let (first, rest) = items.split_first()?;
    let q = match interp {
        2 | 3 => {
            let mut q = first.0;
            let mut acc = first.1;
            for &(qi, wi) in rest {
                acc += wi;
                let f = wi / acc;
                q = if interp == 2 {
                    slerp_shortest(q, qi, f)
                } else {
                    slerp_longest(q, qi, f)
                };
            }
            q
        }
        _ => quat_blend_weighted(&items),
    };
    Some(sanitize_quat(q))
}

/// The rotation, in the constrained node's parent space, whose world
/// orientation is `world`: the rotation part (Gram–Schmidt) of glam
/// `parentInverseMatrix₃ * R(world)`. Exact for parents with rotation and
/// uniform scale; with non-uniform parent scale the child's world axes are
/// sheared anyway and this is the closest-by-Gram–Schmidt rotation.
pub(crate) fn local_rotation(parent_inverse: DMat4, world: DQuat) -> DQuat {
    let m = DMat3::from_mat4(parent_inverse) * DMat3::from_quat(sanitize_quat(world));
    sanitize_quat(DQuat::from_mat3(&orthonormalize(m)))
}

/// The constrained node's rotation inputs: `constraintRotateOrder`,
/// `constraintJointOrient` and `constraintRotateAxis` (degrees).
#[derive(Clone, Copy, Debug)]
pub(crate) struct ChildRotation {
    pub order: Input<i64>,
    pub joint_orient: Input<DVec3>,
    pub rotate_axis: Input<DVec3>,
}

impl ChildRotation {
    /// Declares the three inputs.
    pub fn declare(b: &mut SpecBuilder) -> Self {
        let order = b.input_enum("constraintRotateOrder", &ROTATE_ORDERS, 0);
        b.attr_doc(
            order,
            "rotate order of the constrained node (connect from its rotateOrder)",
        );
        let joint_orient = b.input("constraintJointOrient", DVec3::ZERO);
        b.unit(joint_orient, Unit::Degrees).attr_doc(
            joint_orient,
            "jointOrient of a constrained joint, degrees (leave 0 for transforms)",
        );
        let rotate_axis = b.input("constraintRotateAxis", DVec3::ZERO);
        b.unit(rotate_axis, Unit::Degrees)
            .attr_doc(rotate_axis, "rotateAxis of the constrained node, degrees");
        ChildRotation {
            order,
            joint_orient,
            rotate_axis,
        }
    }

    /// The attribute ids, for `affects`.
    pub fn ids(&self) -> [AttrId; 3] {
        [self.order.id(), self.joint_orient.id(), self.rotate_axis.id()]
    }

    /// The `rotate` value in degrees (constraintRotateOrder) that gives the
    /// node the parent-space rotation `local`, compensating jointOrient and
    /// rotateAxis; of the equivalent euler triples, the one closest to
    /// `near_deg` (the rest rotation).
    pub fn rotate_deg(&self, ctx: &ComputeContext<'_>, local: DQuat, near_deg: DVec3) -> DVec3 {
        let order = RotateOrder::from_index(ctx.get(self.order)).unwrap_or_default();
        rotate_for_orientation_deg(
            local,
            order,
            ctx.get(self.rotate_axis),
            ctx.get(self.joint_orient),
            near_deg,
        )
    }
}

/// The constrained node's `constraintRotatePivot` and
/// `constraintRotateTranslate` (its rotatePivot and rotatePivotTranslate).
#[derive(Clone, Copy, Debug)]
pub(crate) struct ChildPivot {
    pub rotate_pivot: Input<DVec3>,
    pub rotate_translate: Input<DVec3>,
}

impl ChildPivot {
    /// Declares the two inputs.
    pub fn declare(b: &mut SpecBuilder) -> Self {
        let rotate_pivot = b.input("constraintRotatePivot", DVec3::ZERO);
        b.attr_doc(rotate_pivot, "rotatePivot of the constrained node (0 for joints)");
        let rotate_translate = b.input("constraintRotateTranslate", DVec3::ZERO);
        b.attr_doc(
            rotate_translate,
            "rotatePivotTranslate of the constrained node (0 for joints)",
        );
        ChildPivot {
            rotate_pivot,
            rotate_translate,
        }
    }

    /// The attribute ids, for `affects`.
    pub fn ids(&self) -> [AttrId; 2] {
        [self.rotate_pivot.id(), self.rotate_translate.id()]
    }

    /// `rotatePivot + rotatePivotTranslate`: where, in parent space relative
    /// to `translate`, the node's rotate pivot sits.
    pub fn sum(&self, ctx: &ComputeContext<'_>) -> DVec3 {
        ctx.get(self.rotate_pivot) + ctx.get(self.rotate_translate)
    }
}

/// Per-axis skip flags (`skipTranslateX`...) and the rest value
/// (`restTranslate`...) a skipped axis — or every axis, when no target has
/// weight — outputs.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Channel {
    pub skip: [Input<bool>; 3],
    pub rest: Input<DVec3>,
}

impl Channel {
    /// Declares `skip{word}X/Y/Z` and `rest{word}` (default `rest_default`).
    pub fn declare(b: &mut SpecBuilder, word: &str, rest_default: DVec3, unit: Unit) -> Self {
        let skip = ["X", "Y", "Z"].map(|a| {
            let h = b.input(&format!("skip{word}{a}"), false);
            b.attr_doc(h, &format!("when on, {word}{a} outputs rest{word}{a} instead"));
            h
        });
        let rest = b.input(&format!("rest{word}"), rest_default);
        b.unit(rest, unit).attr_doc(
            rest,
            "output for skipped axes, and for all axes when no target has weight",
        );
        Channel { skip, rest }
    }

    /// The attribute ids, for `affects`.
    pub fn ids(&self) -> [AttrId; 4] {
        [self.skip[0].id(), self.skip[1].id(), self.skip[2].id(), self.rest.id()]
    }

    /// The rest value.
    pub fn rest(&self, ctx: &ComputeContext<'_>) -> DVec3 {
        ctx.get(self.rest)
    }

    /// `value` with skipped axes replaced by the rest value; the rest value
    /// itself when `value` is `None` (no weight) or not finite.
    pub fn apply(&self, ctx: &ComputeContext<'_>, value: Option<DVec3>) -> DVec3 {
        let rest = self.rest(ctx);
        match value {
            Some(v) if v.is_finite() => {
                let mut out = v;
                for k in 0..3 {
                    if ctx.get(self.skip[k]) {
                        out[k] = rest[k];
                    }
                }
                out
            }
            _ => rest,
        }
    }
}

/// `euler_to_quat` of an xyz offset in degrees (orient/aim `offset`), memoized ([`memo_quat`]).
pub(crate) fn offset_quat(offset_deg: DVec3) -> DQuat {
    memo_quat(offset_deg, RotateOrder::Xyz)
}

/// Inverse of a parentInverseMatrix (the parent's world matrix), or identity
/// when it is singular or the inverse is not finite ([`inverse_or_identity`]).
pub(crate) fn parent_world(parent_inverse: DMat4) -> DMat4 {
    inverse_or_identity(parent_inverse)
}

/// Collects attribute ids from several groups, for `affects`.
pub(crate) fn ids(parts: &[&[AttrId]]) -> Vec<AttrId> {
    parts.iter().flat_map(|p| p.iter().copied()).collect()
}

/// Declares `constraintParentInverseMatrix`.
pub(crate) fn declare_parent_inverse(b: &mut SpecBuilder) -> Input<DMat4> {
    let h = b.input("constraintParentInverseMatrix", DMat4::IDENTITY);
    b.attr_doc(
        h,
        "inverse of the constrained node's parent world matrix (connect from its parentInverseMatrix)",
    );
    h
}

/// A list that keeps its first `N` items inline (no heap allocation for the usual handful of
/// constraint targets) and moves to a `Vec` beyond that.
#[derive(Clone, Debug)]
pub(crate) enum SmallList<T, const N: usize> {
    /// Up to `N` items, the first `len` of the array.
    Inline([T; N], usize),
    /// More than `N` items.
    Heap(Vec<T>),
}

impl<T: Copy + Default, const N: usize> SmallList<T, N> {
    /// An empty list.
    pub fn new() -> Self {
        SmallList::Inline([T::default(); N], 0)
    }

    /// Appends `item`.
    pub fn push(&mut self, item: T) {
        match self {
            SmallList::Inline(items, len) if *len < N => {
                items[*len] = item;
                *len += 1;
            }
            SmallList::Inline(items, len) => {
                let mut v = Vec::with_capacity(2 * N);
                v.extend_from_slice(&items[..*len]);
                v.push(item);
                *self = SmallList::Heap(v);
            }
            SmallList::Heap(v) => v.push(item),
        }
    }
}

impl<T, const N: usize> std::ops::Deref for SmallList<T, N> {
    type Target = [T];

    fn deref(&self) -> &[T] {
        match self {
            SmallList::Inline(items, len) => items.get(..*len).unwrap_or(&[]),
            SmallList::Heap(v) => v,
        }
    }
}
