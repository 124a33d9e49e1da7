//! Binding a dense mesh to driver meshes and rebuilding it from them: each bound vertex
//! remembers the closest point of the base driver (triangle and barycentric coordinates) and
//! its offset from it in the triangle's frame (`t` along the first edge, `n` the face normal,
//! `b = n × t`); each frame the same point of the deformed driver plus the offset in the
//! deformed triangle's frame gives the vertex. The change `(P' − P) + (F'·o − F·o)` is what
//! a bound vertex moves by (added to the input vertex, so deformers before the wrap compose
//! with it); an unmoved driver gives a change of exactly 0, the input back bit for bit.

use glam::Vec3;
use sinew_core::Mesh;

use crate::deform::closest_point::MeshIndex;

/// One bound vertex.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Binding {
    /// The dense vertex.
    pub vertex: u32,
    /// Driver index (position in the driver list).
    pub driver: u32,
    /// Driver triangle.
    pub triangle: u32,
    /// Barycentric coordinates on it.
    pub bary: Vec3,
    /// Offset in the triangle's frame.
    pub local: Vec3,
    /// `F · local` on the base driver, computed as every frame computes it.
    pub rest_offset: Vec3,
    /// The bound point `P` on the base driver, computed as every frame computes it.
    pub anchor: Vec3,
    /// Distance from the base driver at bind.
    pub distance: f32,
}

/// A bound mesh.
#[derive(Clone, Debug, Default)]
pub struct WrapBind {
    /// The bound vertices, by increasing vertex.
    pub bindings: Vec<Binding>,
    /// Per dense vertex, its position in `bindings` (`u32::MAX` = not bound).
    pub slot: Vec<u32>,
    /// Vertex count of each base driver.
    pub driver_sizes: Vec<usize>,
    /// Triangles of each base driver (the deformed drivers must match).
    pub driver_triangles: Vec<Vec<[u32; 3]>>,
}

/// The point at `bary` on triangle `t` of `positions`, and the triangle's frame.
#[inline]
pub fn frame(positions: &[Vec3], tri: [u32; 3], bary: Vec3) -> (Vec3, [Vec3; 3]) {
    let [a, b, c] = tri.map(|i| positions[i as usize]);
    let p = a * bary.x + b * bary.y + c * bary.z;
    let t = (b - a).normalize_or_zero();
    let n = (b - a).cross(c - a).normalize_or_zero();
    (p, [t, n.cross(t), n])
}

#[inline]
fn apply(f: &[Vec3; 3], o: Vec3) -> Vec3 {
    f[0] * o.x + f[1] * o.y + f[2] * o.z
}

impl WrapBind {
    /// Binds the vertices of `rest` within `max_distance` (0 = any distance) of the base
    /// drivers to their closest driver triangle.
    pub fn new(rest: &Mesh, drivers: &[&Mesh], max_distance: f32) -> Self {
        let indices: Vec<MeshIndex> = drivers.iter().map(|d| MeshIndex::build(d)).collect();
        let mut bindings = Vec::new();
        let mut slot = vec![u32::MAX; rest.positions.len()];
        for (v, &p) in rest.positions.iter().enumerate() {
            let best = indices
                .iter()
                .zip(drivers)
                .enumerate()
                .filter_map(|(k, (ix, d))| ix.closest_point(d, p).map(|h| (k, h)))
                .min_by(|a, b| a.1.distance.total_cmp(&b.1.distance));
            let Some((k, hit)) = best else {
                continue;
            };
            if max_distance > 0.0 && hit.distance > max_distance {
                continue;
            }
            let tri = drivers[k].triangles[hit.triangle as usize];
            let (q, f) = frame(&drivers[k].positions, tri, hit.barycentric);
            let d = p - q;
            let local = Vec3::new(d.dot(f[0]), d.dot(f[1]), d.dot(f[2]));
            slot[v] = bindings.len() as u32;
            bindings.push(Binding {
                vertex: v as u32,
                driver: k as u32,
                triangle: hit.triangle,
                bary: hit.barycentric,
                local,
                rest_offset: apply(&f, local),
                anchor: q,
                distance: hit.distance,
            });
        }
        WrapBind {
            bindings,
            slot,
            driver_sizes: drivers.iter().map(|d| d.positions.len()).collect(),
            driver_triangles: drivers.iter().map(|d| d.triangles.clone()).collect(),
        }
    }

    /// Checks that `drivers` (the deformed ones) match the base drivers; the message names
    /// the driver.
    pub fn check<'m>(&self, drivers: impl ExactSizeIterator<Item = &'m Mesh>) -> Result<(), String> {
        if drivers.len() != self.driver_sizes.len() {
            return Err(format!(
                "{} driverPoints for {} basePoints; connect one deformed driver per base driver",
                drivers.len(),
                self.driver_sizes.len()
            ));
        }
        for (k, d) in drivers.enumerate() {
            if d.positions.len() != self.driver_sizes[k] || d.triangles != self.driver_triangles[k] {
                return Err(format!(
                    "driverPoints[{k}] does not have the topology of basePoints[{k}]; rebind the wrap"
                ));
            }
        }
        Ok(())
    }

    /// How far binding `b`'s vertex moves with the deformed driver `driver` (its driver).
    #[inline]
    pub fn change(&self, b: &Binding, driver: &Mesh) -> Vec3 {
        let tri = self.driver_triangles[b.driver as usize][b.triangle as usize];
        let (q, f) = frame(&driver.positions, tri, b.bary);
        (q - b.anchor) + (apply(&f, b.local) - b.rest_offset)
    }
}
