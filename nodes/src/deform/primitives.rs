//! Procedural primitive meshes (plane, box, UV sphere, cylinder, capsule) for the `mesh` node,
//! tests and examples.
//!
//! Conventions shared by every primitive:
//! - centred at the origin, axis of revolution `+Y`;
//! - triangles are counter-clockwise seen from outside (the side the normals point to);
//! - UVs lie in `[0, 1]²` and never overlap, so a UV identifies one surface point
//!   (what [`super::surface`] needs for follicles);
//! - the UV frame is right-handed with the normal: `dP/du × dP/dv` points along the normal;
//! - surfaces of revolution start at angle 0 on `+Z` and `u` grows towards `+X`; the seam is
//!   duplicated (one column at `u = 0` and one at `u = 1`); poles get one vertex per segment so
//!   each pole triangle has its own `u`.
//!
//! Counts below `segments = 3`, `rings = 1` are raised to those minima (as Maya does);
//! negative, zero or non-finite sizes are an error.

use glam::{Vec2, Vec3};
use sinew_core::data::Mesh;
use std::f32::consts::{FRAC_PI_2, PI, TAU};

/// Why a primitive could not be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PrimitiveError {
    /// A size parameter was zero, negative or not finite.
    #[error("primitive parameter `{name}` is {value}; it must be a finite number greater than 0")]
    NonPositive {
        /// Parameter name.
        name: &'static str,
        /// The value given.
        value: f32,
    },
    /// A capsule shorter than its two hemispheres.
    #[error("capsule height {height} is less than twice its radius {radius}; make the height at least {min}", min = 2.0 * radius)]
    CapsuleTooShort {
        /// Total height given.
        height: f32,
        /// Radius given.
        radius: f32,
    },
}

fn positive(name: &'static str, value: f32) -> Result<f32, PrimitiveError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(PrimitiveError::NonPositive { name, value })
    }
}

/// A flat grid in the XZ plane facing `+Y`, `width` along X and `depth` along Z.
///
/// `u` runs along `+X` and `v` along `-Z` (Maya's polyPlane layout). Subdivisions below 1
/// are raised to 1.
pub fn plane(width: f32, depth: f32, subdivisions_x: u32, subdivisions_z: u32) -> Result<Mesh, PrimitiveError> {
    let (w, d) = (positive("width", width)?, positive("depth", depth)?);
    let (sx, sz) = (subdivisions_x.max(1), subdivisions_z.max(1));
    let mut m = Mesh::default();
    for k in 0..=sz {
        for i in 0..=sx {
            let (s, t) = (i as f32 / sx as f32, k as f32 / sz as f32);
            m.positions.push(Vec3::new(-0.5 * w + w * s, 0.0, 0.5 * d - d * t));
            m.normals.push(Vec3::Y);
            m.uvs.push(Vec2::new(s, t));
        }
    }
    let row = sx + 1;
    for k in 0..sz {
        for i in 0..sx {
            let a = k * row + i;
            let (b, c, dd) = (a + 1, a + row + 1, a + row);
            m.triangles.push([a, b, c]);
            m.triangles.push([a, c, dd]);
        }
    }
    Ok(m)
}

/// An axis-aligned box of the given full extents, four vertices per face (hard edges).
///
/// Each face occupies its own cell of a 3×2 UV atlas: row 0 holds `+X, -X, +Y`,
/// row 1 holds `-Y, +Z, -Z`.
pub fn cuboid(size: Vec3) -> Result<Mesh, PrimitiveError> {
    let h = 0.5
        * Vec3::new(
            positive("size.x", size.x)?,
            positive("size.y", size.y)?,
            positive("size.z", size.z)?,
        );
    // (normal, u axis, v axis) with u × v = normal.
    let faces = [
        (Vec3::X, Vec3::NEG_Z, Vec3::Y),
        (Vec3::NEG_X, Vec3::Z, Vec3::Y),
        (Vec3::Y, Vec3::X, Vec3::NEG_Z),
        (Vec3::NEG_Y, Vec3::X, Vec3::Z),
        (Vec3::Z, Vec3::X, Vec3::Y),
        (Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y),
    ];
    let mut m = Mesh::default();
    let pad = 0.01;
    for (f, (n, u, v)) in faces.into_iter().enumerate() {
        let cell = Vec2::new((f % 3) as f32 / 3.0, (f / 3) as f32 / 2.0);
        let cell_size = Vec2::new(1.0 / 3.0, 0.5) - Vec2::splat(2.0 * pad);
        let base = m.positions.len() as u32;
        for (s, t) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            m.positions.push((n + u * s + v * t) * h);
            m.normals.push(n);
            let st = Vec2::new(0.5 * (s + 1.0), 0.5 * (t + 1.0));
            m.uvs.push(cell + Vec2::splat(pad) + st * cell_size);
        }
        m.triangles.push([base, base + 1, base + 2]);
        m.triangles.push([base, base + 2, base + 3]);
    }
    Ok(m)
}

/// One row of a surface of revolution: radius, height, 2D normal (radial, axial), and `v`.
#[derive(Clone, Copy)]
struct Row {
    r: f32,
    y: f32,
    n: Vec2,
    v: f32,
}

/// Revolves `rows` (ordered bottom to top) around `+Y`; `uv` maps (u, v) into the atlas.
fn revolve(m: &mut Mesh, rows: &[Row], segments: u32, uv: impl Fn(Vec2) -> Vec2) {
    let seg = segments as usize;
    let is_pole = |r: &Row| r.r == 0.0;
    let mut starts = Vec::with_capacity(rows.len());
    for row in rows {
        starts.push(m.positions.len() as u32);
        let pole = is_pole(row);
        let count = if pole { seg } else { seg + 1 };
        for j in 0..count {
            let u = if pole {
                (j as f32 + 0.5) / seg as f32
            } else {
                j as f32 / seg as f32
            };
            // Exact seam: the last column repeats the first one's angle.
            let phi = if j == seg { 0.0 } else { TAU * u };
            let (s, c) = phi.sin_cos();
            m.positions.push(Vec3::new(row.r * s, row.y, row.r * c));
            m.normals
                .push(Vec3::new(row.n.x * s, row.n.y, row.n.x * c).normalize_or(Vec3::Y));
            m.uvs.push(uv(Vec2::new(u, row.v)));
        }
    }
    for i in 0..rows.len().saturating_sub(1) {
        let (lo, hi) = (starts[i], starts[i + 1]);
        for j in 0..segments {
            let (a, b, c, d) = (lo + j, lo + j + 1, hi + j + 1, hi + j);
            if is_pole(&rows[i]) {
                m.triangles.push([a, c, d]);
            } else if is_pole(&rows[i + 1]) {
                m.triangles.push([a, b, d]);
            } else {
                m.triangles.push([a, b, c]);
                m.triangles.push([a, c, d]);
            }
        }
    }
}

/// Appends a flat disk cap at height `y` facing `+Y` (`up`) or `-Y`, UVs in a disk of radius
/// 0.24 around `centre`.
fn cap(m: &mut Mesh, radius: f32, y: f32, up: bool, segments: u32, centre: Vec2) {
    let n = if up { Vec3::Y } else { Vec3::NEG_Y };
    let c = m.positions.len() as u32;
    m.positions.push(Vec3::new(0.0, y, 0.0));
    m.normals.push(n);
    m.uvs.push(centre);
    for j in 0..segments {
        let (s, co) = (TAU * j as f32 / segments as f32).sin_cos();
        m.positions.push(Vec3::new(radius * s, y, radius * co));
        m.normals.push(n);
        // Top: u along +X, v along -Z; bottom: u along +X, v along +Z (u × v = normal).
        let flip = if up { -1.0 } else { 1.0 };
        m.uvs.push(centre + 0.24 * Vec2::new(s, flip * co));
    }
    for j in 0..segments {
        let (p, q) = (c + 1 + j, c + 1 + (j + 1) % segments);
        m.triangles.push(if up { [c, p, q] } else { [c, q, p] });
    }
}

/// A UV sphere: `rings` latitude bands (≥ 2) and `segments` longitude segments (≥ 3).
///
/// `v` runs from 0 at the south pole (`-Y`) to 1 at the north pole.
pub fn uv_sphere(radius: f32, rings: u32, segments: u32) -> Result<Mesh, PrimitiveError> {
    let r = positive("radius", radius)?;
    let (rings, segments) = (rings.max(2), segments.max(3));
    let rows: Vec<Row> = (0..=rings)
        .map(|i| {
            let t = i as f32 / rings as f32;
            let (s, c) = (PI * t).sin_cos();
            let s = if i == 0 || i == rings { 0.0 } else { s };
            Row {
                r: r * s,
                y: -r * c,
                n: Vec2::new(s, -c),
                v: t,
            }
        })
        .collect();
    let mut m = Mesh::default();
    revolve(&mut m, &rows, segments, |uv| uv);
    Ok(m)
}

/// A capped cylinder along `+Y`, centred at the origin, `rings` bands along the height.
///
/// UV layout: the side fills `v ∈ [0, 0.5]`; the bottom cap is a disk around (0.25, 0.75),
/// the top cap a disk around (0.75, 0.75). Without caps the side still uses `v ∈ [0, 0.5]`.
pub fn cylinder(radius: f32, height: f32, rings: u32, segments: u32, caps: bool) -> Result<Mesh, PrimitiveError> {
    let (r, h) = (positive("radius", radius)?, positive("height", height)?);
    let (rings, segments) = (rings.max(1), segments.max(3));
    let rows: Vec<Row> = (0..=rings)
        .map(|i| {
            let t = i as f32 / rings as f32;
            Row {
                r,
                y: -0.5 * h + h * t,
                n: Vec2::X,
                v: t,
            }
        })
        .collect();
    let mut m = Mesh::default();
    revolve(&mut m, &rows, segments, |uv| Vec2::new(uv.x, 0.5 * uv.y));
    if caps {
        cap(&mut m, r, -0.5 * h, false, segments, Vec2::new(0.25, 0.75));
        cap(&mut m, r, 0.5 * h, true, segments, Vec2::new(0.75, 0.75));
    }
    Ok(m)
}

/// A capsule along `+Y`: a cylinder of `rings` bands closed by two hemispheres of
/// `cap_rings` bands each (≥ 1). `height` is the total height, tips included, so it must be
/// at least `2 * radius` (equal gives a sphere).
///
/// `v` runs from 0 at the bottom tip to 1 at the top tip, proportional to arc length.
pub fn capsule(radius: f32, height: f32, rings: u32, segments: u32, cap_rings: u32) -> Result<Mesh, PrimitiveError> {
    let (r, h) = (positive("radius", radius)?, positive("height", height)?);
    if h < 2.0 * r {
        return Err(PrimitiveError::CapsuleTooShort { height: h, radius: r });
    }
    let (rings, segments, cap_rings) = (rings.max(1), segments.max(3), cap_rings.max(1));
    let half = 0.5 * h - r;
    let mut rows = Vec::new();
    // Bottom hemisphere: polar angle from -Y up to the equator.
    for i in 0..=cap_rings {
        let a = FRAC_PI_2 * i as f32 / cap_rings as f32;
        let (s, c) = a.sin_cos();
        let s = if i == 0 { 0.0 } else { s };
        rows.push((
            Row {
                r: r * s,
                y: -half - r * c,
                n: Vec2::new(s, -c),
                v: 0.0,
            },
            r * a,
        ));
    }
    let arc_cap = r * FRAC_PI_2;
    if half > 0.0 {
        for i in 1..=rings {
            let t = i as f32 / rings as f32;
            let row = Row {
                r,
                y: -half + 2.0 * half * t,
                n: Vec2::X,
                v: 0.0,
            };
            rows.push((row, arc_cap + 2.0 * half * t));
        }
    }
    let arc_mid = arc_cap + 2.0 * half;
    for i in 1..=cap_rings {
        let a = FRAC_PI_2 * i as f32 / cap_rings as f32;
        let (s, c) = a.sin_cos();
        let (s, c) = if i == cap_rings { (1.0, 0.0) } else { (s, c) };
        // From the equator up: radius cos(a), height half + r sin(a).
        let row = Row {
            r: if i == cap_rings { 0.0 } else { r * c },
            y: half + r * s,
            n: Vec2::new(c, s),
            v: 0.0,
        };
        rows.push((row, arc_mid + r * a));
    }
    let total = arc_mid + arc_cap;
    let rows: Vec<Row> = rows
        .into_iter()
        .map(|(row, arc)| Row { v: arc / total, ..row })
        .collect();
    let mut m = Mesh::default();
    revolve(&mut m, &rows, segments, |uv| uv);
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every triangle's geometric normal agrees with its vertices' normals, and the UV frame
    /// is right-handed with the normal.
    pub(crate) fn check(m: &Mesh) {
        m.validate().expect("valid mesh");
        assert_eq!(m.normals.len(), m.positions.len());
        assert_eq!(m.uvs.len(), m.positions.len());
        for tri in &m.triangles {
            let [a, b, c] = tri.map(|i| i as usize);
            let (e1, e2) = (m.positions[b] - m.positions[a], m.positions[c] - m.positions[a]);
            let face = e1.cross(e2);
            assert!(face.length() > 1e-9, "degenerate triangle {tri:?}");
            let avg = m.normals[a] + m.normals[b] + m.normals[c];
            assert!(face.dot(avg) > 0.0, "triangle {tri:?} winds against its normals");
            let (d1, d2) = (m.uvs[b] - m.uvs[a], m.uvs[c] - m.uvs[a]);
            assert!(d1.perp_dot(d2) > 0.0, "triangle {tri:?} has a flipped UV frame");
        }
        for n in &m.normals {
            assert!((n.length() - 1.0).abs() < 1e-5);
        }
        for uv in &m.uvs {
            assert!((0.0..=1.0).contains(&uv.x) && (0.0..=1.0).contains(&uv.y));
        }
    }

    #[test]
    fn all_primitives_are_consistent() {
        check(&plane(2.0, 3.0, 4, 5).unwrap());
        check(&cuboid(Vec3::new(1.0, 2.0, 3.0)).unwrap());
        check(&uv_sphere(1.5, 8, 12).unwrap());
        check(&cylinder(0.5, 2.0, 4, 10, true).unwrap());
        check(&cylinder(0.5, 2.0, 1, 3, false).unwrap());
        check(&capsule(0.5, 3.0, 3, 12, 4).unwrap());
        check(&capsule(0.5, 1.0, 3, 12, 2).unwrap());
    }

    #[test]
    fn counts_are_as_documented() {
        let p = plane(1.0, 1.0, 2, 3).unwrap();
        assert_eq!((p.positions.len(), p.triangles.len()), (3 * 4, 2 * 2 * 3));
        let s = uv_sphere(1.0, 4, 6).unwrap();
        // 3 interior rows of 7 plus two poles of 6; 2 quad bands of 6 quads + 2 pole fans of 6.
        assert_eq!(
            (s.positions.len(), s.triangles.len()),
            (3 * 7 + 2 * 6, 2 * 2 * 6 + 2 * 6)
        );
        let c = cylinder(1.0, 1.0, 2, 5, true).unwrap();
        assert_eq!(c.positions.len(), 3 * 6 + 2 * 6);
        assert_eq!(c.triangles.len(), 2 * 2 * 5 + 2 * 5);
    }

    #[test]
    fn sphere_vertices_lie_on_the_sphere() {
        let s = uv_sphere(2.0, 7, 9).unwrap();
        for (p, n) in s.positions.iter().zip(&s.normals) {
            assert!((p.length() - 2.0).abs() < 1e-5);
            assert!((*p / 2.0 - *n).length() < 1e-5);
        }
    }

    #[test]
    fn bad_sizes_are_errors() {
        assert!(uv_sphere(0.0, 4, 4).is_err());
        assert!(plane(f32::NAN, 1.0, 1, 1).is_err());
        assert!(capsule(1.0, 1.5, 1, 8, 2).is_err());
        assert!(cuboid(Vec3::new(1.0, -1.0, 1.0)).is_err());
    }
}
