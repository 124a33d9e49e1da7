//! Robustness: random bytes and random mutations of valid rigs must never
//! make the parser, loader or saver panic (bounded proptest; the `fuzz/`
//! cargo-fuzz target runs the same entry point for longer).

use std::path::Path;
use std::sync::Arc;

use proptest::prelude::*;

use super::*;
use crate::registry::Registry;
use crate::testing;

fn reg() -> Arc<Registry> {
    testing::registry().expect("test registry")
}

fn seeds() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../graphs/tests");
    [
        "basic.ron",
        "biped.ron",
        "parts/arm.ron",
        "invalid/cycle.ron",
        "invalid/many_errors.ron",
    ]
    .iter()
    .map(|f| std::fs::read_to_string(dir.join(f)).expect("seed rig"))
    .collect()
}

fn source() -> MemSource {
    let mut m = MemSource::default();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../graphs/tests");
    m.files.insert(
        "parts/arm.ron".into(),
        std::fs::read_to_string(dir.join("parts/arm.ron")).unwrap(),
    );
    m
}

/// Loads, and when that succeeds saves, reloads and compares: nothing may panic.
pub(crate) fn exercise(text: &str, registry: &Arc<Registry>, src: &MemSource) {
    if let Ok(r) = load_rig_with(text, Path::new("fuzz.ron"), registry, src) {
        let saved = save_rig(&r.graph, &r.document);
        let r2 = load_rig_with(&saved, Path::new("fuzz.ron"), registry, src)
            .unwrap_or_else(|d| panic!("saved text does not load:\n{}\n{saved}", d.render()));
        graph_eq(&r.graph, &r2.graph).unwrap_or_else(|e| panic!("{e}\n{text}\n---\n{saved}"));
        let _ = to_dot(&r.graph);
        let _ = to_json(&r.graph);
    }
}

#[derive(Clone, Debug)]
enum Mutation {
    Delete(usize, usize),
    Insert(usize, String),
    Duplicate(usize, usize, usize),
}

const TOKENS: &[&str] = &[
    "(",
    ")",
    "[",
    "]",
    "{",
    "}",
    ",",
    ":",
    "\"",
    "->",
    ".",
    "-",
    "1e308",
    "1e999",
    "0",
    "-0.0",
    "nan",
    "[4294967295]",
    "\"a.output -> a.input1\"",
    "parent: \"root\"",
    "Use(component: \"leg\", mirror: YZ)",
    "mirror: XY",
    "//",
    "/*",
    "\\u{110000}",
    "r#\"",
    "é",
    "testJoint(",
    "sumMulti(input: {4000000000: 1})",
    "translateX: 1",
    "set: {\"root.rotate\": (1, 2, 3)}",
    "Use(file: \"parts/arm.ron\")",
    "Use(file: \"fuzz.ron\")",
];

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), 0usize..40).prop_map(|(a, n)| Mutation::Delete(a, n)),
        (any::<usize>(), prop::sample::select(TOKENS)).prop_map(|(a, t)| Mutation::Insert(a, t.to_string())),
        (any::<usize>(), any::<usize>(), 1usize..60).prop_map(|(a, b, n)| Mutation::Duplicate(a, b, n)),
    ]
}

fn apply(text: &str, muts: &[Mutation]) -> String {
    let mut b: Vec<char> = text.chars().collect();
    for m in muts {
        let len = b.len().max(1);
        match m {
            Mutation::Delete(a, n) => {
                let a = a % len;
                let e = (a + n).min(b.len());
                if a < e {
                    b.drain(a..e);
                }
            }
            Mutation::Insert(a, t) => {
                let a = a % (b.len() + 1);
                for (k, c) in t.chars().enumerate() {
                    b.insert(a + k, c);
                }
            }
            Mutation::Duplicate(a, at, n) => {
                let a = a % len;
                let e = (a + n).min(b.len());
                let seg: Vec<char> = b.get(a..e).map(|s| s.to_vec()).unwrap_or_default();
                let at = at % (b.len() + 1);
                for (k, c) in seg.into_iter().enumerate() {
                    b.insert(at + k, c);
                }
            }
        }
    }
    b.into_iter().collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1000, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let text = String::from_utf8_lossy(&bytes);
        exercise(&text, &reg(), &source());
    }

    #[test]
    fn mutated_rigs_never_panic(seed in 0usize..5, muts in prop::collection::vec(mutation(), 1..6)) {
        let text = apply(&seeds()[seed], &muts);
        exercise(&text, &reg(), &source());
    }
}
