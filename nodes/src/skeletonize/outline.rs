//! Silhouette outlines: marching squares over the raster mask gives closed, simple,
//! pairwise disjoint loops (outer boundaries counter-clockwise, holes clockwise);
//! Douglas–Peucker simplifies them; loops are grouped into parts (one outer
//! boundary with its holes).
//!
//! Tracing follows a successor table in which every crossing edge has exactly one
//! successor, so each loop is visited once and tracing always terminates.

use glam::DVec2;

use super::raster::Raster;

/// One connected region of the silhouette: an outer boundary and its holes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Part {
    /// Outer boundary, counter-clockwise, in plane coordinates (not repeated at the end).
    pub outer: Vec<DVec2>,
    /// Holes, clockwise.
    pub holes: Vec<Vec<DVec2>>,
    /// Area of the outer boundary minus the holes.
    pub area: f64,
}

impl Part {
    /// Every loop of the part (outer first).
    pub fn loops(&self) -> impl Iterator<Item = &Vec<DVec2>> {
        std::iter::once(&self.outer).chain(self.holes.iter())
    }

    /// Even-odd inside test against all loops of the part.
    pub fn contains(&self, p: DVec2) -> bool {
        self.loops().filter(|l| ring_crossings(l, p)).count() % 2 == 1
    }

    /// Distance from `p` to the nearest outline edge.
    pub fn distance_to_outline(&self, p: DVec2) -> f64 {
        let mut best = f64::INFINITY;
        for l in self.loops() {
            for k in 0..l.len() {
                let (a, b) = (l[k], l[(k + 1) % l.len()]);
                best = best.min(segment_distance(p, a, b));
            }
        }
        best
    }
}

/// Distance from `p` to the segment `ab`.
pub fn segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t).distance(p)
}

/// Whether a ray from `p` toward +x crosses `ring` an odd number of times.
fn ring_crossings(ring: &[DVec2], p: DVec2) -> bool {
    let mut inside = false;
    let n = ring.len();
    for k in 0..n {
        let (a, b) = (ring[k], ring[(k + 1) % n]);
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if p.x < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// Signed area (positive when counter-clockwise).
pub fn signed_area(ring: &[DVec2]) -> f64 {
    let n = ring.len();
    (0..n).map(|k| ring[k].perp_dot(ring[(k + 1) % n])).sum::<f64>() * 0.5
}

/// Traces the mask of `raster` into closed loops in plane coordinates.
///
/// Loops are simple and pairwise disjoint; the filled region is on their left.
/// Diagonal pixel pairs are treated as connected.
pub fn trace(raster: &Raster) -> Vec<Vec<DVec2>> {
    let (w, h) = (raster.width, raster.height);
    if w < 2 || h < 2 {
        return Vec::new();
    }
    let at = |i: usize, j: usize| raster.mask[j * w + i];
    // Grid edges between pixel centres: horizontal h(i, j) joins (i, j)-(i+1, j),
    // vertical v(i, j) joins (i, j)-(i, j+1).
    let hid = |i: usize, j: usize| j * w + i;
    let vid = |i: usize, j: usize| w * h + j * w + i;
    const NONE: u32 = u32::MAX;
    let mut next = vec![NONE; 2 * w * h];
    for j in 0..h - 1 {
        for i in 0..w - 1 {
            // Corners counter-clockwise (y up) and the edges between consecutive ones.
            let c = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
            let e = [hid(i, j), vid(i + 1, j), hid(i, j + 1), vid(i, j)];
            let case = c.iter().enumerate().fold(0, |m, (k, &b)| m | ((b as u8) << k));
            if case == 0 || case == 15 {
                continue;
            }
            // Edge k starts a segment when corner k is filled and k+1 is empty, and
            // ends one in the opposite case.
            match case {
                5 => {
                    // Saddle, corners 0 and 2 filled: connect them through the middle.
                    next[e[0]] = e[1] as u32;
                    next[e[2]] = e[3] as u32;
                }
                10 => {
                    next[e[1]] = e[2] as u32;
                    next[e[3]] = e[0] as u32;
                }
                _ => {
                    let mut start = None;
                    let mut end = None;
                    for k in 0..4 {
                        let (a, b) = (c[k], c[(k + 1) % 4]);
                        if a && !b {
                            start = Some(e[k]);
                        } else if !a && b {
                            end = Some(e[k]);
                        }
                    }
                    if let (Some(s), Some(t)) = (start, end) {
                        next[s] = t as u32;
                    }
                }
            }
        }
    }
    let point = |id: usize| -> DVec2 {
        let (g, horizontal) = if id < w * h { (id, true) } else { (id - w * h, false) };
        let (i, j) = ((g % w) as f64, (g / w) as f64);
        let (x, y) = if horizontal {
            (i + 1.0, j + 0.5)
        } else {
            (i + 0.5, j + 1.0)
        };
        raster.min + DVec2::new(x, y) * raster.pixel
    };
    let mut loops = Vec::new();
    for s in 0..next.len() {
        if next[s] == NONE {
            continue;
        }
        let mut ring = Vec::new();
        let mut cur = s;
        // Every id has one successor and is cleared when visited: this terminates.
        while next[cur] != NONE {
            ring.push(point(cur));
            let n = next[cur] as usize;
            next[cur] = NONE;
            cur = n;
        }
        if ring.len() >= 3 {
            loops.push(ring);
        }
    }
    loops
}

/// Douglas–Peucker simplification of a closed ring to `tol`; keeps at least 3 points
/// when the ring has them.
pub fn simplify_ring(ring: &[DVec2], tol: f64) -> Vec<DVec2> {
    let n = ring.len();
    if n <= 4 {
        return ring.to_vec();
    }
    // Split at the point farthest from ring[0] so both halves are open polylines.
    let far = (1..n)
        .max_by(|&a, &b| {
            ring[0]
                .distance_squared(ring[a])
                .total_cmp(&ring[0].distance_squared(ring[b]))
        })
        .unwrap_or(n / 2);
    let mut keep = vec![false; n + 1];
    keep[0] = true;
    keep[far] = true;
    keep[n] = true;
    let at = |k: usize| ring[k % n];
    let mut stack = vec![(0usize, far), (far, n)];
    while let Some((a, b)) = stack.pop() {
        if b <= a + 1 {
            continue;
        }
        let (pa, pb) = (at(a), at(b));
        let (mut best, mut bi) = (-1.0, a);
        for k in a + 1..b {
            let d = segment_distance(at(k), pa, pb);
            if d > best {
                best = d;
                bi = k;
            }
        }
        if best > tol {
            keep[bi] = true;
            stack.push((a, bi));
            stack.push((bi, b));
        }
    }
    let out: Vec<DVec2> = (0..n).filter(|&k| keep[k]).map(|k| ring[k]).collect();
    if out.len() >= 3 {
        out
    } else {
        // Keep a triangle: the two split points and the point farthest from their chord.
        let third = (1..n)
            .filter(|&k| k != far)
            .max_by(|&a, &b| {
                segment_distance(ring[a], ring[0], ring[far]).total_cmp(&segment_distance(ring[b], ring[0], ring[far]))
            })
            .unwrap_or(1);
        let mut idx = [0, far, third];
        idx.sort_unstable();
        idx.iter().map(|&k| ring[k]).collect()
    }
}

/// Traces, simplifies (tolerance `tol`, world units), drops loops smaller than
/// `min_area`, and groups loops into parts sorted by area, largest first.
pub fn parts(raster: &Raster, tol: f64, min_area: f64) -> Vec<Part> {
    let mut outers: Vec<(Vec<DVec2>, f64)> = Vec::new();
    let mut holes: Vec<(Vec<DVec2>, f64)> = Vec::new();
    for ring in trace(raster) {
        let s = simplify_ring(&ring, tol);
        let a = signed_area(&s);
        if a.abs() < min_area || s.len() < 3 {
            continue;
        }
        if a > 0.0 {
            outers.push((s, a));
        } else {
            holes.push((s, -a));
        }
    }
    let mut parts: Vec<Part> = outers
        .iter()
        .map(|(o, a)| Part {
            outer: o.clone(),
            holes: Vec::new(),
            area: *a,
        })
        .collect();
    for (hole, ha) in holes {
        // The smallest outer boundary containing the hole owns it.
        let probe = hole[0];
        let owner = outers
            .iter()
            .enumerate()
            .filter(|(_, (o, a))| *a > ha && ring_crossings(o, probe))
            .min_by(|a, b| a.1 .1.total_cmp(&b.1 .1))
            .map(|(k, _)| k);
        if let Some(k) = owner {
            parts[k].area -= ha;
            parts[k].holes.push(hole);
        }
    }
    parts.sort_by(|a, b| b.area.total_cmp(&a.area));
    parts
}

#[cfg(test)]
mod tests {
    use super::*;

    fn raster_from(rows: &[&str]) -> Raster {
        // rows[0] is the top row; pad with an empty border.
        let h = rows.len() + 2;
        let w = rows[0].len() + 2;
        let mut mask = vec![false; w * h];
        for (r, line) in rows.iter().enumerate() {
            let j = h - 2 - r;
            for (i, ch) in line.chars().enumerate() {
                mask[j * w + i + 1] = ch == '#';
            }
        }
        Raster {
            width: w,
            height: h,
            min: DVec2::ZERO,
            pixel: 1.0,
            mask,
            front: vec![0.0; w * h],
            back: vec![0.0; w * h],
        }
    }

    #[test]
    fn square_with_hole_gives_ccw_outer_and_cw_hole() {
        let r = raster_from(&["#####", "#...#", "#...#", "#####"]);
        let loops = trace(&r);
        assert_eq!(loops.len(), 2);
        let areas: Vec<f64> = loops.iter().map(|l| signed_area(l)).collect();
        assert_eq!(areas.iter().filter(|a| **a > 0.0).count(), 1);
        assert_eq!(areas.iter().filter(|a| **a < 0.0).count(), 1);
        let p = parts(&r, 0.1, 0.0);
        assert_eq!(p.len(), 1);
        assert_eq!(p[0].holes.len(), 1);
        assert!(p[0].contains(DVec2::new(1.5, 1.5)));
        assert!(!p[0].contains(DVec2::new(3.5, 2.5)));
    }

    #[test]
    fn diagonal_pixels_and_separate_blobs_terminate() {
        let r = raster_from(&["#..#", ".#..", "#.##", "...."]);
        let loops = trace(&r);
        assert!(!loops.is_empty());
        for l in &loops {
            assert!(l.len() >= 3);
        }
    }

    #[test]
    fn simplify_keeps_a_rectangle() {
        let mut ring = Vec::new();
        for i in 0..10 {
            ring.push(DVec2::new(i as f64, 0.0));
        }
        for j in 0..4 {
            ring.push(DVec2::new(10.0, j as f64));
        }
        for i in (1..=10).rev() {
            ring.push(DVec2::new(i as f64, 4.0));
        }
        for j in (1..=4).rev() {
            ring.push(DVec2::new(0.0, j as f64));
        }
        let s = simplify_ring(&ring, 0.1);
        assert_eq!(s.len(), 4);
        assert!((signed_area(&s) - 40.0).abs() < 1e-9);
    }
}
