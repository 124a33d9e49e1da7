//! Hostile input (#22): every case the issue lists, run through the `sinew` binary under a
//! wall-clock timeout and an address-space cap, so a hang fails the test instead of CI and
//! an allocation blow-up aborts the child (a crash the test reports) instead of the machine.
//!
//! Each case asserts the outcome a user gets: a clean error naming the place and the limit
//! (exit code 1, no panic), or the correct result. The fast loaders' own unit tests pin
//! the details; this suite pins that the whole command stays bounded.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Address-space cap of every child, in KiB (`ulimit -v`): well above what these small
/// inputs need, far below the gigabytes the bugs allocated.
const MEMORY_CAP_KIB: u64 = 3 << 20;
/// Wall-clock cap of every child (debug build on a shared 2-core machine).
const TIMEOUT: Duration = Duration::from_secs(60);

struct Run {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

/// A `sinew` command with `args` under the memory cap (through `sh -c 'ulimit -v ...'`).
fn capped(args: &[&str]) -> Command {
    let mut c = Command::new("sh");
    c.arg("-c")
        .arg(format!("ulimit -v {MEMORY_CAP_KIB} && exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_sinew"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"));
    c
}

/// Waits for `child` at most [`TIMEOUT`]; kills it and fails the test on timeout.
fn wait_bounded(child: &mut std::process::Child, what: &str) -> std::process::ExitStatus {
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status;
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what}: still running after {TIMEOUT:?} (a hang)");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Runs `sinew args` to the end under both caps; asserts no panic and no abort.
fn sinew(args: &[&str]) -> Run {
    let what = format!("sinew {}", args.join(" "));
    let mut child = capped(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let (mut out, mut err) = (child.stdout.take().unwrap(), child.stderr.take().unwrap());
    let out_t = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = out.read_to_end(&mut s);
        s
    });
    let err_t = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = err.read_to_end(&mut s);
        s
    });
    let status = wait_bounded(&mut child, &what);
    let run = Run {
        code: status.code(),
        stdout: String::from_utf8_lossy(&out_t.join().unwrap()).into_owned(),
        stderr: String::from_utf8_lossy(&err_t.join().unwrap()).into_owned(),
    };
    assert!(
        run.code.is_some() && !run.stderr.contains("panicked"),
        "{what}: crashed ({status}): {}",
        run.stderr
    );
    run
}

/// `sinew args` must fail with exit code 1 and a message containing every one of `needles`.
fn refused(args: &[&str], needles: &[&str]) -> String {
    let r = sinew(args);
    assert_eq!(r.code, Some(1), "sinew {args:?} should fail: {}{}", r.stdout, r.stderr);
    for n in needles {
        assert!(r.stderr.contains(n), "sinew {args:?}: {n:?} missing from: {}", r.stderr);
    }
    r.stderr
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sinew-hostile-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn write(d: &Path, name: &str, text: impl AsRef<[u8]>) -> String {
    let p = d.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

const ARM: &str = "graphs/examples/arm.ron";

// ---------------------------------------------------------------- crashes and aborts

#[test]
fn a_closed_pipe_ends_quietly_and_a_full_disk_is_an_error() {
    // 1,000,000 frames: the reader takes 100 bytes and closes the pipe.
    let mut child = capped(&["eval", ARM, "--frames", "0..=1000000", "--print", "wrist_L.translate"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = [0u8; 100];
    child.stdout.as_mut().unwrap().read_exact(&mut first).unwrap();
    drop(child.stdout.take());
    let status = wait_bounded(&mut child, "eval | head -c 100");
    let mut err = String::new();
    child.stderr.take().unwrap().read_to_string(&mut err).unwrap();
    assert_eq!(status.code(), Some(0), "a broken pipe is a normal end: {err}");
    assert!(err.is_empty(), "nothing on stderr: {err}");
    if Path::new("/dev/full").exists() {
        let full = std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
        let mut child = capped(&["eval", ARM, "--frames", "0..=10000", "--print", "wrist_L.translate"])
            .stdout(full)
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let status = wait_bounded(&mut child, "eval > /dev/full");
        let mut err = String::new();
        child.stderr.take().unwrap().read_to_string(&mut err).unwrap();
        assert_eq!(status.code(), Some(1), "{err}");
        assert!(
            !err.contains("panicked") && err.to_lowercase().contains("space"),
            "{err}"
        );
    }
}

#[test]
fn sparse_indices_never_size_an_allocation() {
    let d = dir("sparse");
    let m = "(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1)";
    for attr in ["matrix", "bindPreMatrix"] {
        let rig = write(
            &d,
            &format!("{attr}.ron"),
            format!("Rig(\n    nodes: {{\n        \"s\": skinCluster({attr}: {{100000000: {m}}}),\n    }},\n)\n"),
        );
        refused(
            &["check", &rig],
            &[&format!("{attr}.ron:3:"), "above the limit of 1048575"],
        );
    }
    let rig = write(
        &d,
        "connect.ron",
        "Rig(\n    nodes: { \"j\": joint(), \"s\": skinCluster() },\n    connections: [\"j.worldMatrix -> s.matrix[4000000000]\"],\n)\n",
    );
    refused(&["check", &rig], &["connect.ron:3:", "limit"]);
}

// ---------------------------------------------------------------- silent damage

#[test]
fn outputs_never_overwrite_inputs() {
    let d = dir("overwrite");
    let bvh_text = "HIERARCHY\nROOT a\n{\n OFFSET 0 0 0\n CHANNELS 3 Zrotation Xrotation Yrotation\n End Site\n {\n OFFSET 0 1 0\n }\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n0 0 0\n";
    let bvh = write(&d, "in.bvh", bvh_text);
    refused(&["import", &bvh, "-o", &bvh], &[]);
    assert_eq!(
        std::fs::read_to_string(&bvh).unwrap(),
        bvh_text,
        "the input is untouched"
    );
    let obj_text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let obj = write(&d, "in.obj", obj_text);
    refused(&["skeletonize", &obj, "-o", &obj], &[]);
    assert_eq!(std::fs::read_to_string(&obj).unwrap(), obj_text);
    let gltf_text = r#"{"asset":{"version":"2.0"},"nodes":[{"name":"a"}],"scenes":[{"nodes":[0]}]}"#;
    let gltf = write(&d, "in.gltf", gltf_text);
    refused(&["import", &gltf, "-o", &gltf], &[]);
    assert_eq!(std::fs::read_to_string(&gltf).unwrap(), gltf_text);
}

#[test]
fn a_60000_frame_take_round_trips_through_import_and_check() {
    let d = dir("longtake");
    let frames = 60_000;
    let mut text = String::from(
        "HIERARCHY\nROOT hip\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n \
         JOINT knee\n {\n  OFFSET 0 -1 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {\n   OFFSET 0 -1 0\n  }\n }\n}\n",
    );
    text += &format!("MOTION\nFrames: {frames}\nFrame Time: 0.008333333\n");
    for f in 0..frames {
        let a = (f % 360) as f64;
        text += &format!("{} 0 0 {a} 0 0 0 {a} 0\n", f as f64 * 0.01);
    }
    let bvh = write(&d, "take.bvh", text);
    let out = d.join("take.ron");
    let out = out.to_str().unwrap();
    let r = sinew(&["import", &bvh, "-o", out]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let r = sinew(&["check", out]);
    assert_eq!(
        r.code,
        Some(0),
        "a file sinew writes is a file sinew reads: {}",
        r.stderr
    );
    // The last frame's root x is 59,999 × 0.01.
    let r = sinew(&["eval", out, "--frames", "59999", "--print", "hip.translateX"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert!(r.stdout.contains("599.99"), "{}", r.stdout);
}
