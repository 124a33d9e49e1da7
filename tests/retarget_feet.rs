//! Retargeting with IK foot planting (`sinew::io::retarget_feet`): on synthetic BVH takes whose
//! contacts are known by construction, the planted ankle holds still, bone lengths and the
//! ankle's world rotation are kept, frames away from contacts are bit-identical to the plain
//! retarget and out-of-reach plants give a straight leg; on a real walk retargeted onto the
//! biped, both feet's contacts are found and their sliding vanishes.

use std::path::PathBuf;
use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3};
use sinew::core::{load_rig, Graph, Registry, Time, Value};
use sinew::io::parse_bvh;
use sinew::io::retarget::{retarget_with, RetargetOptions, RetargetReport};
use sinew::io::retarget_feet::clean_contacts;
use sinew::io::rig_builder::RigBuilder;

fn registry() -> Arc<Registry> {
    sinew::default_registry().unwrap()
}

fn world(g: &mut Graph, node: &str, frame: usize, fps: f64) -> DMat4 {
    g.set_time(Time::new(frame as f64, fps));
    match g.get_path(&format!("{node}.worldMatrix")).unwrap() {
        Value::Matrix(m) => m,
        v => panic!("{node}.worldMatrix: {v:?}"),
    }
}

fn pos(m: &DMat4) -> DVec3 {
    m.w_axis.truncate()
}

fn horizontal(v: DVec3) -> f64 {
    DVec3::new(v.x, 0.0, v.z).length()
}

fn planting() -> RetargetOptions {
    RetargetOptions {
        plant_feet: true,
        ..Default::default()
    }
}

#[test]
fn retarget_contact_cleanup_fills_gaps_then_drops_short_runs() {
    let flags = |s: &str| s.chars().map(|c| c == '#').collect::<Vec<bool>>();
    //            0123456789012345678
    let f = flags("##.###..#...####.#.");
    // Gaps of 1 (frame 2) and 2 (6..7) are filled with max_gap 2; the 3-frame gap 9..11 is not.
    assert_eq!(clean_contacts(&f, 2, 1), vec![(0, 8), (12, 17)]);
    // Without filling: runs 0..1, 3..5, 8, 12..15, 17; a minimum of 3 keeps 3..5 and 12..15.
    assert_eq!(clean_contacts(&f, 0, 3), vec![(3, 5), (12, 15)]);
    assert_eq!(clean_contacts(&flags("...."), 2, 1), vec![]);
    assert_eq!(clean_contacts(&flags("####"), 0, 5), vec![]);
}

// ---------------------------------------------------------------- synthetic takes

/// Source bones: thigh and shin 0.45 each (leg length 0.9), hips 0.1 to each side, the toe
/// 0.05 below and 0.12 ahead of the ankle. All rotations are about X (the legs move in their
/// sagittal planes): `Rx(φ)·(0, -1, 0) = (0, -cos φ, -sin φ)`.
const SRC_BONE: f64 = 0.45;
const TOE: DVec3 = DVec3::new(0.0, -0.05, 0.12);
const LEGS: [(&str, f64); 2] = [("Left", 0.1), ("Right", -0.1)];

/// One source frame: root position and per side the hip, knee and ankle X angles (radians).
struct SrcFrame {
    root: DVec3,
    legs: [[f64; 3]; 2],
}

/// Angles putting a leg whose hip is at `hip` onto `ankle` (same X), knee forward, foot flat.
/// Hip angle `φ1 = φd − α`: `φd` points from hip to ankle, `α` is the law-of-cosines angle
/// at the hip (smaller `φ` swings the bone forward, to +Z); the shin angle follows from the
/// knee; the ankle undoes the sum so the foot's world rotation is the identity.
fn leg_angles(hip: DVec3, ankle: DVec3) -> [f64; 3] {
    let (dy, dz) = (ankle.y - hip.y, ankle.z - hip.z);
    let d = (dy * dy + dz * dz).sqrt();
    assert!(d <= 2.0 * SRC_BONE, "the synthetic source cannot reach");
    let phi_d = (-dz).atan2(-dy);
    let alpha = (d / (2.0 * SRC_BONE)).clamp(-1.0, 1.0).acos();
    let phi1 = phi_d - alpha;
    let (ky, kz) = (hip.y - SRC_BONE * phi1.cos(), hip.z - SRC_BONE * phi1.sin());
    let phi_s = (-(ankle.z - kz)).atan2(-(ankle.y - ky));
    [phi1, phi_s - phi1, -phi_s]
}

fn bvh_text(frames: &[SrcFrame], frame_time: f64) -> String {
    let mut h = String::from("HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n");
    for (side, x) in LEGS {
        h += &format!(
            " JOINT {side}UpLeg\n {{\n  OFFSET {x} 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  JOINT {side}Leg\n  {{\n   OFFSET 0 -{SRC_BONE} 0\n   CHANNELS 3 Zrotation Xrotation Yrotation\n   JOINT {side}Foot\n   {{\n    OFFSET 0 -{SRC_BONE} 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n    JOINT {side}ToeBase\n    {{\n     OFFSET {} {} {}\n     CHANNELS 3 Zrotation Xrotation Yrotation\n     End Site\n     {{\n      OFFSET 0 0 0.05\n     }}\n    }}\n   }}\n  }}\n }}\n",
            TOE.x, TOE.y, TOE.z
        );
    }
    h += &format!("}}\nMOTION\nFrames: {}\nFrame Time: {frame_time}\n", frames.len());
    for fr in frames {
        let mut v = vec![fr.root.x, fr.root.y, fr.root.z, 0.0, 0.0, 0.0];
        for leg in fr.legs {
            for a in leg {
                v.extend([0.0, a.to_degrees(), 0.0]);
            }
            v.extend([0.0, 0.0, 0.0]);
        }
        h += &v.iter().map(|x| format!("{x:.17e}")).collect::<Vec<_>>().join(" ");
        h.push('\n');
    }
    h
}

/// Target rig: the source's joint names, thigh 0.55 and shin 0.45 (leg length 1.0, so the
/// root-motion scale is 1 / 0.9 but the leg is *not* a scaled copy: feet slide), its own
/// joint orients (bone axis X down the leg, a 20° twist at the knee), same rest pose.
fn target_rig() -> RigBuilder {
    let mut rig = RigBuilder::new("target", 30.0);
    let h = rig.add("Hips", "joint", None, false);
    rig.set(h, "translate", Value::Vec3(DVec3::ZERO));
    for (side, x) in LEGS {
        let names = ["UpLeg", "Leg", "Foot", "ToeBase"].map(|p| format!("{side}{p}"));
        // jointOrient (degrees) and the translate in the parent's frame. World rotations:
        // hip Rz(-90) (its X points down), knee Rz(-90)·Rx(20), ankle Rz(-90)·Rx(20)·Rz(90).
        let jo = [
            DVec3::new(0.0, 0.0, -90.0),
            DVec3::new(20.0, 0.0, 0.0),
            DVec3::new(0.0, 0.0, 90.0),
        ];
        let ankle_world = DQuat::from_rotation_z(-90f64.to_radians())
            * DQuat::from_rotation_x(20f64.to_radians())
            * DQuat::from_rotation_z(90f64.to_radians());
        let translates = [
            DVec3::new(x, 0.0, 0.0),
            DVec3::new(0.55, 0.0, 0.0),
            DVec3::new(0.45, 0.0, 0.0),
            ankle_world.inverse() * TOE,
        ];
        let mut parent = "Hips".to_string();
        for k in 0..4 {
            let n = rig.add(&names[k], "joint", Some(&parent), false);
            rig.set(n, "translate", Value::Vec3(translates[k]));
            if k < 3 {
                rig.set(n, "jointOrient", Value::Vec3(jo[k]));
            }
            parent = names[k].clone();
        }
    }
    rig
}

fn target(reg: &Arc<Registry>) -> Graph {
    target_rig().to_graph(reg).unwrap()
}

const FPS: f64 = 30.0;
/// The left foot's contact, by construction.
const CONTACT: (usize, usize) = (20, 39);

/// 60 frames at 30 fps; the root drifts forward 0.02 per frame (0.6 m/s) at height 0.85.
/// Left foot: planted at (0.1, 0.08, 0.59) over frames 20..=39 (0.59 is the root's z midway,
/// so the hip stays within 0.793 of it: reachable); otherwise 0.15 higher and 0.1 ahead of
/// the hip, moving with the root (too high, too fast). Right foot: always in that swing pose,
/// so it never touches down (0.15 above the lowest ankle, which is the left one).
fn walk_frames() -> Vec<SrcFrame> {
    (0..60)
        .map(|f| {
            let root = DVec3::new(0.0, 0.85, 0.02 * f as f64);
            let legs = [0, 1].map(|i| {
                let hip = root + DVec3::new(LEGS[i].1, 0.0, 0.0);
                let swing = DVec3::new(hip.x, 0.08 + 0.15, hip.z + 0.1);
                let planted = i == 0 && (CONTACT.0..=CONTACT.1).contains(&f);
                let ankle = if planted { DVec3::new(hip.x, 0.08, 0.59) } else { swing };
                leg_angles(hip, ankle)
            });
            SrcFrame { root, legs }
        })
        .collect()
}

fn walk_pair() -> (sinew::io::Bvh, Graph, Graph, RetargetReport) {
    let reg = registry();
    let bvh = parse_bvh(&bvh_text(&walk_frames(), 1.0 / FPS)).unwrap();
    let mut plain = target(&reg);
    retarget_with(&bvh, &mut plain, None, &RetargetOptions::default()).unwrap();
    let mut planted = target(&reg);
    let report = retarget_with(&bvh, &mut planted, None, &planting()).unwrap();
    (bvh, plain, planted, report)
}

#[test]
fn retarget_synthetic_contact_is_detected_and_the_ankle_holds_still() {
    let (bvh, mut plain, mut planted, report) = walk_pair();
    // The construction: the source ankle really is still over the contact.
    let a = bvh.joint_index("LeftFoot").unwrap();
    for f in CONTACT.0..=CONTACT.1 {
        assert!((bvh.world_positions(f)[a] - DVec3::new(0.1, 0.08, 0.59)).length() < 1e-12);
    }
    // Defaults at 30 fps: blend 0.1 s = 3 frames each side.
    assert_eq!(report.feet.len(), 2, "{:?}", report.warnings);
    let left = report.feet.iter().find(|f| f.side == "left").unwrap();
    let right = report.feet.iter().find(|f| f.side == "right").unwrap();
    assert_eq!(left.ankle, "LeftFoot");
    assert_eq!(left.intervals, vec![(20, 39)]);
    assert_eq!(left.affected, vec![(17, 42)]);
    assert!(right.intervals.is_empty(), "{:?}", right.intervals);
    let ankle = |g: &mut Graph, f| pos(&world(g, "LeftFoot", f, FPS));
    // Plant point: the mean of the plain ankle positions over the contact.
    let plain_pos: Vec<DVec3> = (0..60).map(|f| ankle(&mut plain, f)).collect();
    let plant = plain_pos[20..=39].iter().sum::<DVec3>() / 20.0;
    let mut slide = 0.0f64;
    let mut want = 0.0f64;
    // Plain target ankle − (1/0.9)·source ankle = const + 0.05·(dir φ1 − dir φs) (thigh 0.55 vs
    // 0.5, shin 0.45 vs 0.5). Its z part is 0.1·cos φd·sin α with, at frame f, the hip 0.77
    // above the ankle and dz = 0.59 − 0.02 f behind it: d = √(dz² + 0.77²), cos φd = 0.77/d,
    // cos α = d/0.9. The source ankle is still, so the plain target slides by the change of it.
    let c = |f: usize| {
        let dz = 0.59 - 0.02 * f as f64;
        let d = (dz * dz + 0.77 * 0.77).sqrt();
        0.1 * (0.77 / d) * (1.0 - (d / 0.9).powi(2)).sqrt()
    };
    for f in CONTACT.0..=CONTACT.1 {
        let p = ankle(&mut planted, f);
        assert!((p - plant).length() < 1e-9, "frame {f}: {p} vs {plant}");
        slide = slide.max(horizontal(plain_pos[f] - plain_pos[CONTACT.0]));
        want = want.max((c(f) - c(CONTACT.0)).abs());
    }
    eprintln!("synthetic left foot sliding without planting: {slide:.6} (closed form {want:.6})");
    assert!((slide - want).abs() < 1e-9 && want > 5e-3, "{slide} vs {want}");
    // Blend zones: the goal is plain + w·(plant − plain), w = smoothstep(1 − k/4) for the
    // k-th frame outside the contact: k=1: 0.75²·(3 − 1.5) = 0.84375, k=2: 0.5, k=3:
    // 0.25²·(3 − 0.5) = 0.15625 (reachable here, so the ankle lands on the goal).
    for (k, w) in [(1usize, 0.84375), (2, 0.5), (3, 0.15625)] {
        for f in [CONTACT.0 - k, CONTACT.1 + k] {
            let want = plain_pos[f] + (plant - plain_pos[f]) * w;
            let got = ankle(&mut planted, f);
            assert!((got - want).length() < 1e-9, "frame {f}: {got} vs {want}");
        }
    }
}

#[test]
fn retarget_planting_keeps_bone_lengths_and_the_ankle_world_rotation() {
    let (_, mut plain, mut planted, _) = walk_pair();
    for f in 0..60 {
        let [h, k, a] = ["LeftUpLeg", "LeftLeg", "LeftFoot"].map(|n| world(&mut planted, n, f, FPS));
        // Target bones by construction: thigh 0.55, shin 0.45.
        assert!(((pos(&k) - pos(&h)).length() - 0.55).abs() < 1e-9, "frame {f}");
        assert!(((pos(&a) - pos(&k)).length() - 0.45).abs() < 1e-9, "frame {f}");
        let plain_ankle = world(&mut plain, "LeftFoot", f, FPS);
        for c in 0..3 {
            let d = (a.col(c) - plain_ankle.col(c)).truncate().length();
            assert!(d < 1e-9, "frame {f}: ankle axis {c} turned by {d}");
        }
    }
}

#[test]
fn retarget_planting_leaves_frames_away_from_contacts_bit_identical() {
    let (bvh, mut plain, mut planted, _) = walk_pair();
    let names: Vec<String> = bvh.joints.iter().map(|j| j.name.clone()).collect();
    let mut checked = 0;
    for f in (0..60).filter(|f| !(17..=42).contains(f)) {
        for n in &names {
            let (a, b) = (world(&mut plain, n, f, FPS), world(&mut planted, n, f, FPS));
            assert!(Value::Matrix(a).same_bits(&Value::Matrix(b)), "frame {f} {n}");
            checked += 1;
        }
    }
    assert_eq!(checked, 34 * 9);
}

/// Both legs straight down all along, the root rising from 0.85 to 1.15 in place: with a
/// huge height threshold every frame is a contact, the plant point is the mean plain ankle
/// (midway), so in the upper half the hip is more than a leg length above it.
#[test]
fn retarget_unreachable_plant_gives_a_straight_leg() {
    let reg = registry();
    let frames: Vec<SrcFrame> = (0..30)
        .map(|f| SrcFrame {
            root: DVec3::new(0.0, 0.85 + 0.3 * f as f64 / 29.0, 0.0),
            legs: [[0.0; 3]; 2],
        })
        .collect();
    let bvh = parse_bvh(&bvh_text(&frames, 1.0 / FPS)).unwrap();
    let mut g = target(&reg);
    let opts = RetargetOptions {
        contact_height: 10.0,
        ..planting()
    };
    let report = retarget_with(&bvh, &mut g, None, &opts).unwrap();
    let left = report.feet.iter().find(|f| f.side == "left").unwrap();
    assert_eq!(left.intervals, vec![(0, 29)]);
    // Plain pose = rest pose: ankle = hip − (0, 1, 0), so the plant point (mean plain ankle) is
    // the mean hip minus that.
    let hips: Vec<DVec3> = (0..30).map(|f| pos(&world(&mut g, "LeftUpLeg", f, FPS))).collect();
    let plant = hips.iter().sum::<DVec3>() / 30.0 - DVec3::new(0.0, 1.0, 0.0);
    let mut straight = 0;
    for f in 0..30 {
        let [h, k, a] = ["LeftUpLeg", "LeftLeg", "LeftFoot"].map(|n| pos(&world(&mut g, n, f, FPS)));
        assert!(h.is_finite() && k.is_finite() && a.is_finite(), "frame {f}");
        assert!(((k - h).length() - 0.55).abs() < 1e-9 && ((a - k).length() - 0.45).abs() < 1e-9);
        if (plant - h).length() > 1.0 + 1e-9 {
            // Out of reach: straight, pointing at the plant point.
            let dir = (plant - h).normalize();
            assert!((k - (h + dir * 0.55)).length() < 1e-9, "frame {f}: knee {k}");
            assert!((a - (h + dir)).length() < 1e-9, "frame {f}: ankle {a}");
            straight += 1;
        } else {
            assert!((a - plant).length() < 1e-9, "frame {f}: ankle {a} vs plant {plant}");
        }
    }
    // Hip heights (0.85 + 0.3·f/29)/0.9 exceed their mean (taken at f = 14.5) for f ≥ 15.
    assert_eq!(straight, 15);
}

#[test]
fn retarget_cli_plants_feet_on_request() {
    let reg = registry();
    let dir = std::env::temp_dir().join(format!("sinew-retarget-feet-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bvh = dir.join("walk.bvh");
    std::fs::write(&bvh, bvh_text(&walk_frames(), 1.0 / FPS)).unwrap();
    let rig = dir.join("target.ron");
    target_rig().write(&reg, &rig).unwrap();
    let run = |extra: &[&str]| {
        let out = dir.join("out.glb");
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_sinew"))
            .args(["retarget", bvh.to_str().unwrap(), "--to", rig.to_str().unwrap(), "-o"])
            .arg(&out)
            .args(extra)
            .output()
            .unwrap();
        let text = format!(
            "{}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(o.status.success() && out.is_file(), "{text}");
        text
    };
    let planted = run(&["--plant-feet"]);
    assert!(
        planted.contains("left foot (LeftFoot): 1 contacts planted"),
        "{planted}"
    );
    assert!(
        planted.contains("right foot (RightFoot): 0 contacts planted"),
        "{planted}"
    );
    assert!(!run(&[]).contains("contacts planted"));
    // The contact lasts 20 frames = 0.67 s: a 1 s minimum drops it.
    let strict = run(&["--plant-feet", "--min-contact", "1.0"]);
    assert!(strict.contains("left foot (LeftFoot): 0 contacts planted"), "{strict}");
    let help = std::process::Command::new(env!("CARGO_BIN_EXE_sinew"))
        .args(["retarget", "--help"])
        .output()
        .unwrap();
    let help = String::from_utf8_lossy(&help.stdout);
    for flag in [
        "--plant-feet",
        "--contact-height",
        "--contact-speed",
        "--min-contact",
        "--plant-blend",
    ] {
        assert!(help.contains(flag), "{help}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

// ---------------------------------------------------------------- real walk onto the biped

fn shared() -> Option<PathBuf> {
    let d = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/assets/bvh/cmu_12_01_walk.bvh");
    if d.is_file() {
        Some(d)
    } else {
        eprintln!("skipping the real-walk foot planting test: {} is absent", d.display());
        None
    }
}

const BIPED_MAP: &[(&str, &str)] = &[
    ("Hips", "pelvis"),
    ("LeftUpLeg", "hip_L"),
    ("LeftLeg", "knee_L"),
    ("LeftFoot", "ankle_L"),
    ("LeftToeBase", "ball_L"),
    ("RightUpLeg", "hip_R"),
    ("RightLeg", "knee_R"),
    ("RightFoot", "ankle_R"),
    ("RightToeBase", "ball_R"),
];

fn biped(opts: &RetargetOptions, bvh: &sinew::io::Bvh) -> (Graph, RetargetReport) {
    let reg = registry();
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("graphs/examples/biped/biped.ron");
    let mut g = load_rig(&path, &reg).unwrap_or_else(|d| panic!("{}", d.render())).graph;
    let map: Vec<(String, String)> = BIPED_MAP.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    let report = retarget_with(bvh, &mut g, Some(&map), opts).unwrap();
    (g, report)
}

#[test]
fn retarget_walk_onto_biped_plants_both_feet() {
    let Some(file) = shared() else { return };
    let bvh = parse_bvh(&std::fs::read_to_string(file).unwrap()).unwrap();
    let (mut plain, plain_report) = biped(&RetargetOptions::default(), &bvh);
    let (mut planted, report) = biped(&planting(), &bvh);
    assert!(plain_report.feet.is_empty());
    assert_eq!(report.feet.len(), 2, "{:?}", report.warnings);
    for w in &report.warnings {
        eprintln!("warning: {w}");
    }
    let fps = report.fps;
    for foot in &report.feet {
        eprintln!(
            "{} foot: {} contacts {:?}, affected {:?}",
            foot.side,
            foot.intervals.len(),
            foot.intervals,
            foot.affected
        );
        // A 4.4 s walk at about one stride per second: several contacts per foot.
        assert!(foot.intervals.len() >= 3, "{} foot: {:?}", foot.side, foot.intervals);
        let (mut before, mut after) = (0.0f64, 0.0f64);
        for &(s, e) in &foot.intervals {
            let (s, e) = (s as usize, e as usize);
            let p0 = pos(&world(&mut plain, &foot.ankle, s, fps));
            let q0 = pos(&world(&mut planted, &foot.ankle, s, fps));
            for f in s..=e {
                before = before.max(horizontal(pos(&world(&mut plain, &foot.ankle, f, fps)) - p0));
                after = after.max(horizontal(pos(&world(&mut planted, &foot.ankle, f, fps)) - q0));
            }
        }
        eprintln!(
            "{} foot sliding during contacts: {before:.6e} without planting, {after:.3e} with",
            foot.side
        );
        assert!(after < 1e-6, "{} foot slides {after} with planting", foot.side);
        assert!(before > after);
        // No pops: the largest frame-to-frame ankle step, with and without planting (from frame 1:
        // frame 0 of this take is a calibration pose).
        let step = |g: &mut Graph| {
            let p: Vec<DVec3> = (1..bvh.frame_count)
                .map(|f| pos(&world(g, &foot.ankle, f, fps)))
                .collect();
            p.windows(2).map(|w| (w[1] - w[0]).length()).fold(0.0, f64::max)
        };
        let (sp, sq) = (step(&mut plain), step(&mut planted));
        eprintln!(
            "{} foot largest step per frame: {sp:.4} without planting, {sq:.4} with",
            foot.side
        );
        assert!(sq < 1.5 * sp, "{} foot pops: {sq} vs {sp}", foot.side);
    }
}
