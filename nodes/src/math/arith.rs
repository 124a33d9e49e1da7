//! Arithmetic utility nodes: `multiplyDivide`, `plusMinusAverage`, `reverse`, `unitConversion`,
//! `addDoubleLinear`, `multDoubleLinear`.

use glam::DVec3;
use sinew_core::{
    ComputeContext, ComputeError, Input, KernelNode, MultiInput, NodeSpec, NodeType, Output, ScalarOp, SpecError,
};

use super::{finite, finite3, node_type};

/// Maya's `multiplyDivide`: per component, `output = input1 (op) input2`.
///
/// `operation`: `noOperation` (output = input1), `multiply`, `divide`, `power`.
/// Total rules (never NaN or infinity from finite input):
/// - division by zero gives 0 (`x / 0 = 0`, also for `x = 0`);
/// - `power` gives 0 where the real result does not exist (negative base
///   with a fractional exponent) and where it would divide by zero
///   (`0` to a negative power);
/// - results that overflow saturate at `±f64::MAX`.
pub struct MultiplyDivide {
    spec: NodeSpec,
    input1: Input<DVec3>,
    input2: Input<DVec3>,
    operation: Input<i64>,
    output: Output<DVec3>,
}

impl MultiplyDivide {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("multiplyDivide");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[("input1", "i1"), ("input2", "i2"), ("operation", "op"), ("output", "o")]);
        s.doc("output = input1 (noOperation | multiply | divide | power) input2, per component; x/0 = 0");
        let input1 = s.input("input1", DVec3::ZERO);
        let input2 = s.input("input2", DVec3::ONE);
        let operation = s.input_enum("operation", &["noOperation", "multiply", "divide", "power"], 1);
        let output = s.output("output", DVec3::ZERO);
        s.attr_doc(input1, "first operand");
        s.attr_doc(input2, "second operand (divisor, exponent)");
        s.attr_doc(operation, "noOperation, multiply, divide (x/0 = 0) or power (NaN → 0)");
        Ok(MultiplyDivide {
            spec: s.build()?,
            input1,
            input2,
            operation,
            output,
        })
    }
}

/// `a / b` with the division-by-zero rule of [`MultiplyDivide`].
pub fn safe_div(a: f64, b: f64) -> f64 {
    if b == 0.0 {
        0.0
    } else {
        finite(a / b)
    }
}

/// `a` to the power `b` with the rules of [`MultiplyDivide`].
pub fn safe_pow(a: f64, b: f64) -> f64 {
    if a == 0.0 && b < 0.0 {
        return 0.0;
    }
    finite(a.powf(b))
}

impl MultiplyDivide {
    fn run(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let (a, b) = (ctx.get(self.input1), ctx.get(self.input2));
        let f: fn(f64, f64) -> f64 = match ctx.get(self.operation) {
            1 => |x, y| finite(x * y),
            2 => safe_div,
            3 => safe_pow,
            _ => |x, _| finite(x),
        };
        ctx.set(self.output, DVec3::new(f(a.x, b.x), f(a.y, b.y), f(a.z, b.z)));
        Ok(())
    }
}
node_type!(MultiplyDivide);

/// Maya's `plusMinusAverage` over the multis `input1D[]` (floats) and
/// `input3D[]` (vec3, children `input3Dx/y/z` as in Maya).
///
/// `operation`: `noOperation` (the first element), `sum`, `subtract` (the
/// first element minus all the others) or `average`. Elements are taken in
/// logical index order; sparse indices are fine. With no elements the output
/// is 0. `output1D` depends only on `input1D`, `output3D` only on `input3D`.
/// Overflow saturates at `±f64::MAX`.
pub struct PlusMinusAverage {
    spec: NodeSpec,
    operation: Input<i64>,
    input1d: MultiInput<f64>,
    input3d: MultiInput<DVec3>,
    output1d: Output<f64>,
    output3d: Output<DVec3>,
}

impl PlusMinusAverage {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("plusMinusAverage");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[
            ("operation", "op"),
            ("input1D", "i1"),
            ("input3D", "i3"),
            ("output1D", "o1"),
            ("output3D", "o3"),
        ]);
        s.doc("sum, subtract (first minus the rest) or average of input1D[] / input3D[], in index order");
        let operation = s.input_enum("operation", &["noOperation", "sum", "subtract", "average"], 1);
        let input1d = s.multi_input("input1D", 0.0);
        let input3d = s.multi_input("input3D", DVec3::ZERO);
        let output1d = s.output("output1D", 0.0);
        let output3d = s.output("output3D", DVec3::ZERO);
        s.child_suffixes(input3d, ["x", "y", "z"]);
        s.child_suffixes(output3d, ["x", "y", "z"]);
        s.attr_doc(operation, "noOperation (first element), sum, subtract or average");
        s.affects(&[operation.id(), input1d.id()], &[output1d.id()]);
        s.affects(&[operation.id(), input3d.id()], &[output3d.id()]);
        Ok(PlusMinusAverage {
            spec: s.build()?,
            operation,
            input1d,
            input3d,
            output1d,
            output3d,
        })
    }

    fn run(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let op = ctx.get(self.operation);
        if ctx.wants(self.output1d) {
            let n = ctx.multi_len(self.input1d);
            let items = (0..n).filter_map(|k| ctx.multi_at(self.input1d, k).map(|(_, v)| DVec3::splat(v)));
            let r = combine(op, n, items);
            ctx.set(self.output1d, r.x);
        }
        if ctx.wants(self.output3d) {
            let n = ctx.multi_len(self.input3d);
            let items = (0..n).filter_map(|k| ctx.multi_at(self.input3d, k).map(|(_, v)| v));
            let r = combine(op, n, items);
            ctx.set(self.output3d, r);
        }
        Ok(())
    }
}
node_type!(PlusMinusAverage);

/// Combines `n` items (in index order) by the `plusMinusAverage` operation.
fn combine(op: i64, n: usize, items: impl Iterator<Item = DVec3>) -> DVec3 {
    let mut acc = DVec3::ZERO;
    for (k, v) in items.enumerate() {
        acc = match (op, k) {
            (0, 0) => v,
            (0, _) => acc,
            (2, 0) => v,
            (2, _) => acc - v,
            _ => acc + v,
        };
    }
    if op == 3 && n > 0 {
        acc /= n as f64;
    }
    finite3(acc)
}

/// Maya's `reverse`: `output = 1 - input`, per component.
pub struct Reverse {
    spec: NodeSpec,
    input: Input<DVec3>,
    output: Output<DVec3>,
}

impl Reverse {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("reverse");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[("input", "i"), ("output", "o")]);
        s.doc("output = 1 - input, per component");
        let input = s.input("input", DVec3::ZERO);
        let output = s.output("output", DVec3::ONE);
        Ok(Reverse {
            spec: s.build()?,
            input,
            output,
        })
    }

    fn run(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let v = ctx.get(self.input);
        ctx.set(self.output, finite3(DVec3::ONE - v));
        Ok(())
    }
}
node_type!(Reverse);

/// Maya's `unitConversion`: `output = input * conversionFactor`.
///
/// Maya inserts it between plugs of different units (e.g. a degree plug into
/// a unitless one, factor π/180). Overflow saturates at `±f64::MAX`.
///
/// A [`KernelNode`], so compiled programs run it straight over their slots
/// (rigs exported from Maya contain many of these).
pub fn unit_conversion() -> Result<KernelNode, SpecError> {
    let mut s = NodeSpec::builder("unitConversion");
    // Maya's short names (see docs/rig-format.md, "Maya short names").
    s.maya_names(&[("input", "i"), ("conversionFactor", "cf"), ("output", "o")]);
    s.doc("output = input * conversionFactor");
    let input = s.input("input", 0.0);
    let factor = s.input("conversionFactor", 1.0);
    let output = s.output("output", 0.0);
    KernelNode::new(s.build()?, &[input, factor], output, ScalarOp::MulFinite)
}

/// Maya's `addDoubleLinear`: `output = input1 + input2`, overflow saturated at `±f64::MAX`;
/// a [`KernelNode`].
pub fn add_double_linear() -> Result<KernelNode, SpecError> {
    scalar_pair("addDoubleLinear", "output = input1 + input2", ScalarOp::AddFinite)
}

/// Maya's `multDoubleLinear`: `output = input1 · input2`, overflow saturated at `±f64::MAX`;
/// a [`KernelNode`].
pub fn mult_double_linear() -> Result<KernelNode, SpecError> {
    scalar_pair("multDoubleLinear", "output = input1 * input2", ScalarOp::MulFinite)
}

/// A node type `name` with float inputs `input1`, `input2` and `output = op(input1, input2)`.
fn scalar_pair(name: &str, doc: &str, op: ScalarOp) -> Result<KernelNode, SpecError> {
    let mut s = NodeSpec::builder(name);
    // Maya's short names (see docs/rig-format.md, "Maya short names").
    s.maya_names(&[("input1", "i1"), ("input2", "i2"), ("output", "o")]);
    s.doc(doc);
    let input1 = s.input("input1", 0.0);
    let input2 = s.input("input2", 0.0);
    let output = s.output("output", 0.0);
    KernelNode::new(s.build()?, &[input1, input2], output, op)
}
