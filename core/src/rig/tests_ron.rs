//! RON conformance, with the `ron` crate (0.12) as the oracle: every rig in `graphs/`
//! and every text `save_rig` writes reads with `ron::from_str::<ron::Value>`; sinew's
//! parser and `ron` agree on accept/reject and on the value for generated documents
//! (every number form, escapes, raw strings and identifiers, nested comments, RON's
//! Unicode whitespace). Values are compared through [`Common`], what both can say.
//!
//! Intended differences (documented in docs/rig-format.md) are not generated:
//! non-finite numbers (`inf`, `NaN`), character and byte literals, and ranges.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use proptest::prelude::*;

use super::parse::{parse, Ast, Node};
use super::*;
use crate::testing;

/// A value as both parsers can express it: `ron::Value` drops struct and enum names
/// and reads a bare identifier as `()`; numbers compare as f64 (so `-0` equals `0`).
#[derive(Clone, Debug)]
enum Common {
    Bool(bool),
    Num(f64),
    Str(String),
    Seq(Vec<Common>),
    /// Key-value pairs, later duplicate keys replacing earlier ones.
    Map(Vec<(Common, Common)>),
    Opt(Option<Box<Common>>),
    /// `()`, a bare identifier, or an empty tuple (`ron` reads `()` as unit and
    /// `Name()` as an empty sequence).
    Unit,
}

impl PartialEq for Common {
    fn eq(&self, other: &Common) -> bool {
        use Common::*;
        match (self, other) {
            (Bool(a), Bool(b)) => a == b,
            (Num(a), Num(b)) => a == b,
            (Str(a), Str(b)) => a == b,
            (Seq(a), Seq(b)) => a == b,
            (Seq(a), Unit) | (Unit, Seq(a)) => a.is_empty(),
            (Map(a), Map(b)) => {
                a.len() == b.len() && a.iter().all(|(k, v)| b.iter().any(|(k2, v2)| k == k2 && v == v2))
            }
            (Opt(a), Opt(b)) => a == b,
            (Unit, Unit) => true,
            _ => false,
        }
    }
}

fn map_of(pairs: Vec<(Common, Common)>) -> Common {
    let mut out: Vec<(Common, Common)> = Vec::new();
    for (k, v) in pairs {
        // Keys compare strictly here (`()` and `[]` are different keys).
        match out.iter_mut().find(|(k2, _)| format!("{k2:?}") == format!("{k:?}")) {
            Some(e) => e.1 = v,
            None => out.push((k, v)),
        }
    }
    Common::Map(out)
}

fn from_sinew(n: &Node) -> Common {
    match &n.kind {
        Ast::Bool(b) => Common::Bool(*b),
        Ast::Int(i) => Common::Num(*i as f64),
        Ast::Float(x) => Common::Num(*x),
        Ast::Str { value, .. } => Common::Str(value.clone()),
        Ast::Ident(s) if s == "None" => Common::Opt(None),
        Ast::Ident(_) => Common::Unit,
        Ast::List(v) => Common::Seq(v.iter().map(from_sinew).collect()),
        Ast::Map(v) => map_of(v.iter().map(|(k, v)| (from_sinew(k), from_sinew(v))).collect()),
        Ast::Group { name: Some(s), items } if s == "Some" && items.len() == 1 => {
            Common::Opt(Some(Box::new(from_sinew(&items[0].value))))
        }
        Ast::Group { items, .. } if items.iter().any(|i| i.key.is_some()) => map_of(
            items
                .iter()
                .map(|i| {
                    let k = i.key.as_ref().map(|k| k.0.clone()).unwrap_or_default();
                    (Common::Str(k), from_sinew(&i.value))
                })
                .collect(),
        ),
        // `ron` reads `()` as unit and `Name()` as an empty sequence.
        Ast::Group { name: None, items } if items.is_empty() => Common::Unit,
        Ast::Group { items, .. } => Common::Seq(items.iter().map(|i| from_sinew(&i.value)).collect()),
    }
}

fn from_ron(v: &ron::Value) -> Common {
    match v {
        ron::Value::Bool(b) => Common::Bool(*b),
        ron::Value::Number(n) => Common::Num(n.into_f64()),
        ron::Value::String(s) => Common::Str(s.clone()),
        ron::Value::Seq(v) => Common::Seq(v.iter().map(from_ron).collect()),
        ron::Value::Map(m) => map_of(m.iter().map(|(k, v)| (from_ron(k), from_ron(v))).collect()),
        ron::Value::Option(o) => Common::Opt(o.as_ref().map(|v| Box::new(from_ron(v)))),
        ron::Value::Unit => Common::Unit,
        // Never generated, never in a rig: sinew refuses them.
        ron::Value::Char(c) => Common::Str(format!("char {c:?}")),
        ron::Value::Bytes(b) => Common::Str(format!("bytes {b:?}")),
    }
}

/// Both parsers on `text`: agree on accept/reject, and on the value when accepted.
fn agree(text: &str) -> Result<(), String> {
    let file: Arc<PathBuf> = Arc::new(PathBuf::from("gen.ron"));
    let ours = parse(text, &file);
    let theirs = ron::from_str::<ron::Value>(text);
    match (ours, theirs) {
        (Ok(a), Ok(b)) => {
            let (a, b) = (from_sinew(&a), from_ron(&b));
            if a == b {
                Ok(())
            } else {
                Err(format!("values differ for {text:?}:\n sinew {a:?}\n ron   {b:?}"))
            }
        }
        (Err(_), Err(_)) => Ok(()),
        // Refused on purpose: sinew reads no non-finite number (even one a later
        // duplicate key would replace).
        (Err(e), Ok(_)) if e.message.contains("finite") => Ok(()),
        (Ok(a), Err(e)) => Err(format!(
            "sinew accepts, ron refuses ({e}) {text:?}: {:?}",
            from_sinew(&a)
        )),
        (Err(e), Ok(v)) => Err(format!("ron accepts ({v:?}), sinew refuses {text:?}: {}", e.render())),
    }
}

fn graphs_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../graphs")
}

fn ron_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).expect("graphs dir") {
        let p = e.expect("dir entry").path();
        if p.is_dir() {
            ron_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "ron") {
            out.push(p);
        }
    }
}

/// Every file in `graphs/` (the invalid fixtures too): both accept it with the same
/// value, or both refuse it.
#[test]
fn ron_reads_every_rig_in_graphs_as_sinew_does() {
    let mut files = Vec::new();
    ron_files(&graphs_dir(), &mut files);
    assert!(files.len() >= 20, "found {} rigs", files.len());
    for f in files {
        let text = std::fs::read_to_string(&f).expect("rig text");
        agree(&text).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
    }
}

/// What `save_rig` writes (canonical text of every rig the test registry loads, a
/// generated rig, and a graph built in code) is RON that `ron` reads with the value
/// sinew reads.
#[test]
fn everything_save_rig_writes_is_ron() {
    let reg = testing::registry().expect("test registry");
    let mut files = Vec::new();
    ron_files(&graphs_dir().join("tests"), &mut files);
    let mut texts = Vec::new();
    for f in files {
        if let Ok(r) = load_rig(&f, &reg) {
            texts.push((f.display().to_string(), save_rig(&r.graph, &r.document)));
        }
    }
    assert!(texts.len() >= 2, "saved {}", texts.len());
    let generated = load_rig_str(&super::tests::generated_rig(30), Path::new("gen.ron"), &reg).expect("generated rig");
    texts.push(("generated".into(), save_rig(&generated.graph, &generated.document)));
    for (name, text) in texts {
        ron::from_str::<ron::Value>(&text)
            .unwrap_or_else(|e| panic!("{name}: ron refuses the saved text: {e}\n{text}"));
        agree(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}

/// Each divergence the hostile-input report listed: `ron` accepts these rigs, and
/// sinew reads them with the value `ron` gives.
#[test]
fn listed_divergences_are_read_as_ron_reads_them() {
    let cases = [
        r#"Rig(name: "\x61rm")"#,
        "Rig(name: \"a\\\n     rm\")",
        "Rig(frames: (0x18, 0o30), fps: 0b11)",
        "Rig(fps: 24.0f64, frames: (1i64, 24u8))",
        "Rig(\u{0B}name:\u{85}\"a\",\u{2028}fps:\u{2029}24.0\u{200E}\u{200F})",
        "Rig(nodes: { \"a\": r#joint() })",
        "#![enable(implicit_some)] Rig(name: \"a\")",
        "#![enable(\n  implicit_some,\n  unwrap_newtypes,\n)]\nRig(name: \"a\")",
        "Rig(uses: [(component: \"leg\", mirror: Some(YZ))])",
        "Rig(fps: -0)",
        "Rig(name: r##\"a \"# b\"##, fps: 1_000.5e-2)",
        "/* a /* nested */ comment */ Rig()",
    ];
    for c in cases {
        ron::from_str::<ron::Value>(c).unwrap_or_else(|e| panic!("ron refuses {c:?}: {e}"));
        agree(c).unwrap_or_else(|e| panic!("{e}"));
    }
    // Typed: `-0` in a float slot is -0.0, as `ron` reads it into an f64.
    let x: f64 = ron::from_str("-0").expect("ron reads -0");
    assert!(x == 0.0 && x.is_sign_negative());
    let reg = testing::registry().expect("test registry");
    let r = load_rig_str(
        "Rig(nodes: { \"a\": testJoint(translate: (-0, 0x18, 24.0f64), rotateOrder: 0b11) })",
        Path::new("mem.ron"),
        &reg,
    )
    .unwrap_or_else(|d| panic!("{}", d.render()));
    let t = r
        .graph
        .stored(r.graph.plug("a.translate").expect("plug"))
        .expect("value");
    let crate::value::Value::Vec3(v) = t else {
        panic!("{t:?}")
    };
    assert!(v.x == 0.0 && v.x.is_sign_negative());
    assert_eq!((v.y, v.z), (24.0, 24.0));
    assert_eq!(
        r.graph
            .stored(r.graph.plug("a.rotateOrder").expect("plug"))
            .and_then(|v| v.as_f64()),
        Some(3.0)
    );
    // The other direction: sinew no longer accepts any `#` line at the top.
    for bad in ["# a comment\nRig()", "#!enable(x)\nRig()", "#![enable(no_such)] Rig()"] {
        assert!(ron::from_str::<ron::Value>(bad).is_err(), "{bad:?}");
        assert!(parse(bad, &Arc::new(PathBuf::from("t.ron"))).is_err(), "{bad:?}");
    }
}

/// An invisible character where a value belongs is named by its code point, never
/// printed bare.
#[test]
fn invisible_characters_are_named_in_errors() {
    let e = parse("Rig(name: \u{200B}\"a\")", &Arc::new(PathBuf::from("t.ron"))).expect_err("zero width space");
    assert!(e.message.contains("U+200B"), "{}", e.message);
    assert!(!e.message.contains('\u{200B}'));
}

// --- generated documents ---

fn ws() -> impl Strategy<Value = String> {
    prop::collection::vec(
        prop_oneof![
            4 => Just(" ".to_string()),
            2 => Just("\n".to_string()),
            1 => Just("\t".to_string()),
            1 => Just("\r\n".to_string()),
            1 => prop::sample::select(vec!["\u{0B}", "\u{0C}", "\u{85}", "\u{200E}", "\u{200F}", "\u{2028}", "\u{2029}"])
                .prop_map(str::to_string),
            1 => Just("// line comment\n".to_string()),
            1 => Just("/* block /* nested */ comment */".to_string()),
            1 => Just("/**/".to_string()),
        ],
        0..3,
    )
    .prop_map(|v| v.concat())
}

fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        (any::<i32>()).prop_map(|i| i.to_string()),
        (any::<i64>()).prop_map(|i| i.to_string()),
        (0u64..u64::MAX).prop_map(|i| i.to_string()),
        (any::<u16>()).prop_map(|i| format!("{i:#x}")),
        (any::<u16>()).prop_map(|i| format!("-{i:#o}")),
        (any::<u8>()).prop_map(|i| format!("+{i:#b}")),
        (any::<u8>()).prop_map(|i| format!("{}_{}", i, i % 10)),
        (-1e6f64..1e6).prop_map(|x| format!("{x}")),
        (-1e6f64..1e6).prop_map(|x| format!("{x:e}")),
        (any::<f32>())
            .prop_filter("finite", |x| x.is_finite())
            .prop_map(|x| format!("{x:?}f32")),
        (any::<i16>()).prop_map(|i| format!("{i}i16")),
        (any::<u8>()).prop_map(|i| format!("{i}u8")),
        (any::<i32>()).prop_map(|i| format!("{i}.0f64")),
        prop::sample::select(vec![
            "-0",
            "+0",
            "0.",
            ".5",
            "-.5",
            "1e5",
            "1E-5",
            "2.5e+3",
            "1_000_000",
            "0x_1",
            "_1",
            "1__0",
            "1._5",
            "0b102",
            "0o8",
            "300u8",
            "-1u8",
            "1e",
            "1.5.3",
            "0X18",
            "12ab",
            "1f32",
            "1_f32",
            "9223372036854775808",
            "-9223372036854775809",
            "18446744073709551616",
            "1e999",
            "--1",
            "+-1",
            "-",
            ".",
        ])
        .prop_map(str::to_string),
    ]
}

fn string() -> impl Strategy<Value = String> {
    prop_oneof![
        "[a-z é😀\\n]{0,8}".prop_map(|s| format!("{s:?}")),
        prop::sample::select(vec![
            r#""\x61\x7F""#,
            r#""\xC3\xA9""#,
            r#""\xC3""#,
            r#""\xZZ""#,
            r#""\u{41}\u{1F600}""#,
            r#""\u{}""#,
            r#""\u{D800}""#,
            r#""\u{1234567}""#,
            "\"a\\\n    b\"",
            "\"a\\\r\n\tb\"",
            r#""\n\r\t\0\\\"\'""#,
            r#""\q""#,
            r#""\b""#,
            "\"multi\nline\"",
            r#"r"raw \n""#,
            r###"r#"a "quoted" b"#"###,
            r###"r##"a "# b"##"###,
            r#"r#"unterminated""#,
            r#""unterminated"#,
        ])
        .prop_map(str::to_string),
    ]
}

fn ident() -> impl Strategy<Value = String> {
    prop_oneof![
        "[a-zA-Z_][a-zA-Z0-9_]{0,6}".prop_filter("keywords", |s| {
            !matches!(
                s.as_str(),
                "true" | "false" | "Some" | "None" | "inf" | "NaN" | "r" | "b" | "br"
            ) && !s.starts_with("inf")
                && !s.starts_with("NaN")
        }),
        prop::sample::select(vec!["r#joint", "r#type", "r#a.b", "r#true", "héllo", "ñ_1", "_", "xzy"])
            .prop_map(str::to_string),
    ]
}

fn atom() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => number(),
        2 => string(),
        2 => ident(),
        1 => prop::sample::select(vec!["true", "false", "None", "()"]).prop_map(str::to_string),
    ]
}

fn value() -> impl Strategy<Value = String> {
    atom().prop_recursive(4, 40, 5, |inner| {
        let entries = prop::collection::vec((ws(), inner.clone(), ws()), 0..5)
            .prop_map(|v| v.into_iter().map(|(a, x, b)| format!("{a}{x}{b}")).collect::<Vec<_>>())
            .boxed();
        prop_oneof![
            (entries.clone(), any::<bool>()).prop_map(|(v, t)| format!(
                "[{}{}]",
                v.join(","),
                if t && !v.is_empty() { "," } else { "" }
            )),
            (entries.clone(), any::<bool>()).prop_map(|(v, t)| format!(
                "({}{})",
                v.join(","),
                if t && !v.is_empty() { "," } else { "" }
            )),
            (ident(), entries.clone()).prop_map(|(n, v)| format!("{n}({})", v.join(","))),
            (
                prop::collection::vec((ident(), ws(), inner.clone()), 1..4),
                any::<bool>()
            )
                .prop_map(|(v, named)| {
                    let body: Vec<String> = v.iter().map(|(k, w, x)| format!("{k}{w}:{x}")).collect();
                    if named {
                        format!("S({})", body.join(","))
                    } else {
                        format!("({})", body.join(","))
                    }
                }),
            prop::collection::vec((inner.clone(), ws(), inner.clone()), 0..4).prop_map(|v| format!(
                "{{{}}}",
                v.iter()
                    .map(|(k, w, x)| format!("{k}{w}: {x}"))
                    .collect::<Vec<_>>()
                    .join(",")
            )),
            inner.clone().prop_map(|v| format!("Some({v})")),
        ]
    })
}

fn document() -> impl Strategy<Value = String> {
    (
        prop::sample::select(vec![
            "",
            "#![enable(implicit_some)]\n",
            "#![enable(unwrap_newtypes, implicit_some,)] ",
        ]),
        ws(),
        value(),
        ws(),
    )
        .prop_map(|(h, a, v, b)| format!("{h}{a}{v}{b}"))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    /// Generated documents: sinew and `ron` agree on accept/reject and on the value.
    #[test]
    fn sinew_and_ron_agree_on_generated_documents(doc in document()) {
        if let Err(e) = agree(&doc) {
            prop_assert!(false, "{}", e);
        }
    }
}

/// The generator reaches both outcomes: a sample of generated documents has accepted
/// and refused ones (so agreement is not vacuous).
#[test]
fn generated_documents_are_both_accepted_and_refused() {
    use proptest::strategy::ValueTree;
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let (mut ok, mut bad) = (0, 0);
    for _ in 0..200 {
        let doc = document().new_tree(&mut runner).expect("tree").current();
        match ron::from_str::<ron::Value>(&doc) {
            Ok(_) => ok += 1,
            Err(_) => bad += 1,
        }
    }
    assert!(ok >= 40 && bad >= 20, "accepted {ok}, refused {bad}");
}
