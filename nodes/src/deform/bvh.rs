//! A small bounding volume hierarchy over axis-aligned boxes, used for closest-point queries
//! on triangles ([`super::closest_point`]) and point-in-UV-triangle lookups
//! ([`super::surface`]).
//!
//! Why hand-written: the queries need the primitive's exact distance (point-to-triangle with
//! barycentrics) and an in-place **refit** when a skinned mesh moves, which keeps the tree
//! (built once per topology) valid without a rebuild. Ray-tracing BVH crates target rays,
//! and `rstar` (R*-tree) has no refit and needs a newer Rust than the workspace's MSRV.
//!
//! Build: top-down median split on the longest axis of the centroid bounds, at most
//! [`LEAF_SIZE`] primitives per leaf, O(n log n). Because every split halves the range,
//! depth is at most `log2(n) + 1`, so traversal uses a fixed stack and never allocates.

use glam::Vec3A;

/// Maximum primitives per leaf.
pub const LEAF_SIZE: usize = 4;

/// An axis-aligned bounding box; `min > max` on some axis means empty.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: Vec3A,
    /// Upper corner.
    pub max: Vec3A,
}

impl Aabb {
    /// The empty box (union identity).
    pub const EMPTY: Aabb = Aabb {
        min: Vec3A::splat(f32::INFINITY),
        max: Vec3A::splat(f32::NEG_INFINITY),
    };

    /// The smallest box holding all `points`.
    pub fn from_points(points: &[Vec3A]) -> Aabb {
        points.iter().fold(Aabb::EMPTY, |b, &p| Aabb {
            min: b.min.min(p),
            max: b.max.max(p),
        })
    }

    /// The smallest box holding both.
    pub fn union(self, o: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// Squared distance from `p` to the box (0 inside).
    #[inline]
    pub fn distance_squared(&self, p: Vec3A) -> f32 {
        let d = (self.min - p).max(p - self.max).max(Vec3A::ZERO);
        d.length_squared()
    }

    /// Whether `p` lies inside the box grown by `eps`.
    #[inline]
    pub fn contains(&self, p: Vec3A, eps: f32) -> bool {
        p.cmpge(self.min - eps).all() && p.cmple(self.max + eps).all()
    }

    fn centroid(&self) -> Vec3A {
        (self.min + self.max) * 0.5
    }
}

#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Aabb,
    /// Leaf: first entry in `prims`. Inner: index of the left child (right is `start + 1`).
    start: u32,
    /// Number of primitives for a leaf, 0 for an inner node.
    count: u32,
}

/// A BVH over primitives `0..n`, each given by its bounding box.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    prims: Vec<u32>,
}

const STACK: usize = 64;

impl Bvh {
    /// Builds the hierarchy over `boxes` (primitive `i` has box `boxes[i]`).
    pub fn build(boxes: &[Aabb]) -> Bvh {
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(2 * boxes.len() / LEAF_SIZE + 1),
            prims: (0..boxes.len() as u32).collect(),
        };
        if !boxes.is_empty() {
            bvh.nodes.push(Node {
                bounds: Aabb::EMPTY,
                start: 0,
                count: 0,
            });
            bvh.split(0, 0, boxes.len(), boxes);
        }
        bvh
    }

    fn split(&mut self, node: usize, lo: usize, hi: usize, boxes: &[Aabb]) {
        let range = &mut self.prims[lo..hi];
        let bounds = range.iter().fold(Aabb::EMPTY, |b, &i| b.union(boxes[i as usize]));
        let cb = range.iter().fold(Aabb::EMPTY, |b, &i| {
            let c = boxes[i as usize].centroid();
            b.union(Aabb { min: c, max: c })
        });
        self.nodes[node].bounds = bounds;
        if hi - lo <= LEAF_SIZE {
            self.nodes[node].start = lo as u32;
            self.nodes[node].count = (hi - lo) as u32;
            return;
        }
        let ext = cb.max - cb.min;
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        let mid = (lo + hi) / 2;
        range.select_nth_unstable_by(mid - lo, |&a, &b| {
            let (ca, cb) = (boxes[a as usize].centroid()[axis], boxes[b as usize].centroid()[axis]);
            ca.total_cmp(&cb)
        });
        let left = self.nodes.len();
        self.nodes.push(Node {
            bounds: Aabb::EMPTY,
            start: 0,
            count: 0,
        });
        self.nodes.push(Node {
            bounds: Aabb::EMPTY,
            start: 0,
            count: 0,
        });
        self.nodes[node].start = left as u32;
        self.split(left, lo, mid, boxes);
        self.split(left + 1, mid, hi, boxes);
    }

    /// Number of primitives indexed.
    pub fn len(&self) -> usize {
        self.prims.len()
    }

    /// Whether no primitive is indexed.
    pub fn is_empty(&self) -> bool {
        self.prims.is_empty()
    }

    /// Recomputes every box bottom-up after primitives moved (same primitive count and
    /// meaning). O(n); the tree shape is kept, so queries stay exact but may slow down if
    /// the deformation is extreme (rebuild then).
    pub fn refit(&mut self, mut prim_box: impl FnMut(u32) -> Aabb) {
        // Children are always stored after their parent.
        for n in (0..self.nodes.len()).rev() {
            let node = self.nodes[n];
            self.nodes[n].bounds = if node.count > 0 {
                let r = node.start as usize..(node.start + node.count) as usize;
                self.prims[r].iter().fold(Aabb::EMPTY, |b, &i| b.union(prim_box(i)))
            } else {
                let l = node.start as usize;
                self.nodes[l].bounds.union(self.nodes[l + 1].bounds)
            };
        }
    }

    /// Finds the primitive minimizing `dist2(prim, best_so_far)`, a squared distance from
    /// `p` that must not be smaller than the squared distance from `p` to the primitive's
    /// box. Returns `(prim, squared distance)`; `None` when empty or nothing is finite.
    pub fn nearest(&self, p: Vec3A, mut dist2: impl FnMut(u32) -> f32) -> Option<(u32, f32)> {
        let mut best: Option<(u32, f32)> = None;
        let mut best_d = f32::INFINITY;
        let mut stack = [(0u32, 0f32); STACK];
        if self.nodes.is_empty() {
            return None;
        }
        stack[0] = (0, self.nodes[0].bounds.distance_squared(p));
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let (n, d) = stack[sp];
            if d >= best_d {
                continue;
            }
            let node = self.nodes[n as usize];
            if node.count > 0 {
                let r = node.start as usize..(node.start + node.count) as usize;
                for &i in &self.prims[r] {
                    let di = dist2(i);
                    if di < best_d {
                        best_d = di;
                        best = Some((i, di));
                    }
                }
            } else if sp + 2 <= STACK {
                let l = node.start;
                let (dl, dr) = (
                    self.nodes[l as usize].bounds.distance_squared(p),
                    self.nodes[l as usize + 1].bounds.distance_squared(p),
                );
                // Push the farther child first so the nearer one is visited first.
                let (first, second) = if dl <= dr {
                    ((l + 1, dr), (l, dl))
                } else {
                    ((l, dl), (l + 1, dr))
                };
                stack[sp] = first;
                stack[sp + 1] = second;
                sp += 2;
            }
        }
        best
    }

    /// Calls `visit(prim)` for every primitive whose box contains `p` (grown by `eps`),
    /// stopping early when `visit` returns `true`. Returns whether it stopped early.
    pub fn find_containing(&self, p: Vec3A, eps: f32, mut visit: impl FnMut(u32) -> bool) -> bool {
        let mut stack = [0u32; STACK];
        if self.nodes.is_empty() {
            return false;
        }
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let node = self.nodes[stack[sp] as usize];
            if !node.bounds.contains(p, eps) {
                continue;
            }
            if node.count > 0 {
                let r = node.start as usize..(node.start + node.count) as usize;
                if self.prims[r].iter().any(|&i| visit(i)) {
                    return true;
                }
            } else if sp + 2 <= STACK {
                stack[sp] = node.start;
                stack[sp + 1] = node.start + 1;
                sp += 2;
            }
        }
        false
    }

    /// Rebuilds the hierarchy over `boxes` in place: the tree [`Bvh::build`] makes, reusing
    /// this one's buffers, so a rebuild every frame allocates nothing once they are large
    /// enough (the node count depends only on the primitive count).
    pub fn rebuild(&mut self, boxes: &[Aabb]) {
        self.nodes.clear();
        self.prims.clear();
        self.prims.extend(0..boxes.len() as u32);
        if !boxes.is_empty() {
            self.nodes.push(Node {
                bounds: Aabb::EMPTY,
                start: 0,
                count: 0,
            });
            self.split(0, 0, boxes.len(), boxes);
        }
    }

    /// The primitive whose hit `hit(prim)` (a ray parameter `t`, `None` for a miss) is the
    /// smallest, for the ray `origin + t·dir`, `t ∈ [0, max_t]`. `hit` must only return
    /// parameters of points inside the primitive's box. Returns `(prim, t)`.
    pub fn ray_nearest(
        &self,
        origin: Vec3A,
        dir: Vec3A,
        max_t: f32,
        mut hit: impl FnMut(u32) -> Option<f32>,
    ) -> Option<(u32, f32)> {
        if self.nodes.is_empty() {
            return None;
        }
        let (o, d) = (origin.to_array(), dir.to_array());
        // Entry parameter of the ray into a box, `None` when it misses within `[0, best]`.
        let enter = |b: &Aabb, best: f32| -> Option<f32> {
            let (lo, hi) = (b.min.to_array(), b.max.to_array());
            let (mut t0, mut t1) = (0f32, best);
            for k in 0..3 {
                if d[k] == 0.0 {
                    if o[k] < lo[k] || o[k] > hi[k] {
                        return None;
                    }
                    continue;
                }
                let inv = 1.0 / d[k];
                let (a, b) = ((lo[k] - o[k]) * inv, (hi[k] - o[k]) * inv);
                let (near, far) = if a <= b { (a, b) } else { (b, a) };
                t0 = t0.max(near);
                t1 = t1.min(far);
                if t0 > t1 {
                    return None;
                }
            }
            Some(t0)
        };
        let mut best: Option<(u32, f32)> = None;
        let mut best_t = max_t;
        let mut stack = [(0u32, 0f32); STACK];
        let t_root = enter(&self.nodes[0].bounds, best_t)?;
        stack[0] = (0, t_root);
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let (n, t) = stack[sp];
            if t > best_t {
                continue;
            }
            let node = self.nodes[n as usize];
            if node.count > 0 {
                let r = node.start as usize..(node.start + node.count) as usize;
                for &i in &self.prims[r] {
                    if let Some(ti) = hit(i) {
                        if (0.0..=best_t).contains(&ti) && best.is_none_or(|(_, bt)| ti < bt) {
                            best_t = ti;
                            best = Some((i, ti));
                        }
                    }
                }
            } else if sp + 2 <= STACK {
                let l = node.start;
                let tl = enter(&self.nodes[l as usize].bounds, best_t);
                let tr = enter(&self.nodes[l as usize + 1].bounds, best_t);
                // Push the farther child first so the nearer one is visited first.
                let mut push = |c: u32, t: Option<f32>| {
                    if let Some(t) = t {
                        stack[sp] = (c, t);
                        sp += 1;
                    }
                };
                if tl.unwrap_or(f32::INFINITY) <= tr.unwrap_or(f32::INFINITY) {
                    push(l + 1, tr);
                    push(l, tl);
                } else {
                    push(l, tl);
                    push(l + 1, tr);
                }
            }
        }
        best
    }
}
