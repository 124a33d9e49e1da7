//! `sinew view` as a command, without a browser: its status lines follow the CLI's output
//! rules (a closed standard output ends it quietly with exit 0, another write error exits
//! 1 naming it), and a build without the `view` feature says the viewer is not built in.

use std::process::{Command, Stdio};
#[cfg(feature = "view")]
use std::time::{Duration, Instant};

const SINEW: &str = env!("CARGO_BIN_EXE_sinew");
const STRIP: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/graphs/tests/view/skinned_strip.ron");

/// Waits for `child` to exit, at most `limit`.
#[cfg(feature = "view")]
fn wait_exit(child: &mut std::process::Child, limit: Duration, mut poke: impl FnMut()) -> std::process::ExitStatus {
    let started = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status;
        }
        if started.elapsed() > limit {
            let _ = child.kill();
            panic!("sinew view did not exit within {limit:?}");
        }
        poke();
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[cfg(feature = "view")]
#[test]
fn view_status_lines_follow_the_output_rules() {
    // A write error other than a closed pipe: exit 1, named.
    if std::path::Path::new("/dev/full").exists() {
        let out = Command::new(SINEW)
            .args(["view", STRIP, "--port", "0"])
            .stdout(std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap())
            .stderr(Stdio::piped())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(err.contains("error: cannot write to standard output"), "{err}");
    } else {
        eprintln!("no /dev/full here: the write-error case is not checked");
    }

    // A closed pipe: the next status line (a reload's) ends the viewer quietly, exit 0.
    let dir = std::env::temp_dir().join(format!("sinew-view-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let rig = dir.join("strip.ron");
    let text = std::fs::read_to_string(STRIP).unwrap();
    std::fs::write(&rig, &text).unwrap();
    let mut child = Command::new(SINEW)
        .args(["view", rig.to_str().unwrap(), "--port", "0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdout = child.stdout.take().unwrap();
    let mut first = [0u8; 12];
    std::io::Read::read_exact(&mut stdout, &mut first).unwrap();
    assert_eq!(&first, b"sinew view: ");
    drop(stdout);
    // Saves until the watcher sees one (it starts watching after the first line).
    let status = wait_exit(&mut child, Duration::from_secs(60), || {
        std::fs::write(&rig, &text).unwrap()
    });
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    assert!(status.success(), "{status:?}: {err}");
    assert_eq!(err, "", "a closed pipe ends quietly");
    let _ = std::fs::remove_dir_all(&dir);
}

#[cfg(not(feature = "view"))]
#[test]
fn view_says_it_is_not_built_in() {
    let out = Command::new(SINEW)
        .args(["view", STRIP, "--port", "0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("built without the viewer"), "{err}");
    let out = Command::new(SINEW).args(["graph", STRIP, "--svg"]).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("without the `view` feature"), "{err}");
    // Everything else works: the rig evaluates.
    let out = Command::new(SINEW)
        .args(["eval", STRIP, "--frames", "1", "--print", "tip.worldMatrix"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}
