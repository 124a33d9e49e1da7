//! Deformer kernels against the skinCluster LBS kernel, per vertex, on the same 100,000-vertex
//! mesh in the same run (a 320 × 313 grid with a wavy height, triangulated).
//!
//! Each deformer case runs what `outputGeometry`'s compute runs per frame once its
//! parameters are read: the copy of the input positions into the output buffer (skipped, as
//! the node skips it, when the kernel overwrites every vertex) and the deformer's kernel over
//! every vertex (weight 1, envelope 1, serial). The LBS case is
//! `skin` with prepared weights (4 influences per vertex from 64 joints, as in the skinning
//! bench), serial, positions only; `copy` copies the positions (the memory floor).
//!
//! Report: all cases run alternately 200 times (each twice in a row, the second run timed),
//! and each one's fastest and median times are printed with their ratio to LBS's. The issue's
//! targets: cluster, softMod, nonLinear, ffd at most 1× LBS; deltaMush (10 iterations) at most
//! 10× LBS. Then criterion measures each case on its own.
//!
//! Run: `cargo bench -p sinew-nodes --no-default-features --bench deformers --
//! --warm-up-time 1 --measurement-time 2`. To profile one case: build with `--profile
//! bench-quick --no-run`, then `perf record -g <bench binary> --bench --profile-time 5
//! 'deformers_100k/bend$'` (the interleaved report is skipped under `--profile-time`).

use std::f32::consts::FRAC_PI_2;

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use glam::{Mat4, Quat, Vec3};
use sinew_core::{Mesh, ObjectRef, Weights};
use sinew_nodes::cluster::falloff::Ramp;
use sinew_nodes::cluster::handle::Cluster;
use sinew_nodes::cluster::soft_mod::{SoftMod, SoftModFrame};
use sinew_nodes::deform::dual_quat::DqPalette;
use sinew_nodes::deform::skinning::{skin, PreparedWeights, SkinInput, SkinMethod, SkinOutput};
use sinew_nodes::deformer::{Deformer, DeformerNode, Job, Membership};
use sinew_nodes::lattice::ffd::Lattice;
use sinew_nodes::lattice::nodes::{Ffd, FfdFrame};
use sinew_nodes::mush::delta_mush::{DeltaMush, MushBind, MushFrame};
use sinew_nodes::mush::tension::{Relax, Tension, TensionBind, TensionFrame};
use sinew_nodes::nonlinear::funcs::Func;
use sinew_nodes::nonlinear::nodes::{NonLinear, NonLinearFrame};

const NX: usize = 320;
const NY: usize = 313;
const JOINTS: usize = 64;

fn mesh() -> Mesh {
    let mut m = Mesh::default();
    for j in 0..NY {
        for i in 0..NX {
            let (x, y) = (
                i as f32 / (NX - 1) as f32 * 2.0 - 1.0,
                j as f32 / (NY - 1) as f32 * 2.0 - 1.0,
            );
            m.positions
                .push(Vec3::new(x, y, 0.1 * (5.0 * x).sin() * (3.0 * y).cos()));
        }
    }
    for j in 0..NY - 1 {
        for i in 0..NX - 1 {
            let a = (j * NX + i) as u32;
            let (b, c, d) = (a + 1, a + NX as u32 + 1, a + NX as u32);
            m.triangles.push([a, b, c]);
            m.triangles.push([a, c, d]);
        }
    }
    m
}

fn lbs_rig(n: usize) -> (Weights, Vec<Mat4>) {
    let mut s = 0x5eed_u64;
    let mut rnd = move || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((s >> 40) as f32) / (1u64 << 24) as f32
    };
    let lists: Vec<Vec<(u32, f32)>> = (0..n)
        .map(|v| {
            let j0 = (v * JOINTS / n) as u32;
            let row: Vec<(u32, f32)> = (0..4u32).map(|k| ((j0 + k) % JOINTS as u32, 0.1 + rnd())).collect();
            let sum: f32 = row.iter().map(|r| r.1).sum();
            row.into_iter().map(|(j, w)| (j, w / sum)).collect()
        })
        .collect();
    let palette = (0..JOINTS)
        .map(|_| {
            let q = Quat::from_euler(glam::EulerRot::XYZ, rnd(), rnd(), rnd());
            Mat4::from_rotation_translation(q, Vec3::new(rnd(), rnd(), rnd()))
        })
        .collect();
    (Weights::from_lists(lists), palette)
}

/// A deformer and its frame, run as the node runs them (copy, then kernel).
struct Case<D: Deformer> {
    name: &'static str,
    node: DeformerNode<D>,
    frame: D::Frame,
}

trait Run {
    fn name(&self) -> &'static str;
    fn run(&self, input: &Mesh, out: &mut [Vec3]);
}

impl<D: Deformer> Run for Case<D> {
    fn name(&self) -> &'static str {
        self.name
    }
    fn run(&self, input: &Mesh, out: &mut [Vec3]) {
        // As the node: the copy only when the kernel does not overwrite every vertex.
        if !self.node.deformer().writes_every_vertex(&self.frame) {
            out.copy_from_slice(&input.positions);
        }
        let job = Job {
            input,
            out,
            membership: &Membership::default(),
            envelope: 1.0,
        };
        self.node.deformer().deform(self.name, &self.frame, job).unwrap();
    }
}

fn case<D: Deformer>(name: &'static str, ty: &'static str, frame: D::Frame) -> Box<dyn Run> {
    Box::new(Case {
        name,
        node: DeformerNode::<D>::new(ty, "").unwrap(),
        frame,
    })
}

fn nonlinear(name: &'static str, func: Func) -> Box<dyn Run> {
    // The handle turned and moved, so the space changes are real matrices.
    let to = Mat4::from_rotation_translation(Quat::from_rotation_z(0.3), Vec3::new(0.1, 0.2, 0.0));
    case::<NonLinear>(
        name,
        "nonLinear",
        NonLinearFrame {
            func: Some(func),
            to,
            back: to.inverse(),
        },
    )
}

fn cases(m: &Mesh) -> Vec<Box<dyn Run>> {
    let d = Mat4::from_rotation_translation(Quat::from_rotation_y(0.2), Vec3::new(0.1, 0.0, 0.3));
    let mut lattice = Lattice::undisturbed([2, 5, 2]);
    for (k, p) in lattice.points.iter_mut().enumerate() {
        p.y -= 0.05 * (k % 3) as f32;
    }
    let ffd = |name, local| {
        case::<Ffd>(
            name,
            "ffd",
            FfdFrame {
                lattice: ObjectRef::new(lattice.clone()),
                to: Mat4::from_scale(Vec3::splat(0.45)),
                back: Mat4::from_scale(Vec3::splat(2.2)),
                local,
                outside: 1,
                falloff: 1.0,
            },
        )
    };
    let (lb, hb) = (-1.0, 1.0);
    vec![
        case::<Cluster>("cluster", "cluster", d),
        case::<SoftMod>(
            "softMod",
            "softMod",
            SoftModFrame {
                d,
                center: Vec3::ZERO,
                radius: 1.0,
                surface: false,
                ramp: ObjectRef::new(Ramp::default()),
            },
        ),
        nonlinear("bend", Func::Bend { k: FRAC_PI_2, lb, hb }),
        nonlinear(
            "twist",
            Func::Twist {
                lb,
                hb,
                a0: 0.0,
                a1: 1.0,
            },
        ),
        nonlinear(
            "squash",
            Func::Squash {
                lb,
                hb,
                f: 0.5,
                expand: 1.0,
                m: 0.5,
                ss: 0.2,
                es: 0.0,
            },
        ),
        nonlinear(
            "flare",
            Func::Flare {
                lb,
                hb,
                start: [1.0, 1.2],
                end: [0.5, 2.0],
                curve: 0.3,
            },
        ),
        nonlinear(
            "sine",
            Func::Sine {
                lb,
                hb,
                amplitude: 0.1,
                wavelength: 0.5,
                offset: 0.0,
                dropoff: 0.3,
            },
        ),
        nonlinear(
            "wave",
            Func::Wave {
                r0: 0.0,
                r1: 1.0,
                amplitude: 0.1,
                wavelength: 0.5,
                offset: 0.0,
                dropoff: 0.3,
                dropoff_position: 0.0,
            },
        ),
        ffd("ffd_2x5x2", None),
        ffd("ffd_2x5x2_local", Some([2, 2, 2])),
        case::<DeltaMush>(
            "deltaMush_10",
            "deltaMush",
            MushFrame {
                bind: ObjectRef::new(MushBind::new(m, 10, 0.5, true)),
                displacement: 1.0,
                inward: 0.0,
                outward: 0.0,
                scale: Vec3::ONE,
            },
        ),
        case::<Tension>(
            "tension_10",
            "tension",
            TensionFrame {
                bind: ObjectRef::new(TensionBind::new(m, true)),
                relax: Relax {
                    iterations: 10,
                    step: 0.5,
                    stretch: 1.0,
                    squash: 1.0,
                },
            },
        ),
    ]
}

fn report(m: &Mesh, input: &Mesh, prepared: &PreparedWeights, palette: &[Mat4], cases: &[Box<dyn Run>]) {
    let n = m.positions.len();
    let mut out = vec![Vec3::ZERO; n];
    let mut dq = DqPalette::new();
    let lbs = SkinInput {
        positions: &m.positions,
        normals: &[],
        weights: prepared.into(),
        palette,
    };
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); cases.len() + 2];
    let mut timed = |k: usize, run: &mut dyn FnMut()| {
        run();
        let t = std::time::Instant::now();
        run();
        times[k].push(t.elapsed().as_secs_f64());
    };
    for _ in 0..200 {
        timed(0, &mut || out.copy_from_slice(black_box(&m.positions)));
        timed(1, &mut || {
            let o = SkinOutput {
                positions: &mut out,
                normals: &mut [],
            };
            skin(black_box(&lbs), SkinMethod::Linear, &mut dq, o).unwrap();
        });
        for (k, c) in cases.iter().enumerate() {
            timed(k + 2, &mut || c.run(black_box(input), &mut out));
        }
    }
    let stats: Vec<(f64, f64)> = times
        .into_iter()
        .map(|mut v| {
            v.sort_by(f64::total_cmp);
            (v[0], v[v.len() / 2])
        })
        .collect();
    let (lbs_fast, lbs_med) = stats[1];
    let ns = |t: f64| t * 1e9 / n as f64;
    println!("interleaved, {n} vertices, 200 runs (fastest / median, ns per vertex, ratio to LBS):");
    let names = ["copy positions", "LBS (skinCluster kernel)"];
    for (k, (fast, med)) in stats.iter().enumerate() {
        let name = names.get(k).copied().unwrap_or_else(|| cases[k - 2].name());
        println!(
            "  {name:<26} {:>6.2} / {:>6.2} ns  ({:.2}× / {:.2}× LBS)",
            ns(*fast),
            ns(*med),
            fast / lbs_fast,
            med / lbs_med
        );
    }
}

fn bench(c: &mut Criterion) {
    let m = mesh();
    let (weights, palette) = lbs_rig(m.positions.len());
    let prepared = PreparedWeights::new(&weights);
    let cases = cases(&m);
    // Under `--profile-time` (profiling one case with perf) the interleaved report is skipped.
    if !std::env::args().any(|a| a == "--profile-time") {
        report(&m, &m, &prepared, &palette, &cases);
    }
    let mut g = c.benchmark_group("deformers_100k");
    g.throughput(Throughput::Elements(m.positions.len() as u64));
    let mut out = vec![Vec3::ZERO; m.positions.len()];
    let mut dq = DqPalette::new();
    let lbs = SkinInput {
        positions: &m.positions,
        normals: &[],
        weights: (&prepared).into(),
        palette: &palette,
    };
    g.bench_function("lbs_prepared", |b| {
        b.iter(|| {
            let o = SkinOutput {
                positions: &mut out,
                normals: &mut [],
            };
            skin(black_box(&lbs), SkinMethod::Linear, &mut dq, o).unwrap();
        })
    });
    for c in &cases {
        g.bench_function(c.name(), |b| b.iter(|| c.run(black_box(&m), &mut out)));
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
