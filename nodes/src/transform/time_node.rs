//! The `time` node plugin: the graph's current time as plugs, the source
//! that animation curves and other time-driven nodes connect from.

use sinew_core::{ComputeContext, ComputeError, NodeSpec, NodeType, Output, SpecError, Unit};

/// Maya's `time` node: `outTime` is the current frame (may be fractional)
/// and `outSeconds` the same time in seconds (`frame / fps`; 0 when the
/// frame rate is not positive). Time-dependent; no inputs.
pub struct TimeNode {
    spec: NodeSpec,
    out_time: Output<f64>,
    out_seconds: Output<f64>,
}

impl TimeNode {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("time");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[("outTime", "o")]);
        s.doc("the current time: outTime in frames, outSeconds in seconds");
        s.time_dependent();
        let out_time = s.output("outTime", 0.0);
        s.unit(out_time, Unit::Frames).attr_doc(out_time, "current frame");
        let out_seconds = s.output("outSeconds", 0.0);
        s.attr_doc(out_seconds, "current time in seconds (frame / fps)");
        Ok(TimeNode {
            spec: s.build()?,
            out_time,
            out_seconds,
        })
    }
}

impl NodeType for TimeNode {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let t = ctx.time();
        ctx.set(self.out_time, t.frame);
        ctx.set(self.out_seconds, t.seconds());
        Ok(())
    }
}
