//! Bake, animation channels: the sampled TRS and morph weights as LINEAR glTF channels,
//! channels that never move left out, keys that interpolation reproduces within the tolerance
//! removed.

use glam::{Quat, Vec3};

use super::bake::BakeOptions;
use super::scene::{AnimPath, Animation, AnimationChannel, Interpolation, Scene};

/// The baked animation: for each DAG node `i` its sampled `trs[i]` (scale, rotation,
/// translation per frame) against the rest TRS on `scene.nodes[i]`, and for each morphing
/// node `morph_nodes[k]` its weights `morph[k]` (`widths[k]` per frame).
pub(crate) fn animation(
    scene: &Scene,
    trs: &[Vec<(Vec3, Quat, Vec3)>],
    morph: &[Vec<f32>],
    widths: &[usize],
    morph_nodes: &[usize],
    times: &[f32],
    opts: &BakeOptions,
) -> Animation {
    let mut anim = Animation {
        name: Some(opts.name.clone()),
        channels: Vec::new(),
    };
    for (i, keys) in trs.iter().enumerate() {
        let ts: Vec<[f32; 3]> = keys.iter().map(|k| k.2.to_array()).collect();
        let ss: Vec<[f32; 3]> = keys.iter().map(|k| k.0.to_array()).collect();
        let mut rs: Vec<[f32; 4]> = Vec::with_capacity(keys.len());
        for k in keys {
            let mut q = k.1;
            if let Some(prev) = rs.last() {
                if Quat::from_array(*prev).dot(q) < 0.0 {
                    q = -q;
                }
            }
            rs.push(q.to_array());
        }
        let rest_node = &scene.nodes[i];
        let rest_t = [rest_node.translation.as_vec3().to_array()];
        let rest_s = [rest_node.scale.as_vec3().to_array()];
        let rest_r = rest_node.rotation.as_quat();
        push_channel(
            &mut anim,
            i,
            AnimPath::Translation,
            times,
            &ts,
            &rest_t,
            opts.tolerance,
            false,
        );
        push_channel(
            &mut anim,
            i,
            AnimPath::Scale,
            times,
            &ss,
            &rest_s,
            opts.tolerance,
            false,
        );
        let rest_rr = [if rs.first().is_some_and(|q| Quat::from_array(*q).dot(rest_r) < 0.0) {
            (-rest_r).to_array()
        } else {
            rest_r.to_array()
        }];
        push_channel(
            &mut anim,
            i,
            AnimPath::Rotation,
            times,
            &rs,
            &rest_rr,
            opts.tolerance,
            true,
        );
    }
    for (k, w) in morph.iter().enumerate() {
        let width = widths[k];
        let keys: Vec<Vec<f32>> = w.chunks(width).map(|c| c.to_vec()).collect();
        let rest = [keys[0].clone()];
        push_channel(
            &mut anim,
            morph_nodes[k],
            AnimPath::Weights,
            times,
            &keys,
            &rest,
            opts.tolerance,
            false,
        );
    }
    anim
}

fn dist(a: &[f32], b: &[f32], rotation: bool) -> f64 {
    if rotation {
        let d: f64 = a.iter().zip(b).map(|(x, y)| *x as f64 * *y as f64).sum();
        2.0 * d.abs().min(1.0).acos()
    } else {
        a.iter()
            .zip(b)
            .map(|(x, y)| (*x as f64 - *y as f64).abs())
            .fold(0.0, f64::max)
    }
}

fn interp(a: &[f32], b: &[f32], s: f64, rotation: bool) -> Vec<f32> {
    if rotation {
        let q = Quat::from_slice(a).slerp(Quat::from_slice(b), s as f32);
        q.to_array().to_vec()
    } else {
        a.iter()
            .zip(b)
            .map(|(x, y)| ((1.0 - s) * *x as f64 + s * *y as f64) as f32)
            .collect()
    }
}

/// Adds a LINEAR channel unless every key equals `rest` within `tol`; with `tol > 0`
/// removes keys that interpolation reproduces within `tol`.
#[allow(clippy::too_many_arguments)]
fn push_channel<K: AsRef<[f32]>>(
    anim: &mut Animation,
    node: usize,
    path: AnimPath,
    times: &[f32],
    keys: &[K],
    rest: &[K],
    tol: f64,
    rotation: bool,
) {
    let Some(r) = rest.first() else { return };
    let still = tol.max(1e-7);
    if keys.iter().all(|k| dist(k.as_ref(), r.as_ref(), rotation) <= still) {
        return;
    }
    let mut keep = vec![0usize];
    if tol > 0.0 {
        let mut a = 0;
        let mut j = 2;
        while j < keys.len() {
            let ok = (a + 1..j).all(|m| {
                let s = (times[m] - times[a]) as f64 / (times[j] - times[a]) as f64;
                let v = interp(keys[a].as_ref(), keys[j].as_ref(), s, rotation);
                dist(&v, keys[m].as_ref(), rotation) <= tol
            });
            if !ok {
                keep.push(j - 1);
                a = j - 1;
            }
            j += 1;
        }
        if keys.len() > 1 {
            keep.push(keys.len() - 1);
        }
    } else {
        keep = (0..keys.len()).collect();
    }
    let width = r.as_ref().len();
    anim.channels.push(AnimationChannel {
        node,
        path,
        interpolation: Interpolation::Linear,
        times: keep.iter().map(|&k| times[k]).collect(),
        width,
        values: keep.iter().flat_map(|&k| keys[k].as_ref().to_vec()).collect(),
    });
}
