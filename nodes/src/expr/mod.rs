//! The `expression` node: the small arithmetic riggers write in Maya
//! expressions, in a safe, sandboxed language compiled once to bytecode.
//!
//! The node has Maya's `expression` layout: a string `expression`, the multi
//! inputs `input[]` and the multi outputs `output[]`, and reads the time. The
//! text names its plugs: `in speed, amp` makes `in.speed` read `input[0]` and
//! `in.amp` `input[1]`; `out y` makes `out.y = ...` write `output[0]`
//! (`input[k]`/`output[k]` also work directly). Connect other nodes to those
//! elements in the rig file (`"ctrl.speed -> wave.input[0]"`,
//! `"wave.output[0] -> ball.translateY"`).
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
    AttrId, ComputeContext, ComputeError, Input, InputError, MultiInput, MultiOutput, NodeSpec, NodeType, ObjectRef,
    Output, Registry, SpecError, Value,
};

pub use code::{compile, Compiled, Env};
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

impl NodeType for ExpressionNode {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if ctx.wants(self.program) {
            let compiled = ctx
                .with_ref(self.expression, |text| compile(text))
                .map_err(|e| ComputeError::new(e.to_string()))?;
            ctx.set(self.program, ObjectRef::new(compiled));
        }
        if ctx.wants(self.output) {
            let mut inputs = [0.0; MAX_PORTS];
            let mut outputs = [0.0; MAX_PORTS];
            let time = ctx.time();
            let ran = ctx.with_output_ref(self.program, |p| {
                let Some(c) = p.downcast::<Compiled>() else {
                    return false;
                };
                for (k, slot) in inputs.iter_mut().enumerate().take(c.input_count) {
                    *slot = ctx.get_at(self.input, k as u32).unwrap_or(0.0);
                }
                let env = Env {
                    inputs: &inputs,
                    time: time.seconds(),
                    frame: time.frame,
                };
                c.run(&env, &mut outputs);
                true
            });
            if !ran {
                return Err(ComputeError::new(
                    "the expression was not compiled (its program group did not run); re-evaluate the node",
                ));
            }
            for k in 0..ctx.multi_out_len(self.output) {
                let v = ctx
                    .multi_out_index(self.output, k)
                    .and_then(|i| outputs.get(i as usize).copied())
                    .unwrap_or(0.0);
                ctx.set_elem(self.output, k, v);
            }
        }
        Ok(())
    }

    /// A rig file's expression text is compiled when the rig loads, so a mistake is
    /// reported at its line and column in the file.
    fn check_input(&self, attr: AttrId, value: &Value) -> Result<(), InputError> {
        match value {
            Value::String(text) if attr == self.expression.id() => compile(text).map(|_| ()).map_err(|e| InputError {
                offset: Some(e.pos.offset),
                message: e.message,
                hint: e.hint,
            }),
            _ => Ok(()),
        }
    }
}

/// Registers this family's node types.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    registry.register(ExpressionNode::new()?)?;
    Ok(())
}
