//! Scalar kernels: an opt-in fast path for trivial float nodes. A node type
//! whose compute is "one float output = a pure function of up to four float
//! inputs" can describe itself as a [`ScalarKernel`]; a compiled
//! [`Program`](crate::Program) then runs the kernel straight over its value
//! slots, without building a [`ComputeContext`] or calling `compute`.
//!
//! The kernel is also the node's compute ([`ScalarKernel::compute`]), so the
//! lazy graph and the compiled program run the same arithmetic and stay
//! bit-identical.

use crate::error::{ComputeError, SpecError};
use crate::node::{ComputeContext, NodeType};
use crate::program::{AttrBinding, Binding};
use crate::slots::Slots;
use crate::spec::{AttrId, Direction, Input, NodeSpec, Output};
use crate::value::AttrType;

/// Most inputs a [`ScalarKernel`] may read.
pub const MAX_KERNEL_INPUTS: usize = 4;

/// The arithmetic of a [`ScalarKernel`], applied to its inputs in order.
#[derive(Clone, Copy, Debug)]
pub enum ScalarOp {
    /// `x[0] + x[1]`.
    Add,
    /// `x[0] - x[1]`.
    Sub,
    /// `x[0] * x[1]`.
    Mul,
    /// `finite(x[0] + x[1])` ([`finite`]: Maya's `addDoubleLinear` saturates).
    AddFinite,
    /// `finite(x[0] * x[1])` ([`finite`]: `multDoubleLinear`, `unitConversion`).
    MulFinite,
    /// Any pure, total function of the inputs (`x.len()` is the kernel's input count).
    Custom(fn(&[f64]) -> f64),
}

/// The two-input operations of [`ScalarOp`]: their arithmetic, defined once for
/// `compute`, compiled kernels and tapes ([`crate::tape`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Arith {
    /// `a + b`
    Add,
    /// `a - b`
    Sub,
    /// `a * b`
    Mul,
    /// `finite(a + b)`
    AddFinite,
    /// `finite(a * b)`
    MulFinite,
}

impl Arith {
    /// The operation on `a` and `b`.
    #[inline(always)]
    pub(crate) fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            Arith::Add => a + b,
            Arith::Sub => a - b,
            Arith::Mul => a * b,
            Arith::AddFinite => finite(a + b),
            Arith::MulFinite => finite(a * b),
        }
    }
}

impl ScalarOp {
    /// The two-input operation this is (`None` for [`ScalarOp::Custom`]).
    fn arith(self) -> Option<Arith> {
        match self {
            ScalarOp::Add => Some(Arith::Add),
            ScalarOp::Sub => Some(Arith::Sub),
            ScalarOp::Mul => Some(Arith::Mul),
            ScalarOp::AddFinite => Some(Arith::AddFinite),
            ScalarOp::MulFinite => Some(Arith::MulFinite),
            ScalarOp::Custom(_) => None,
        }
    }

    /// Applies the operation to the first `n` values of `x`.
    #[inline(always)]
    fn eval(self, x: &[f64; MAX_KERNEL_INPUTS], n: usize) -> f64 {
        match (self, self.arith()) {
            (ScalarOp::Custom(f), _) => f(&x[..n.min(MAX_KERNEL_INPUTS)]),
            (_, Some(arith)) => arith.apply(x[0], x[1]),
            (_, None) => 0.0, // only `Custom` has no `Arith`
        }
    }

    /// How many inputs the operation needs (`None`: any count from 1 to [`MAX_KERNEL_INPUTS`]).
    fn arity(self) -> Option<usize> {
        self.arith().map(|_| 2)
    }
}

/// A node's whole compute as `output = op(inputs...)` over floats.
///
/// Return it from [`NodeType::scalar_kernel`]
/// and implement `compute` as [`ScalarKernel::compute`]. The node must have a
/// single compute group (all inputs affect the output); when it does not, or
/// when a handle does not belong to the node's spec, the compiled program
/// ignores the kernel and calls `compute` as usual.
#[derive(Clone, Copy, Debug)]
pub struct ScalarKernel {
    inputs: [Input<f64>; MAX_KERNEL_INPUTS],
    len: u8,
    output: Output<f64>,
    op: ScalarOp,
}

impl ScalarKernel {
    /// A kernel computing `output = op(inputs...)` for the node type with
    /// `spec`. Fails when there are no inputs, more than
    /// [`MAX_KERNEL_INPUTS`] or not the count `op` needs, when the spec has
    /// more than one compute group, or when a handle is not a single float
    /// attribute of `spec` with the right direction.
    pub fn new(spec: &NodeSpec, inputs: &[Input<f64>], output: Output<f64>, op: ScalarOp) -> Result<Self, SpecError> {
        let fail = |message: String| SpecError {
            node_type: spec.name.clone(),
            message,
        };
        let count_ok = match op.arity() {
            Some(n) => inputs.len() == n,
            None => (1..=MAX_KERNEL_INPUTS).contains(&inputs.len()),
        };
        if !count_ok {
            return Err(fail(format!(
                "a scalar kernel ({op:?}) cannot take {} inputs",
                inputs.len()
            )));
        }
        if spec.groups().len() != 1 {
            return Err(fail("a scalar kernel needs a node with one compute group".into()));
        }
        let check = |id: AttrId, dir: Direction| match spec.attrs.get(id.index()) {
            Some(a) if a.ty == AttrType::Float && !a.multi && a.direction == dir => Ok(()),
            Some(a) => Err(fail(format!(
                "scalar kernel attribute `{}` is not a single float {}",
                a.name,
                if dir == Direction::Input { "input" } else { "output" }
            ))),
            None => Err(fail(format!(
                "scalar kernel attribute {} is not in the spec",
                id.index()
            ))),
        };
        check(output.id(), Direction::Output)?;
        for h in inputs {
            check(h.id(), Direction::Input)?;
        }
        let mut all = [Input::new(output.id()); MAX_KERNEL_INPUTS];
        all[..inputs.len()].copy_from_slice(inputs);
        Ok(ScalarKernel {
            inputs: all,
            len: inputs.len() as u8,
            output,
            op,
        })
    }

    /// Applies the operation to `x` (one value per input, in order), as both
    /// evaluation modes do.
    pub fn apply(&self, x: &[f64]) -> f64 {
        let mut a = [0.0; MAX_KERNEL_INPUTS];
        for (d, s) in a.iter_mut().zip(x) {
            *d = *s;
        }
        self.op.eval(&a, self.len as usize)
    }

    /// The inputs, in the order `op` receives them.
    pub fn inputs(&self) -> &[Input<f64>] {
        &self.inputs[..self.len as usize]
    }

    /// The output written.
    pub fn output(&self) -> Output<f64> {
        self.output
    }

    /// The operation.
    pub fn op(&self) -> ScalarOp {
        self.op
    }

    /// The node's compute: reads the inputs through `ctx`, applies the
    /// operation and writes the output. Never fails.
    pub fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let [i0, i1, ..] = self.inputs;
        let r = match self.op {
            ScalarOp::Add => ctx.get(i0) + ctx.get(i1),
            ScalarOp::Sub => ctx.get(i0) - ctx.get(i1),
            ScalarOp::Mul => ctx.get(i0) * ctx.get(i1),
            ScalarOp::AddFinite => finite(ctx.get(i0) + ctx.get(i1)),
            ScalarOp::MulFinite => finite(ctx.get(i0) * ctx.get(i1)),
            ScalarOp::Custom(_) => {
                let mut x = [0.0; MAX_KERNEL_INPUTS];
                for (v, &h) in x.iter_mut().zip(self.inputs()) {
                    *v = ctx.get(h);
                }
                self.op.eval(&x, self.len as usize)
            }
        };
        ctx.set(self.output, r);
        Ok(())
    }
}

/// Where a compiled kernel reads one input.
#[derive(Clone, Copy, Debug)]
pub(crate) struct KernelInput {
    slot: u32,
    /// `0..3`: that component of a vec3 slot; [`WHOLE`]: the whole (float) slot.
    lane: u8,
}

/// The `lane` of a kernel input that reads a whole float slot.
const WHOLE: u8 = u8::MAX;

/// How a compiled kernel runs: the common shapes get their own straight-line code.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Code {
    /// A two-input operation on two whole float slots.
    Whole(Arith),
    /// Anything else: inputs read by lane, then `op`.
    General,
}

/// A node type whose whole compute is one [`ScalarKernel`]: the spec plus the kernel, with
/// `compute` implemented as [`ScalarKernel::compute`]. Build the spec as usual and register
/// `KernelNode::new(spec, inputs, output, op)?` instead of writing a type per node.
#[derive(Debug)]
pub struct KernelNode {
    spec: NodeSpec,
    kernel: ScalarKernel,
}

impl KernelNode {
    /// The node type of `spec` computing `output = op(inputs...)`; fails as
    /// [`ScalarKernel::new`] does.
    pub fn new(spec: NodeSpec, inputs: &[Input<f64>], output: Output<f64>, op: ScalarOp) -> Result<Self, SpecError> {
        let kernel = ScalarKernel::new(&spec, inputs, output, op)?;
        Ok(KernelNode { spec, kernel })
    }
}

impl NodeType for KernelNode {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }
    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        self.kernel.compute(ctx)
    }
    fn scalar_kernel(&self) -> Option<&ScalarKernel> {
        Some(&self.kernel)
    }
}

/// `x` made finite: NaN becomes 0, infinities saturate at `±f64::MAX` (the convention of
/// the utility nodes, after Maya's saturating `addDoubleLinear`/`multDoubleLinear`).
#[inline]
#[allow(clippy::eq_op)]
pub fn finite(x: f64) -> f64 {
    // A finite `x` passes through untouched behind a predictable branch, so the value
    // itself takes no extra latency (chains of utility nodes are latency-bound).
    // `x - x` is 0 when `x` is finite and NaN for NaN and the infinities: one float
    // compare, where `is_finite` becomes integer masking.
    let d = x - x;
    if d == d {
        x
    } else {
        non_finite(x)
    }
}

/// [`finite`] for NaN and the infinities (out of line: rare).
#[cold]
#[inline(never)]
fn non_finite(x: f64) -> f64 {
    if x.is_nan() {
        0.0
    } else {
        x.clamp(-f64::MAX, f64::MAX)
    }
}

/// A scalar kernel bound to the slots of one compiled step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct KernelStep {
    code: Code,
    op: ScalarOp,
    inputs: [KernelInput; MAX_KERNEL_INPUTS],
    len: u8,
    output: u32,
}

impl KernelStep {
    /// Binds `kernel` to a step of a node with `spec` whose attribute
    /// bindings are `attrs`. `None` (the step calls `compute`) unless the node
    /// has one compute group and every handle is a single float attribute of
    /// the right direction bound to a slot or a vec3 component.
    pub(crate) fn bind(kernel: &ScalarKernel, spec: &NodeSpec, attrs: &[AttrBinding]) -> Option<KernelStep> {
        if spec.groups().len() != 1 {
            return None;
        }
        let single = |id: AttrId, dir: Direction| -> Option<AttrBinding> {
            let a = spec.attrs.get(id.index())?;
            let b = attrs.get(id.index())?;
            (a.ty == AttrType::Float && !a.multi && a.direction == dir && b.len == 1).then_some(*b)
        };
        let out = single(kernel.output.id(), Direction::Output)?;
        let Binding::Slot(output) = out.head else { return None };
        let mut inputs = [KernelInput { slot: 0, lane: 0 }; MAX_KERNEL_INPUTS];
        for (k, h) in inputs.iter_mut().zip(kernel.inputs()) {
            *k = match single(h.id(), Direction::Input)?.head {
                Binding::Slot(slot) => KernelInput { slot, lane: WHOLE },
                Binding::Component(slot, lane) if lane < 3 => KernelInput { slot, lane },
                _ => return None,
            };
        }
        let whole = inputs[..kernel.len as usize].iter().all(|i| i.lane == WHOLE);
        let code = match kernel.op.arith() {
            Some(arith) if whole => Code::Whole(arith),
            _ => Code::General,
        };
        Some(KernelStep {
            code,
            op: kernel.op,
            inputs,
            len: kernel.len,
            output,
        })
    }

    /// `(arithmetic, input 0's slot, input 1's slot, output slot)` for the two-input
    /// whole-slot shapes (what a tape runs, see [`crate::tape`]).
    pub(crate) fn shape(&self) -> Option<(Arith, u32, u32, u32)> {
        match self.code {
            Code::Whole(arith) => Some((arith, self.inputs[0].slot, self.inputs[1].slot, self.output)),
            Code::General => None,
        }
    }

    /// Runs the kernel over `slots`. Returns `false`, having changed nothing, when a
    /// slot is not what the binding expects (a whole input or the output outside the
    /// dense float store, a lane of something other than a vec3): the caller then runs
    /// the node's `compute`, whose fallbacks define the result.
    #[inline(always)]
    pub(crate) fn run(&self, slots: &mut Slots) -> bool {
        let [i0, i1, ..] = self.inputs;
        let floats = &mut *slots.floats;
        let r = match self.code {
            Code::Whole(arith) => match (floats.get(i0.slot as usize), floats.get(i1.slot as usize)) {
                (Some(&a), Some(&b)) => arith.apply(a, b),
                _ => return false,
            },
            Code::General => match self.general(slots) {
                Some(r) => r,
                None => return false,
            },
        };
        match slots.floats.get_mut(self.output as usize) {
            Some(o) => {
                *o = r;
                true
            }
            None => false,
        }
    }

    /// Reads every input by lane and applies `op` (out of line: the uncommon shapes).
    #[inline(never)]
    fn general(&self, slots: &Slots) -> Option<f64> {
        let mut x = [0.0; MAX_KERNEL_INPUTS];
        let n = (self.len as usize).min(MAX_KERNEL_INPUTS);
        for (v, &input) in x[..n].iter_mut().zip(&self.inputs) {
            *v = read(slots, input)?;
        }
        Some(self.op.eval(&x, n))
    }
}

/// One kernel input's value, or `None` when its slot does not hold what the binding expects.
#[inline]
fn read(slots: &Slots, input: KernelInput) -> Option<f64> {
    if input.lane == WHOLE {
        return slots.float(input.slot);
    }
    if input.lane < 3 {
        slots.lane(input.slot, input.lane)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::registry::Registry;
    use crate::slots::Slots;
    use crate::value::Value;
    use crate::{testing, CompileOptions, Graph, Instance, Program, Time};

    /// `fma3`'s kernel: `output = a * b + c` (a custom op with three inputs).
    fn fma(x: &[f64]) -> f64 {
        match x {
            [a, b, c, ..] => a * b + c,
            _ => 0.0,
        }
    }

    fn registry() -> Arc<Registry> {
        let mut r = Registry::new();
        r.register(testing::add().unwrap()).unwrap();
        r.register(testing::VecScale::new().unwrap()).unwrap();
        let mut s = NodeSpec::builder("fma3");
        let a = s.input("a", 0.0);
        let b = s.input("b", 1.0);
        let c = s.input("c", 0.0);
        let out = s.output("output", 0.0);
        let spec = s.build().unwrap();
        r.register(KernelNode::new(spec, &[a, b, c], out, ScalarOp::Custom(fma)).unwrap())
            .unwrap();
        Arc::new(r)
    }

    #[test]
    fn new_rejects_bad_arity_groups_and_types() {
        let mut s = NodeSpec::builder("k");
        let a = s.input("a", 0.0);
        let v = s.input("v", glam::DVec3::ZERO);
        let o = s.output("o", 0.0);
        let spec = s.build().unwrap();
        assert!(ScalarKernel::new(&spec, &[a], o, ScalarOp::Add).is_err());
        assert!(ScalarKernel::new(&spec, &[], o, ScalarOp::Custom(fma)).is_err());
        assert!(ScalarKernel::new(&spec, &[a; 5], o, ScalarOp::Custom(fma)).is_err());
        // A vec3 input passed off as a float handle.
        let fake = Input::<f64>::new(v.id());
        assert!(ScalarKernel::new(&spec, &[a, fake], o, ScalarOp::Add).is_err());
        // The output passed as an input.
        assert!(ScalarKernel::new(&spec, &[a, Input::new(o.id())], o, ScalarOp::Add).is_err());
        assert!(ScalarKernel::new(&spec, &[a, a], o, ScalarOp::Sub).is_ok());

        let mut s = NodeSpec::builder("two");
        let a = s.input("a", 0.0);
        let b = s.input("b", 0.0);
        let o1 = s.output("o1", 0.0);
        let o2 = s.output("o2", 0.0);
        s.affects(&[a.id()], &[o1.id()]);
        s.affects(&[b.id()], &[o2.id()]);
        let spec = s.build().unwrap();
        let e = ScalarKernel::new(&spec, &[a, b], o1, ScalarOp::Add).unwrap_err();
        assert!(e.message.contains("one compute group"), "{e}");
    }

    #[test]
    fn kernels_match_compute_over_slots_and_components() {
        let mut g = Graph::new(registry());
        g.add_node("vecScale", "v").unwrap();
        g.add_node("add", "sum").unwrap();
        g.add_node("fma3", "f").unwrap();
        g.set_path("v.input", Value::Vec3(glam::DVec3::new(0.1, 0.2, 0.3)))
            .unwrap();
        g.set_path("v.factor", Value::Float(3.0)).unwrap();
        g.set_path("sum.input2", Value::Float(0.7)).unwrap();
        // sum reads whole slots except input1, a vec3 lane (the general code).
        g.connect_path("v.outputY", "sum.input1").unwrap();
        g.connect_path("sum.output", "f.a").unwrap();
        g.connect_path("v.outputZ", "f.b").unwrap();
        g.set_path("f.c", Value::Float(-0.1)).unwrap();
        let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
        assert_eq!(program.steps.iter().filter(|s| s.kernel.is_some()).count(), 2);
        // A program loaded from bytes binds its kernels again.
        let loaded = Program::from_bytes(&program.to_bytes(), &registry()).unwrap();
        assert_eq!(loaded.steps.iter().filter(|s| s.kernel.is_some()).count(), 2);
        let mut inst = Instance::new(program.clone());
        inst.evaluate(Time::default()).unwrap();
        for p in ["sum.output", "f.output"] {
            let lazy = g.get_path(p).unwrap();
            let compiled = inst.get(&program.handle(p).unwrap());
            assert!(lazy.same_bits(&compiled), "{p}: lazy {lazy} != compiled {compiled}");
        }
        // Independent check: (0.2 * 3 + 0.7) * (0.3 * 3) - 0.1, in f64 as written.
        let sum = 0.2f64 * 3.0 + 0.7;
        let expected = sum * (0.3f64 * 3.0) + -0.1;
        assert_eq!(g.get_path("f.output").unwrap().as_f64(), Some(expected));
    }

    #[test]
    fn finite_keeps_every_finite_bit_pattern_and_saturates_the_rest() {
        for x in [0.0, -0.0, 1.5, -f64::MAX, f64::MAX, f64::MIN_POSITIVE, 5e-324, -5e-324] {
            assert_eq!(finite(x).to_bits(), x.to_bits(), "{x:e}");
        }
        assert_eq!(finite(f64::NAN).to_bits(), 0.0f64.to_bits());
        assert_eq!(finite(-f64::NAN).to_bits(), 0.0f64.to_bits());
        assert_eq!(finite(f64::INFINITY), f64::MAX);
        assert_eq!(finite(f64::NEG_INFINITY), -f64::MAX);
    }

    #[test]
    fn saturating_ops_run_straight_line_and_saturate() {
        for (op, arith, a, b, want) in [
            (ScalarOp::MulFinite, Arith::MulFinite, 1e300, -1e300, -f64::MAX),
            (ScalarOp::AddFinite, Arith::AddFinite, f64::MAX, f64::MAX, f64::MAX),
            (ScalarOp::MulFinite, Arith::MulFinite, 0.75, -4.0, -3.0),
        ] {
            let mut s = NodeSpec::builder("sat");
            let (x, y) = (s.input("x", 0.0), s.input("y", 0.0));
            let out = s.output("output", 0.0);
            let mut r = Registry::new();
            r.register(KernelNode::new(s.build().unwrap(), &[x, y], out, op).unwrap())
                .unwrap();
            let mut g = Graph::new(Arc::new(r));
            g.add_node("sat", "n").unwrap();
            g.set_path("n.x", Value::Float(a)).unwrap();
            g.set_path("n.y", Value::Float(b)).unwrap();
            let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
            let k = program.steps[0].kernel.expect("a kernel");
            assert_eq!(k.code, Code::Whole(arith));
            let mut inst = Instance::new(program.clone());
            inst.evaluate(Time::default()).unwrap();
            assert_eq!(inst.get_typed::<f64>(&program.handle("n.output").unwrap()), Some(want));
            assert_eq!(g.get_path("n.output").unwrap().as_f64(), Some(want), "compute agrees");
        }
    }

    #[test]
    fn a_slot_outside_the_float_store_leaves_the_step_to_compute() {
        let mut g = Graph::new(testing::registry().unwrap());
        g.add_node("add", "a").unwrap();
        let program = Program::compile(&g, &CompileOptions::default()).unwrap();
        let k = program.steps[0].kernel.expect("add has a kernel");
        assert_eq!(
            program.initial.floats.len(),
            3,
            "the compiler puts the floats in the dense store"
        );
        // The same values, every one stored as a `Value` (as a program from an older binary).
        let mut slots = Slots::all_values(program.initial.to_values());
        let before = slots.values.clone();
        assert!(!k.run(&mut slots));
        slots.values[k.inputs[0].slot as usize] = Value::Int(3);
        assert!(!k.run(&mut slots));
        assert!(slots.values[k.output as usize].same_bits(&before[k.output as usize]));
        // In the dense store the kernel runs.
        let mut slots = program.initial.clone();
        assert!(k.run(&mut slots));
    }
}
