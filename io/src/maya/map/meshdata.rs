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

/// How the sinew vertices of an imported mesh relate to Maya's: vertices `0..maya` are
/// Maya's `.vt[0..maya]` in file order; each vertex after them is a copy of Maya vertex
/// `copies[k]` made where the vertex sits on a UV seam (its face corners carry different
/// UVs), so that every face corner keeps its own UV on a mesh with one UV per vertex.
///
/// Per-vertex data the file indexes by Maya's vertex (skin weights, blendShape deltas and
/// maps, deformer weights and memberships) is extended to the copies with the values of
/// the vertex they copy, so a copy deforms exactly as its original does.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VertexMap {
    /// Maya's vertex count.
    pub maya: usize,
    /// The Maya vertex each appended copy duplicates.
    pub copies: Vec<u32>,
}

impl VertexMap {
    /// The Maya vertex of every sinew vertex (as floats: a custom attribute's array type;
    /// exact below 2^53).
    pub fn maya_index(&self) -> Vec<f64> {
        (0..self.maya as u32)
            .chain(self.copies.iter().copied())
            .map(f64::from)
            .collect()
    }

    /// Extends a dense per-Maya-vertex list (length `maya`) with the copies' values; a list
    /// of another length is left alone.
    pub fn extend_dense<T: Clone>(&self, v: &mut Vec<T>) {
        if v.len() == self.maya {
            for &c in &self.copies {
                v.push(v[c as usize].clone());
            }
        }
    }

    /// Extends sparse per-vertex data (`idx[i]` carries `vals[i]`) with an entry per copy
    /// of a listed vertex.
    pub fn extend_sparse<T: Clone>(&self, idx: &mut Vec<u32>, vals: &mut Vec<T>) {
        if self.copies.is_empty() {
            return;
        }
        let mut at = vec![None; self.maya];
        for (i, &v) in idx.iter().enumerate() {
            if let Some(slot) = at.get_mut(v as usize) {
                *slot = Some(i);
            }
        }
        for (k, &c) in self.copies.iter().enumerate() {
            if let Some(i) = at[c as usize] {
                idx.push((self.maya + k) as u32);
                vals.push(vals[i].clone());
            }
        }
    }

    /// Extends a sorted vertex list (a membership) with the copies of listed vertices.
    pub fn extend_list(&self, list: &mut Vec<i64>) {
        let listed: std::collections::HashSet<i64> = list.iter().copied().collect();
        for (k, &c) in self.copies.iter().enumerate() {
            if listed.contains(&i64::from(c)) {
                list.push((self.maya + k) as i64);
            }
        }
    }
}

/// The result of [`PolyMesh::to_mesh`].
#[derive(Clone, Debug)]
pub struct Converted {
    /// The triangle mesh (UVs per vertex, seam vertices split).
    pub mesh: Mesh,
    /// Maya's vertex of each sinew vertex.
    pub map: VertexMap,
    /// Face corners without a UV in the first set (they take their vertex's UV from
    /// another face, or `(0, 0)`), when the mesh has UVs at all.
    pub corners_without_uv: usize,
}

impl PolyMesh {
    /// Triangulates (fans from each face's first vertex, Maya's winding) into a sinew mesh;
    /// `to_sinew` converts an internal-unit point.
    ///
    /// UVs: Maya stores them per face corner (`mu` in `polyFaces`), sinew per vertex. A
    /// vertex whose corners all carry the same UV value keeps its index; each further
    /// distinct UV value at a vertex (a UV seam) becomes a copy of the vertex appended
    /// after Maya's vertices (see [`VertexMap`]), and the corners with that UV use the
    /// copy, so every corner's UV is exactly the file's. Normals are computed on Maya's
    /// welded topology (angle and area weighted) and shared by the copies, so a UV seam is
    /// not a shading seam.
    pub fn to_mesh(&self, to_sinew: impl Fn(glam::DVec3) -> glam::DVec3) -> Result<Converted, MeshError> {
        let n = self.points.len();
        let mut welded = Mesh {
            positions: self.points.iter().map(|&p| to_sinew(p).as_vec3()).collect(),
            ..Mesh::default()
        };
        for (f, face) in self.faces.iter().enumerate() {
            if let Some(&bad) = face.iter().find(|&&v| v as usize >= n) {
                return Err(format!("face {f} uses vertex {bad} but the mesh has {n} points"));
            }
            for k in 1..face.len().saturating_sub(1) {
                welded.triangles.push([face[0], face[k], face[k + 1]]);
            }
        }
        welded.recompute_normals();
        let mut map = VertexMap {
            maya: n,
            copies: Vec::new(),
        };
        if self.uv_points.is_empty() {
            return Ok(Converted {
                mesh: welded,
                map,
                corners_without_uv: 0,
            });
        }
        // The sinew vertex of each face corner, and the UV of each sinew vertex.
        let mut uvs: Vec<Option<Vec2>> = vec![None; n];
        // Per Maya vertex, its copies' (UV, sinew index).
        let mut split: Vec<Vec<(Vec2, u32)>> = vec![Vec::new(); n];
        let mut without = 0usize;
        let mut triangles = Vec::with_capacity(welded.triangles.len());
        for (f, face) in self.faces.iter().enumerate() {
            let corner_uvs = self.face_uvs.get(f).filter(|u| u.len() == face.len());
            let mut corners = Vec::with_capacity(face.len());
            for (c, &v) in face.iter().enumerate() {
                let uv = match corner_uvs {
                    Some(u) => Some(self.uv_points.get(u[c] as usize).copied().ok_or_else(|| {
                        format!(
                            "face {f} uses UV {} but the first UV set has {}",
                            u[c],
                            self.uv_points.len()
                        )
                    })?),
                    None => None,
                };
                let s = match (uv, uvs[v as usize]) {
                    (None, _) => {
                        without += 1;
                        v
                    }
                    (Some(uv), None) => {
                        uvs[v as usize] = Some(uv);
                        v
                    }
                    (Some(uv), Some(old)) if old == uv => v,
                    (Some(uv), Some(_)) => match split[v as usize].iter().find(|(u, _)| *u == uv) {
                        Some(&(_, s)) => s,
                        None => {
                            let s = (n + map.copies.len()) as u32;
                            map.copies.push(v);
                            split[v as usize].push((uv, s));
                            uvs.push(Some(uv));
                            s
                        }
                    },
                };
                corners.push(s);
            }
            for k in 1..corners.len().saturating_sub(1) {
                triangles.push([corners[0], corners[k], corners[k + 1]]);
            }
        }
        let mut mesh = welded;
        mesh.triangles = triangles;
        map.extend_dense(&mut mesh.positions);
        map.extend_dense(&mut mesh.normals);
        mesh.uvs = uvs.into_iter().map(|u| u.unwrap_or(Vec2::ZERO)).collect();
        Ok(Converted {
            mesh,
            map,
            corners_without_uv: without,
        })
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
        let c = poly_cube(2.0, 1.0, 1.0).to_mesh(|p| p).unwrap();
        let m = c.mesh;
        // 14 UVs on 8 points: the seams add 6 copies.
        assert_eq!((m.positions.len(), m.triangles.len(), c.map.copies.len()), (14, 12, 6));
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let n = (b - a).cross(c - a);
            assert!(n.dot((a + b + c) / 3.0) > 0.0);
        }
        let c = poly_plane(2.0, 4.0, 1, 2).to_mesh(|p| p).unwrap();
        assert!(c.map.copies.is_empty(), "a plane has no UV seams");
        let p = c.mesh;
        assert_eq!(p.positions[0], Vec3::new(-1.0, 0.0, 2.0));
        assert_eq!(p.positions[5], Vec3::new(1.0, 0.0, -2.0));
        for t in &p.triangles {
            let [a, b, c] = t.map(|i| p.positions[i as usize]);
            assert!((b - a).cross(c - a).y > 0.0);
        }
        assert_eq!(p.uvs[5], Vec2::new(1.0, 1.0));
    }
}
