//! `ComputeContext::multi_read_into` reads what `multi_at` reads, element by element, in lazy
//! and compiled evaluation, for sparse indices, connected elements, component connections and
//! unset defaults; `set_elem` writes the element `set_at` writes.

use std::sync::Arc;

use sinew_core::{
    testing, CompileOptions, ComputeContext, ComputeError, Graph, Instance, MultiInput, NodeSpec, NodeType, Output,
    Program, Registry, SpecError, Time, Value,
};

/// `readBoth`: `bulk` and `single` are `sum of (index + 1) * value.x + value.y` over the
/// elements of `input`, read by `multi_read_into` and by `multi_at`; `count` is how many
/// elements the bulk read returned.
struct ReadBoth {
    spec: NodeSpec,
    input: MultiInput<glam::DVec3>,
    bulk: Output<f64>,
    single: Output<f64>,
    count: Output<f64>,
}

impl ReadBoth {
    fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("readBoth");
        let input = s.multi_input("input", glam::DVec3::new(0.5, 0.25, 0.0));
        let bulk = s.output("bulk", 0.0);
        let single = s.output("single", 0.0);
        let count = s.output("count", 0.0);
        Ok(ReadBoth {
            spec: s.build()?,
            input,
            bulk,
            single,
            count,
        })
    }
}

fn term(i: u32, v: glam::DVec3) -> f64 {
    (i as f64 + 1.0) * v.x + v.y
}

impl NodeType for ReadBoth {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }
    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let mut all = Vec::new();
        ctx.multi_read_into(self.input, &mut all);
        let bulk: f64 = all.iter().map(|&(i, v)| term(i, v)).sum();
        let mut single = 0.0;
        let mut k = 0;
        while let Some((i, v)) = ctx.multi_at(self.input, k) {
            single += term(i, v);
            k += 1;
        }
        ctx.set(self.bulk, bulk);
        ctx.set(self.single, single);
        ctx.set(self.count, all.len() as f64);
        Ok(())
    }
}

fn graph() -> Graph {
    let mut r = Registry::new();
    r.register(ReadBoth::new().expect("spec")).expect("register");
    let test_types = testing::registry().expect("registry");
    for t in ["timeSource", "vecScale", "sumMulti"] {
        let kind = test_types.get(t).expect("type");
        r.register_arc(kind.clone()).expect("register");
    }
    let mut g = Graph::new(Arc::new(r));
    g.add_node("readBoth", "r").expect("add");
    g.add_node("timeSource", "t").expect("add");
    g.add_node("vecScale", "v").expect("add");
    g.add_node("sumMulti", "s").expect("add");
    // Sparse: elements 0, 3 and 7; 3 is a whole connection, 7 has one component connected.
    g.set_path("r.input[0]", Value::Vec3(glam::DVec3::new(1.0, 2.0, 3.0)))
        .expect("set");
    g.connect_path("t.output", "v.factor").expect("connect");
    g.set_path("v.input", Value::Vec3(glam::DVec3::new(2.0, -1.0, 0.5)))
        .expect("set");
    g.connect_path("v.output", "r.input[3]").expect("connect");
    g.set_path("r.input[7]", Value::Vec3(glam::DVec3::new(0.0, 4.0, 0.0)))
        .expect("set");
    g.connect_path("t.output", "r.input[7].x").expect("connect");
    // Multi output written by position and by index: spread[1] (k = 0) and spread[4] (k = 1).
    g.connect_path("t.output", "s.input[0]").expect("connect");
    g.connect_path("s.spread[1]", "r.input[9].y").expect("connect");
    g.connect_path("s.spread[4]", "r.input[9].x").expect("connect");
    g
}

/// The sum by hand at frame `f`: element 0 `(1, 2, 3)`, element 3 `(2f, -f, f/2)`,
/// element 7 `(f, 4, 0)`, element 9 `(4f, f, 0)` (spread[i] = f * i).
fn expected(f: f64) -> f64 {
    (1.0 + 2.0) + (4.0 * 2.0 * f - f) + (8.0 * f + 4.0) + (10.0 * 4.0 * f + f)
}

#[test]
fn bulk_read_matches_element_reads_lazy_and_compiled() {
    let mut g = graph();
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).expect("compile"));
    let mut inst = Instance::new(program.clone());
    for f in [0.0, 1.0, 2.5, -3.0] {
        let time = Time::new(f, 24.0);
        g.set_time(time);
        inst.evaluate(time).expect("evaluate");
        for (name, want) in [("r.bulk", expected(f)), ("r.single", expected(f)), ("r.count", 4.0)] {
            let lazy = g.get_path(name).expect("get").as_f64();
            assert_eq!(lazy, Some(want), "lazy {name} at frame {f}");
            let h = program.handle(name).expect("handle");
            assert_eq!(inst.get_typed::<f64>(&h), Some(want), "compiled {name} at frame {f}");
        }
    }
}
