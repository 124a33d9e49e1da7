//! The compiled schedule evaluates a frame without allocating: a counting
//! global allocator proves it for a graph of chains, fan-outs, component
//! connections, multi attributes and time-dependent nodes.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use sinew_core::{testing, CompileOptions, Graph, Instance, Program, Time, Value};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn compiled_frames_do_not_allocate() {
    let mut g = Graph::new(testing::registry().expect("registry"));
    g.add_node("timeSource", "t").expect("add");
    g.add_node("cachedRamp", "ramp").expect("add");
    g.add_node("sumMulti", "sum").expect("add");
    g.add_node("vecScale", "v").expect("add");
    for i in 0..50 {
        g.add_node("add", &format!("a{i}")).expect("add");
        let src = if i == 0 {
            "t.output".to_string()
        } else {
            format!("a{}.output", i - 1)
        };
        g.connect_path(&src, &format!("a{i}.input1")).expect("connect");
        g.set_path(&format!("a{i}.input2"), Value::Float(0.5)).expect("set");
    }
    g.connect_path("a49.output", "sum.input[0]").expect("connect");
    g.connect_path("ramp.output", "sum.input[3]").expect("connect");
    g.connect_path("sum.spread[2]", "v.inputY").expect("connect");
    g.connect_path("t.output", "v.factor").expect("connect");
    let program = Arc::new(Program::compile(&g, &CompileOptions::default()).expect("compile"));
    assert!(program.frame_step_count() >= 53);
    let mut inst = Instance::new(program.clone());
    inst.evaluate(Time::new(0.0, 24.0)).expect("first frame");
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    for f in 1..100 {
        inst.evaluate(Time::new(f as f64, 24.0)).expect("frame");
    }
    let after = ALLOCATIONS.load(Ordering::SeqCst);
    assert_eq!(after - before, 0, "allocations during 99 compiled frames");
    // Sanity: the values moved with time (sum = (f + 25) + 2f*f... just check change).
    let h = program.handle("v.output").expect("handle");
    assert!(inst.get(&h).component(1).is_some_and(|y| y != 0.0));
}
