//! Skinning throughput: 100,000 vertices, 4 influences each, 64 joints. In one run:
//! - `baseline_copy_inputs`: copies the bytes LBS reads for positions (positions + CSR
//!   weights) into output buffers: the memory-bandwidth floor; `baseline_copy_inputs_normals`
//!   copies the normals too, the floor of the `*_normals` cases;
//! - the raw kernels (`lbs_*`, `dqs_*`, serial and parallel, with and without normals), on
//!   raw weights (validated per vertex on every call) and, for `*_prepared`, on
//!   [`PreparedWeights`] validated once (what `skinCluster` caches);
//! - `node_skincluster_*_compiled`: a `skinCluster` node in a compiled program, one joint
//!   matrix set per frame (a dynamic input), so each iteration runs the palette and the
//!   deformation steps exactly as a game loop would.
//!
//! Criterion reports elements/s (vertices/s); divide 1e9 by it for ns per vertex. Before the
//! benchmarks, the node loop is also run with a counting allocator and the allocations per
//! compiled frame are printed, and so is an interleaved comparison: the two copies, LBS,
//! prepared LBS and prepared LBS with normals run alternately 300 times (each twice in a row,
//! the second run timed, so caches are warm as in criterion's loop) and the fastest and
//! median runs of each are reported with their ratios to the copy of the same bytes. Alternating makes the ratios immune to the machine's drift between
//! criterion's separate measurements.
//!
//! Run briefly: `cargo bench -p sinew-nodes --no-default-features --bench skinning --
//! --warm-up-time 1 --measurement-time 3`.

use std::sync::Arc;

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use glam::{DMat4, DVec3, Mat4, Quat, Vec3};
use sinew_core::{CompileOptions, Graph, Instance, Mesh, Program, Time, Value, Weights};
use sinew_nodes::deform::dual_quat::DqPalette;
use sinew_nodes::deform::skinning::{skin, skin_parallel, PreparedWeights, SkinInput, SkinMethod, SkinOutput};

#[path = "../tests/common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::allocations;

const VERTICES: usize = 100_000;
const JOINTS: usize = 64;

struct Rig {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    weights: Weights,
    palette: Vec<Mat4>,
}

fn rig() -> Rig {
    let mut s = 0x5eed_u64;
    let mut rnd = move || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((s >> 40) as f32) / (1u64 << 24) as f32
    };
    let mut positions = Vec::with_capacity(VERTICES);
    let mut normals = Vec::with_capacity(VERTICES);
    let mut lists = Vec::with_capacity(VERTICES);
    for v in 0..VERTICES {
        positions.push(Vec3::new(rnd(), rnd(), rnd()) * 2.0 - 1.0);
        normals.push((Vec3::new(rnd(), rnd(), rnd()) - 0.5).normalize_or(Vec3::Y));
        // Neighbouring joints, as on a real limb: vertex v is near joint v·64/N.
        let j0 = (v * JOINTS / VERTICES) as u32;
        let row: Vec<(u32, f32)> = (0..4u32).map(|k| ((j0 + k) % JOINTS as u32, 0.1 + rnd())).collect();
        let sum: f32 = row.iter().map(|r| r.1).sum();
        lists.push(row.into_iter().map(|(j, w)| (j, w / sum)).collect::<Vec<_>>());
    }
    let palette = (0..JOINTS)
        .map(|_| {
            let q = Quat::from_euler(glam::EulerRot::XYZ, rnd(), rnd(), rnd());
            Mat4::from_rotation_translation(q, Vec3::new(rnd(), rnd(), rnd()))
        })
        .collect();
    Rig {
        positions,
        normals,
        weights: Weights::from_lists(lists),
        palette,
    }
}

/// A graph `mesh → skinCluster` with the rig's weights and joint matrices (bindPreMatrix
/// identity, so the palette is the rig's palette), compiled with every `matrix[i]` dynamic.
fn node_instance(r: &Rig, method: i64) -> (Instance, sinew_core::PlugHandle) {
    let mut g = Graph::new(sinew_nodes::registry().unwrap());
    g.add_node("mesh", "body").unwrap();
    let mesh = Mesh {
        positions: r.positions.clone(),
        normals: r.normals.clone(),
        ..Default::default()
    };
    g.set_path("body.inMesh", Value::Mesh(Arc::new(mesh))).unwrap();
    g.add_node("skinCluster", "skin").unwrap();
    g.connect_path("body.outMesh", "skin.inputGeometry").unwrap();
    g.set_path("skin.weightList", Value::Weights(Arc::new(r.weights.clone())))
        .unwrap();
    g.set_path("skin.skinningMethod", Value::Enum(method)).unwrap();
    let mut dynamic = Vec::new();
    for (i, m) in r.palette.iter().enumerate() {
        let path = format!("skin.matrix[{i}]");
        g.set_path(&path, Value::Matrix(m.as_dmat4())).unwrap();
        g.set_path(&format!("skin.bindPreMatrix[{i}]"), Value::Matrix(DMat4::IDENTITY))
            .unwrap();
        dynamic.push(g.plug(&path).unwrap());
    }
    let program = Arc::new(
        Program::compile(
            &g,
            &CompileOptions {
                dynamic_inputs: dynamic,
                ..Default::default()
            },
        )
        .unwrap(),
    );
    let h = program.handle("skin.matrix[0]").unwrap();
    let mut inst = Instance::new(program);
    inst.evaluate(Time::default()).unwrap();
    (inst, h)
}

fn frame(inst: &mut Instance, h: &sinew_core::PlugHandle, k: u64, base: DMat4) {
    let m = DMat4::from_translation(DVec3::new((k % 7) as f64 * 0.01, 0.0, 0.0)) * base;
    inst.set(h, Value::Matrix(m)).unwrap();
    inst.evaluate(Time::new(k as f64, 24.0)).unwrap();
}

fn report_allocations(r: &Rig) {
    for (name, method) in [("classicLinear", 0), ("dualQuaternion", 1)] {
        let (mut inst, h) = node_instance(r, method);
        let base = r.palette[0].as_dmat4();
        for k in 0..3 {
            frame(&mut inst, &h, k, base);
        }
        let before = allocations();
        let frames = 20;
        for k in 0..frames {
            frame(&mut inst, &h, k + 3, base);
        }
        let n = allocations() - before;
        println!("skinCluster {name}, compiled: {n} allocations in {frames} frames");
        // The count means something only if the counter is installed.
        counting_alloc::assert_counter_counts();
    }
}

/// The bytes LBS reads, copied into output buffers: the bandwidth baseline. Positions and
/// the CSR weights always; the normals too when made [`CopyBaseline::with_normals`].
struct CopyBaseline {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    offsets: Vec<u32>,
    joints: Vec<u32>,
    weights: Vec<f32>,
}

impl CopyBaseline {
    /// The baseline for deforming positions only.
    fn new(r: &Rig) -> Self {
        CopyBaseline {
            positions: vec![Vec3::ZERO; VERTICES],
            normals: Vec::new(),
            offsets: vec![0; r.weights.offsets.len()],
            joints: vec![0; r.weights.joints.len()],
            weights: vec![0.0; r.weights.weights.len()],
        }
    }

    /// The baseline for deforming positions and normals.
    fn with_normals(r: &Rig) -> Self {
        CopyBaseline {
            normals: vec![Vec3::ZERO; VERTICES],
            ..CopyBaseline::new(r)
        }
    }

    fn run(&mut self, r: &Rig) {
        self.positions.copy_from_slice(black_box(&r.positions));
        if !self.normals.is_empty() {
            self.normals.copy_from_slice(black_box(&r.normals));
        }
        self.offsets.copy_from_slice(black_box(&r.weights.offsets));
        self.joints.copy_from_slice(black_box(&r.weights.joints));
        self.weights.copy_from_slice(black_box(&r.weights.weights));
        black_box((
            &self.positions,
            &self.normals,
            &self.offsets,
            &self.joints,
            &self.weights,
        ));
    }
}

/// The two copies and three LBS runs (raw weights, prepared weights, prepared weights with
/// normals), alternately, each run twice in a row and the second run timed (warm caches, as
/// in criterion's loop); prints each one's fastest and median time and the ratios of the
/// LBS runs to the copy of the same bytes.
fn report_interleaved(r: &Rig, prepared: &PreparedWeights) {
    let mut copy = CopyBaseline::new(r);
    let mut copy_n = CopyBaseline::with_normals(r);
    let mut out = vec![Vec3::ZERO; VERTICES];
    let mut out_n = vec![Vec3::ZERO; VERTICES];
    let mut scratch = DqPalette::new();
    let raw = SkinInput {
        positions: &r.positions,
        normals: &[],
        weights: (&r.weights).into(),
        palette: &r.palette,
    };
    let prep = SkinInput {
        weights: prepared.into(),
        ..raw
    };
    let prep_n = SkinInput {
        normals: &r.normals,
        ..prep
    };
    let mut times: [Vec<f64>; 5] = Default::default();
    let mut timed = |k: usize, run: &mut dyn FnMut()| {
        run();
        let t = std::time::Instant::now();
        run();
        times[k].push(t.elapsed().as_secs_f64());
    };
    for _ in 0..300 {
        timed(0, &mut || copy.run(r));
        timed(1, &mut || copy_n.run(r));
        for (k, input) in [(2, &raw), (3, &prep), (4, &prep_n)] {
            timed(k, &mut || {
                let normals: &mut [Vec3] = if k == 4 { &mut out_n } else { &mut [] };
                let o = SkinOutput {
                    positions: &mut out,
                    normals,
                };
                skin(black_box(input), SkinMethod::Linear, &mut scratch, o).unwrap();
                black_box((&out, &out_n));
            });
        }
    }
    let [copy, copy_n, raw, prep, prep_n] = times.map(|mut v| {
        v.sort_by(f64::total_cmp);
        (v[0] * 1e6, v[v.len() / 2] * 1e6)
    });
    let line = |name: &str, (fast, median): (f64, f64), base: (f64, f64)| {
        format!(
            "{name} {fast:.1} / {median:.1} µs ({:.2}× / {:.2}× copy)",
            fast / base.0,
            median / base.1
        )
    };
    println!(
        "interleaved, warm, 300 runs (fastest / median): copy {:.1} / {:.1} µs; {}; {}",
        copy.0,
        copy.1,
        line("LBS positions", raw, copy),
        line("prepared", prep, copy)
    );
    println!(
        "interleaved, with normals: copy {:.1} / {:.1} µs; {}",
        copy_n.0,
        copy_n.1,
        line("prepared LBS positions + normals", prep_n, copy_n)
    );
}

fn bench(c: &mut Criterion) {
    let r = rig();
    report_allocations(&r);
    let prepared = PreparedWeights::new(&r.weights);
    assert!(prepared.clean_max_joint().is_some(), "the bench weights are clean");
    report_interleaved(&r, &prepared);
    let mut g = c.benchmark_group("skinning_100k_4inf_64j");
    g.throughput(Throughput::Elements(VERTICES as u64));
    let mut out_p = vec![Vec3::ZERO; VERTICES];
    let mut out_n = vec![Vec3::ZERO; VERTICES];
    let mut scratch = DqPalette::new();

    // Baseline: copy every input byte LBS reads for positions (positions + offsets + joints
    // + weights) into output buffers.
    let mut copy = CopyBaseline::new(&r);
    g.bench_function("baseline_copy_inputs", |b| b.iter(|| copy.run(&r)));
    drop(copy);
    // The same with the normals: the baseline of the `*_normals` cases.
    let mut copy = CopyBaseline::with_normals(&r);
    g.bench_function("baseline_copy_inputs_normals", |b| b.iter(|| copy.run(&r)));
    drop(copy);

    let with_n = SkinInput {
        positions: &r.positions,
        normals: &r.normals,
        weights: (&r.weights).into(),
        palette: &r.palette,
    };
    let no_n = SkinInput { normals: &[], ..with_n };
    let prep_n = SkinInput {
        weights: (&prepared).into(),
        ..with_n
    };
    let prep = SkinInput { normals: &[], ..prep_n };
    let cases: [(&str, SkinInput, SkinMethod, bool, bool); 8] = [
        ("lbs_positions", no_n, SkinMethod::Linear, false, false),
        ("lbs_positions_prepared", prep, SkinMethod::Linear, false, false),
        ("lbs_positions_normals", with_n, SkinMethod::Linear, true, false),
        (
            "lbs_positions_normals_prepared",
            prep_n,
            SkinMethod::Linear,
            true,
            false,
        ),
        ("dqs_positions", no_n, SkinMethod::DualQuaternion, false, false),
        ("dqs_positions_normals", with_n, SkinMethod::DualQuaternion, true, false),
        ("lbs_positions_normals_parallel", with_n, SkinMethod::Linear, true, true),
        (
            "dqs_positions_normals_parallel",
            with_n,
            SkinMethod::DualQuaternion,
            true,
            true,
        ),
    ];
    for (name, input, method, normals, parallel) in cases {
        g.bench_function(name, |b| {
            b.iter(|| {
                let n: &mut [Vec3] = if normals { &mut out_n } else { &mut [] };
                let out = SkinOutput {
                    positions: &mut out_p,
                    normals: n,
                };
                if parallel {
                    skin_parallel(black_box(&input), method, &mut scratch, out).unwrap();
                } else {
                    skin(black_box(&input), method, &mut scratch, out).unwrap();
                }
                black_box(&out_p);
            })
        });
    }

    for (name, method) in [
        ("node_skincluster_lbs_compiled", 0),
        ("node_skincluster_dqs_compiled", 1),
    ] {
        let (mut inst, h) = node_instance(&r, method);
        let base = r.palette[0].as_dmat4();
        let mut k = 0u64;
        g.bench_function(name, |b| {
            b.iter(|| {
                k += 1;
                frame(&mut inst, &h, k, base);
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
