//! The `ikRP` node (rotate-plane IK with pole vector and twist) and the goal/stretch inputs it shares with `ikSC`.

use glam::{DMat4, DVec3};
use sinew_core::{ComputeContext, ComputeError, Input, MultiInput, NodeSpec, NodeType, SpecBuilder, SpecError, Unit};

use super::chain::{mat_finite, Chain, IkError, IkSolution};
use super::iterative::IterParams;
use super::node_chain::{ChainInputs, ChainOutputs, ErrorKind, ErrorValue};
use super::node_scratch::{with_node_scratch, Needed, NodeScratch, Solvers};
use super::soft::ReachParams;
use super::two_bone::{solve_plane_into, solve_rotate_plane_into, RpParams, RpWanted};

/// Largest accepted `maxIterations` (bigger values are clamped to it).
pub const MAX_ITERATIONS_CAP: i64 = 100_000;

/// The goal, stretch, soft-IK and iteration inputs of `ikRP` and `ikSC`.
#[derive(Clone, Copy, Debug)]
pub(super) struct GoalInputs {
    pub(super) goal_matrix: Input<DMat4>,
    stretch: Input<bool>,
    max_stretch: Input<f64>,
    soft: Input<f64>,
    tolerance: Input<f64>,
    max_iterations: Input<i64>,
}

/// The goal inputs of one compute.
#[derive(Clone, Copy, Debug)]
pub(super) struct GoalRead {
    /// World-space goal position (translation of `goalMatrix`).
    pub goal: DVec3,
    /// Stretch and soft settings.
    pub reach: ReachParams,
    /// Tolerance and iteration cap (method FABRIK; `ikSC` overrides it).
    pub iter: IterParams,
    /// The first non-finite input, by name.
    pub non_finite: Option<&'static str>,
}

impl GoalInputs {
    /// Declares the goal inputs on `b`.
    pub fn declare(b: &mut SpecBuilder) -> Self {
        let goal_matrix = b.input("goalMatrix", DMat4::IDENTITY);
        b.attr_doc(
            goal_matrix,
            "world matrix whose translation is the goal (connect an IK control's worldMatrix)",
        );
        let stretch = b.input("stretch", false);
        b.attr_doc(stretch, "stretch all bones uniformly so the chain reaches a far goal");
        let max_stretch = b.input("maxStretch", 0.0);
        b.attr_doc(
            max_stretch,
            "cap on the stretch factor; 0 (or less) = no cap, values in (0, 1) count as 1",
        );
        let soft = b.input("soft", 0.0);
        b.attr_doc(
            soft,
            "soft-IK distance: the last `soft` units of reach are eased (no knee pop); 0 = off",
        );
        b.unit(soft, Unit::Distance);
        let tolerance = b.input("tolerance", IterParams::default().tolerance);
        b.attr_doc(
            tolerance,
            "iterative solves stop when the end is this close to the aim point",
        );
        let max_iterations = b.input("maxIterations", i64::from(IterParams::default().max_iterations));
        b.attr_doc(max_iterations, "cap on iterative sweeps (clamped to 0..100000)");
        GoalInputs {
            goal_matrix,
            stretch,
            max_stretch,
            soft,
            tolerance,
            max_iterations,
        }
    }

    /// Reads the goal inputs.
    pub fn read(&self, ctx: &ComputeContext<'_>) -> GoalRead {
        // Only the translation and finiteness of the matrix are used: read it in place.
        let (goal, goal_finite) = ctx.with_ref(self.goal_matrix, |m| (m.w_axis.truncate(), mat_finite(m)));
        let max_stretch = ctx.get(self.max_stretch);
        let soft = ctx.get(self.soft);
        let tolerance = ctx.get(self.tolerance);
        let non_finite = if !goal_finite {
            Some("goalMatrix")
        } else if !max_stretch.is_finite() {
            Some("maxStretch")
        } else if !soft.is_finite() {
            Some("soft")
        } else if !tolerance.is_finite() {
            Some("tolerance")
        } else {
            None
        };
        let iters = ctx.get(self.max_iterations).clamp(0, MAX_ITERATIONS_CAP);
        GoalRead {
            goal,
            reach: ReachParams {
                stretch: ctx.get(self.stretch),
                max_stretch: if max_stretch > 0.0 { max_stretch } else { f64::INFINITY },
                soft: soft.max(0.0),
            },
            iter: IterParams {
                tolerance: tolerance.max(0.0),
                max_iterations: u32::try_from(iters).unwrap_or(0),
                ..IterParams::default()
            },
            non_finite,
        }
    }
}

/// Runs `solve` unless an input is non-finite, then writes the blended pose.
///
/// Shared by `ikRP` and `ikSC`: NaN/inf (which can only arrive through connections)
/// gives the rest pose with status 3 instead of reaching the solver. `ns.read` holds the
/// chain inputs; `solve` writes its solution into the given buffer (the rotations of the
/// joints the [`Needed`] set names are all that is read of them).
pub(super) fn solve_and_write(
    ctx: &mut ComputeContext<'_>,
    outputs: &ChainOutputs,
    ns: &mut NodeScratch,
    goal: &GoalRead,
    extra_non_finite: Option<&'static str>,
    solve: impl FnOnce(&Chain, &mut Solvers, Needed, &mut IkSolution),
) {
    let NodeScratch {
        read,
        chain,
        sol,
        pose,
        solvers,
        euler,
    } = ns;
    let read_bad = read.non_finite();
    read.chain_into(chain, euler, read_bad.is_none());
    let bad = read_bad.or(goal.non_finite).or(extra_non_finite);
    let needed = outputs.rotate_needed(ctx, read);
    match bad {
        Some(name) => *sol = IkSolution::invalid(chain, IkError::NonFinite(name)),
        None => solve(chain, solvers, needed, sol),
    }
    pose.blend_into(read, sol, None, needed);
    outputs.write(ctx, read, pose, ErrorValue::Goal(goal.goal));
}

/// `ikRP`: rotate-plane IK (Maya's ikRPsolver on an ikHandle, as one node).
///
/// Three joints use the exact law-of-cosines two-bone solve; other lengths (2 or more
/// joints) the plane-constrained FABRIK of
/// [`solve_rotate_plane`](super::two_bone::solve_rotate_plane). `poleVector` is a
/// world-space vector from the start joint: the middle joint bends towards the side it
/// points to, in the plane of start joint, goal and `start + poleVector`; `twist`
/// (degrees) turns that plane about the start→goal axis. A zero or collinear pole keeps
/// the chain's rest bend plane (Maya sets the pole from that plane when a handle is
/// created, so the default `poleVector` is zero).
///
/// `ikSpring` ([`IkRp::spring`]) is the same node with Maya's spring solver: chains of 4 or
/// more joints bend by angles proportional to `springAngleBias[i]` (per joint, default 1:
/// evenly distributed) instead of FABRIK (see [`super::spring`]).
pub struct IkRp {
    spec: NodeSpec,
    chain: ChainInputs,
    goal: GoalInputs,
    pole_vector: Input<DVec3>,
    twist: Input<f64>,
    spring_bias: Option<MultiInput<f64>>,
    outputs: ChainOutputs,
}

impl IkRp {
    /// Creates the `ikRP` node type.
    pub fn new() -> Result<Self, SpecError> {
        Self::build("ikRP")
    }

    /// Creates the `ikSpring` node type (Maya's ikSpringSolver on an ikHandle).
    pub fn spring() -> Result<Self, SpecError> {
        Self::build("ikSpring")
    }

    fn build(name: &str) -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder(name);
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        b.maya_names(&[("poleVector", "pv"), ("twist", "twi")]);
        b.doc(if name == "ikSpring" {
            "spring IK: rotate-plane IK whose bends spread over the chain by springAngleBias"
        } else {
            "rotate-plane IK: chain rest data, goal, pole vector and twist in; joint rotations out"
        });
        let chain = ChainInputs::declare(&mut b);
        let goal = GoalInputs::declare(&mut b);
        let pole_vector = b.input("poleVector", DVec3::ZERO);
        b.mirror(pole_vector, sinew_core::MirrorRole::WorldVector);
        b.attr_doc(
            pole_vector,
            "world-space vector from the start joint towards the bend side; zero keeps the rest bend plane",
        );
        let twist = b.input("twist", 0.0);
        b.attr_doc(
            twist,
            "rotation of the bend plane about the start-to-goal axis (degrees)",
        );
        b.unit(twist, Unit::Degrees);
        let spring_bias = (name == "ikSpring").then(|| {
            let h = b.multi_input("springAngleBias", 1.0);
            b.attr_doc(
                h,
                "bend of joint i relative to the others (default 1 = even; 0 = straight; all 0 = even)",
            );
            h
        });
        let outputs = ChainOutputs::declare(&mut b, ErrorKind::EndToGoal);
        Ok(IkRp {
            spec: b.build()?,
            chain,
            goal,
            pole_vector,
            twist,
            spring_bias,
            outputs,
        })
    }
}

impl NodeType for IkRp {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn authoring_fields(&self) -> &[sinew_core::AuthoringField] {
        &crate::authoring::ik::RP_FIELDS
    }

    fn expand(&self, cx: &mut sinew_core::ExpandContext<'_>) {
        crate::authoring::ik::expand(cx, crate::authoring::ik::Solver::RotatePlane)
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        with_node_scratch(|ns| self.compute_with(ctx, ns))
    }
}

impl IkRp {
    /// The compute, with the per-thread buffers.
    fn compute_with(&self, ctx: &mut ComputeContext<'_>, ns: &mut NodeScratch) -> Result<(), ComputeError> {
        self.chain.read_into(ctx, 2, "ikRP", &mut ns.read)?;
        let goal = self.goal.read(ctx);
        let pole = ctx.get(self.pole_vector);
        let twist = ctx.get(self.twist);
        let extra = if !pole.is_finite() {
            Some("poleVector")
        } else if !twist.is_finite() {
            Some("twist")
        } else {
            None
        };
        let rp = RpParams {
            pole_vector: pole,
            twist: twist.to_radians(),
        };
        let spring = self.spring_bias.is_some();
        if let Some(h) = self.spring_bias {
            ctx.multi_read_into(h, &mut ns.solvers.spring_bias);
        }
        // The node's `error` is measured from `endEffector` (another compute group), so the
        // solver skips its own error. Three joints: `solve_two_bone`, which is the
        // rotate-plane solve with default iteration settings.
        solve_and_write(ctx, &self.outputs, ns, &goal, extra, |chain, solvers, needed, out| {
            let iter = if chain.joints.len() == 3 {
                IterParams::default()
            } else {
                goal.iter
            };
            let wanted = RpWanted::Pose(needed);
            let Solvers {
                rp: scratch,
                spring_bias,
                ..
            } = solvers;
            if spring {
                let table = &*spring_bias;
                let bias = |i: usize| match table.binary_search_by_key(&(i as u32), |e| e.0) {
                    Ok(k) => table[k].1,
                    Err(_) => 1.0,
                };
                solve_plane_into(
                    chain,
                    goal.goal,
                    &rp,
                    &goal.reach,
                    &iter,
                    scratch,
                    out,
                    wanted,
                    Some(&bias),
                );
            } else {
                solve_rotate_plane_into(chain, goal.goal, &rp, &goal.reach, &iter, scratch, out, wanted);
            }
        });
        Ok(())
    }
}
