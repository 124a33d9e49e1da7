//! A rig file's expression is compiled when the rig loads: a mistake is
//! reported at its file:line:col inside the string literal (raw, multi-line or
//! with escapes), so `sinew check` catches it.

use std::path::Path;

use sinew::core::load_rig_str;

/// Loads `text` as `mem/rig.ron`; returns the first error as `line:col: message (hint)`.
fn first_error(text: &str) -> String {
    let registry = sinew::default_registry().expect("registry");
    match load_rig_str(text, Path::new("mem/rig.ron"), &registry) {
        Ok(_) => "loaded".to_string(),
        Err(d) => {
            let e = &d.errors[0];
            format!(
                "{}:{}: {} ({})",
                e.span.line,
                e.span.col,
                e.message,
                e.hint.clone().unwrap_or_default()
            )
        }
    }
}

#[test]
fn expression_errors_point_into_the_rig_file() {
    // A raw multi-line string: line 4 of the file, `spede` at column 21.
    let raw = "Rig(name: \"r\", nodes: {\n  \"e\": expression(expression: r#\"\n    in speed\n    out y; out.y = spede * 2\n  \"#),\n})\n";
    let e = first_error(raw);
    assert!(e.starts_with("4:20: `expression`: unknown name `spede`"), "{e}");
    assert!(e.contains("did you mean `speed`?"), "{e}");
    // A one-line string with an escape before the mistake: `\"` is two characters in the
    // file and one in the value.
    let esc = "Rig(name: \"r\", nodes: { \"e\": expression(expression: \"out y; out.y = 1 \\t+ wat\") })";
    let e = first_error(esc);
    let col = esc.find("wat").unwrap() + 1;
    assert!(
        e.starts_with(&format!("1:{col}: `expression`: unknown name `wat`")),
        "{e}"
    );
    // A valid expression loads.
    let ok = "Rig(name: \"r\", nodes: { \"e\": expression(expression: \"out y; out.y = sin(time)\") })";
    assert_eq!(first_error(ok), "loaded");
}
