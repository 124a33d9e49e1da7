//! The library example from the README, kept compiling and correct.

use std::sync::Arc;

use sinew::prelude::*;

#[test]
fn readme_library_example() -> Result<(), Box<dyn std::error::Error>> {
    let mut graph = Graph::new(default_registry()?);
    graph.add_node("multiplyDivide", "md")?;
    graph.set_path("md.input1", Value::Vec3(glam::DVec3::new(1.0, 2.0, 3.0)))?;
    graph.set_path("md.input2", Value::Vec3(glam::DVec3::splat(2.0)))?;
    let out = graph.get_path("md.output")?; // lazy: computes only what is needed

    let program = Arc::new(Program::compile(&graph, &CompileOptions::default())?);
    let mut instance = Instance::new(program.clone()); // compiled: flat schedule, no allocation per frame
    instance.evaluate(Time::new(1.0, 24.0))?;
    let out2 = instance.get(&program.handle("md.output")?);
    assert!(out.same_bits(&out2)); // lazy and compiled agree bit for bit
    assert!(out.same_bits(&Value::Vec3(glam::DVec3::new(2.0, 4.0, 6.0))));
    Ok(())
}
