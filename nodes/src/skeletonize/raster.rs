//! The view of the mesh that skeleton extraction works from: the projection frame
//! (principal axes), and a silhouette raster holding coverage plus the front and back
//! depth of the surface at every pixel.
//!
//! Rasterising the projected triangles instead of tracing their edges makes the
//! silhouette robust by construction: holes, several parts, non-manifold edges,
//! duplicate vertices and degenerate triangles only ever add or leave out pixels.

use glam::{DMat3, DVec2, DVec3};

use sinew_core::data::Mesh;

/// An orthonormal, right-handed projection frame: `u` and `v` span the silhouette
/// plane (largest and second-largest principal axes), `w` is the view axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Area-weighted centroid of the surface (world space).
    pub origin: DVec3,
    /// First in-plane axis (largest extent).
    pub u: DVec3,
    /// Second in-plane axis.
    pub v: DVec3,
    /// View (depth) axis, `u × v`; signed to point toward world +Z when it can.
    pub w: DVec3,
}

impl Frame {
    /// The principal-axes frame of `mesh`, viewing along the axis of least variance
    /// (or along `view_axis` when given). `None` when the mesh has no usable points.
    pub fn principal(mesh: &Mesh, view_axis: Option<DVec3>) -> Option<Frame> {
        let (origin, cov) = moments(mesh)?;
        let (w, u) = match view_axis.and_then(|a| a.try_normalize()) {
            Some(w) => {
                // Largest in-plane variance direction: eigen-decompose the covariance
                // restricted to the plane by projecting the principal axes.
                let p = DMat3::IDENTITY - outer(w, w);
                let (vals, vecs) = sym_eigen(p * cov * p);
                let i = (0..3).max_by(|&a, &b| vals[a].total_cmp(&vals[b])).unwrap_or(0);
                let u = (vecs.col(i) - w * vecs.col(i).dot(w))
                    .try_normalize()
                    .unwrap_or_else(|| w.any_orthonormal_vector());
                (w, u)
            }
            None => {
                let (vals, vecs) = sym_eigen(cov);
                let mut order = [0usize, 1, 2];
                order.sort_by(|&a, &b| vals[b].total_cmp(&vals[a]));
                (vecs.col(order[2]), vecs.col(order[0]))
            }
        };
        let w = sign_toward(w, [DVec3::Z, DVec3::Y, DVec3::X]);
        let u = sign_toward(u, [DVec3::X, DVec3::Y, DVec3::Z]);
        let v = w.cross(u).normalize_or_zero();
        if !(u.is_finite() && v.is_finite() && w.is_finite()) || v == DVec3::ZERO {
            return None;
        }
        Some(Frame { origin, u, v, w })
    }

    /// In-plane coordinates of a world point.
    pub fn to_plane(&self, p: DVec3) -> DVec2 {
        let d = p - self.origin;
        DVec2::new(d.dot(self.u), d.dot(self.v))
    }

    /// Depth of a world point along the view axis.
    pub fn depth(&self, p: DVec3) -> f64 {
        (p - self.origin).dot(self.w)
    }

    /// The world point with in-plane coordinates `q` and depth `d`.
    pub fn to_world(&self, q: DVec2, d: f64) -> DVec3 {
        self.origin + self.u * q.x + self.v * q.y + self.w * d
    }
}

fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

fn sign_toward(a: DVec3, prefs: [DVec3; 3]) -> DVec3 {
    for p in prefs {
        let d = a.dot(p);
        if d.abs() > 1e-9 {
            return if d < 0.0 { -a } else { a };
        }
    }
    a
}

/// Area-weighted centroid and covariance of the surface (triangle centroids weighted
/// by area); falls back to the plain vertex cloud when the surface has no area.
fn moments(mesh: &Mesh) -> Option<(DVec3, DMat3)> {
    let pos = |i: u32| mesh.positions.get(i as usize).map(|p| p.as_dvec3());
    let mut samples: Vec<(DVec3, f64)> = Vec::with_capacity(mesh.triangles.len());
    for t in &mesh.triangles {
        if let (Some(a), Some(b), Some(c)) = (pos(t[0]), pos(t[1]), pos(t[2])) {
            let area = 0.5 * (b - a).cross(c - a).length();
            if area > 0.0 && area.is_finite() {
                samples.push(((a + b + c) / 3.0, area));
            }
        }
    }
    if samples.is_empty() {
        samples = mesh.positions.iter().map(|p| (p.as_dvec3(), 1.0)).collect();
    }
    let total: f64 = samples.iter().map(|s| s.1).sum();
    if samples.is_empty() || total <= 0.0 || !total.is_finite() {
        return None;
    }
    let c = samples.iter().map(|(p, a)| *p * *a).sum::<DVec3>() / total;
    let mut cov = DMat3::ZERO;
    for (p, a) in &samples {
        let d = *p - c;
        cov += outer(d, d) * *a;
    }
    Some((c, cov * (1.0 / total)))
}

/// Eigenvalues and eigenvectors (as columns) of a symmetric 3×3 matrix (cyclic Jacobi).
pub(crate) fn sym_eigen(m: DMat3) -> ([f64; 3], DMat3) {
    let mut a = m.to_cols_array_2d();
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..32 {
        let off = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
        if off < 1e-30 * (a[0][0].powi(2) + a[1][1].powi(2) + a[2][2].powi(2)).max(1e-300) {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() < 1e-300 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in a.iter_mut() {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (rp, rq) = (a[p], a[q]);
            a[p] = std::array::from_fn(|k| c * rp[k] - s * rq[k]);
            a[q] = std::array::from_fn(|k| s * rp[k] + c * rq[k]);
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    // `v[row][col]`: eigenvector k is column k.
    let cols = DMat3::from_cols(
        DVec3::new(v[0][0], v[1][0], v[2][0]),
        DVec3::new(v[0][1], v[1][1], v[2][1]),
        DVec3::new(v[0][2], v[1][2], v[2][2]),
    );
    ([a[0][0], a[1][1], a[2][2]], cols)
}

/// A silhouette raster: pixel `(i, j)` covers the square of side `pixel` whose
/// lower-left corner is `min + (i, j) * pixel` in plane coordinates.
#[derive(Clone, Debug)]
pub struct Raster {
    /// Width in pixels (including an empty border).
    pub width: usize,
    /// Height in pixels (including an empty border).
    pub height: usize,
    /// Plane coordinates of the lower-left corner of pixel (0, 0).
    pub min: DVec2,
    /// Side of one pixel in world units.
    pub pixel: f64,
    /// Coverage, row-major (`j * width + i`).
    pub mask: Vec<bool>,
    /// Nearest surface depth per pixel (`+inf` where nothing was drawn).
    pub front: Vec<f32>,
    /// Farthest surface depth per pixel (`-inf` where nothing was drawn).
    pub back: Vec<f32>,
}

/// Empty pixels kept around the drawing (closing needs one, marching squares one).
const BORDER: usize = 3;

impl Raster {
    /// Rasterises `mesh` in `frame` with `resolution` pixels along the longer side
    /// and closes gaps up to `2 * close_radius` pixels wide.
    ///
    /// Returns `None` when the projected extent is zero or not finite.
    pub fn draw(mesh: &Mesh, frame: &Frame, resolution: usize, close_radius: usize) -> Option<Self> {
        let pts: Vec<(DVec2, f64)> = mesh
            .positions
            .iter()
            .map(|p| {
                let p = p.as_dvec3();
                (frame.to_plane(p), frame.depth(p))
            })
            .collect();
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        for t in &mesh.triangles {
            for &i in t {
                if let Some((q, _)) = pts.get(i as usize) {
                    lo = lo.min(*q);
                    hi = hi.max(*q);
                }
            }
        }
        let ext = hi - lo;
        if !ext.is_finite() || ext.max_element() <= 0.0 {
            return None;
        }
        let res = resolution.clamp(8, 4096) as f64;
        let pixel = ext.max_element() / res;
        let pad = (BORDER + close_radius) as f64;
        let width = (ext.x / pixel).ceil() as usize + 2 * (BORDER + close_radius);
        let height = (ext.y / pixel).ceil() as usize + 2 * (BORDER + close_radius);
        let min = lo - DVec2::splat(pad * pixel);
        let n = width * height;
        let mut r = Raster {
            width,
            height,
            min,
            pixel,
            mask: vec![false; n],
            front: vec![f32::INFINITY; n],
            back: vec![f32::NEG_INFINITY; n],
        };
        // Pixel-space coordinates: pixel (i, j) has its centre at (i + 0.5, j + 0.5).
        let px: Vec<(DVec2, f64)> = pts.iter().map(|(q, d)| ((*q - min) / pixel, *d)).collect();
        for t in &mesh.triangles {
            let (Some(a), Some(b), Some(c)) = (px.get(t[0] as usize), px.get(t[1] as usize), px.get(t[2] as usize))
            else {
                continue;
            };
            if !r.fill_triangle(*a, *b, *c) {
                r.line(*a, *b);
                r.line(*b, *c);
                r.line(*c, *a);
            }
        }
        if close_radius > 0 {
            r.close(close_radius);
        }
        Some(r)
    }

    fn plot(&mut self, i: usize, j: usize, d: f64) {
        if i < self.width && j < self.height {
            let k = j * self.width + i;
            self.mask[k] = true;
            let d = d as f32;
            self.front[k] = self.front[k].min(d);
            self.back[k] = self.back[k].max(d);
        }
    }

    /// Fills the pixels whose centres lie inside the triangle; false if none did.
    fn fill_triangle(&mut self, a: (DVec2, f64), b: (DVec2, f64), c: (DVec2, f64)) -> bool {
        let (pa, pb, pc) = (a.0, b.0, c.0);
        let area = (pb - pa).perp_dot(pc - pa);
        if area.abs() < 1e-12 || !area.is_finite() {
            return false;
        }
        let lo = pa.min(pb).min(pc);
        let hi = pa.max(pb).max(pc);
        let i0 = (lo.x - 0.5).ceil().max(0.0) as usize;
        let j0 = (lo.y - 0.5).ceil().max(0.0) as usize;
        let i1 = ((hi.x - 0.5).floor().min(self.width as f64 - 1.0)).max(-1.0);
        let j1 = ((hi.y - 0.5).floor().min(self.height as f64 - 1.0)).max(-1.0);
        if i1 < 0.0 || j1 < 0.0 {
            return false;
        }
        let (i1, j1) = (i1 as usize, j1 as usize);
        let inv = 1.0 / area;
        let mut any = false;
        for j in j0..=j1 {
            for i in i0..=i1 {
                let p = DVec2::new(i as f64 + 0.5, j as f64 + 0.5);
                let wa = (pb - p).perp_dot(pc - p) * inv;
                let wb = (pc - p).perp_dot(pa - p) * inv;
                let wc = 1.0 - wa - wb;
                if wa >= -1e-9 && wb >= -1e-9 && wc >= -1e-9 {
                    self.plot(i, j, wa * a.1 + wb * b.1 + wc * c.1);
                    any = true;
                }
            }
        }
        any
    }

    /// Marks every pixel the segment passes through (slivers and degenerate triangles).
    fn line(&mut self, a: (DVec2, f64), b: (DVec2, f64)) {
        let len = (b.0 - a.0).abs().max_element();
        let steps = (len * 2.0).ceil().clamp(1.0, 1e6) as usize;
        for s in 0..=steps {
            let t = s as f64 / steps as f64;
            let p = a.0.lerp(b.0, t);
            if p.x >= 0.0 && p.y >= 0.0 {
                self.plot(p.x as usize, p.y as usize, a.1 + (b.1 - a.1) * t);
            }
        }
    }

    /// Morphological closing (dilate then erode) with a square of radius `r`.
    fn close(&mut self, r: usize) {
        let dil = self.morph(&self.mask, r, true);
        let ero = self.morph(&dil, r, false);
        self.mask = ero;
    }

    /// Separable square dilation (`grow`) or erosion of `m` by radius `r`; pixels
    /// outside the raster count as empty.
    fn morph(&self, m: &[bool], r: usize, grow: bool) -> Vec<bool> {
        let (w, h) = (self.width, self.height);
        let pass = |src: &[bool], len: usize, stride: usize, count: usize, step: usize| {
            let mut out = vec![false; w * h];
            for line in 0..count {
                let base = line * step;
                for x in 0..len {
                    let (a, b) = (x.saturating_sub(r), x + r);
                    let clipped = a + r != x || b >= len;
                    let mut any = false;
                    let mut all = !clipped;
                    for y in a..=b.min(len - 1) {
                        let v = src[base + y * stride];
                        any |= v;
                        all &= v;
                    }
                    out[base + x * stride] = if grow { any } else { all };
                }
            }
            out
        };
        let rows = pass(m, w, 1, h, w);
        pass(&rows, h, w, w, 1)
    }

    /// Plane coordinates of the centre of pixel `(i, j)`.
    pub fn center(&self, i: usize, j: usize) -> DVec2 {
        self.min + DVec2::new(i as f64 + 0.5, j as f64 + 0.5) * self.pixel
    }

    /// Mid-depth of the surface around plane point `q`: the mean over nearby drawn
    /// pixels of `(front + back) / 2`, searching outward up to `max_ring` pixels.
    pub fn mid_depth(&self, q: DVec2, max_ring: usize) -> Option<f64> {
        let g = (q - self.min) / self.pixel;
        if !g.is_finite() {
            return None;
        }
        let ci = g.x.floor().clamp(0.0, self.width as f64 - 1.0) as i64;
        let cj = g.y.floor().clamp(0.0, self.height as f64 - 1.0) as i64;
        for ring in 1..=max_ring.max(1) as i64 {
            let (mut sum, mut n) = (0.0, 0usize);
            for j in cj - ring..=cj + ring {
                for i in ci - ring..=ci + ring {
                    if i < 0 || j < 0 || i >= self.width as i64 || j >= self.height as i64 {
                        continue;
                    }
                    let k = j as usize * self.width + i as usize;
                    if self.front[k] <= self.back[k] {
                        sum += 0.5 * (self.front[k] as f64 + self.back[k] as f64);
                        n += 1;
                    }
                }
            }
            if n > 0 {
                return Some(sum / n as f64);
            }
        }
        None
    }
}
