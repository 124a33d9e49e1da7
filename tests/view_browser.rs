//! `sinew view` in a real browser: starts the viewer on a free port and drives headless
//! Chromium through chromedriver (WebDriver over HTTP). Checks that the page loads without
//! console errors, draws as many joints as the rig has, that a slider edit moves the
//! expected joint to where `sinew eval` puts it (bit for bit) and changes the screenshot
//! around that joint only, that a broken save shows its `file:line:col` error over the
//! last good scene and the fix restores it, and that the deformed mesh drawn equals
//! `sinew eval`'s output. Skips with a message where Chromium or chromedriver is missing.
//! With `SINEW_UPDATE_SCREENSHOTS=1` it also writes the screenshots in docs/images/.
#![cfg(feature = "view")]

#[path = "support/browser.rs"]
mod browser;

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use browser::{chromium, epoch_ms, image, save_screenshot, serve, Browser, SINEW};
use serde_json::{json, Value};

/// `sinew eval` of one plug at one frame as numbers (parsed exactly from its CSV).
fn eval(rig: &Path, frame: u32, plug: &str, set: &[&str]) -> Vec<f64> {
    let mut cmd = Command::new(SINEW);
    cmd.args([
        "eval",
        rig.to_str().unwrap(),
        "--frames",
        &frame.to_string(),
        "--print",
        plug,
    ]);
    for s in set {
        cmd.args(["--set", s]);
    }
    let out = cmd.output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    let row = text.lines().nth(1).expect("a row");
    row.split(',').skip(1).map(|x| x.parse().unwrap()).collect()
}

/// The page's numbers for a drawn item's matrix, exactly (as decimal strings).
fn page_matrix(b: &Browser, name: &str) -> Vec<f64> {
    let v = b.js(&format!(
        "const s = window.sinew; const i = s.scene.items.findIndex((x) => x.name === {name:?});
         return Array.from(new Float64Array(s.buffer, i * 128, 16)).map(String);"
    ));
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_str().unwrap().parse().unwrap())
        .collect()
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
}

/// Pixels that differ between two screenshots inside `rect` (x, y, w, h): their count and
/// bounding box.
fn diff(
    a: &image::Rgba,
    b: &image::Rgba,
    rect: (usize, usize, usize, usize),
) -> (usize, Option<(usize, usize, usize, usize)>) {
    let (mut n, mut bbox) = (0, None::<(usize, usize, usize, usize)>);
    for y in rect.1..(rect.1 + rect.3).min(a.height) {
        for x in rect.0..(rect.0 + rect.2).min(a.width) {
            let i = (y * a.width + x) * 4;
            let d: i32 = (0..3)
                .map(|c| (a.data[i + c] as i32 - b.data[i + c] as i32).abs())
                .sum();
            if d > 30 {
                n += 1;
                bbox = Some(match bbox {
                    None => (x, y, x, y),
                    Some((x0, y0, x1, y1)) => (x0.min(x), y0.min(y), x1.max(x), y1.max(y)),
                });
            }
        }
    }
    (n, bbox)
}

#[test]
fn viewer_in_headless_chromium() {
    let Some((chromium, chromedriver)) = chromium("viewer_in_headless_chromium") else {
        return;
    };
    let started = Instant::now();
    let dir = std::env::temp_dir().join(format!("sinew-view-test-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    copy_dir(&root.join("graphs/examples/biped"), &dir.join("biped"));
    let rig = dir.join("biped/biped.ron");
    let (_server, url) = serve(&rig);
    let b = Browser::start(&chromium, &chromedriver, &dir);
    b.go(&url);
    b.wait("window.sinew && window.sinew.ready", "the page to load the scene");

    // No console errors; as many joints drawn as the rig has.
    assert_eq!(b.js("return window.__errors;"), json!([]));
    let registry = sinew::default_registry().unwrap();
    let loaded = sinew_core_load(&rig, &registry);
    let joints = loaded.iter().filter(|t| t.as_str() == "joint").count();
    assert!(joints > 50, "{joints}");
    assert_eq!(b.js("return window.sinew.jointCount;"), json!(joints));
    b.js("await window.sinew.setFrame(7); return 0;");
    save_screenshot(&b.screenshot().0, "viewer-biped.png");

    // Select the jaw control, drag its rotateX slider: the jaw's child joint moves to where
    // `sinew eval --set` puts it, bit for bit.
    b.js("await window.sinew.select('jaw_ctrl'); return 0;");
    b.wait(
        "document.querySelector('input[type=range][data-plug=\"jaw_ctrl.rotate#0\"]')",
        "the rotateX slider",
    );
    let before_png = b.screenshot();
    let jaw_before = b.js("return window.sinew.screenPosition('jaw_end');");
    let m_before = page_matrix(&b, "jaw_end");
    b.js(
        "const r = document.querySelector('input[type=range][data-plug=\"jaw_ctrl.rotate#0\"]');
          window.sinew.lastEdit = null; r.value = 40; r.dispatchEvent(new Event('input')); return 0;",
    );
    b.wait(
        "window.sinew.lastEdit && window.sinew.lastEdit.computes > 0",
        "the edit to be applied",
    );
    let edit = b.js("return window.sinew.lastEdit;");
    // Only what depends on jaw_ctrl.rotate recomputed: far fewer groups than the rig has.
    assert!(edit["computes"].as_u64().unwrap() < 40, "{edit}");
    // setAttr redraws the frame before the edit's promise settles; give the canvas a
    // couple of animation frames to present it.
    b.js("await new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))); return 0;");
    std::thread::sleep(Duration::from_millis(100));
    let m_after = page_matrix(&b, "jaw_end");
    let expected = eval(&rig, 7, "jaw_end.worldMatrix", &["jaw_ctrl.rotate=(40, 0, 0)"]);
    assert_ne!(m_before, m_after, "the joint did not move");
    assert_eq!(
        m_after.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        expected.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
    );
    // The screenshot changed around the jaw only (inside the 3D view).
    let after_png = b.screenshot();
    let jaw_after = b.js("return window.sinew.screenPosition('jaw_end');");
    let canvas = b.js("const r = document.querySelector('#viewport canvas').getBoundingClientRect(); return [r.x, r.y, r.width, r.height];");
    let c: Vec<usize> = canvas
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap() as usize)
        .collect();
    let (changed, bbox) = diff(&before_png.1, &after_png.1, (c[0], c[1], c[2], c[3]));
    let (x0, y0, x1, y1) = bbox.expect("the edit changed no pixel of the 3D view");
    assert!(
        changed < c[2] * c[3] / 50,
        "{changed} pixels changed: more than the jaw"
    );
    for p in [&jaw_before, &jaw_after] {
        let (px, py) = (
            p["x"].as_f64().unwrap() + c[0] as f64,
            p["y"].as_f64().unwrap() + c[1] as f64,
        );
        assert!(
            px >= x0 as f64 - 12.0 && px <= x1 as f64 + 12.0 && py >= y0 as f64 - 12.0 && py <= y1 as f64 + 12.0,
            "jaw_end at ({px}, {py}) outside the changed region {bbox:?}"
        );
    }
    save_screenshot(&after_png.0, "viewer-edit.png");

    // Hot reload: a broken save shows its file:line:col over the last good scene; the fix
    // restores it, and the edit stays.
    let good = std::fs::read_to_string(&rig).unwrap();
    let needle = "\"pelvis\": joint(parent";
    let at = good.find(needle).expect("the pelvis line");
    // The position of the misspelt type name: 1-based line and column.
    let line = good[..at].matches('\n').count() + 1;
    let col = at - good[..at].rfind('\n').map(|i| i + 1).unwrap_or(0) + "\"pelvis\": ".len() + 1;
    let rev = b.js("return window.sinew.revision;").as_u64().unwrap();
    let saved = Instant::now();
    std::fs::write(&rig, good.replacen(needle, "\"pelvis\": jiont(parent", 1)).unwrap();
    b.wait(
        &format!("window.sinew.revision > {rev} && !document.querySelector('#overlay').hidden"),
        "the error overlay",
    );
    let reload_ms = saved.elapsed().as_secs_f64() * 1e3;
    let overlay = b.js("return document.querySelector('#overlay').textContent;");
    let want = format!("biped.ron:{line}:{col}");
    assert!(
        overlay.as_str().unwrap().contains(&want),
        "{overlay} does not name {want}"
    );
    assert!(overlay.as_str().unwrap().contains("jiont"), "{overlay}");
    assert_eq!(
        b.js("return window.sinew.jointCount;"),
        json!(joints),
        "the last good scene stays"
    );
    save_screenshot(&b.screenshot().0, "viewer-error.png");
    let rev = b.js("return window.sinew.revision;").as_u64().unwrap();
    let saved_at = epoch_ms();
    std::fs::write(&rig, &good).unwrap();
    b.wait(
        &format!("window.sinew.revision > {rev} && document.querySelector('#overlay').hidden"),
        "the fixed scene",
    );
    // Where the reload's time went, from the save (the page records each reload's times
    // in epoch milliseconds: the server's file event and reload, then its own steps).
    b.wait(
        &format!("window.sinew.reloads.some((t) => t.pageRevision > {rev})"),
        "the reload's times",
    );
    let t = b.js(&format!(
        "return window.sinew.reloads.find((t) => t.pageRevision > {rev});"
    ));
    let at = |k: &str| t[k].as_f64().unwrap_or_else(|| panic!("no {k} in {t}")) - saved_at;
    // The server's steps in order, and the page's (each on its own clock).
    for steps in [
        &["eventAt", "reloadedAt"][..],
        &["sceneAt", "frameAt", "drawnAt", "panelsAt"],
    ] {
        for w in steps.windows(2) {
            assert!(at(w[0]) <= at(w[1]), "{} after {}: {t}", w[0], w[1]);
        }
    }
    eprintln!(
        "hot reload of the biped from the save: file event {:.1} ms, reloaded {:.1} ms, scene and frame \
         fetched {:.1} ms, drawn {:.1} ms, panels {:.1} ms",
        at("eventAt"),
        at("reloadedAt"),
        at("frameAt"),
        at("drawnAt"),
        at("panelsAt")
    );
    assert_eq!(
        page_matrix(&b, "jaw_end")
            .iter()
            .map(|x| x.to_bits())
            .collect::<Vec<_>>(),
        expected.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        "the edit survives the reload"
    );
    assert_eq!(b.js("return window.sinew.selected;"), json!("jaw_ctrl"));
    assert_eq!(b.js("return window.__errors;"), json!([]));
    eprintln!("broken save to error overlay: {reload_ms:.0} ms (through the page's polling)");

    // Playback: frames advance and are drawn (no rate asserted: the machine may be loaded).
    let played = Instant::now();
    b.js("window.sinew.framesShown = 0; window.sinew.setPlaying(true); return 0;");
    b.wait("window.sinew.framesShown >= 3", "three frames of playback");
    let shown = b
        .js("window.sinew.setPlaying(false); return window.sinew.framesShown;")
        .as_u64()
        .unwrap();
    eprintln!(
        "biped playback in the test browser: {shown} frames in {:.2} s (debug build)",
        played.elapsed().as_secs_f64()
    );

    // A skinned mesh: the vertices drawn equal sinew eval's deformed mesh.
    let strip = root.join("graphs/tests/view/skinned_strip.ron");
    let (_server2, url2) = serve(&strip);
    b.go(&url2);
    b.wait("window.sinew && window.sinew.ready", "the skinned strip");
    b.js("await window.sinew.setFrame(10); return 0;");
    let drawn = b.js("const m = window.sinew.scene.meshes[0];
        return [m.name, Array.from(new Float32Array(window.sinew.buffer.slice(m.offset, m.offset + m.vertices * 12))).map(String)];");
    assert_eq!(drawn[0], json!("skin"));
    let drawn: Vec<f32> = drawn[1]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_str().unwrap().parse().unwrap())
        .collect();
    let out = Command::new(SINEW)
        .args([
            "eval",
            strip.to_str().unwrap(),
            "--frames",
            "10",
            "--print",
            "skin.outputGeometry",
            "--format",
            "jsonl",
        ])
        .output()
        .unwrap();
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    // Positions as [x, y, z] per vertex, each f32 in its shortest decimal form.
    let want: Vec<f32> = v["values"]["skin.outputGeometry"]["positions"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|p| p.as_array().unwrap().iter().map(|x| x.as_f64().unwrap() as f32))
        .collect();
    assert_eq!(drawn, want);
    // Closed form: the tip vertex (-0.2, 1, 0), fully on the tip joint, turned 60° about Z
    // around (0, 1, 0) lands at (-0.2 cos 60°, 1 - 0.2 sin 60°).
    assert!((drawn[12] - (-0.1)).abs() < 1e-6 && (drawn[13] - (1.0 - 0.2 * 3f32.sqrt() / 2.0)).abs() < 1e-6);
    save_screenshot(&b.screenshot().0, "viewer-skin.png");
    assert_eq!(b.js("return window.__errors;"), json!([]));
    let _ = std::fs::remove_dir_all(&dir);
    eprintln!("browser test took {:.1} s", started.elapsed().as_secs_f64());
}

/// The node types of a rig, loaded through the library (independent of the viewer).
fn sinew_core_load(rig: &Path, registry: &std::sync::Arc<sinew::core::Registry>) -> Vec<String> {
    let loaded = sinew::io::mesh_file::load_rig(rig, registry).unwrap();
    let g = &loaded.graph;
    g.nodes()
        .into_iter()
        .filter_map(|n| g.node_type(n).map(str::to_string))
        .collect()
}
