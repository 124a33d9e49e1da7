//! Small node types for testing and benchmarking the core itself (the core
//! registers no real node type). They are public so benches, property tests
//! and third-party plugin authors can use them as examples.

use std::sync::Arc;

use glam::{DMat4, DVec3};

use crate::error::{ComputeError, SpecError};
use crate::kernel::{KernelNode, ScalarOp};
use crate::node::{ComputeContext, KnownInputs, NodeType};
use crate::registry::Registry;
use crate::spec::{AttrId, Input, MirrorRole, MultiInput, MultiOutput, NodeSpec, Output, Unit};

/// `add`: `output = input1 + input2` (floats), a [`KernelNode`], so compiled programs run
/// it without a compute context.
pub fn add() -> Result<KernelNode, SpecError> {
    let mut s = NodeSpec::builder("add");
    s.doc("output = input1 + input2");
    let a = s.input("input1", 0.0);
    let b = s.input("input2", 0.0);
    let out = s.output("output", 0.0);
    KernelNode::new(s.build()?, &[a, b], out, ScalarOp::Add)
}

/// `addGeneral`: the same arithmetic as [`add`] through an ordinary `compute` (no
/// scalar kernel), so benchmarks can report the general per-node path beside the kernel one.
pub struct AddGeneral {
    spec: NodeSpec,
    a: crate::Input<f64>,
    b: crate::Input<f64>,
    out: crate::Output<f64>,
}

impl AddGeneral {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("addGeneral");
        s.doc("output = input1 + input2, through compute");
        let a = s.input("input1", 0.0);
        let b = s.input("input2", 0.0);
        let out = s.output("output", 0.0);
        Ok(AddGeneral {
            spec: s.build()?,
            a,
            b,
            out,
        })
    }
}

impl NodeType for AddGeneral {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }
    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let v = ctx.get(self.a) + ctx.get(self.b);
        ctx.set(self.out, v);
        Ok(())
    }
}

/// `clampPositive`: `output = max(input, 0)`; fails on inputs below -1000
/// (to test error paths).
pub struct ClampPositive {
    spec: NodeSpec,
    input: Input<f64>,
    out: Output<f64>,
}

impl ClampPositive {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("clampPositive");
        let input = s.input("input", 0.0);
        let out = s.output("output", 0.0);
        Ok(ClampPositive {
            spec: s.build()?,
            input,
            out,
        })
    }
}

impl NodeType for ClampPositive {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }
    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let x = ctx.get(self.input);
        if x < -1000.0 {
            return Err(ComputeError::new(format!("input {x} is below -1000")));
        }
        ctx.set(self.out, x.max(0.0));
        Ok(())
    }
}

/// `twoGroups`: `sum = a + b` and `echo = b`, with `a` affecting only `sum`,
/// so `echo -> a` on the same node is a node-level loop but not a plug cycle.
pub struct TwoGroups {
    spec: NodeSpec,
    a: Input<f64>,
    b: Input<f64>,
    sum: Output<f64>,
    echo: Output<f64>,
}

impl TwoGroups {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("twoGroups");
        let a = s.input("a", 0.0);
        let b = s.input("b", 0.0);
        let sum = s.output("sum", 0.0);
        let echo = s.output("echo", 0.0);
        s.affects(&[a.id(), b.id()], &[sum.id()]);
        s.affects(&[b.id()], &[echo.id()]);
        Ok(TwoGroups {
            spec: s.build()?,
            a,
            b,
            sum,
            echo,
        })
    }
}

impl NodeType for TwoGroups {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }
    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if ctx.wants(self.sum) {
            let v = ctx.get(self.a) + ctx.get(self.b);
            ctx.set(self.sum, v);
        }
        if ctx.wants(self.echo) {
            let v = ctx.get(self.b);
            ctx.set(self.echo, v);
        }
        Ok(())
    }
}

/// `vecScale`: `output = input * factor` (vec3 by float), to test components.
pub struct VecScale {
    spec: NodeSpec,
    input: Input<DVec3>,
    factor: Input<f64>,
    out: Output<DVec3>,
}

impl VecScale {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("vecScale");
        let input = s.input("input", DVec3::ZERO);
        let factor = s.input("factor", 1.0);
        let out = s.output("output", DVec3::ZERO);
        Ok(VecScale {
            spec: s.build()?,
            input,
            factor,
            out,
        })
    }
}

impl NodeType for VecScale {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }
    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let v = ctx.get(self.input) * ctx.get(self.factor);
        ctx.set(self.out, v);
        Ok(())
    }
}

/// `sumMulti`: `output = sum of input[i]`, and `spread[i] = output * i` for
/// each existing element of the multi output `spread`.
pub struct SumMulti {
    spec: NodeSpec,
    input: MultiInput<f64>,
    out: Output<f64>,
    spread: MultiOutput<f64>,
}

impl SumMulti {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("sumMulti");
        let input = s.multi_input("input", 0.0);
        let out = s.output("output", 0.0);
        let spread = s.multi_output("spread", 0.0);
        Ok(SumMulti {
            spec: s.build()?,
            input,
            out,
            spread,
        })
    }
}

impl NodeType for SumMulti {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }
    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let mut sum = 0.0;
        let mut k = 0;
        while let Some((_, v)) = ctx.multi_at(self.input, k) {
            sum += v;
            k += 1;
        }
        ctx.set(self.out, sum);
        // Even positions by logical index, odd ones by position (both write element k).
        for k in 0..ctx.multi_out_len(self.spread) {
            if let Some(i) = ctx.multi_out_index(self.spread, k) {
                if k % 2 == 0 {
                    ctx.set_at(self.spread, i, sum * i as f64);
                } else {
                    ctx.set_elem(self.spread, k, sum * i as f64);
                }
            }
        }
        Ok(())
    }
}

/// `timeSource`: `output = frame * scale`; time-dependent.
pub struct TimeSource {
    spec: NodeSpec,
    scale: Input<f64>,
    out: Output<f64>,
}

impl TimeSource {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("timeSource");
        let scale = s.input("scale", 1.0);
        let out = s.output("output", 0.0);
        s.time_dependent();
        Ok(TimeSource {
            spec: s.build()?,
            scale,
            out,
        })
    }
}

impl NodeType for TimeSource {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }
    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let v = ctx.time().frame * ctx.get(self.scale);
        ctx.set(self.out, v);
        Ok(())
    }
}

/// `pick`: `output = b` when `select` is true, else `a`; names the other input as unread
/// when `select` is known (a selector, to test [`NodeType::unread_inputs`]).
pub struct Pick {
    spec: NodeSpec,
    select: Input<bool>,
    a: Input<f64>,
    b: Input<f64>,
    out: Output<f64>,
}

impl Pick {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("pick");
        let select = s.input("select", false);
        let a = s.input("a", 0.0);
        let b = s.input("b", 0.0);
        let out = s.output("output", 0.0);
        Ok(Pick {
            spec: s.build()?,
            select,
            a,
            b,
            out,
        })
    }
}

impl NodeType for Pick {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }
    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let v = if ctx.get(self.select) {
            ctx.get(self.b)
        } else {
            ctx.get(self.a)
        };
        ctx.set(self.out, v);
        Ok(())
    }
    fn unread_inputs(&self, known: &KnownInputs<'_>) -> Vec<AttrId> {
        match known.get(self.select) {
            Some(true) => vec![self.a.id()],
            Some(false) => vec![self.b.id()],
            None => Vec::new(),
        }
    }
}

/// `testJoint` / `testTransform`: a small DAG node with Maya-like channels
/// and mirror roles, for rig-file tests. `matrix = T * JO * R` (column
/// vectors, rotate order honoured, scale ignored), `worldMatrix =
/// parentMatrix * matrix`. `testJoint` has `jointOrient` and an
/// `inverseScale` fed by its parent's `scale`; `testTransform` has an
/// `aimVector` (local) and a `worldUpVector` (world) instead.
pub struct TestXform {
    spec: NodeSpec,
    translate: Input<DVec3>,
    rotate: Input<DVec3>,
    rotate_order: Input<i64>,
    joint_orient: Option<Input<DVec3>>,
    parent_matrix: Input<DMat4>,
    matrix: Output<DMat4>,
    world_matrix: Output<DMat4>,
}

impl TestXform {
    /// Creates `testJoint` (`joint = true`) or `testTransform`.
    pub fn new(joint: bool) -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder(if joint { "testJoint" } else { "testTransform" });
        s.doc("a minimal transform for rig-file tests");
        let translate = s.input("translate", DVec3::ZERO);
        let rotate = s.input("rotate", DVec3::ZERO);
        let rotate_order = s.input_enum("rotateOrder", &["xyz", "yzx", "zxy", "xzy", "yxz", "zyx"], 0);
        let scale = s.input("scale", DVec3::ONE);
        let joint_orient = joint.then(|| s.input("jointOrient", DVec3::ZERO));
        let inverse_scale = joint.then(|| s.input("inverseScale", DVec3::ONE));
        let extra = (!joint).then(|| (s.input("aimVector", DVec3::X), s.input("worldUpVector", DVec3::Y)));
        let parent_matrix = s.input("parentMatrix", DMat4::IDENTITY);
        let matrix = s.output("matrix", DMat4::IDENTITY);
        let world_matrix = s.output("worldMatrix", DMat4::IDENTITY);
        s.mirror(translate, MirrorRole::Translate)
            .mirror(rotate, MirrorRole::Rotate)
            .mirror(rotate_order, MirrorRole::RotateOrder)
            .unit(rotate, Unit::Degrees);
        let mut local = vec![translate.id(), rotate.id(), rotate_order.id(), scale.id()];
        if let Some(jo) = joint_orient {
            s.mirror(jo, MirrorRole::JointOrient).unit(jo, Unit::Degrees);
            local.push(jo.id());
        }
        if let Some((aim, up)) = extra {
            s.mirror(aim, MirrorRole::LocalVector)
                .mirror(up, MirrorRole::WorldVector);
        }
        s.affects(&local, &[matrix.id(), world_matrix.id()]);
        s.affects(&[parent_matrix.id()], &[world_matrix.id()]);
        if let Some(is) = inverse_scale {
            s.affects(&[is.id()], &[matrix.id(), world_matrix.id()]);
        }
        s.dag(parent_matrix, world_matrix);
        if let Some(is) = inverse_scale {
            s.dag_link("scale", is);
            s.maya_names(&[("jointOrient", "jo"), ("inverseScale", "is")]);
        }
        s.maya_names(&[
            ("translate", "t"),
            ("rotate", "r"),
            ("rotateOrder", "ro"),
            ("scale", "s"),
            ("parentMatrix", "pm"),
            ("matrix", "m"),
            ("worldMatrix", "wm"),
        ]);
        Ok(TestXform {
            spec: s.build()?,
            translate,
            rotate,
            rotate_order,
            joint_orient,
            parent_matrix,
            matrix,
            world_matrix,
        })
    }
}

impl NodeType for TestXform {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }
    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let order = ctx.get(self.rotate_order);
        let r = crate::rig::mirror::euler_to_quat(ctx.get(self.rotate), order);
        let jo = self
            .joint_orient
            .map(|h| crate::rig::mirror::euler_to_quat(ctx.get(h), 0))
            .unwrap_or_default();
        let local = DMat4::from_translation(ctx.get(self.translate)) * DMat4::from_quat(jo * r);
        if ctx.wants(self.matrix) {
            ctx.set(self.matrix, local);
        }
        if ctx.wants(self.world_matrix) {
            let w = ctx.get(self.parent_matrix) * local;
            ctx.set(self.world_matrix, w);
        }
        Ok(())
    }
}

/// `cachedRamp`: a precompute group turns `factor` into an `Object` cache
/// (`2 * factor`), and a time-dependent group computes `output = cache * frame`.
/// Only the second group re-runs when time changes.
pub struct CachedRamp {
    spec: NodeSpec,
    factor: Input<f64>,
    cache: Output<crate::value::ObjectRef>,
    out: Output<f64>,
}

impl CachedRamp {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("cachedRamp");
        let factor = s.input("factor", 1.0);
        let cache = s.output("cache", crate::value::ObjectRef::default());
        let out = s.output("output", 0.0);
        s.affects(&[factor.id()], &[cache.id()]);
        s.affects(&[cache.id()], &[out.id()]);
        s.time_affects(&[out.id()]);
        Ok(CachedRamp {
            spec: s.build()?,
            factor,
            cache,
            out,
        })
    }
}

impl NodeType for CachedRamp {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }
    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if ctx.wants(self.cache) {
            let f = ctx.get(self.factor);
            ctx.set(self.cache, crate::value::ObjectRef::new(2.0 * f));
        }
        if ctx.wants(self.out) {
            let k = ctx.get_output(self.cache).downcast::<f64>().copied().unwrap_or(0.0);
            ctx.set(self.out, k * ctx.time().frame);
        }
        Ok(())
    }
}

/// `exprSum`: a node type whose compute uses custom attributes, like an expression node.
/// Custom float outputs are allowed; the `k`-th one is `bias + frame + (k + 1) * sum` of
/// the node's single custom float inputs, so every custom float input, `bias` and time
/// affect every custom output (see [`NodeType::custom_affects`]). Its own output `echo`
/// is `bias`.
pub struct ExprSum {
    spec: NodeSpec,
    bias: Input<f64>,
    echo: Output<f64>,
}

impl ExprSum {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("exprSum");
        let bias = s.input("bias", 0.0);
        let echo = s.output("echo", 0.0);
        Ok(ExprSum {
            spec: s.build()?,
            bias,
            echo,
        })
    }

    fn summed(spec: &NodeSpec) -> impl Iterator<Item = AttrId> + '_ {
        spec.attr_ids().filter(|&a| {
            let x = spec.attr(a);
            spec.is_custom(a) && x.is_input() && !x.multi && x.ty == crate::value::AttrType::Float
        })
    }
}

impl NodeType for ExprSum {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }
    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let spec = ctx.node_spec();
        let bias = ctx.get(self.bias);
        if ctx.wants(self.echo) {
            ctx.set(self.echo, bias);
        }
        let outputs: Vec<AttrId> = spec
            .attr_ids()
            .filter(|&a| spec.is_custom(a) && !spec.attr(a).is_input())
            .collect();
        if !outputs.iter().any(|&o| ctx.wants(o)) {
            return Ok(()); // the `echo` group reads only `bias`
        }
        let sum: f64 = Self::summed(spec).map(|a| ctx.get(Input::<f64>::new(a))).sum();
        let frame = ctx.time().frame;
        for (k, o) in outputs.into_iter().enumerate() {
            if ctx.wants(o) {
                ctx.set(Output::<f64>::new(o), bias + frame + (k as f64 + 1.0) * sum);
            }
        }
        Ok(())
    }
    fn custom_affects(&self, custom: &[crate::spec::AttrSpec], first: AttrId) -> Result<crate::CustomAffects, String> {
        let id = |k: usize| AttrId(first.0 + k as u16);
        let mut inputs = vec![self.bias.id()];
        let mut outputs = Vec::new();
        for (k, a) in custom.iter().enumerate() {
            match (a.is_input(), a.ty, a.multi) {
                (true, crate::value::AttrType::Float, false) => inputs.push(id(k)),
                (true, ..) => {}
                (false, crate::value::AttrType::Float, false) => outputs.push(id(k)),
                (false, ..) => return Err(format!("custom output {} must be a single float", a.name)),
            }
        }
        let affects = outputs
            .iter()
            .flat_map(|&o| inputs.iter().map(move |&i| (i, o)))
            .collect();
        Ok(crate::CustomAffects {
            affects,
            time_outputs: outputs,
        })
    }
}

/// A registry with all the test node types.
pub fn registry() -> Result<Arc<Registry>, SpecError> {
    let mut r = Registry::new();
    r.register(add()?)?;
    r.register(AddGeneral::new()?)?;
    r.register(ClampPositive::new()?)?;
    r.register(TwoGroups::new()?)?;
    r.register(VecScale::new()?)?;
    r.register(SumMulti::new()?)?;
    r.register(TimeSource::new()?)?;
    r.register(Pick::new()?)?;
    r.register(CachedRamp::new()?)?;
    r.register(ExprSum::new()?)?;
    r.register(TestXform::new(true)?)?;
    r.register(TestXform::new(false)?)?;
    Ok(Arc::new(r))
}
