//! Determinism: the same inputs give bit-identical outputs across runs, rayon
//! thread counts (1, 2, 4) and batch sizes, for joint matrices, palettes and
//! skinned meshes.

mod common;

use glam::DVec3;
use sinew_runtime::{evaluate_batch, Rig, RigInstance, Runtime, Time};

/// Per-instance inputs that differ between instances (a look target and a foot offset).
fn drive(rig: &Rig, instances: &mut [RigInstance], first: usize, frame: usize) {
    let look = rig.input::<DVec3>("look_ctrl.translate").unwrap();
    let foot = rig.input::<f64>("foot_ctrl_L.translateX").unwrap();
    let pole = rig.input::<DVec3>("leg_pole_ctrl_R.translate").unwrap();
    for (k, inst) in instances.iter_mut().enumerate() {
        let i = (first + k) as f64;
        let f = frame as f64;
        inst.set(
            &look,
            DVec3::new(0.3 * (i * 0.37 + f * 0.1).sin(), 0.68, 0.6 + 0.01 * i),
        )
        .unwrap();
        inst.set(&foot, 0.1 + 0.03 * (i * 0.11 + f * 0.2).cos()).unwrap();
        inst.set(&pole, DVec3::new(-0.05 * (i * 0.5).sin(), 0.43, 0.5)).unwrap();
    }
}

/// Every output of every instance over several frames, as bits.
fn run(rig: &Rig, count: usize, batch: usize, threads: usize) -> Vec<u64> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    let mut instances: Vec<RigInstance> = (0..count).map(|_| rig.instantiate()).collect();
    let mut out = Vec::new();
    for frame in 0..4 {
        for (c, chunk) in instances.chunks_mut(batch).enumerate() {
            drive(rig, chunk, c * batch, frame);
            pool.install(|| evaluate_batch(chunk, Time::new(1.0 + 5.5 * frame as f64, rig.fps())))
                .unwrap();
        }
        for inst in &instances {
            for j in 0..rig.joint_count() {
                out.extend(inst.joint_matrix(j).to_cols_array().map(f64::to_bits));
            }
            for s in 0..rig.skin_count() {
                let p = inst.palette(s).unwrap();
                out.extend(p.iter().flat_map(|m| m.to_cols_array().map(f64::to_bits)));
                let mesh = inst.skinned_mesh(s).unwrap();
                out.extend(
                    mesh.positions
                        .iter()
                        .flat_map(|v| v.to_array().map(|x| x.to_bits() as u64)),
                );
                out.extend(
                    mesh.normals
                        .iter()
                        .flat_map(|v| v.to_array().map(|x| x.to_bits() as u64)),
                );
            }
        }
    }
    out
}

#[test]
fn biped_is_bit_identical_across_threads_batches_and_runs() {
    let rt = Runtime::new().unwrap();
    let rig = common::load_biped(&rt);
    let reference = run(&rig, 24, 24, 1);
    assert_eq!(run(&rig, 24, 24, 1), reference, "second run");
    for (threads, batch) in [(2, 24), (4, 24), (2, 5), (4, 1), (1, 7)] {
        assert_eq!(
            run(&rig, 24, batch, threads),
            reference,
            "{threads} threads, batches of {batch}"
        );
    }
    // A rig reloaded from its compiled bytes too.
    let reloaded = rt.load_rig_bytes(&rig.to_bytes()).unwrap();
    assert_eq!(run(&reloaded, 24, 8, 2), reference, "reloaded from bytes");
}

#[test]
fn skinned_biped_is_bit_identical_across_threads_and_batches() {
    let rt = Runtime::new().unwrap();
    // Above the skinCluster's parallel threshold, so the skinning kernel itself runs on rayon too.
    let rig = common::load_skinned_biped(&rt, 20_000, &common::biped_options());
    let mut probe = rig.instantiate();
    probe.evaluate_frame(1.0).unwrap();
    assert!(probe.skinned_mesh(0).unwrap().positions.len() >= sinew_nodes::deform::skin_cluster::PARALLEL_THRESHOLD);
    let reference = run(&rig, 6, 6, 1);
    for (threads, batch) in [(2, 6), (4, 6), (4, 1), (2, 4)] {
        assert_eq!(
            run(&rig, 6, batch, threads),
            reference,
            "{threads} threads, batches of {batch}"
        );
    }
}
