//! The `expression` node: the small arithmetic riggers write in Maya
//! expressions, in a safe, sandboxed language compiled once to bytecode.
//!
//! The node has Maya's `expression` layout: a string `expression`, the multi
//! inputs `input[]` and the multi outputs `output[]`, and reads the time. The
//! text names its plugs: `in speed, amp` makes `in.speed` read `input[0]` and
//! `in.amp` `input[1]`; `out y` makes `out.y = ...` write `output[0]`
//! (`input[k]`/`output[k]` also work directly). Connect other nodes to those
//! elements in the rig file (`"ctrl.speed -> wave.input[0]"`,
//! `"wave.output[0] -> ball.translateY"`). Or use custom attributes (Maya's
//! addAttr; `attrs: {..}` in rig files): a name the text does not declare is
//! the node's custom float input (`in.speed`) or output (`out.x`); the node
//! type opts in with [`NodeType::custom_affects`] (custom outputs read the
//! program, `input[]`, every custom input and time).
//!
//! ```text
//! in speed, amp
//! out y
//! phase = time * speed        // a local number
//! out.y = amp * sin(phase)
//! ```
//!
//! The language (`docs/expression.md` has the full reference): numbers and
//! vectors (`<<x, y, z>>`, `v.x`), `+ - * / % ^` (`^` is power for numbers,
//! cross product for vectors; `*` of two vectors is the dot product, as in
//! MEL), comparisons and `&& || !` (1 true, 0 false), `c ? a : b`,
//! `if (c) { .. } else { .. }`, local names, `time` (seconds) and `frame`,
//! and the functions of [`code`] (`sin`.. in radians as in MEL, `clamp(min,
//! max, v)` and `smoothstep(start, end, v)` in MEL's argument order, `lerp`,
//! `noise`...). There are no loops, no calls out of the node and no state:
//! a run depends only on the inputs and the time, and always terminates.
//!
//! Compilation happens once per expression text: the compiled program is the
//! node's `program` output (an object computed from `expression` alone), and
//! each frame runs it over fixed-size registers without allocating. Errors
//! name the place inside the text (`expression:2:9: unknown name ...`); in a
//! rig file the loader compiles the text ([`NodeType::check_input`]) and
//! reports the mistake at its `file:line:col` inside the string literal, so
//! `sinew check` catches it. Totality: division by zero and other undefined results give 0,
//! outputs are made finite, and outputs not assigned on a run are 0.
//!
//! Crate choice: no crate fits. `evalexpr` is AGPL-3.0 (sinew is MIT/Apache)
//! and looks variables up in a hash map per evaluation; `fasteval` (MIT) has
//! been unmaintained since 2020, evaluates single expressions without
//! statements or vectors and resolves names by string per evaluation; `rhai`
//! is a whole scripting language whose dynamic values allocate per run and
//! would bring a large dependency tree into `sinew-runtime`. The language
//! here is about 900 lines with no dependency.

pub mod code;
mod noise;
pub mod parse;

#[cfg(test)]
mod tests;

use std::sync::Arc;

use sinew_core::{
    AttrId, AttrSpec, AttrType, ComputeContext, ComputeError, CustomAffects, Input, InputError, MultiInput,
    MultiOutput, NodeSpec, NodeType, ObjectRef, Output, Registry, SpecError, Value,
};

pub use code::{compile, compile_for, Compiled, Env, Sink, Source};
pub use parse::{ExprError, Pos, MAX_PORTS};

/// Maya's `expression` node (see the module documentation).
pub struct ExpressionNode {
    spec: NodeSpec,
    expression: Input<Arc<str>>,
    input: MultiInput<f64>,
    program: Output<ObjectRef>,
    output: MultiOutput<f64>,
}

impl ExpressionNode {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("expression");
        s.doc("runs its expression text each frame: output[k] from input[k], time and frame");
        let expression = s.input("expression", Arc::<str>::from(""));
        s.attr_doc(
            expression,
            "the text; `in a, b` / `out y` name input[0], input[1] / output[0]",
        );
        let input = s.multi_input("input", 0.0);
        s.attr_doc(input, "values the expression reads (in.name or input[k])");
        let program = s.output("program", ObjectRef::default());
        s.attr_doc(program, "the compiled expression (computed when the text changes)");
        let output = s.multi_output("output", 0.0);
        s.attr_doc(
            output,
            "values the expression writes (out.name or output[k]); 0 when not assigned",
        );
        s.affects(&[expression.id()], &[program.id()]);
        s.affects(&[program.id(), input.id()], &[output.id()]);
        s.time_affects(&[output.id()]);
        Ok(ExpressionNode {
            spec: s.build()?,
            expression,
            input,
            program,
            output,
        })
    }
}

impl ExpressionNode {
    /// Runs the compiled program with its sources read from `ctx`; returns the sink
    /// values (or `None` when the program group has not run).
    fn run(&self, ctx: &ComputeContext<'_>, outputs: &mut [f64; MAX_PORTS]) -> Option<()> {
        let time = ctx.time();
        ctx.with_output_ref(self.program, |p| {
            let c = p.downcast::<Compiled>()?;
            let mut inputs = [0.0; MAX_PORTS];
            for (slot, src) in inputs.iter_mut().zip(&c.sources) {
                *slot = match *src {
                    Source::Element(k) => ctx.get_at(self.input, k).unwrap_or(0.0),
                    Source::Attr(id) => ctx.get(Input::<f64>::new(id)),
                };
            }
            let env = Env {
                inputs: &inputs,
                time: time.seconds(),
                frame: time.frame,
            };
            c.run(&env, outputs);
            Some(())
        })
    }

    fn not_compiled() -> ComputeError {
        ComputeError::new("the expression was not compiled (its program group did not run); re-evaluate the node")
    }
}

impl NodeType for ExpressionNode {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if ctx.wants(self.program) {
            let spec = ctx.node_spec();
            let compiled = ctx
                .with_ref(self.expression, |text| compile_for(text, Some(spec)))
                .map_err(|e| ComputeError::new(e.to_string()))?;
            ctx.set(self.program, ObjectRef::new(compiled));
        }
        let mut outputs = [0.0; MAX_PORTS];
        let spec = ctx.node_spec();
        let custom_wanted = spec
            .attr_ids()
            .any(|a| spec.is_custom(a) && !spec.attr(a).is_input() && ctx.wants(a));
        if custom_wanted {
            self.run(ctx, &mut outputs).ok_or_else(Self::not_compiled)?;
            // The custom attribute each sink slot writes (a fixed array: no allocation).
            let mut sinks: [Option<AttrId>; MAX_PORTS] = [None; MAX_PORTS];
            ctx.with_output_ref(self.program, |p| {
                if let Some(c) = p.downcast::<Compiled>() {
                    for (slot, s) in sinks.iter_mut().zip(&c.sinks) {
                        if let Sink::Attr(a) = *s {
                            *slot = Some(a);
                        }
                    }
                }
            });
            for a in spec.attr_ids() {
                if spec.is_custom(a) && !spec.attr(a).is_input() && ctx.wants(a) {
                    let v = sinks
                        .iter()
                        .position(|s| *s == Some(a))
                        .map_or(0.0, |slot| outputs[slot]);
                    ctx.set(Output::<f64>::new(a), v);
                }
            }
        }
        if ctx.wants(self.output) {
            // An expression that uses custom attributes leaves output[] at 0 (its group
            // reads no custom input).
            let uses_attrs = ctx.with_output_ref(self.program, |p| p.downcast::<Compiled>().map(Compiled::uses_attrs));
            let uses_attrs = uses_attrs.ok_or_else(Self::not_compiled)?;
            outputs = [0.0; MAX_PORTS];
            let mut sinks = [None; MAX_PORTS];
            if !uses_attrs {
                self.run(ctx, &mut outputs).ok_or_else(Self::not_compiled)?;
                ctx.with_output_ref(self.program, |p| {
                    if let Some(c) = p.downcast::<Compiled>() {
                        for (slot, s) in sinks.iter_mut().zip(&c.sinks) {
                            if let Sink::Element(k) = *s {
                                *slot = Some(k);
                            }
                        }
                    }
                });
            }
            for k in 0..ctx.multi_out_len(self.output) {
                let index = ctx.multi_out_index(self.output, k);
                let v = sinks
                    .iter()
                    .position(|s| s.is_some() && *s == index)
                    .map_or(0.0, |slot| outputs[slot]);
                ctx.set_elem(self.output, k, v);
            }
        }
        Ok(())
    }

    /// Custom float outputs are computed from the program, `input[]`, every custom input
    /// and the time; other custom outputs are refused.
    fn custom_affects(&self, custom: &[AttrSpec], first: AttrId) -> Result<CustomAffects, String> {
        let id = |k: usize| AttrId(first.0 + k as u16);
        // `expression` too, so the custom outputs form a group of their own (output[]'s
        // group reads the program and input[] only).
        let mut inputs = vec![self.expression.id(), self.program.id(), self.input.id()];
        let mut outputs = Vec::new();
        for (k, a) in custom.iter().enumerate() {
            match (a.is_input(), a.ty, a.multi) {
                (true, ..) => inputs.push(id(k)),
                (false, AttrType::Float, false) => outputs.push(id(k)),
                (false, ..) => {
                    return Err(format!(
                        "custom output {} must be a single float (expressions write numbers)",
                        a.name
                    ))
                }
            }
        }
        let affects = outputs
            .iter()
            .flat_map(|&o| inputs.iter().map(move |&i| (i, o)))
            .collect();
        Ok(CustomAffects {
            affects,
            time_outputs: outputs,
        })
    }

    /// A rig file's expression text is compiled when the rig loads, so a mistake is
    /// reported at its line and column in the file.
    fn check_input(&self, spec: &NodeSpec, attr: AttrId, value: &Value) -> Result<(), InputError> {
        match value {
            Value::String(text) if attr == self.expression.id() => {
                compile_for(text, Some(spec)).map(|_| ()).map_err(|e| InputError {
                    offset: Some(e.pos.offset),
                    message: e.message,
                    hint: e.hint,
                })
            }
            _ => Ok(()),
        }
    }
}

/// Registers this family's node types.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    registry.register(ExpressionNode::new()?)?;
    Ok(())
}
