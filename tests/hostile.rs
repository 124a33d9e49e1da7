//! Hostile input (#22): every case the issue lists, run through the `sinew` binary under a
//! wall-clock timeout and an address-space cap, so a hang fails the test instead of CI and
//! an allocation blow-up aborts the child (a crash the test reports) instead of the machine.
//!
//! Each case asserts the outcome a user gets: a clean error naming the place and the limit
//! (exit code 1, no panic), or the correct result. The fast loaders' own unit tests pin
//! the details; this suite pins that the whole command stays bounded. Big inputs are
//! generated in the test; the cases are grouped as the issue groups them:
//! - `crashes`: extreme frame ranges, closed pipes and full disks, sparse indices, endless
//!   and oversized files, huge glTF accessor counts, deep nesting;
//! - `hangs`: exponential components, large multis, long chains, streamed output;
//! - `damage`: outputs that would overwrite inputs, large sidecars that must read back.
//!
//! Altered compiled-rig bytes have no CLI path (only `Runtime::load_rig_bytes` and the C
//! API's `sinew_rig_load_bytes` read them): runtime/tests/runtime.rs and
//! core/tests/program_bin.rs cover them, and the `load_rig_bytes` fuzz target.

#[path = "hostile/crashes.rs"]
mod crashes;
#[path = "hostile/damage.rs"]
mod damage;
#[path = "hostile/hangs.rs"]
mod hangs;

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Address-space cap of every child, in KiB (`ulimit -v`): well above what these small
/// inputs need, far below the gigabytes the bugs allocated.
const MEMORY_CAP_KIB: u64 = 3 << 20;
/// CPU-time cap of every child, in seconds (`ulimit -t`): a hang that computes is killed
/// after this much CPU however busy the machine is (each case needs a few seconds of CPU
/// in a debug build).
const CPU_CAP_SECS: u64 = 60;
/// Wall-clock cap of every child: catches a hang that waits instead of computing. Long,
/// because a shared CI machine may give a child a small share of a core.
const TIMEOUT: Duration = Duration::from_secs(300);

/// What a finished `sinew` run gave.
struct Run {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

/// A `sinew` command with `args` under the memory and CPU caps (through
/// `sh -c 'ulimit -v ... -t ...'`).
fn capped(args: &[&str]) -> Command {
    let mut c = Command::new("sh");
    c.arg("-c")
        .arg(format!(
            "ulimit -v {MEMORY_CAP_KIB} && ulimit -t {CPU_CAP_SECS} && exec \"$0\" \"$@\""
        ))
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

/// A fresh folder `name` under this run's one temporary folder.
fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir()
        .join(format!("sinew-hostile-{}", std::process::id()))
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes `text` to `d/name`; returns the path as a string for the command line.
fn write(d: &Path, name: &str, text: impl AsRef<[u8]>) -> String {
    let p = d.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

/// A small example rig with a `wrist_L` joint.
const ARM: &str = "graphs/examples/arm.ron";

/// Starts `sinew args`, reads the first `n` lines of its output, then closes the pipe (as
/// `| head -n` does). Fails if the lines do not arrive within [`TIMEOUT`] (output held
/// back until the end) or the process does not end quietly after the pipe closes.
fn first_lines_then_close(args: &[&str], n: usize) -> Vec<String> {
    use std::io::BufRead;
    let what = format!("sinew {} | head -n {n}", args.join(" "));
    let mut child = capped(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let out = child.stdout.take().unwrap();
    let (send, recv) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        // The reader (and with it the pipe) is dropped when the thread ends.
        let lines: Vec<String> = std::io::BufReader::new(out)
            .lines()
            .take(n)
            .map_while(Result::ok)
            .collect();
        let _ = send.send(lines);
    });
    let lines = match recv.recv_timeout(TIMEOUT) {
        Ok(lines) => lines,
        Err(_) => {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what}: no output within {TIMEOUT:?} (not streamed)");
        }
    };
    let status = wait_bounded(&mut child, &what);
    let mut err = String::new();
    child.stderr.take().unwrap().read_to_string(&mut err).unwrap();
    assert_eq!(status.code(), Some(0), "{what}: a broken pipe is a normal end: {err}");
    assert!(err.is_empty(), "{what}: nothing on stderr: {err}");
    lines
}
