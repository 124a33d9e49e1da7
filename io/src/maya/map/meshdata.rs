//! Geometry data of Maya meshes: the points (`.vt` plus the `.pt` tweaks), the faces
//! (`.fc` polyFaces over the edges `.ed`), triangulated as fans in Maya's vertex order, and
//! the per-vertex UVs when every vertex has one UV; and Maya's `polyCube` / `polyPlane`
//! creation nodes generated with Maya's own vertex numbering.
//!
//! The vertex order is the file's: vertex `k` of the sinew mesh is `.vt[k]`, which is what
//! skin weights (`.wl[k]`), blend shape components (`vtx[k]`) and tweaks index.

use glam::Vec2;
#[cfg(test)]
use glam::Vec3;
use sinew_core::Mesh;

/// A polygon mesh before triangulation: points and faces as vertex loops, with optional
/// per-face-vertex UV indices.
#[derive(Clone, Debug, Default)]
pub struct PolyMesh {
    /// Points in internal units (centimetres).
    pub points: Vec<glam::DVec3>,
    /// Faces as vertex loops.
    pub faces: Vec<Vec<u32>>,
    /// UV points of the first UV set.
    pub uv_points: Vec<Vec2>,
    /// Per face, UV indices parallel to its vertex loop (empty when the face has none).
    pub face_uvs: Vec<Vec<u32>>,
    /// Faces that had holes (the holes are not imported).
    pub holes: usize,
}

/// Why mesh data could not be read.
pub type MeshError = String;

/// Vertex loops of faces given as edge loops (`polyFaces`): edge `e >= 0` runs
/// `edges[e].0 → edges[e].1`, `-1 - e` runs backwards; each face starts each edge at its
/// first vertex.
pub fn faces_from_edges(edges: &[(u32, u32)], face_edges: &[Vec<i64>]) -> Result<Vec<Vec<u32>>, MeshError> {
    face_edges
        .iter()
        .enumerate()
        .map(|(f, loop_)| {
            loop_
                .iter()
                .map(|&e| {
                    let (k, rev) = if e >= 0 { (e, false) } else { (-1 - e, true) };
                    let (a, b) = usize::try_from(k)
                        .ok()
                        .and_then(|k| edges.get(k))
                        .copied()
                        .ok_or_else(|| format!("face {f} uses edge {k} but the mesh has {} edges", edges.len()))?;
                    Ok(if rev { b } else { a })
                })
                .collect()
        })
        .collect()
}

impl PolyMesh {
    /// Triangulates (fans from each face's first vertex, Maya's winding) into a sinew mesh
    /// with recomputed smooth normals; `to_sinew` converts an internal-unit point. Returns the
    /// mesh and a note when UVs had to be dropped.
    pub fn to_mesh(&self, to_sinew: impl Fn(glam::DVec3) -> glam::DVec3) -> Result<(Mesh, Option<String>), MeshError> {
        let n = self.points.len();
        let mut m = Mesh {
            positions: self.points.iter().map(|&p| to_sinew(p).as_vec3()).collect(),
            ..Mesh::default()
        };
        for (f, face) in self.faces.iter().enumerate() {
            if let Some(&bad) = face.iter().find(|&&v| v as usize >= n) {
                return Err(format!("face {f} uses vertex {bad} but the mesh has {n} points"));
            }
            for k in 1..face.len().saturating_sub(1) {
                m.triangles.push([face[0], face[k], face[k + 1]]);
            }
        }
        let mut note = None;
        if !self.uv_points.is_empty() {
            let mut uv: Vec<Option<u32>> = vec![None; n];
            let mut seams = 0usize;
            let mut missing = false;
            for (face, uvs) in self.faces.iter().zip(&self.face_uvs) {
                if uvs.len() != face.len() {
                    missing = true;
                    continue;
                }
                for (&v, &u) in face.iter().zip(uvs) {
                    match uv[v as usize] {
                        None => uv[v as usize] = Some(u),
                        Some(old) if self.uv_points.get(old as usize) != self.uv_points.get(u as usize) => seams += 1,
                        Some(_) => {}
                    }
                }
            }
            let all: Option<Vec<Vec2>> = uv
                .iter()
                .map(|u| u.and_then(|u| self.uv_points.get(u as usize).copied()))
                .collect();
            match all {
                Some(all) if seams == 0 && !missing => m.uvs = all,
                _ => {
                    note = Some(format!(
                        "UVs not imported: {} (a sinew mesh has one UV per vertex and keeps Maya's vertex order)",
                        if seams > 0 {
                            format!("{seams} face corners sit on UV seams")
                        } else {
                            "some faces or vertices have no UV".to_string()
                        }
                    ))
                }
            }
        }
        m.recompute_normals();
        Ok((m, note))
    }
}

/// Maya's `polyCube` with one subdivision per side: 8 points, 6 quads (the numbering of
/// Maya's node, as a duplicated default cube stores it in a file), 14 UVs.
pub fn poly_cube(w: f64, h: f64, d: f64) -> PolyMesh {
    let (x, y, z) = (0.5 * w, 0.5 * h, 0.5 * d);
    let points = vec![
        glam::DVec3::new(-x, -y, z),
        glam::DVec3::new(x, -y, z),
        glam::DVec3::new(-x, y, z),
        glam::DVec3::new(x, y, z),
        glam::DVec3::new(-x, y, -z),
        glam::DVec3::new(x, y, -z),
        glam::DVec3::new(-x, -y, -z),
        glam::DVec3::new(x, -y, -z),
    ];
    let faces = vec![
        vec![0, 1, 3, 2],
        vec![2, 3, 5, 4],
        vec![4, 5, 7, 6],
        vec![6, 7, 1, 0],
        vec![1, 7, 5, 3],
        vec![6, 0, 2, 4],
    ];
    let uv_points = [
        (0.375, 0.0),
        (0.625, 0.0),
        (0.375, 0.25),
        (0.625, 0.25),
        (0.375, 0.5),
        (0.625, 0.5),
        (0.375, 0.75),
        (0.625, 0.75),
        (0.375, 1.0),
        (0.625, 1.0),
        (0.875, 0.0),
        (0.875, 0.25),
        (0.125, 0.0),
        (0.125, 0.25),
    ]
    .iter()
    .map(|&(u, v)| Vec2::new(u, v))
    .collect();
    let face_uvs = vec![
        vec![0, 1, 3, 2],
        vec![2, 3, 5, 4],
        vec![4, 5, 7, 6],
        vec![6, 7, 9, 8],
        vec![1, 10, 11, 3],
        vec![12, 0, 2, 13],
    ];
    PolyMesh {
        points,
        faces,
        uv_points,
        face_uvs,
        holes: 0,
    }
}

/// Maya's `polyPlane` facing `+Y`: `(sw + 1) × (sh + 1)` points row by row from `+Z` to
/// `-Z`, each row from `-X` to `+X`; quads `(a, a+1, a+row+1, a+row)`; UVs `(i/sw, k/sh)`.
pub fn poly_plane(w: f64, h: f64, sw: u32, sh: u32) -> PolyMesh {
    let (sw, sh) = (sw.max(1), sh.max(1));
    let row = sw + 1;
    let mut m = PolyMesh::default();
    for k in 0..=sh {
        for i in 0..=sw {
            let (s, t) = (f64::from(i) / f64::from(sw), f64::from(k) / f64::from(sh));
            m.points.push(glam::DVec3::new(-0.5 * w + w * s, 0.0, 0.5 * h - h * t));
            m.uv_points.push(Vec2::new(s as f32, t as f32));
        }
    }
    for k in 0..sh {
        for i in 0..sw {
            let a = k * row + i;
            let face = vec![a, a + 1, a + row + 1, a + row];
            m.face_uvs.push(face.clone());
            m.faces.push(face);
        }
    }
    m
}

/// Rotates points so a primitive built facing `+Y` faces `axis` (Maya's `axis` attribute).
pub fn orient_to_axis(m: &mut PolyMesh, axis: glam::DVec3) {
    let axis = axis.normalize_or_zero();
    if axis == glam::DVec3::ZERO || (axis - glam::DVec3::Y).length() < 1e-12 {
        return;
    }
    let q = glam::DQuat::from_rotation_arc(glam::DVec3::Y, axis);
    for p in &mut m.points {
        *p = q * *p;
    }
}

/// Adds tweak offsets (`.pt[k]`, a tweak node's `vlist`) to points; offsets past the last
/// point are ignored.
pub fn add_offsets(points: &mut [glam::DVec3], offsets: &[(u32, glam::DVec3)]) {
    for &(k, d) in offsets {
        if let Some(p) = points.get_mut(k as usize) {
            *p += d;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cube's edge list and face loops as a Maya file stores a duplicated default cube
    /// give the same vertex loops as the generator.
    #[test]
    fn cube_faces_match_a_stored_cube() {
        let edges = [
            (0, 1),
            (2, 3),
            (4, 5),
            (6, 7),
            (0, 2),
            (1, 3),
            (2, 4),
            (3, 5),
            (4, 6),
            (5, 7),
            (6, 0),
            (7, 1),
        ];
        let loops = vec![
            vec![0, 5, -2, -5],
            vec![1, 7, -3, -7],
            vec![2, 9, -4, -9],
            vec![3, 11, -1, -11],
            vec![-12, -10, -8, -6],
            vec![10, 4, 6, 8],
        ];
        assert_eq!(
            faces_from_edges(&edges, &loops).unwrap(),
            poly_cube(1.0, 1.0, 1.0).faces
        );
        assert!(faces_from_edges(&edges, &[vec![12]]).is_err());
    }

    /// Every face of the cube and the plane points away from the centre / up (Maya's
    /// counter-clockwise winding survives triangulation).
    #[test]
    fn triangles_face_outwards() {
        let (m, note) = poly_cube(2.0, 1.0, 1.0).to_mesh(|p| p).unwrap();
        assert!(note.is_some(), "the cube's UVs have seams");
        assert_eq!((m.positions.len(), m.triangles.len()), (8, 12));
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let n = (b - a).cross(c - a);
            assert!(n.dot((a + b + c) / 3.0) > 0.0);
        }
        let (p, note) = poly_plane(2.0, 4.0, 1, 2).to_mesh(|p| p).unwrap();
        assert!(note.is_none());
        assert_eq!(p.positions[0], Vec3::new(-1.0, 0.0, 2.0));
        assert_eq!(p.positions[5], Vec3::new(1.0, 0.0, -2.0));
        for t in &p.triangles {
            let [a, b, c] = t.map(|i| p.positions[i as usize]);
            assert!((b - a).cross(c - a).y > 0.0);
        }
        assert_eq!(p.uvs[5], Vec2::new(1.0, 1.0));
    }
}
