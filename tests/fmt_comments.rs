//! `sinew fmt` keeps comments on the example rigs (full registry): comments inserted at
//! every position of each rig in `graphs/examples` that loads on its own survive
//! formatting, each attached to the same entry; the graph is unchanged and the result
//! is a fixed point. (Component files such as `biped/leg.ron` are not rewritten by
//! `sinew fmt biped.ron`; their comments are never touched.)

use std::path::{Path, PathBuf};

use sinew::default_registry;
use sinew_core::rig::comment_check::{check_canonical_with_comments, check_written_with_comments};
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
