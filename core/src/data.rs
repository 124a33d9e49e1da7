//! Heavy data that flows through the graph behind an `Arc`: meshes, skin weights, curves and
//! NURBS surfaces.
//!
//! These are plain data types with no behaviour beyond validation and cheap
//! helpers; deformers and other plugins in `sinew-nodes` do the work. Positions
//! and normals are `f32` (the precision of glTF and of GPU skinning); curves are
//! `f64` because they live in the authoring path.

use glam::{DVec3, Vec2, Vec3};

/// A triangle mesh: positions, optional per-vertex normals and UVs, and triangles.
///
/// `normals` and `uvs` are either empty or exactly as long as `positions`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions in object space.
    pub positions: Vec<Vec3>,
    /// Per-vertex unit normals (empty when the mesh has none).
    pub normals: Vec<Vec3>,
    /// Per-vertex texture coordinates (empty when the mesh has none).
    pub uvs: Vec<Vec2>,
    /// Triangles as three vertex indices each, counter-clockwise when seen from the front.
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Checks the invariants: attribute lengths match and every index is in range.
    ///
    /// Returns a message naming the first problem and how to fix it.
    pub fn validate(&self) -> Result<(), String> {
        let n = self.positions.len();
        if !self.normals.is_empty() && self.normals.len() != n {
            return Err(format!(
                "mesh has {n} positions but {} normals; give one normal per vertex or none",
                self.normals.len()
            ));
        }
        if !self.uvs.is_empty() && self.uvs.len() != n {
            return Err(format!(
                "mesh has {n} positions but {} uvs; give one uv per vertex or none",
                self.uvs.len()
            ));
        }
        for (t, tri) in self.triangles.iter().enumerate() {
            if let Some(&bad) = tri.iter().find(|&&i| i as usize >= n) {
                return Err(format!(
                    "triangle {t} uses vertex {bad} but the mesh has only {n} vertices"
                ));
            }
        }
        if let Some(i) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(format!("vertex {i} has a non-finite position"));
        }
        Ok(())
    }

    /// Recomputes smooth vertex normals from the triangles, weighted by angle and area as
    /// Maya's default *Vertex Normal Method* ("Angle and Area Weighted"): each triangle adds
    /// its normal scaled by its area and by its corner angle at the vertex.
    ///
    /// Vertices touched by no triangle (or only by degenerate ones) get `+Y`.
    pub fn recompute_normals(&mut self) {
        let mut acc = vec![Vec3::ZERO; self.positions.len()];
        for tri in &self.triangles {
            let [a, b, c] = tri.map(|i| i as usize);
            if a >= acc.len() || b >= acc.len() || c >= acc.len() {
                continue;
            }
            let p = [self.positions[a], self.positions[b], self.positions[c]];
            // |cross| is twice the area: the face normal scaled by the area (up to 2).
            let n = (p[1] - p[0]).cross(p[2] - p[0]);
            for (k, v) in [a, b, c].into_iter().enumerate() {
                let (e1, e2) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
                let angle = e1.cross(e2).length().atan2(e1.dot(e2));
                if angle.is_finite() {
                    acc[v] += n * angle;
                }
            }
        }
        self.normals = acc.into_iter().map(|n| n.try_normalize().unwrap_or(Vec3::Y)).collect();
    }
}

/// Sparse skin weights in compressed-row form: vertex `v` has influences
/// `joints[offsets[v]..offsets[v + 1]]` with weights `weights[same range]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Weights {
    /// `vertex_count + 1` offsets into `joints`/`weights`, starting at 0, non-decreasing.
    pub offsets: Vec<u32>,
    /// Influence (joint) index of each entry.
    pub joints: Vec<u32>,
    /// Weight of each entry.
    pub weights: Vec<f32>,
}

impl Default for Weights {
    fn default() -> Self {
        Weights {
            offsets: vec![0],
            joints: Vec::new(),
            weights: Vec::new(),
        }
    }
}

impl Weights {
    /// Builds weights from one list of `(joint, weight)` pairs per vertex.
    pub fn from_lists<I, L>(per_vertex: I) -> Self
    where
        I: IntoIterator<Item = L>,
        L: IntoIterator<Item = (u32, f32)>,
    {
        let mut w = Weights::default();
        for list in per_vertex {
            for (j, x) in list {
                w.joints.push(j);
                w.weights.push(x);
            }
            w.offsets.push(w.joints.len() as u32);
        }
        w
    }

    /// Number of vertices these weights cover.
    pub fn vertex_count(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// The influences of vertex `v` as parallel slices (joints, weights).
    ///
    /// Out-of-range vertices have no influences.
    pub fn influences(&self, v: usize) -> (&[u32], &[f32]) {
        match (self.offsets.get(v), self.offsets.get(v + 1)) {
            (Some(&a), Some(&b)) if a <= b && (b as usize) <= self.joints.len() => {
                let r = a as usize..b as usize;
                (&self.joints[r.clone()], &self.weights[r])
            }
            _ => (&[], &[]),
        }
    }

    /// Checks the compressed-row invariants and that weights are finite.
    pub fn validate(&self) -> Result<(), String> {
        if self.offsets.first() != Some(&0) {
            return Err("weights offsets must start at 0".into());
        }
        if self.joints.len() != self.weights.len() {
            return Err(format!(
                "weights have {} joint indices but {} weights; they must be parallel",
                self.joints.len(),
                self.weights.len()
            ));
        }
        if self.offsets.windows(2).any(|w| w[0] > w[1]) {
            return Err("weights offsets must not decrease".into());
        }
        if self.offsets.last().copied().unwrap_or(0) as usize != self.joints.len() {
            return Err("the last weights offset must equal the number of entries".into());
        }
        if let Some(i) = self.weights.iter().position(|w| !w.is_finite()) {
            return Err(format!("weight entry {i} is not finite"));
        }
        Ok(())
    }
}

/// Whether a curve is open or closed (periodic).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CurveForm {
    /// An open curve that starts at its first and ends at its last control point (clamped knots).
    #[default]
    Open,
    /// A periodic closed curve.
    Periodic,
}

/// A non-rational B-spline curve (Maya's nurbsCurve with all weights 1).
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// Polynomial degree (1 = polyline, 3 = cubic).
    pub degree: u32,
    /// Control points.
    pub points: Vec<DVec3>,
    /// Knot vector of length `points.len() + degree + 1`; empty means uniform clamped.
    pub knots: Vec<f64>,
    /// Open or periodic.
    pub form: CurveForm,
}

impl Default for Curve {
    fn default() -> Self {
        Curve {
            degree: 3,
            points: Vec::new(),
            knots: Vec::new(),
            form: CurveForm::Open,
        }
    }
}

/// A non-rational B-spline surface (Maya's nurbsSurface with all weights 1): a grid of
/// control points, a degree, knots and a form in each of the two directions.
///
/// Control points are stored `u`-major as Maya lists them (`v` varies fastest):
/// point `(i, j)` is `points[i * count_v + j]`, `i < count_u`, `j < count_v`. Each
/// direction follows [`Curve`]'s conventions: empty knots mean uniform (clamped when
/// open, with the first `degree` rows or columns wrapped when periodic), explicit knots
/// are `count + degree + 1` values or Maya's `count + degree - 1`.
#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    /// Degree in `u` (1 = bilinear across, 3 = cubic).
    pub degree_u: u32,
    /// Degree in `v`.
    pub degree_v: u32,
    /// Open or periodic in `u`.
    pub form_u: CurveForm,
    /// Open or periodic in `v`.
    pub form_v: CurveForm,
    /// Number of control points along `u` (rows).
    pub count_u: u32,
    /// Number of control points along `v` (columns).
    pub count_v: u32,
    /// `count_u * count_v` control points, `v` varying fastest.
    pub points: Vec<DVec3>,
    /// Knot vector in `u`; empty means uniform.
    pub knots_u: Vec<f64>,
    /// Knot vector in `v`; empty means uniform.
    pub knots_v: Vec<f64>,
}

impl Default for Surface {
    fn default() -> Self {
        Surface {
            degree_u: 3,
            degree_v: 3,
            form_u: CurveForm::Open,
            form_v: CurveForm::Open,
            count_u: 0,
            count_v: 0,
            points: Vec::new(),
            knots_u: Vec::new(),
            knots_v: Vec::new(),
        }
    }
}

impl Surface {
    /// Checks that the grid holds `count_u * count_v` points (the one invariant the type
    /// itself keeps; degrees, knots and finiteness are checked where the surface is
    /// evaluated, with messages naming the fix).
    pub fn validate(&self) -> Result<(), String> {
        let want = self.count_u as usize * self.count_v as usize;
        if self.points.len() != want {
            return Err(format!(
                "surface has {} control points but a {} x {} grid needs {want}",
                self.points.len(),
                self.count_u,
                self.count_v
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Maya's "Angle and Area Weighted" vertex normal, by hand: vertex 0 is a 90° corner of
    /// a triangle of area 1/2 with normal +Z and a 45° corner of a triangle of area 1/2 with
    /// normal +Y, so its normal is (0, π/4, π/2) normalized = (0, 1, 2)/√5 (area weighting
    /// alone would give (0, 1, 1)/√2).
    #[test]
    fn smooth_normals_weight_by_angle_and_area() {
        let mut m = Mesh {
            positions: vec![
                Vec3::ZERO,
                Vec3::X,
                Vec3::Y,
                Vec3::Z,
                Vec3::new(1.0, 0.0, 1.0),
                Vec3::splat(5.0),
            ],
            normals: Vec::new(),
            uvs: Vec::new(),
            triangles: vec![[0, 1, 2], [0, 3, 4]],
        };
        m.recompute_normals();
        let want = Vec3::new(0.0, 1.0, 2.0) / 5f32.sqrt();
        assert!((m.normals[0] - want).length() < 1e-6, "{}", m.normals[0]);
        assert_eq!(m.normals[1], Vec3::Z);
        assert_eq!(m.normals[4], Vec3::Y);
        assert_eq!(m.normals[5], Vec3::Y, "unused vertex");
    }
}
