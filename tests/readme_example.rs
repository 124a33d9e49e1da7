//! The README's examples, kept compiling and correct: the library example and the
//! hand-written leg rig.

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

/// The `ron` block of "Writing a rig by hand" loads and does what it says: the leg IK puts
/// the ankle on the foot control (within reach: 0.85 from the hip, the leg 0.90 long), the
/// toe IK aims the toe at its control, and the skin bound at load leaves the mesh where it
/// is in the bind pose.
#[test]
fn readme_rig_example() {
    let readme = include_str!("../README.md");
    let start = readme.find("```ron\n").expect("a ron block in the README") + "```ron\n".len();
    let text = &readme[start..start + readme[start..].find("```").unwrap()];
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md");
    let rig = sinew_core::load_rig_str(text, &path, &default_registry().unwrap())
        .unwrap_or_else(|d| panic!("{}", d.render()));
    let mut g = rig.graph;
    let pos = |g: &mut Graph, p: &str| match g.get_path(&format!("{p}.worldMatrix")).unwrap() {
        Value::Matrix(m) => m.w_axis.truncate(),
        other => panic!("{other:?}"),
    };
    let ankle = pos(&mut g, "ankle_L");
    assert!((ankle - glam::DVec3::new(0.0, -0.4, 0.05)).length() < 1e-9, "{ankle}");
    let (ball, toe, target) = (pos(&mut g, "ball_L"), pos(&mut g, "toe_L"), pos(&mut g, "toe_ctrl_L"));
    assert!(((toe - ball).normalize() - (target - ball).normalize()).length() < 1e-9);
    let mesh = |g: &mut Graph, p: &str| match g.get_path(p).unwrap() {
        Value::Mesh(m) => m,
        other => panic!("{other:?}"),
    };
    let (rest, skinned) = (mesh(&mut g, "leg_mesh.output"), mesh(&mut g, "leg_skin.outputGeometry"));
    assert_eq!(rest.positions.len(), skinned.positions.len());
    for (a, b) in rest.positions.iter().zip(&skinned.positions) {
        assert!((*a - *b).length() < 1e-5, "{a} -> {b}");
    }
    assert!(matches!(g.get_path("foot_ctrl_L.ikFk").unwrap(), Value::Enum(1)));
}
