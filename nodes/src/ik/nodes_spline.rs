//! The `ikSpline` node: a joint chain laid along a curve, with offset, roll, twist and stretch.

use std::sync::Arc;

use sinew_core::{
    ComputeContext, ComputeError, Curve, Input, NodeSpec, NodeType, Problem, SpecError, Unit, ValidateInputs,
};

use super::chain::{IkError, IkSolution};
use super::node_chain::{ChainInputs, ChainOutputs, ErrorKind, ErrorValue};
use super::node_scratch::{with_node_scratch, NodeScratch};
use super::spline::{solve_spline_into, SplineParams};

/// `ikSpline`: spline IK (Maya's ikSplineSolver on a spline ikHandle, as one node).
///
/// `curve` is in world space (connect a `curveFromPoints.outCurve`, or any curve
/// output). The start joint sits at `offset` (0..1, a fraction of the curve's arc
/// length, as Maya's ikHandle.offset; periodic curves wrap) and each next joint at its
/// rest bone length (chord) further along the curve; joints past the end of an open
/// curve continue along its end tangent (status 1, `error` = the overrun). With
/// `stretch` the chain spans the curve from the offset to its end (capped by
/// `maxStretch`, 0 = no cap), and `outTranslate`/`outStretch` carry the stretch. `roll`
/// spins the whole chain about the start bone, `twist` is spread linearly to the end
/// joint (both degrees). With `rootOnCurve` (default, as in Maya) `outTranslate[0]` is
/// the start joint's translate on the curve; without it the curve is used as if moved
/// rigidly onto the start joint. An empty or invalid curve gives the rest pose with
/// status 3 (the message says what is wrong with the curve).
pub struct IkSpline {
    spec: NodeSpec,
    chain: ChainInputs,
    curve: Input<Arc<Curve>>,
    offset: Input<f64>,
    roll: Input<f64>,
    twist: Input<f64>,
    stretch: Input<bool>,
    max_stretch: Input<f64>,
    root_on_curve: Input<bool>,
    outputs: ChainOutputs,
}

impl IkSpline {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("ikSpline");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        b.maya_names(&[("twist", "twi")]);
        b.doc("spline IK: chain rest data and a world-space curve in; joint rotations and translates out");
        let chain = ChainInputs::declare(&mut b);
        let curve = b.input("curve", Arc::new(Curve::default()));
        b.attr_doc(
            curve,
            "world-space curve the chain follows (e.g. curveFromPoints.outCurve)",
        );
        let offset = b.input("offset", 0.0);
        b.attr_doc(
            offset,
            "where the start joint sits, as a fraction (0..1) of the curve's length",
        );
        let roll = b.input("roll", 0.0);
        b.attr_doc(roll, "rotation of the whole chain about the start bone (degrees)");
        b.unit(roll, Unit::Degrees);
        let twist = b.input("twist", 0.0);
        b.attr_doc(
            twist,
            "twist added linearly from the start (0) to the end joint (degrees)",
        );
        b.unit(twist, Unit::Degrees);
        let stretch = b.input("stretch", false);
        b.attr_doc(
            stretch,
            "stretch or squash the bones so the chain spans the curve to its end",
        );
        let max_stretch = b.input("maxStretch", 0.0);
        b.attr_doc(max_stretch, "cap on the stretch factor; 0 (or less) = no cap");
        let root_on_curve = b.input("rootOnCurve", true);
        b.attr_doc(
            root_on_curve,
            "move the start joint onto the curve (outTranslate[0]); off: the curve moves to the joint",
        );
        let outputs = ChainOutputs::declare(&mut b, ErrorKind::FromSolve);
        Ok(IkSpline {
            spec: b.build()?,
            chain,
            curve,
            offset,
            roll,
            twist,
            stretch,
            max_stretch,
            root_on_curve,
            outputs,
        })
    }
}

impl NodeType for IkSpline {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    /// A known, non-empty curve must be a valid B-spline (knot count for its degree and
    /// points, non-decreasing knots): an invalid one would leave the chain at rest.
    fn validate(&self, inputs: &ValidateInputs<'_>) -> Vec<Problem> {
        match inputs.get(self.curve) {
            Some(c) if !c.points.is_empty() => match super::curve::BSpline::new(&c) {
                Ok(_) => Vec::new(),
                Err(e) => vec![Problem::new(self.curve, e).hint(
                    "knots: points + degree + 1 values (or Maya's points + degree - 1), non-decreasing; or none for uniform",
                )],
            },
            _ => Vec::new(),
        }
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        with_node_scratch(|ns| self.compute_with(ctx, ns))
    }
}

impl IkSpline {
    /// The compute, with the per-thread buffers.
    fn compute_with(&self, ctx: &mut ComputeContext<'_>, ns: &mut NodeScratch) -> Result<(), ComputeError> {
        let NodeScratch {
            read,
            chain,
            sol,
            pose,
            solvers,
            euler,
        } = ns;
        self.chain.read_into(ctx, 2, "ikSpline", read)?;
        let curve = ctx.get(self.curve);
        let offset = ctx.get(self.offset);
        let roll = ctx.get(self.roll);
        let twist = ctx.get(self.twist);
        let max_stretch = ctx.get(self.max_stretch);
        let read_bad = read.non_finite();
        read.chain_into(chain, euler, read_bad.is_none());
        let bad = read_bad.or_else(|| {
            [
                (offset, "offset"),
                (roll, "roll"),
                (twist, "twist"),
                (max_stretch, "maxStretch"),
            ]
            .iter()
            .find(|(v, _)| !v.is_finite())
            .map(|(_, name)| *name)
        });
        let root = match bad {
            Some(name) => {
                *sol = IkSolution::invalid(chain, IkError::NonFinite(name));
                None
            }
            None => {
                let mut params = SplineParams {
                    offset: 0.0,
                    roll: roll.to_radians(),
                    twist: twist.to_radians(),
                    stretch: ctx.get(self.stretch),
                    max_stretch: if max_stretch > 0.0 { max_stretch } else { f64::INFINITY },
                    root_on_curve: ctx.get(self.root_on_curve),
                };
                // The curve's length is needed (and summed) only to turn a non-zero offset into
                // an arc length.
                let want_length = offset != 0.0;
                let (mut root, length) =
                    solve_spline_into(chain, &curve, &params, &mut solvers.spline, sol, want_length);
                if want_length && !sol.is_invalid() {
                    params.offset = offset * length;
                    (root, _) = solve_spline_into(chain, &curve, &params, &mut solvers.spline, sol, false);
                }
                Some(root)
            }
        };
        let needed = self.outputs.rotate_needed(ctx, read);
        pose.blend_into(read, sol, root, needed);
        self.outputs.write(ctx, read, pose, ErrorValue::Value(sol.error));
        Ok(())
    }
}
