//! The `ikSC` node: single-chain position IK for chains of any length (FABRIK or CCD).

use glam::{DMat4, DQuat};
use sinew_core::{ComputeContext, ComputeError, Input, NodeSpec, NodeType, SpecError};

use super::iterative::{solve_sc, IterMethod};
use super::node_chain::{ChainInputs, ChainOutputs, ErrorKind};
use super::node_scratch::{with_node_scratch, NodeScratch};
use super::nodes_rp::{solve_and_write, GoalInputs};
use super::sc_orient::roll_to_goal_orientation;

/// Choices of the `solver` enum, by index.
pub const SOLVER_CHOICES: [&str; 2] = ["fabrik", "ccd"];

/// `ikSC`: single-chain IK (Maya's ikSCsolver on an ikHandle, position only, as one node).
///
/// The end joint reaches the translation of `goalMatrix`; rotations are minimal-twist
/// deltas from the preferred pose. `solver` picks FABRIK (default) or CCD; both stop at
/// `tolerance` or `maxIterations`. Unreachable goals give a straight chain pointing at
/// the goal (status 1). Needs at least 2 joints.
///
/// `orientToGoal` (off by default) adds Maya's orientation step: after the position solve
/// the chain rolls about the start→end line so that the effector — the end joint's
/// parent's frame times the rotation of `effectorOffset` — turns as close as possible to
/// the rotation of `goalMatrix` (see [`super::sc_orient`]). The Maya importer turns it on
/// for ikSCsolver handles, so rotating the handle rolls the chain as in Maya.
pub struct IkSc {
    spec: NodeSpec,
    chain: ChainInputs,
    goal: GoalInputs,
    solver: Input<i64>,
    orient: Input<bool>,
    effector_offset: Input<DMat4>,
    outputs: ChainOutputs,
}

impl IkSc {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("ikSC");
        b.doc("single-chain IK (FABRIK or CCD): chain rest data and goal in; joint rotations out");
        let chain = ChainInputs::declare(&mut b);
        let goal = GoalInputs::declare(&mut b);
        let solver = b.input_enum("solver", &SOLVER_CHOICES, 0);
        b.attr_doc(
            solver,
            "fabrik (default: fast, no twist drift) or ccd (curls from the tip)",
        );
        let orient = b.input("orientToGoal", false);
        b.attr_doc(
            orient,
            "when on, the chain also rolls about the start-to-end line toward goalMatrix's rotation (Maya's ikSCsolver)",
        );
        let effector_offset = b.input("effectorOffset", DMat4::IDENTITY);
        b.attr_doc(
            effector_offset,
            "the effector's rotation relative to the end joint's parent (orientToGoal; identity by default)",
        );
        let outputs = ChainOutputs::declare(&mut b, ErrorKind::EndToGoal);
        Ok(IkSc {
            spec: b.build()?,
            chain,
            goal,
            solver,
            orient,
            effector_offset,
            outputs,
        })
    }
}

impl NodeType for IkSc {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn authoring_fields(&self) -> &[sinew_core::AuthoringField] {
        &crate::authoring::ik::SC_FIELDS
    }

    fn expand(&self, cx: &mut sinew_core::ExpandContext<'_>) {
        crate::authoring::ik::expand(cx, crate::authoring::ik::Solver::SingleChain)
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        with_node_scratch(|ns| self.compute_with(ctx, ns))
    }
}

impl IkSc {
    /// The compute, with the per-thread buffers.
    fn compute_with(&self, ctx: &mut ComputeContext<'_>, ns: &mut NodeScratch) -> Result<(), ComputeError> {
        self.chain.read_into(ctx, 2, "ikSC", &mut ns.read)?;
        let mut goal = self.goal.read(ctx);
        goal.iter.method = match ctx.get(self.solver) {
            0 => IterMethod::Fabrik,
            1 => IterMethod::Ccd,
            other => {
                return Err(ComputeError::new(format!(
                    "solver is {other}; use 0 (fabrik) or 1 (ccd)"
                )))
            }
        };
        let orient = ctx.get(self.orient).then(|| {
            let offset = ctx.with_ref(self.effector_offset, |m| {
                let (_, r, _) = m.to_scale_rotation_translation();
                r
            });
            (ctx.with_ref(self.goal.goal_matrix, |m| *m), offset)
        });
        solve_and_write(ctx, &self.outputs, ns, &goal, None, |chain, _, _, out| {
            *out = solve_sc(chain, goal.goal, &goal.iter, &goal.reach);
            if let Some((goal_matrix, offset)) = orient {
                let offset: DQuat = if offset.is_finite() { offset } else { DQuat::IDENTITY };
                roll_to_goal_orientation(chain, out, &goal_matrix, offset);
            }
        });
        Ok(())
    }
}
