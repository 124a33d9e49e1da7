//! How fast `sinew view` plays and reloads, in a real browser: the numbers docs/viewer.md
//! quotes. Plays the biped and a 20,000-vertex skin as fast as frames come (the page's
//! `measurePlayback`: server evaluation, transfer and drawing, one animation frame each)
//! and saves the biped five times to time the hot reload from the save. Saving a component
//! file and a mesh file the rigs use reloads them too (the mesh drawn from the new file).
//!
//! It asserts what it can justify (every frame shown, the whole deformed mesh transferred,
//! every reload reaching the page) and prints the rates; it asserts no wall-clock time.
//! For release numbers serve with a release build:
//! `cargo build --release && SINEW_VIEW_BIN=target/release/sinew cargo test --test view_rates -- --nocapture`.
//! Skips with a message where Chromium or chromedriver is missing.
#![cfg(feature = "view")]

#[path = "support/browser.rs"]
mod browser;

use std::fmt::Write as _;
use std::path::Path;

use browser::{chromium, epoch_ms, serve, view_bin, Browser};
use serde_json::{json, Value};

/// Columns and rows of the skinned grid: 200 × 100 = 20,000 vertices.
const GRID: (usize, usize) = (200, 100);

/// Writes a grid of `GRID` vertices (unit spacing / 10, in the XY plane) skinned to two
/// joints, the upper one bending over frames 1..48, with its OBJ beside it.
fn write_grid_rig(dir: &Path) -> std::path::PathBuf {
    let (nx, ny) = GRID;
    let mut obj = String::new();
    for j in 0..ny {
        for i in 0..nx {
            writeln!(obj, "v {} {} 0", i as f64 * 0.01, j as f64 * 0.02).unwrap();
        }
    }
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let v = |i: usize, j: usize| j * nx + i + 1;
            writeln!(obj, "f {} {} {}", v(i, j), v(i + 1, j), v(i + 1, j + 1)).unwrap();
            writeln!(obj, "f {} {} {}", v(i, j), v(i + 1, j + 1), v(i, j + 1)).unwrap();
        }
    }
    std::fs::write(dir.join("grid.obj"), obj).unwrap();
    // The weight of the upper joint rises linearly with height; the two always sum to one.
    let mut weights = String::new();
    for j in 0..ny {
        let w = j as f64 / (ny - 1) as f64;
        for _ in 0..nx {
            write!(weights, "[(0, {}), (1, {})], ", 1.0 - w, w).unwrap();
        }
    }
    let rig = format!(
        r#"Rig(
    name: "grid_skin",
    fps: 24.0,
    frames: (1, 48),
    nodes: {{
        "root": joint(),
        "upper": joint(parent: "root", translate: (0.0, 1.0, 0.0)),
        "bend": animCurveTA(keyTime: [1, 48], keyValue: [0.0, 90.0]),
        "grid": mesh(inMesh: File("grid.obj")),
        "skin": skinCluster(bind: (geometry: "grid", influences: ["root", "upper"]), weights: [{weights}]),
    }},
    connections: ["bend.output -> upper.rotateZ"],
)
"#
    );
    let path = dir.join("grid_skin.ron");
    std::fs::write(&path, rig).unwrap();
    path
}

/// Plays `frames` frames of the page's rig as fast as they come and prints the rate.
fn measure(b: &Browser, what: &str, frames: usize) -> Value {
    let m = b.js(&format!("return await window.sinew.measurePlayback({frames});"));
    assert_eq!(m["frames"], json!(frames), "{m}");
    let f = |k: &str| m[k].as_f64().unwrap_or_else(|| panic!("no {k} in {m}"));
    assert!(f("fps") > 0.0 && f("evalMs") >= 0.0, "{m}");
    eprintln!(
        "{what} ({}): {:.1} frames/s as fast as they come; per frame: server evaluation {:.3} ms, \
         request and transfer of {} bytes {:.2} ms, drawing {:.2} ms",
        view_bin(),
        f("fps"),
        f("evalMs"),
        m["frameBytes"],
        f("fetchMs"),
        f("drawMs")
    );
    m
}

#[test]
fn playback_and_reload_rates() {
    let Some((chromium, chromedriver)) = chromium("playback_and_reload_rates") else {
        return;
    };
    let dir = std::env::temp_dir().join(format!("sinew-view-rates-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("biped")).unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for e in std::fs::read_dir(root.join("graphs/examples/biped")).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), dir.join("biped").join(e.file_name())).unwrap();
    }
    let b = Browser::start(&chromium, &chromedriver, &dir);

    // The biped: playback, then five saves timed from the save to the page's panels.
    let rig = dir.join("biped/biped.ron");
    let (_biped, url) = serve(&rig);
    b.go(&url);
    b.wait("window.sinew && window.sinew.ready", "the biped");
    measure(&b, "biped", 48);
    let text = std::fs::read_to_string(&rig).unwrap();
    let mut reloads = Vec::new();
    for k in 0..5 {
        let rev = b.js("return window.sinew.revision;").as_u64().unwrap();
        let saved_at = epoch_ms();
        std::fs::write(&rig, format!("{text}// save {k}\n")).unwrap();
        b.wait(
            &format!("window.sinew.reloads.some((t) => t.pageRevision > {rev})"),
            "the reload's times",
        );
        let t = b.js(&format!(
            "return window.sinew.reloads.find((t) => t.pageRevision > {rev});"
        ));
        let at = |k: &str| t[k].as_f64().unwrap_or_else(|| panic!("no {k} in {t}")) - saved_at;
        assert_eq!(t["ok"], json!(true), "{t}");
        reloads.push((at("reloadedAt"), at("panelsAt")));
    }
    reloads.sort_by(|a, b| a.0.total_cmp(&b.0));
    eprintln!(
        "biped hot reload from the save, 5 saves ({}): server reloaded after {} ms; page redrawn with \
         its panels after {} ms",
        view_bin(),
        reloads
            .iter()
            .map(|r| format!("{:.0}", r.0))
            .collect::<Vec<_>>()
            .join(", "),
        reloads
            .iter()
            .map(|r| format!("{:.0}", r.1))
            .collect::<Vec<_>>()
            .join(", "),
    );
    // A component file the rig uses reloads it too.
    let arm = dir.join("biped/arm.ron");
    let rev = b.js("return window.sinew.revision;").as_u64().unwrap();
    let arm_text = std::fs::read_to_string(&arm).unwrap();
    std::fs::write(&arm, format!("{arm_text}// saved\n")).unwrap();
    b.wait(
        &format!("window.sinew.reloads.some((t) => t.pageRevision > {rev} && t.ok)"),
        "a reload after saving the arm component",
    );
    assert_eq!(b.js("return window.__errors;"), json!([]));

    // A 20,000-vertex skin: every frame carries the whole deformed mesh.
    let grid = write_grid_rig(&dir);
    let (_grid, url) = serve(&grid);
    b.go(&url);
    b.wait("window.sinew && window.sinew.ready", "the grid skin");
    let m = measure(&b, "20,000-vertex skin", 24);
    let bytes = m["frameBytes"].as_u64().unwrap();
    assert!(
        bytes >= (GRID.0 * GRID.1 * 12) as u64,
        "a frame of {bytes} bytes cannot hold 20,000 positions"
    );
    // Saving the mesh file reloads it: vertex 0, weighted fully to the root joint at the
    // origin, is drawn where the new file puts it.
    let rev = b.js("return window.sinew.revision;").as_u64().unwrap();
    let obj = std::fs::read_to_string(dir.join("grid.obj")).unwrap();
    let obj = obj.replacen("v 0 0 0\n", "v 0 0 5\n", 1);
    std::fs::write(dir.join("grid.obj"), obj).unwrap();
    b.wait(
        &format!("window.sinew.drawnRevision > {rev}"),
        "a reload after saving grid.obj",
    );
    let v0 = b.js("const m = window.sinew.scene.meshes[0];
        return Array.from(new Float32Array(window.sinew.buffer.slice(m.offset, m.offset + 12)));");
    let v0: Vec<f64> = v0.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    assert_eq!(v0, [0.0, 0.0, 5.0], "vertex 0 after the save");
    assert_eq!(b.js("return window.__errors;"), json!([]));
    drop((_biped, _grid, b));
    let _ = std::fs::remove_dir_all(&dir);
}
