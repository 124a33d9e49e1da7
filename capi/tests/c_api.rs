//! The C API from C: compiles `examples/c/biped.c` with the system `cc`
//! against the static and the shared library cargo built, runs it on the
//! example biped and checks its numbers against the Rust runtime; checks that
//! the committed header is what cbindgen generates (when cbindgen is installed).

use std::path::{Path, PathBuf};
use std::process::Command;

use glam::DVec3;
use sinew_runtime::{evaluate_batch, LoadOptions, Runtime, Time};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Builds `libsinew_capi.{a,so}` and returns the directory holding them.
///
/// `cargo test` builds the library only as an rlib and holds the lock on its
/// target directory while tests run, so this runs `cargo build` into a
/// separate target directory next to it (`<target>/c-api`; incremental after the first run).
fn lib_dir() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let target = exe.ancestors().nth(3).unwrap().to_path_buf();
    let dir = target.join("c-api");
    let status = Command::new(env!("CARGO"))
        .current_dir(repo())
        .args(["build", "--quiet", "-p", "sinew-capi", "--lib", "--target-dir"])
        .arg(&dir)
        .status()
        .expect("cargo runs");
    assert!(status.success(), "cargo build -p sinew-capi failed");
    dir.join("debug")
}

fn compile(dir: &Path, out: &Path, link_static: bool) {
    let mut cmd = Command::new("cc");
    cmd.arg(repo().join("examples/c/biped.c"))
        .arg("-std=c99")
        .arg("-Wall")
        .arg("-Werror")
        .arg("-I")
        .arg(repo().join("capi/include"))
        .arg("-o")
        .arg(out);
    if link_static {
        cmd.arg(dir.join("libsinew_capi.a"));
        // `rustc --print native-static-libs` for this target.
        cmd.args(["-lgcc_s", "-lutil", "-lrt", "-lpthread", "-lm", "-ldl", "-lc"]);
    } else {
        cmd.arg("-L")
            .arg(dir)
            .arg("-lsinew_capi")
            .arg(format!("-Wl,-rpath,{}", dir.display()));
    }
    let status = cmd.status().expect("the system C compiler `cc` runs");
    assert!(status.success(), "cc failed: {cmd:?}");
}

/// What the C program should print for joint positions: the same instances through the Rust API.
fn expected_joints() -> Vec<(String, i32, [f64; 3])> {
    let rt = Runtime::new().unwrap();
    let options = LoadOptions::default()
        .dynamic("look_ctrl.translate")
        .dynamic("foot_ctrl_*.translateX");
    let rig = rt
        .load_rig_file(repo().join("graphs/examples/biped/biped.ron"), &options)
        .unwrap();
    let look = rig.input::<DVec3>("look_ctrl.translate").unwrap();
    let foot = rig.input::<f64>("foot_ctrl_L.translateX").unwrap();
    let ikfk = rig.input::<f64>("arm_settings_L.ikFk").unwrap();
    let mut instances: Vec<_> = (0..4).map(|_| rig.instantiate()).collect();
    for (i, inst) in instances.iter_mut().enumerate() {
        inst.set(&look, DVec3::new(0.1 * i as f64, 0.7, 0.6)).unwrap();
        inst.set(&foot, 0.1 + 0.02 * i as f64).unwrap();
    }
    instances[3].set(&ikfk, 1.0).unwrap();
    evaluate_batch(&mut instances, Time::new(10.0, rig.fps())).unwrap();
    let last = &instances[3];
    rig.joints()
        .iter()
        .enumerate()
        .map(|(j, joint)| {
            let t = last.joint_matrix(j).as_mat4().w_axis;
            (
                joint.name.clone(),
                rig.parent_indices()[j],
                [t.x as f64, t.y as f64, t.z as f64],
            )
        })
        .collect()
}

fn run_and_check(binary: &Path) {
    let out = Command::new(binary)
        .arg(repo().join("graphs/examples/biped/biped.ron"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let expected = expected_joints();
    let lines: Vec<&str> = stdout.lines().collect();
    assert!(
        lines.contains(&format!("joints {}", expected.len()).as_str()),
        "{stdout}"
    );
    let joints: Vec<Vec<&str>> = lines
        .iter()
        .filter(|l| l.starts_with("joint "))
        .map(|l| l.split(' ').collect())
        .collect();
    assert_eq!(joints.len(), expected.len());
    for (got, (name, parent, t)) in joints.iter().zip(&expected) {
        assert_eq!(got[1], name);
        assert_eq!(got[2].parse::<i32>().unwrap(), *parent);
        for k in 0..3 {
            let v: f64 = got[3 + k].parse().unwrap();
            assert!((v - t[k]).abs() <= 1e-6, "{name}[{k}]: C {v} vs Rust {}", t[k]);
        }
    }
    let errors: Vec<&&str> = lines.iter().filter(|l| l.starts_with("error ")).collect();
    assert_eq!(errors.len(), 4, "{stdout}");
    assert!(
        errors[0].starts_with("error 5 ") && errors[0].contains("translate"),
        "{}",
        errors[0]
    );
    assert!(
        errors[1].starts_with("error 6 ") && errors[1].contains("99"),
        "{}",
        errors[1]
    );
    assert!(
        errors[2].starts_with("error 1 ") && errors[2].contains("null"),
        "{}",
        errors[2]
    );
    // A custom attribute's declared limits hold through the C API.
    assert!(
        errors[3].starts_with("error 6 ") && errors[3].contains("outside [0, 1]"),
        "{}",
        errors[3]
    );
    assert_eq!(lines.last(), Some(&"ok"));
}

#[test]
fn c_example_builds_and_evaluates_the_biped() {
    let tmp = std::env::temp_dir().join(format!("sinew-capi-test-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let dir = lib_dir();
    for link_static in [true, false] {
        let exe = tmp.join(if link_static { "biped_static" } else { "biped_shared" });
        compile(&dir, &exe, link_static);
        run_and_check(&exe);
    }
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn committed_header_matches_cbindgen() {
    let cbindgen = [
        "cbindgen".to_string(),
        format!("{}/.cargo/bin/cbindgen", std::env::var("HOME").unwrap_or_default()),
    ]
    .into_iter()
    .find(|c| {
        Command::new(c)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    });
    let Some(cbindgen) = cbindgen else {
        eprintln!("cbindgen is not installed (cargo install cbindgen); header check skipped");
        return;
    };
    let capi = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let out = std::env::temp_dir().join(format!("sinew-h-{}.h", std::process::id()));
    let status = Command::new(cbindgen)
        .current_dir(&capi)
        .args(["--config", "cbindgen.toml", "--crate", "sinew-capi", "--output"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let generated = std::fs::read_to_string(&out).unwrap();
    let _ = std::fs::remove_file(&out);
    let committed = std::fs::read_to_string(capi.join("include/sinew.h")).unwrap();
    assert!(
        generated == committed,
        "capi/include/sinew.h is stale: run `cbindgen --config cbindgen.toml --crate sinew-capi --output include/sinew.h` in capi/"
    );
}

/// The API refuses bad arguments with codes instead of crashing.
#[test]
fn null_and_bad_arguments_give_codes() {
    use sinew_capi::*;
    use std::ffi::CString;
    unsafe {
        assert_eq!(
            sinew_rig_load_file(std::ptr::null(), std::ptr::null(), 0, std::ptr::null_mut()),
            SinewStatus::SINEW_ERROR_NULL
        );
        let mut rig = std::ptr::null_mut();
        let p = CString::new("/nonexistent/rig.ron").unwrap();
        assert_eq!(
            sinew_rig_load_file(p.as_ptr(), std::ptr::null(), 0, &mut rig),
            SinewStatus::SINEW_ERROR_LOAD
        );
        assert!(rig.is_null());
        assert_eq!(
            sinew_rig_load_bytes(b"junk".as_ptr(), 4, &mut rig),
            SinewStatus::SINEW_ERROR_FORMAT
        );
        let text = CString::new("Rig(nodes: { \"j\": joint(translate: (1.0, 2.0, 3.0)) })").unwrap();
        assert_eq!(
            sinew_rig_load_text(text.as_ptr(), std::ptr::null(), 0, &mut rig),
            SinewStatus::SINEW_OK
        );
        let mut inst = std::ptr::null_mut();
        assert_eq!(sinew_instance_new(rig, &mut inst), SinewStatus::SINEW_OK);
        sinew_rig_free(rig); // the instance keeps the rig alive
        assert_eq!(sinew_instance_evaluate(inst, 1.0), SinewStatus::SINEW_OK);
        let mut m = [0f32; 16];
        assert_eq!(
            sinew_instance_joint_matrices(inst, m.as_mut_ptr(), 1),
            SinewStatus::SINEW_OK
        );
        assert_eq!(&m[12..15], &[1.0, 2.0, 3.0]);
        let mut n = 0usize;
        assert_eq!(
            sinew_instance_palette(inst, 0, std::ptr::null_mut(), 0, &mut n),
            SinewStatus::SINEW_ERROR_NOT_FOUND
        );
        let same = [inst, inst];
        assert_eq!(
            sinew_evaluate_batch(same.as_ptr(), 2, 1.0),
            SinewStatus::SINEW_ERROR_ARGUMENT
        );
        sinew_instance_free(inst);
        sinew_instance_free(std::ptr::null_mut());
    }
}
