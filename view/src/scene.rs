//! What the viewer draws, decided from node specs and value types (not node type names,
//! but for the few drawing rules below): DAG nodes by their world matrix (joints, those
//! that declare `jointOrient`, as bones; other DAG nodes as transforms), the final
//! meshes and curves of the rig (a node's mesh or curve output that feeds nothing, on a
//! node none of whose outputs of that type feeds anything: the end of each deformer
//! chain), and markers for follicle-like nodes (types in [`MARKER_TYPES`]).
//!
//! Each frame is sent as one binary buffer whose layout [`Scene::to_json`] describes:
//! the drawn matrices as f64 (16 per item, glam's column order), then curve samples as
//! f64 (x y z per sample), then mesh positions as f32 (x y z per vertex), all little
//! endian. Mesh positions are `f32` in sinew, so the page gets exactly what sinew
//! computed.

use glam::DVec3;
use serde_json::json;
use sinew_core::{AttrType, Curve, CurveForm, Direction, Graph, Instance, NodeId, PlugHandle, Program, Value};

/// Non-DAG node types drawn as a locator at an output matrix: (type, matrix output).
pub const MARKER_TYPES: &[(&str, &str)] = &[("follicle", "outMatrix")];

/// Samples drawn per curve span.
const SAMPLES_PER_SPAN: usize = 8;

/// How a drawn matrix item looks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrawKind {
    /// A joint: a sphere, and a bone to its joint children.
    Joint,
    /// A transform or control: a small locator cross.
    Transform,
    /// A follicle-like marker.
    Marker,
}

impl DrawKind {
    fn name(self) -> &'static str {
        match self {
            DrawKind::Joint => "joint",
            DrawKind::Transform => "transform",
            DrawKind::Marker => "marker",
        }
    }
}

/// A node drawn at a matrix.
#[derive(Clone, Debug)]
pub struct MatrixItem {
    /// Node name.
    pub name: String,
    /// How it is drawn.
    pub kind: DrawKind,
    /// The drawn parent (index into [`Scene::items`]).
    pub parent: Option<usize>,
    /// Display radius (`radius` attribute, 1 when absent).
    pub radius: f64,
    /// The plug read each frame.
    pub plug: String,
}

/// A drawn mesh or curve.
#[derive(Clone, Debug)]
pub struct GeoItem {
    /// Node name.
    pub name: String,
    /// The plug read each frame.
    pub plug: String,
    /// Mesh: vertices; curve: samples.
    pub count: usize,
    /// Mesh triangles (empty for curves).
    pub triangles: Vec<[u32; 3]>,
}

/// Everything the page draws, and where each frame's values come from.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// Joints, transforms and markers.
    pub items: Vec<MatrixItem>,
    /// Final meshes.
    pub meshes: Vec<GeoItem>,
    /// Final curves.
    pub curves: Vec<GeoItem>,
}

fn outputs_of(graph: &Graph, id: NodeId, ty: AttrType) -> Vec<(String, bool)> {
    let Some(spec) = graph.node_spec(id) else {
        return Vec::new();
    };
    let name = graph.node_name(id).unwrap_or_default().to_string();
    let connected: std::collections::HashSet<String> = graph
        .connections()
        .iter()
        .filter(|(s, _)| s.node == id)
        .map(|(s, _)| spec.attr(s.attr).name.clone())
        .collect();
    spec.attrs
        .iter()
        .filter(|a| a.direction == Direction::Output && a.ty == ty && !a.multi)
        .map(|a| (format!("{name}.{}", a.name), connected.contains(&a.name)))
        .collect()
}

/// The plug of `id`'s final output of type `ty`: its last such output when none of them
/// feeds anything.
fn final_output(graph: &Graph, id: NodeId, ty: AttrType) -> Option<String> {
    let outs = outputs_of(graph, id, ty);
    if outs.iter().any(|(_, connected)| *connected) {
        return None;
    }
    outs.into_iter().last().map(|(p, _)| p)
}

impl Scene {
    /// Decides what `graph` draws (evaluating meshes and curves once for their sizes).
    pub fn build(graph: &mut Graph) -> Scene {
        let mut scene = Scene::default();
        let mut index = std::collections::HashMap::new();
        let nodes = graph.nodes();
        let mut dag = Vec::new();
        for &id in &nodes {
            let Some(spec) = graph.node_spec(id) else { continue };
            let name = graph.node_name(id).unwrap_or_default().to_string();
            let ty = graph.node_type(id).unwrap_or_default();
            if let Some(d) = &spec.dag {
                let kind = if spec.find("jointOrient").is_some() {
                    DrawKind::Joint
                } else {
                    DrawKind::Transform
                };
                let plug = format!("{name}.{}", spec.attr(d.world_matrix).name);
                dag.push((id, name, kind, plug));
            } else if let Some((_, out)) = MARKER_TYPES.iter().find(|(t, _)| *t == ty) {
                dag.push((id, name.clone(), DrawKind::Marker, format!("{name}.{out}")));
            }
        }
        for (id, name, kind, plug) in dag {
            let radius = graph
                .plug(&format!("{name}.radius"))
                .ok()
                .and_then(|p| graph.stored(p))
                .and_then(|v| v.as_f64())
                .filter(|r| r.is_finite() && *r > 0.0)
                .unwrap_or(1.0);
            index.insert(id, scene.items.len());
            scene.items.push(MatrixItem {
                name,
                kind,
                parent: None,
                radius,
                plug,
            });
        }
        for (&id, &i) in &index {
            scene.items[i].parent = graph.parent_of(id).and_then(|p| index.get(&p).copied());
        }
        for &id in &nodes {
            let name = graph.node_name(id).unwrap_or_default().to_string();
            if let Some(plug) = final_output(graph, id, AttrType::Mesh) {
                if let Ok(Value::Mesh(m)) = graph.get_path(&plug) {
                    if !m.positions.is_empty() {
                        scene.meshes.push(GeoItem {
                            name: name.clone(),
                            plug,
                            count: m.positions.len(),
                            triangles: m.triangles.clone(),
                        });
                    }
                }
            }
            if let Some(plug) = final_output(graph, id, AttrType::Curve) {
                if let Ok(Value::Curve(c)) = graph.get_path(&plug) {
                    let count = sample_count(&c);
                    if count > 0 {
                        scene.curves.push(GeoItem {
                            name,
                            plug,
                            count,
                            triangles: Vec::new(),
                        });
                    }
                }
            }
        }
        scene
    }

    /// Bytes of one frame (see the module docs).
    pub fn frame_len(&self) -> usize {
        self.items.len() * 128
            + self.curves.iter().map(|c| c.count * 24).sum::<usize>()
            + self.meshes.iter().map(|m| m.count * 12).sum::<usize>()
    }

    /// The scene for the page: items, geometry and the frame layout.
    pub fn to_json(&self) -> serde_json::Value {
        let mut offset = self.items.len() * 128;
        let curves: Vec<_> = self
            .curves
            .iter()
            .map(|c| {
                let o = offset;
                offset += c.count * 24;
                json!({ "name": c.name, "plug": c.plug, "samples": c.count, "offset": o })
            })
            .collect();
        let meshes: Vec<_> = self
            .meshes
            .iter()
            .map(|m| {
                let o = offset;
                offset += m.count * 12;
                json!({
                    "name": m.name, "plug": m.plug, "vertices": m.count, "offset": o,
                    "triangles": m.triangles.iter().flatten().collect::<Vec<_>>(),
                })
            })
            .collect();
        let items: Vec<_> = self
            .items
            .iter()
            .map(|i| {
                json!({ "name": i.name, "kind": i.kind.name(), "parent": i.parent,
                        "radius": i.radius, "plug": i.plug })
            })
            .collect();
        json!({ "items": items, "curves": curves, "meshes": meshes, "frameBytes": self.frame_len() })
    }

    /// Resolves the plugs this scene reads in `program` (in frame order); a plug the
    /// program cannot read gives `None` and is sent as zeros.
    pub fn handles(&self, program: &Program) -> Vec<Option<PlugHandle>> {
        let items = self.items.iter().map(|i| &i.plug);
        let geo = self.curves.iter().chain(&self.meshes).map(|g| &g.plug);
        items.chain(geo).map(|p| program.handle(p).ok()).collect()
    }

    /// Writes the frame `instance` holds (see the module docs).
    pub fn write_frame(&self, instance: &Instance, handles: &[Option<PlugHandle>], out: &mut Vec<u8>) {
        let value = |k: usize| handles.get(k).and_then(|h| h.as_ref()).map(|h| instance.get(h));
        self.write_values(value, out);
    }

    /// Writes a frame from the lazy graph (what an edit pulls).
    pub fn write_frame_lazy(&self, graph: &mut Graph, out: &mut Vec<u8>) -> Vec<(String, String)> {
        let mut errors = Vec::new();
        let plugs: Vec<&String> = self
            .items
            .iter()
            .map(|i| &i.plug)
            .chain(self.curves.iter().chain(&self.meshes).map(|g| &g.plug))
            .collect();
        let values: Vec<Option<Value>> = plugs
            .iter()
            .map(|p| match graph.get_path(p) {
                Ok(v) => Some(v),
                Err(e) => {
                    errors.push((p.split('.').next().unwrap_or_default().to_string(), e.to_string()));
                    None
                }
            })
            .collect();
        self.write_values(|k| values.get(k).cloned().flatten(), out);
        errors
    }

    fn write_values(&self, value: impl Fn(usize) -> Option<Value>, out: &mut Vec<u8>) {
        out.clear();
        out.reserve(self.frame_len());
        let mut k = 0;
        for _ in &self.items {
            let m = match value(k) {
                Some(Value::Matrix(m)) => m.to_cols_array(),
                _ => [0.0; 16],
            };
            m.iter().for_each(|x| out.extend_from_slice(&x.to_le_bytes()));
            k += 1;
        }
        for c in &self.curves {
            let pts = match value(k) {
                Some(Value::Curve(curve)) => sample_curve(&curve),
                _ => Vec::new(),
            };
            for i in 0..c.count {
                let p = pts.get(i).copied().unwrap_or(DVec3::ZERO);
                p.to_array()
                    .iter()
                    .for_each(|x| out.extend_from_slice(&x.to_le_bytes()));
            }
            k += 1;
        }
        for m in &self.meshes {
            let mesh = match value(k) {
                Some(Value::Mesh(mesh)) => Some(mesh),
                _ => None,
            };
            for i in 0..m.count {
                let p = mesh
                    .as_ref()
                    .and_then(|x| x.positions.get(i))
                    .copied()
                    .unwrap_or_default();
                p.to_array()
                    .iter()
                    .for_each(|x| out.extend_from_slice(&x.to_le_bytes()));
            }
            k += 1;
        }
    }
}

/// Samples drawn for a curve: [`SAMPLES_PER_SPAN`] per span, plus the end.
fn sample_count(c: &Curve) -> usize {
    let n = c.points.len();
    let d = c.degree.max(1) as usize;
    if n <= d {
        return n;
    }
    let spans = match c.form {
        CurveForm::Open => n - d,
        CurveForm::Periodic => n,
    };
    spans * SAMPLES_PER_SPAN + 1
}

/// Points along a B-spline by de Boor's algorithm (Piegl & Tiller, The NURBS Book,
/// A2.1/A3.1): the curve's knots, else uniform clamped knots (open) or uniform
/// unclamped knots over the points wrapped by `degree` (periodic). Curves with no more
/// points than their degree are drawn as their control polygon.
pub fn sample_curve(c: &Curve) -> Vec<DVec3> {
    let d = c.degree.max(1) as usize;
    let mut pts = c.points.clone();
    if pts.len() <= d {
        return pts;
    }
    if c.form == CurveForm::Periodic {
        pts.extend(c.points.iter().take(d).copied());
    }
    let n = pts.len();
    let knots: Vec<f64> = if c.knots.len() == n + d + 1 && c.form == CurveForm::Open {
        c.knots.clone()
    } else if c.form == CurveForm::Open {
        (0..n + d + 1).map(|i| i.saturating_sub(d).min(n - d) as f64).collect()
    } else {
        (0..n + d + 1).map(|i| i as f64).collect()
    };
    let (t0, t1) = (knots[d], knots[n]);
    let count = sample_count(c);
    (0..count)
        .map(|s| {
            let t = t0 + (t1 - t0) * s as f64 / (count - 1).max(1) as f64;
            // The span k with knots[k] <= t < knots[k + 1], within [d, n - 1].
            let mut k = d;
            while k + 1 < n && knots[k + 1] <= t {
                k += 1;
            }
            let mut p: Vec<DVec3> = (0..=d).map(|j| pts[k - d + j]).collect();
            for r in 1..=d {
                for j in (r..=d).rev() {
                    let i = k - d + j;
                    let den = knots[i + d + 1 - r] - knots[i];
                    let a = if den == 0.0 { 0.0 } else { (t - knots[i]) / den };
                    p[j] = p[j - 1] * (1.0 - a) + p[j] * a;
                }
            }
            p[d]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A degree-1 curve is its polyline; a clamped cubic starts and ends at its end points
    /// and passes (1/6, 2/3, 1/6) of the middle three points at the middle of a uniform
    /// span with interior knots (the cubic B-spline basis at a knot).
    #[test]
    fn curve_samples() {
        let line = Curve {
            degree: 1,
            points: vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0)],
            ..Curve::default()
        };
        let s = sample_curve(&line);
        assert_eq!(s.len(), 2 * SAMPLES_PER_SPAN + 1);
        assert_eq!(s[SAMPLES_PER_SPAN / 2], DVec3::new(0.5, 0.0, 0.0));
        assert_eq!(*s.last().unwrap(), DVec3::new(1.0, 1.0, 0.0));
        let pts: Vec<DVec3> = (0..5).map(|i| DVec3::new(i as f64, (i * i) as f64, 0.0)).collect();
        let cubic = Curve {
            degree: 3,
            points: pts.clone(),
            ..Curve::default()
        };
        let s = sample_curve(&cubic);
        assert_eq!(s.len(), 2 * SAMPLES_PER_SPAN + 1);
        assert!((s[0] - pts[0]).length() < 1e-12);
        assert!((*s.last().unwrap() - pts[4]).length() < 1e-12);
        // Knots 0 0 0 0 1 2 2 2 2: at t = 1 the basis of points 1, 2, 3 is 1/4, 1/2, 1/4.
        let mid = s[SAMPLES_PER_SPAN];
        let expect = pts[1] * 0.25 + pts[2] * 0.5 + pts[3] * 0.25;
        assert!((mid - expect).length() < 1e-12, "{mid} vs {expect}");
    }
}
