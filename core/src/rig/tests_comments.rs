//! `sinew fmt` keeps comments: hand-written cases with their expected text, and every
//! rig of `graphs/` with comments inserted at every position.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::comment_check::{check_canonical_with_comments, check_fmt_with_taken_values, check_written_with_comments};
use super::*;
use crate::testing;

fn reg() -> Arc<crate::registry::Registry> {
    testing::registry().expect("test registry")
}

fn fmt(text: &str) -> String {
    format_rig_str(text, Path::new("mem.ron"), &reg()).unwrap_or_else(|d| panic!("{}\n{text}", d.render()))
}

/// Formats `input`, expects `want`, and checks that formatting `want` again changes
/// nothing and that both load to the same graph.
fn case(input: &str, want: &str) {
    let got = fmt(input);
    assert_eq!(got, want, "\n--- got ---\n{got}--- want ---\n{want}");
    assert_eq!(fmt(&got), got, "not a fixed point");
    let (a, b) = (
        load_rig_str(input, Path::new("mem.ron"), &reg()),
        load_rig_str(&got, Path::new("mem.ron"), &reg()),
    );
    graph_eq(&a.expect("input").graph, &b.expect("output").graph).expect("same graph");
}

#[test]
fn comments_stay_with_their_entries() {
    case(
        r#"// header
Rig( // on open
    name: "c", // trailing name


    // before fps (two blank lines above collapse to one)
    fps: 24.0,
    nodes: {
        // first node
        "a": add(input1: 1.0 /* one */, input2: 2.0), // after a
        "b": add(), /* b */


        // group two
        "c": add(),
        // end of nodes
    },
    connections: [
        ("a.output", "b.input1"), // tuple form
        "b.output -> c.input1",
    ],
) // after rig
// eof
"#,
        r#"// header
Rig( // on open
    name: "c", // trailing name

    // before fps (two blank lines above collapse to one)
    fps: 24.0,
    nodes: {
        // first node
        "a": add(
            input1: 1.0, /* one */
            input2: 2.0,
        ), // after a
        "b": add(), /* b */

        // group two
        "c": add(),
        // end of nodes
    },
    connections: [
        "a.output -> b.input1", // tuple form
        "b.output -> c.input1",
    ],
) // after rig
// eof
"#,
    );
}

/// A matrix written as 4 rows of 4 with a comment per row is printed as 16 numbers,
/// each comment after the last number of its row (or before the first): numbers fill a
/// line until a comment ends it, so a row with no comment after it joins the next.
#[test]
fn a_comment_per_matrix_row_keeps_its_row() {
    case(
        r#"Rig(nodes: {
    "j": testJoint(parentMatrix: (
        (1, 0, 0, 0), // x axis
        (0, 1, 0, 0), // y axis
        // the z axis
        (0, 0, 1, 0),
        (2, 3, 4, 1), // position
    )),
})
"#,
        r#"Rig(
    nodes: {
        "j": testJoint(
            parentMatrix: (
                1.0, 0.0, 0.0, 0.0, // x axis
                0.0, 1.0, 0.0, 0.0, // y axis
                // the z axis
                0.0, 0.0, 1.0, 0.0, 2.0, 3.0, 4.0, 1.0, // position
            ),
        ),
    },
)
"#,
    );
}

/// The comments of an entry the canonical text drops (a default value) move to the
/// next remaining entry, or to the end of the container.
#[test]
fn comments_of_dropped_entries_move_to_the_next_one() {
    case(
        r#"Rig(nodes: {
    "a": add(
        // default, so not written
        input1: 0.0,
        input2: 2.0, // two
    ),
    "b": add(input2: 2.0, input1: 0.0 /* zero */),
})
"#,
        r#"Rig(
    nodes: {
        "a": add(
            // default, so not written
            input2: 2.0, // two
        ),
        "b": add(
            input2: 2.0,
            /* zero */
        ),
    },
)
"#,
    );
}

/// A vec3 child written alone (`translateX`) is printed as the whole vec3: its comment
/// goes with it.
#[test]
fn a_child_field_comment_follows_the_vec3() {
    case(
        "Rig(nodes: { \"t\": testTransform(translateX: 2.5 /* tx */) })",
        r#"Rig(
    nodes: {
        "t": testTransform(
            translate: (2.5, 0.0, 0.0), /* tx */
        ),
    },
)
"#,
    );
}

#[test]
fn components_and_uses_keep_comments() {
    let text = r#"Rig(
    components: {
        // the leg
        "leg": (
            nodes: {
                "hip_L": testJoint(), // hip
            },
        ),
    },
    uses: [
        Use(component: "leg"), // left
        // right
        Use(component: "leg", mirror: YZ),
    ],
)
"#;
    case(text, text);
}

fn graphs_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../graphs")
}

/// The rigs of `graphs/tests` the test registry loads on their own.
fn test_rigs() -> Vec<PathBuf> {
    let rigs: Vec<PathBuf> = ["basic.ron", "biped.ron"]
        .iter()
        .map(|f| graphs_dir().join("tests").join(f))
        .collect();
    assert!(rigs.iter().all(|p| p.exists()));
    rigs
}

#[test]
fn every_test_rig_keeps_comments_inserted_everywhere() {
    let reg = reg();
    for p in test_rigs() {
        let text = std::fs::read_to_string(&p).expect("rig");
        check_canonical_with_comments(&text, &p, &reg);
        check_written_with_comments(&text, &p, &reg);
    }
}

/// The loaded document takes node field values out of the syntax tree kept for fmt: the
/// text is the same as with the tree as parsed, on the test rigs and on values with and
/// without comments side by side (a vec3 with a comment inside, a child field, custom
/// attributes, whose entries fmt matches one by one).
#[test]
fn fmt_is_the_same_with_values_taken_from_the_tree() {
    let reg = reg();
    for p in test_rigs() {
        let text = std::fs::read_to_string(&p).expect("rig");
        assert!(check_fmt_with_taken_values(&text, &p, &reg), "{}", p.display());
    }
    let text = r#"Rig(
    nodes: {
        "a": testTransform(translate: (1, /* y */ 2, 3), rotate: (4, 5, 6), scaleX: 2, attrs: {
            "k": float(default: 1),

            "gain": float(default: 2),
        }, k: 3, gain: 4), // gain
        "b": testTransform(parent: "a", translate: (1, 0, 0)),
    },
)"#;
    if let Err(d) = load_rig_str(text, Path::new("mem.ron"), &reg) {
        panic!("{}", d.render());
    }
    assert!(check_fmt_with_taken_values(text, Path::new("mem.ron"), &reg));
}
