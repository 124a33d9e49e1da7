//! `sinew fmt` keeps comments on the example rigs (full registry): comments inserted at
//! every position of each rig in `graphs/examples` that loads on its own survive
//! formatting, each attached to the same entry; the graph is unchanged and the result
//! is a fixed point. (Component files such as `biped/leg.ron` are not rewritten by
//! `sinew fmt biped.ron`; their comments are never touched.)

use std::path::{Path, PathBuf};

use sinew::default_registry;
use sinew_core::rig::comment_check::{
    check_canonical_with_comments, check_fmt_with_taken_values, check_written_with_comments,
};
use sinew_core::rig::rig_dependencies;

#[test]
fn example_rigs_keep_comments_inserted_everywhere() {
    let reg = default_registry().expect("registry");
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs/examples");
    let rigs: Vec<PathBuf> = ["arm.ron", "stretchy_limb.ron", "biped/biped.ron"]
        .iter()
        .map(|f| dir.join(f))
        .collect();
    for p in &rigs {
        let text = std::fs::read_to_string(p).expect("rig");
        check_canonical_with_comments(&text, p, &reg);
        check_written_with_comments(&text, p, &reg);
    }
    // Every other file under graphs/examples is a component of these.
    let used: Vec<PathBuf> = rigs.iter().flat_map(|r| rig_dependencies(r)).collect();
    for e in std::fs::read_dir(dir.join("biped")).expect("biped dir") {
        let p = sinew_core::rig::normalize(&e.expect("entry").path());
        assert!(
            used.contains(&p),
            "{} is neither a rig nor a component of one",
            p.display()
        );
    }
}

/// The loaded document takes node field values out of the syntax tree `sinew fmt` reads
/// comments from: every rig under `graphs/` that loads formats the same as with the tree
/// as parsed (as written, and with comments next to some values and not others).
#[test]
fn fmt_does_not_depend_on_values_taken_from_the_tree() {
    let reg = default_registry().expect("registry");
    let mut todo = vec![Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs")];
    let mut checked = 0;
    while let Some(dir) = todo.pop() {
        for e in std::fs::read_dir(&dir).expect("graphs dir") {
            let p = e.expect("entry").path();
            if p.is_dir() {
                todo.push(p);
            } else if p.extension().is_some_and(|x| x == "ron") {
                let text = std::fs::read_to_string(&p).expect("rig");
                checked += usize::from(check_fmt_with_taken_values(&text, &p, &reg));
            }
        }
    }
    // Most files under graphs/ are components or invalid on purpose; 11 load on their own.
    assert!(checked >= 10, "only {checked} rigs under graphs/ load");
}
