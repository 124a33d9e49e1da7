//! BVH reader and forward-kinematics tests.

use glam::{DMat3, DVec3};
use proptest::prelude::*;

use super::assets_dir;
use crate::bvh::{parse_bvh, Axis, Channel};

const TINY: &str = "HIERARCHY\r\nROOT hips\n{\r\n\tOFFSET 0 0 0\n\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\r\n\
\tJOINT spine\n\t{\n\t\tOFFSET 0 10 0\r\n\t\tCHANNELS 3 Zrotation Xrotation Yrotation\n\t\tEnd Site\n\t\t{\n\t\t\tOFFSET 0 5 0\n\t\t}\n\t}\n\
  JOINT leg\n  {\n    OFFSET   3 0 0\n    CHANNELS 3 Xrotation Yrotation Zrotation\n    End Site\n    {\n      OFFSET 0 -4 0\n    }\n  }\n}\n\
MOTION\r\nFrames: 3\r\nFrame Time: 0.5\r\n\
0 0 0 0 0 0 0 0 0 0 0 0\r\n\
\n\
1 2 3 90 0 0 0 90 0 0 0 0\n\
0 0 0 0 0 0 90 90 0 0 0 0   \r\n";

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-9
}

#[test]
fn tiny_file_structure() {
    let b = parse_bvh(TINY).expect("tiny file parses");
    assert_eq!(b.joints.len(), 3);
    assert_eq!(b.end_site_count(), 2);
    assert_eq!(b.frame_count, 3);
    assert_eq!(b.frame_time, 0.5);
    assert_eq!(b.channel_count(), 12);
    assert_eq!(b.values.len(), 36);
    assert_eq!(b.joints[1].parent, Some(0));
    assert_eq!(b.joints[2].parent, Some(0));
    assert_eq!(b.joints[2].first_channel, 9);
    assert_eq!(b.joints[0].channels[0], Channel::Position(Axis::X));
    assert_eq!(b.rotation_order(0), Some([Axis::Z, Axis::X, Axis::Y]));
    assert_eq!(b.rotation_order(2), Some([Axis::X, Axis::Y, Axis::Z]));
    assert_eq!(b.joints[2].end_site, Some(DVec3::new(0.0, -4.0, 0.0)));
}

#[test]
fn tiny_file_forward_kinematics() {
    let b = parse_bvh(TINY).unwrap();
    // Frame 0: rest pose = accumulated offsets.
    let p = b.world_positions(0);
    assert!(close(p[1], DVec3::new(0.0, 10.0, 0.0)));
    assert!(close(p[2], DVec3::new(3.0, 0.0, 0.0)));
    // Frame 1: root at (1,2,3) turned 90° about Z: (0,10,0) -> (-10,0,0), (3,0,0) -> (0,3,0).
    // The spine turns 90° about X: its end site (0,5,0) -> (0,0,5), unchanged by Rz.
    let p = b.world_positions(1);
    assert!(close(p[0], DVec3::new(1.0, 2.0, 3.0)));
    assert!(close(p[1], DVec3::new(-9.0, 2.0, 3.0)), "{:?}", p[1]);
    assert!(close(p[2], DVec3::new(1.0, 5.0, 3.0)), "{:?}", p[2]);
    let e = b.end_site_positions(1);
    assert!(close(e[1].unwrap(), DVec3::new(-9.0, 2.0, 8.0)), "{:?}", e[1]);
    // Frame 2: spine "Zrotation Xrotation" = 90, 90 means Rz * Rx: (0,5,0) -Rx-> (0,0,5)
    // -Rz-> (0,0,5). The opposite order would give (-5,0,0).
    let e = b.end_site_positions(2);
    assert!(close(e[1].unwrap(), DVec3::new(0.0, 10.0, 5.0)), "{:?}", e[1]);
    assert!(b.world_positions(3).is_empty());
    assert!(b.local_transform(9, 0).is_none());
}

fn rot(axis: Axis, deg: f64) -> DMat3 {
    let (s, c) = deg.to_radians().sin_cos();
    // Right-handed rotation matrices written out by hand (column-vector convention).
    match axis {
        Axis::X => DMat3::from_cols_array(&[1.0, 0.0, 0.0, 0.0, c, s, 0.0, -s, c]),
        Axis::Y => DMat3::from_cols_array(&[c, 0.0, -s, 0.0, 1.0, 0.0, s, 0.0, c]),
        Axis::Z => DMat3::from_cols_array(&[c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0]),
    }
}

proptest! {
    /// The local rotation equals the product of per-axis matrices in channel order.
    #[test]
    fn rotation_is_product_in_channel_order(a in -180.0f64..180.0, b in -180.0f64..180.0, c in -180.0f64..180.0) {
        let text = format!(
            "HIERARCHY\nROOT r\n{{\nOFFSET 0 0 0\nCHANNELS 3 Yrotation Zrotation Xrotation\n}}\nMOTION\nFrames: 1\nFrame Time: 1\n{a} {b} {c}\n"
        );
        let bvh = parse_bvh(&text).unwrap();
        let (_, q) = bvh.local_transform(0, 0).unwrap();
        let m = rot(Axis::Y, a) * rot(Axis::Z, b) * rot(Axis::X, c);
        let d = DMat3::from_quat(q) - m;
        prop_assert!(d.x_axis.length() + d.y_axis.length() + d.z_axis.length() < 1e-9);
    }

    /// Random byte edits of a valid file never panic.
    #[test]
    fn mutations_do_not_panic(edits in proptest::collection::vec((0usize..TINY.len(), 0u8..128, 0u8..3), 1..8), cut in 0usize..TINY.len() + 1) {
        let mut bytes = TINY.as_bytes().to_vec();
        for (at, byte, op) in edits {
            let at = at.min(bytes.len().saturating_sub(1));
            match op {
                0 if !bytes.is_empty() => bytes[at] = byte,
                1 if !bytes.is_empty() => { bytes.remove(at); }
                _ => bytes.insert(at, byte),
            }
        }
        bytes.truncate(cut.max(1));
        let text = String::from_utf8_lossy(&bytes);
        let _ = parse_bvh(&text);
    }
}

fn expect_err(text: &str, line: usize, needle: &str) {
    match parse_bvh(text) {
        Ok(_) => panic!("expected an error containing '{needle}'"),
        Err(e) => {
            let msg = e.to_string();
            assert_eq!(e.line, line, "wrong line in: {msg}");
            assert!(msg.contains(needle), "'{msg}' does not mention '{needle}'");
        }
    }
}

#[test]
fn malformed_inputs_give_line_numbered_errors() {
    // The tiny file's frame lines are 28, 30 and 31 (29 is blank).
    let short = TINY.replace("1 2 3 90 0 0 0 90 0 0 0 0", "1 2 3 90 0 0 0 90 0 0 0");
    expect_err(
        &short,
        30,
        "frame 1 has 11 values but the hierarchy declares 12 channels",
    );
    let bad = TINY.replace("1 2 3 90", "1 2 x3 90");
    expect_err(&bad, 30, "value 3 is not a number: 'x3'");
    let nan = TINY.replace("1 2 3 90", "1 2 NaN 90");
    expect_err(&nan, 30, "not a number");
    let bad_offset = TINY.replace("OFFSET   3 0 0", "OFFSET   3 zero 0");
    expect_err(&bad_offset, 17, "expected the OFFSET y value but found 'zero'");
    let missing_brace = TINY.replacen("\t}\nJOINT leg", "JOINT leg", 1);
    assert_ne!(missing_brace, TINY);
    expect_err(&missing_brace, 24, "joint hips opened on line 2 is not closed");
    let truncated = &TINY[..TINY.find("0 0 0 0 0 0 90").unwrap()];
    expect_err(
        truncated,
        31,
        "file ends after 2 frames but 'Frames:' on line 26 declares 3",
    );
    let cut_hierarchy = &TINY[..TINY.find("End Site").unwrap()];
    assert!(parse_bvh(cut_hierarchy).unwrap_err().to_string().contains("MOTION"));
    expect_err(
        "HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 2 Xrotation Wrotation\n}\n",
        5,
        "found 'Wrotation'",
    );
    expect_err("ROOT a\n", 1, "expected HIERARCHY");
    let frames = TINY.replace("Frames: 3", "Frames: three");
    expect_err(&frames, 26, "whole number of frames");
    let extra = format!("{TINY}0 0 0 0 0 0 0 0 0 0 0 0\n");
    expect_err(&extra, 32, "extra data after the 3 frames");
}

#[test]
fn multiple_roots_are_separate_skeletons() {
    let text = "HIERARCHY\nROOT a\n{\nOFFSET 1 0 0\nCHANNELS 1 Xposition\n}\nROOT b\n{\nOFFSET 0 2 0\nCHANNELS 1 Yrotation\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n5 30\n";
    let b = parse_bvh(text).unwrap();
    assert_eq!(b.joints.len(), 2);
    assert_eq!(b.joints[1].parent, None);
    let p = b.world_positions(0);
    // The Xposition channel replaces the x offset.
    assert!(close(p[0], DVec3::new(5.0, 0.0, 0.0)));
    assert!(close(p[1], DVec3::new(0.0, 2.0, 0.0)));
}

#[test]
fn cmu_walk_asset() {
    let Some(dir) = assets_dir() else { return };
    let text = std::fs::read_to_string(dir.join("bvh/cmu_12_01_walk.bvh")).unwrap();
    let lf_only = text.split('\n').filter(|l| !l.is_empty() && !l.ends_with('\r')).count();
    assert!(text.contains("\r\n") && lf_only > 0, "expected mixed line endings");
    let b = parse_bvh(&text).unwrap();
    assert_eq!(b.joints.len(), 31);
    assert_eq!(b.end_site_count(), 7);
    assert_eq!(b.frame_count, 524);
    assert!((1.0 / b.frame_time - 120.0).abs() < 0.01);
    assert_eq!(b.channel_count(), 6 + 30 * 3);
    assert_eq!(b.values.len(), 524 * 96);
    assert_eq!(b.rotation_order(0), Some([Axis::Z, Axis::Y, Axis::X]));
    for f in [0, 100, 523] {
        let p = b.world_positions(f);
        assert_eq!(p.len(), 31);
        assert!(p.iter().all(|v| v.is_finite()));
        // Bones keep their length under FK.
        for (i, j) in b.joints.iter().enumerate() {
            if let Some(par) = j.parent {
                assert!(((p[i] - p[par]).length() - j.offset.length()).abs() < 1e-9);
            }
        }
    }
}

#[test]
fn pybvh_60_joint_asset() {
    let Some(dir) = assets_dir() else { return };
    let text = std::fs::read_to_string(dir.join("bvh/pybvh_test3_60joints.bvh")).unwrap();
    let b = parse_bvh(&text).unwrap();
    assert_eq!(b.joints.len(), 60);
    assert_eq!(b.end_site_count(), 13);
    assert_eq!(b.frame_count, 100);
    assert_eq!(b.channel_count(), 6 + 59 * 3);
    let orders: std::collections::HashSet<_> = (0..60).filter_map(|j| b.rotation_order(j)).collect();
    assert!(orders.len() >= 3, "the file mixes rotation orders");
    assert_eq!(b.world_positions(99).len(), 60);
}
