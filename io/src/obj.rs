//! Wavefront OBJ meshes in and out.
//!
//! Reading keeps the file's vertex order exactly: vertex `i` of the mesh is the file's
//! `i`-th `v` line (every one, used by a face or not), so skin weights, blend shape
//! targets and any other per-vertex array written in the file's order (as Maya writes
//! them) line up. Faces are triangulated as fans; all objects and groups are merged.
//! Face corners may be written `v`, `v/vt`, `v//vn` or `v/vt/vn`, with negative (relative)
//! indices. Colours after `v x y z` and `w` components are ignored, as are materials,
//! smoothing groups, lines, points and free-form statements.
//!
//! A sinew mesh has one normal and one UV per vertex, so vertices are never split:
//! - Normals: when every face corner has a `vn`, each vertex takes the normal its corners
//!   give (all the same for smooth geometry; normalized unless already of unit length
//!   within 1e-5, which is kept to the bit); where corners of one vertex give different
//!   normals (a hard edge), the vertex takes their normalized sum, so the edge is shaded
//!   smooth. Without `vn` on every corner, normals are computed smooth from the triangles
//!   ([`Mesh::recompute_normals`], angle and area weighted, Maya's default).
//! - UVs: kept when every face corner has a `vt`; a vertex whose corners give different
//!   UVs (a seam) takes the UV of the first face that uses it. Vertices no face uses get
//!   UV `(0, 0)`.
//!
//! Errors name the file and line: a face index out of range, a malformed or non-finite
//! number, a face with fewer than three corners.

use glam::{Vec2, Vec3};
use sinew_core::Mesh;

/// A parse error at a 1-based line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ObjError {
    /// Line of the problem.
    pub line: usize,
    /// What is wrong and how to fix it.
    pub message: String,
}

impl std::fmt::Display for ObjError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.line, self.message)
    }
}

/// One face corner: vertex, UV and normal indices (0-based, resolved).
#[derive(Clone, Copy)]
struct Corner {
    v: u32,
    vt: Option<u32>,
    vn: Option<u32>,
}

/// Parses OBJ text into a mesh (see the module docs).
pub fn parse_obj(text: &str) -> Result<Mesh, ObjError> {
    let mut positions: Vec<Vec3> = Vec::new();
    let mut uvs: Vec<Vec2> = Vec::new();
    let mut normals: Vec<Vec3> = Vec::new();
    let mut corners: Vec<Corner> = Vec::new();
    let mut line_no = 0;
    let mut logical = String::new();
    let mut start_line = 0;
    for raw in text.lines() {
        line_no += 1;
        if logical.is_empty() {
            start_line = line_no;
        }
        // A backslash at the end of a line continues it.
        if let Some(head) = raw.strip_suffix('\\') {
            logical.push_str(head);
            logical.push(' ');
            continue;
        }
        logical.push_str(raw);
        let line = std::mem::take(&mut logical);
        let err = |message: String| ObjError {
            line: start_line,
            message,
        };
        let content = line.split('#').next().unwrap_or("");
        let mut words = content.split_whitespace();
        let Some(keyword) = words.next() else { continue };
        match keyword {
            "v" => positions.push(Vec3::from_array(numbers::<3>(&mut words, "v", 3).map_err(err)?)),
            "vn" => normals.push(Vec3::from_array(numbers::<3>(&mut words, "vn", 3).map_err(err)?)),
            "vt" => uvs.push(Vec2::from_array(numbers::<2>(&mut words, "vt", 1).map_err(err)?)),
            "f" => {
                let face: Vec<Corner> = words
                    .map(|w| corner(w, positions.len(), uvs.len(), normals.len()))
                    .collect::<Result<_, _>>()
                    .map_err(err)?;
                if face.len() < 3 {
                    return Err(err(format!(
                        "a face needs at least 3 corners, this one has {}",
                        face.len()
                    )));
                }
                for k in 1..face.len() - 1 {
                    corners.extend([face[0], face[k], face[k + 1]]);
                }
            }
            _ => {}
        }
    }
    if positions.len() > u32::MAX as usize {
        return Err(ObjError {
            line: line_no,
            message: "more than 2^32 vertices".into(),
        });
    }
    let mut mesh = Mesh {
        triangles: corners.chunks_exact(3).map(|c| [c[0].v, c[1].v, c[2].v]).collect(),
        positions,
        normals: Vec::new(),
        uvs: Vec::new(),
    };
    let n = mesh.positions.len();
    if !corners.is_empty() && corners.iter().all(|c| c.vt.is_some()) {
        let mut per_vertex: Vec<Option<Vec2>> = vec![None; n];
        for c in &corners {
            let slot = &mut per_vertex[c.v as usize];
            if slot.is_none() {
                *slot = c.vt.map(|t| uvs[t as usize]);
            }
        }
        mesh.uvs = per_vertex.into_iter().map(|u| u.unwrap_or(Vec2::ZERO)).collect();
    }
    if !corners.is_empty() && corners.iter().all(|c| c.vn.is_some()) {
        mesh.recompute_normals();
        // Each vertex: the sum of the distinct normals its corners give, normalized.
        let mut given: Vec<Vec<u32>> = vec![Vec::new(); n];
        for c in &corners {
            let list = &mut given[c.v as usize];
            if let Some(vn) = c.vn.filter(|vn| !list.contains(vn)) {
                list.push(vn);
            }
        }
        for (v, list) in given.iter().enumerate() {
            let sum: Vec3 = list.iter().map(|&k| normals[k as usize]).sum();
            // One unit normal is kept to the bit (what `obj_text` wrote reads back the same).
            if list.len() == 1 && (sum.length() - 1.0).abs() < 1e-5 {
                mesh.normals[v] = sum;
            } else if let Some(unit) = sum.try_normalize() {
                mesh.normals[v] = unit;
            }
        }
    } else {
        mesh.recompute_normals();
    }
    Ok(mesh)
}

/// Reads `N` numbers (at least `required`, the rest 0) after an OBJ keyword.
fn numbers<'a, const N: usize>(
    words: &mut impl Iterator<Item = &'a str>,
    keyword: &str,
    required: usize,
) -> Result<[f32; N], String> {
    let mut out = [0.0f32; N];
    for (k, o) in out.iter_mut().enumerate() {
        match words.next() {
            Some(w) => {
                let x: f32 = w.parse().map_err(|_| format!("`{keyword}`: {w:?} is not a number"))?;
                if !x.is_finite() {
                    return Err(format!("`{keyword}`: {w} is not a finite number"));
                }
                *o = x;
            }
            None if k < required => {
                return Err(format!("`{keyword}` needs {required} numbers, found {k}"));
            }
            None => break,
        }
    }
    Ok(out)
}

/// Resolves an OBJ index (1-based, or negative: relative to the last of `count` defined).
fn index(text: &str, count: usize, what: &str) -> Result<u32, String> {
    let i: i64 = text
        .parse()
        .map_err(|_| format!("face corner: {text:?} is not a {what} index"))?;
    let resolved = if i > 0 {
        i - 1
    } else if i < 0 {
        count as i64 + i
    } else {
        -1
    };
    if resolved < 0 || resolved >= count as i64 {
        return Err(format!(
            "face uses {what} {i} but {count} {what}s are defined before it; OBJ indices start at 1 (negative ones count back from the last)"
        ));
    }
    Ok(resolved as u32)
}

fn corner(word: &str, nv: usize, nt: usize, nn: usize) -> Result<Corner, String> {
    let mut parts = word.split('/');
    let v = index(parts.next().unwrap_or(""), nv, "vertex")?;
    let vt = match parts.next() {
        None | Some("") => None,
        Some(t) => Some(index(t, nt, "texture coordinate")?),
    };
    let vn = match parts.next() {
        None | Some("") => None,
        Some(t) => Some(index(t, nn, "normal")?),
    };
    if parts.next().is_some() {
        return Err(format!("face corner {word:?} has more than three indices"));
    }
    Ok(Corner { v, vt, vn })
}

/// The mesh as OBJ text: `v` lines in vertex order, `vt` and `vn` (one per vertex, when the
/// mesh has them) and one `f` line per triangle; `comment` becomes the first line. Floats
/// are written in their shortest exact form, so [`parse_obj`] reads back the same
/// positions, UVs and triangles (and normals, which per vertex are given consistently).
pub fn obj_text(mesh: &Mesh, comment: &str) -> String {
    use std::fmt::Write as _;
    let mut s = String::with_capacity(32 * (mesh.positions.len() * 3 + mesh.triangles.len()));
    for line in comment.lines() {
        let _ = writeln!(s, "# {line}");
    }
    for p in &mesh.positions {
        let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
    }
    for t in &mesh.uvs {
        let _ = writeln!(s, "vt {} {}", t.x, t.y);
    }
    for n in &mesh.normals {
        let _ = writeln!(s, "vn {} {} {}", n.x, n.y, n.z);
    }
    let (uv, nrm) = (!mesh.uvs.is_empty(), !mesh.normals.is_empty());
    for tri in &mesh.triangles {
        s.push('f');
        for &i in tri {
            let k = i + 1;
            let _ = match (uv, nrm) {
                (false, false) => write!(s, " {k}"),
                (true, false) => write!(s, " {k}/{k}"),
                (false, true) => write!(s, " {k}//{k}"),
                (true, true) => write!(s, " {k}/{k}/{k}"),
            };
        }
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Faces that visit the vertices out of order keep the file's vertex order.
    #[test]
    fn vertex_order_is_the_files() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 9 9 9\n\
                    o second\nf 3 4 1\nf 2 3 1\n";
        let m = parse_obj(text).unwrap();
        assert_eq!(m.positions[2], Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(m.positions.len(), 5, "unused vertices are kept");
        assert_eq!(m.triangles, vec![[2, 3, 0], [1, 2, 0]]);
        // Counter-clockwise seen from +Z: smooth normals point to +Z (vertex 4 is unused: +Y).
        assert!(m.normals[..4].iter().all(|n| (*n - Vec3::Z).length() < 1e-6));
        assert_eq!(m.normals[4], Vec3::Y);
    }

    #[test]
    fn corners_uvs_normals_and_relative_indices() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.25\nvt 1 1\nvn 0 0 2\nvn 1 0 0\n\
                    f -3/1/1 -2/2/1 -1/2/2\n";
        let m = parse_obj(text).unwrap();
        assert_eq!(m.triangles, vec![[0, 1, 2]]);
        assert_eq!(m.uvs, vec![Vec2::new(0.5, 0.25), Vec2::ONE, Vec2::ONE]);
        assert_eq!(m.normals[0], Vec3::Z, "given normals are normalized");
        assert_eq!(m.normals[2], Vec3::X);
        // A vertex whose corners give two normals takes their normalized sum.
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 1\nvn 1 0 0\n\
                    f 1//1 2//1 3//1\nf 1//2 3//2 4//2\n";
        let m = parse_obj(text).unwrap();
        let h = std::f32::consts::FRAC_1_SQRT_2;
        assert!((m.normals[0] - Vec3::new(h, 0.0, h)).length() < 1e-6);
        assert_eq!(m.normals[1], Vec3::Z);
        assert_eq!(m.normals[3], Vec3::X);
    }

    #[test]
    fn bad_input_names_the_line() {
        for (text, line, what) in [
            ("v 0 0 0\nv 1 0 0\nf 1 2 3\n", 3, "vertex 3"),
            ("v 0 0\n", 1, "needs 3"),
            ("v 0 nan 0\n", 1, "not a finite"),
            ("v 0 0 0\n\nf 1 1\n", 3, "at least 3"),
            ("v 0 0 0\nf 0 1 1\n", 2, "start at 1"),
            ("v 0 0 0\nf 1/2 1 1\n", 2, "texture coordinate 2"),
            ("v 0 0 0\nvt 0 0\nvn 0 0 1\nf 1/1/1/1 1 1\n", 4, "more than three"),
        ] {
            let e = parse_obj(text).unwrap_err();
            assert_eq!(e.line, line, "{text:?}: {e}");
            assert!(e.message.contains(what), "{text:?}: {e}");
        }
    }

    #[test]
    fn written_text_reads_back() {
        let text = "v 0.1 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nf 1/1 2/2 3/3\n";
        let m = parse_obj(text).unwrap();
        let back = parse_obj(&obj_text(&m, "round trip")).unwrap();
        assert_eq!(back, m);
    }
}
