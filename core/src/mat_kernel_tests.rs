//! Tests of [`super::MatrixKernel`]: validation, binding, bit-identity with `compute`, and
//! the fallback to `compute` when slots are not matrix slots.

use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3};

use super::*;
use crate::error::ComputeError;
use crate::node::{ComputeContext, NodeType, Time};
use crate::program::{CompileOptions, Instance, Program};
use crate::registry::Registry;
use crate::spec::Input;
use crate::value::Value;
use crate::Graph;

/// `a · b · c`, the kernel's function (and the node's compute for that group).
fn product(a: &DMat4, b: &DMat4, c: &DMat4) -> DMat4 {
    *a * *b * *c
}

/// `chain3`: `out = a · b · c` (the kernel's group), and a second group `inv = out⁻¹`.
struct Chain3 {
    spec: NodeSpec,
    a: Input<DMat4>,
    b: Input<DMat4>,
    c: Input<DMat4>,
    out: Output<DMat4>,
    inv: Output<DMat4>,
    kernel: MatrixKernel,
}

impl Chain3 {
    fn new() -> Chain3 {
        let mut s = NodeSpec::builder("chain3");
        let a = s.input("a", DMat4::IDENTITY);
        let b = s.input("b", DMat4::IDENTITY);
        let c = s.input("c", DMat4::IDENTITY);
        let out = s.output("out", DMat4::IDENTITY);
        let inv = s.output("inv", DMat4::IDENTITY);
        s.affects(&[a.id(), b.id(), c.id()], &[out.id()]);
        s.affects(&[out.id()], &[inv.id()]);
        let spec = s.build().unwrap();
        let kernel = MatrixKernel::new(&spec, [a.id(), b.id(), c.id()], out, product).unwrap();
        Chain3 {
            spec,
            a,
            b,
            c,
            out,
            inv,
            kernel,
        }
    }
}

impl NodeType for Chain3 {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }
    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        if ctx.wants(self.out) {
            let m = product(&ctx.get(self.a), &ctx.get(self.b), &ctx.get(self.c));
            ctx.set(self.out, m);
        } else if ctx.wants(self.inv) {
            let m = ctx.get_output(self.out).inverse();
            ctx.set(self.inv, m);
        }
        Ok(())
    }
    fn matrix_kernel(&self) -> Option<&MatrixKernel> {
        Some(&self.kernel)
    }
}

fn registry() -> Arc<Registry> {
    let mut r = Registry::new();
    r.register(Chain3::new()).unwrap();
    Arc::new(r)
}

fn rigid(seed: f64) -> DMat4 {
    let q = DQuat::from_euler(glam::EulerRot::XYZ, 0.3 * seed, -0.7 + seed, 1.1 * seed);
    DMat4::from_scale_rotation_translation(DVec3::new(1.0, 2.0, 0.5 + seed), q, DVec3::new(seed, -2.0, 3.5))
}

#[test]
fn new_refuses_what_it_cannot_replace() {
    let mut s = NodeSpec::builder("bad");
    let a = s.input("a", DMat4::IDENTITY);
    let f = s.input("f", 1.0);
    let extra = s.input("extra", DMat4::IDENTITY);
    let out = s.output("out", DMat4::IDENTITY);
    let other = s.output("other", DMat4::IDENTITY);
    s.affects(&[a.id(), f.id(), extra.id()], &[out.id(), other.id()]);
    let spec = s.build().unwrap();
    let err = |r: Result<MatrixKernel, SpecError>| r.unwrap_err().message;
    assert!(err(MatrixKernel::new(&spec, [a.id(), f.id(), a.id()], out, product)).contains("not a single matrix"));
    // The group computes `other` too, and reads `f`.
    assert!(err(MatrixKernel::new(&spec, [a.id(), extra.id(), a.id()], out, product)).contains("only its output"));
}

#[test]
fn compiled_kernels_match_compute_bit_for_bit_and_bind_only_their_group() {
    let mut g = Graph::new(registry());
    g.add_node("chain3", "p").unwrap();
    g.add_node("chain3", "q").unwrap();
    for (k, plug) in ["p.a", "p.b", "p.c", "q.b"].iter().enumerate() {
        g.set_path(plug, Value::Matrix(rigid(k as f64 + 0.25))).unwrap();
    }
    g.connect_path("p.out", "q.a").unwrap();
    g.connect_path("p.inv", "q.c").unwrap();
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
    // Two `out` steps run the kernel; the `inv` steps call compute.
    let bound: Vec<_> = program.steps.iter().filter_map(|s| s.mat_kernel).collect();
    assert_eq!(bound.len(), 2);
    assert_eq!(program.steps.iter().filter(|s| s.mat_kernel.is_none()).count(), 2);
    // A program loaded from bytes binds them again.
    let loaded = Program::from_bytes(&program.to_bytes(), &registry()).unwrap();
    assert_eq!(loaded.steps.iter().filter(|s| s.mat_kernel.is_some()).count(), 2);
    let mut inst = Instance::new(program.clone());
    inst.evaluate(Time::default()).unwrap();
    for p in ["p.out", "q.out", "q.inv"] {
        let lazy = g.get_path(p).unwrap();
        let compiled = inst.get(&program.handle(p).unwrap());
        assert!(lazy.same_bits(&compiled), "{p}: lazy {lazy} != compiled {compiled}");
    }
    // Independent: q.out = (p.a · p.b · p.c) · q.b · (p.a · p.b · p.c)⁻¹.
    let pa = rigid(0.25) * rigid(1.25) * rigid(2.25);
    let expected = pa * rigid(3.25) * pa.inverse();
    let got = g.get_path("q.out").unwrap();
    let Value::Matrix(got) = got else {
        panic!("q.out is {got}")
    };
    assert!(got.abs_diff_eq(expected, 1e-9), "{got} vs {expected}");
}

#[test]
fn a_kernel_over_non_matrix_slots_leaves_them_to_compute() {
    let kernel = Chain3::new().kernel;
    let step = MatKernelStep {
        inputs: [0, 1, 2],
        output: 3,
        f: kernel.f,
    };
    // Slots with no matrix array (all values): nothing is written, the step falls back.
    let values = vec![Value::Matrix(DMat4::IDENTITY); 4];
    let mut slots = Slots::from_values(values);
    assert!(slots.mats.len() == 4, "whole matrices go to the dense array");
    assert!(step.run(&mut slots));
    slots.mats.clear();
    assert!(!step.run(&mut slots));
}
