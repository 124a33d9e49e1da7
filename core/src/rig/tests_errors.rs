//! Error recovery: one cause gives one error (follow-on errors from the same cause are
//! suppressed), and non-finite numbers are named.

use std::path::Path;

use super::*;
use crate::testing;

fn load_biped_with(from: &str, to: &str) -> Diagnostics {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../graphs/tests");
    let text = std::fs::read_to_string(dir.join("biped.ron")).expect("biped");
    assert!(text.contains(from), "{from}");
    let text = text.replace(from, to);
    let reg = testing::registry().expect("registry");
    load_rig_str(&text, &dir.join("biped.ron"), &reg).expect_err("must fail")
}

/// `mirror: Some(YZ)` is RON's spelling of an optional plane and loads; a bad plane is
/// one error: the mirrored `Use` creates nothing, and references to the nodes it would
/// have created (`hip_R`, ...) report nothing more.
#[test]
fn a_bad_mirror_is_one_error_not_a_cascade() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../graphs/tests");
    let text = std::fs::read_to_string(dir.join("biped.ron")).expect("biped");
    let reg = testing::registry().expect("registry");
    let plain = load_rig_str(&text, &dir.join("biped.ron"), &reg).expect("biped loads");
    let some = text.replace(
        "Use(component: \"leg\", mirror: YZ)",
        "Use(component: \"leg\", mirror: Some(YZ))",
    );
    let r = load_rig_str(&some, &dir.join("biped.ron"), &reg).unwrap_or_else(|d| panic!("{}", d.render()));
    graph_eq(&plain.graph, &r.graph).expect("Some(YZ) is YZ");
    let d = load_biped_with(
        "Use(component: \"leg\", mirror: YZ)",
        "Use(component: \"leg\", mirror: Some(QQ))",
    );
    assert_eq!(d.len(), 1, "{}", d.render());
    assert!(d.errors[0].message.starts_with("mirror must be"), "{}", d.render());
}

/// A missing component file is one error however many references point into it, with
/// "did you mean" for a near file name, and a note counting the references not reported.
#[test]
fn a_missing_component_file_is_one_error_with_a_suggestion() {
    let d = load_biped_with("Use(file: \"parts/arm.ron\"),", "Use(file: \"parts/arms.ron\"),");
    assert_eq!(d.len(), 1, "{}", d.render());
    let e = &d.errors[0];
    assert!(e.message.starts_with("cannot read component file"), "{}", e.message);
    assert!(
        e.hint.as_deref().is_some_and(|h| h.contains("did you mean `arm.ron`?")),
        "{:?}",
        e.hint
    );
    // The mirrored and prefixed uses of the same file still load; what the first use
    // defined (shoulder_L, ...) is referenced elsewhere only if the rig does so.
    let mut mem = MemSource::default();
    mem.files
        .insert("rigs/parts/arm.ron".into(), "Rig(nodes: { \"a\": add() })".into());
    let text = "Rig(uses: [Use(file: \"parts/arms.ron\")], connections: [\"a.output -> b.input1\", \"x.output -> y.input1\"], set: { \"q.input1\": 1.0 })";
    let reg = testing::registry().expect("registry");
    let d = load_rig_with(text, Path::new("rigs/main.ron"), &reg, &mem).expect_err("missing file");
    assert_eq!(d.len(), 1, "{}", d.render());
    assert!(
        d.errors[0].hint.as_deref().is_some_and(|h| h.contains("`arm.ron`")),
        "{}",
        d.render()
    );
    assert!(
        d.errors[0].notes.iter().any(|(_, n)| n.starts_with("5 references")),
        "{}",
        d.render()
    );
}

/// A non-finite number in a vec3 is named, at its own position.
#[test]
fn a_nan_in_a_vec3_names_the_number() {
    let reg = testing::registry().expect("registry");
    for (word, col) in [("NaN", 51), ("inf", 51), ("-inf", 51)] {
        let text = format!("Rig(nodes: {{ \"a\": testJoint(translate: (0.0, 1.0, {word})) }})");
        let d = load_rig_str(&text, Path::new("mem.ron"), &reg).expect_err("non-finite");
        assert_eq!(d.len(), 1, "{}", d.render());
        let e = &d.errors[0];
        assert!(e.message.contains("finite"), "{}", e.message);
        assert!(!e.message.contains("tuple"), "{}", e.message);
        assert_eq!((e.span.line, e.span.col), (1, col), "{}", d.render());
    }
}
