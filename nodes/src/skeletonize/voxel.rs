//! The mesh as a solid: a voxel grid whose cells the surface passes through (the
//! shell, by an exact triangle–box overlap test) plus every cell the outside cannot
//! reach (a flood fill from the grid's border). Overlapping parts, self-intersections,
//! duplicate vertices, non-manifold edges and inconsistent orientation only change
//! which cells are marked, so the solid of any triangle soup is well defined.
//!
//! Open meshes (an edge used by one triangle only, once vertices at the same position
//! are welded): a hole wider than a cell would let the flood fill in, so the fill is
//! also run with the shell thickened by 1, 2, 4 and then 8 cells (a morphological
//! closing: the fill cannot pass the thickened shell, and then reclaims that many cells
//! back through the unthickened one), which seals holes up to about twice that width.
//! The closing kept is the one whose volume jumps most over the previous one's (it
//! filled the inside); later ones only fill creases. Without a jump of a third,
//! nothing was sealed and the plain fill stays. A mesh open so wide that no
//! closing seals it is left as its shell (documented fallback: thin sheets and
//! wide-open surfaces), flagged [`Solid::shell_only`].

use glam::DVec3;

use sinew_core::data::Mesh;

/// Cells of padding around the mesh's bounding box (the border stays outside).
const PAD: usize = 2;
/// Closing radii tried, in cells, when the plain fill leaks.
const CLOSINGS: [usize; 4] = [1, 2, 4, 8];
/// Largest number of cells a grid may have; the cell size grows to respect it.
pub const MAX_CELLS: usize = 1 << 24;

/// A regular grid of cubic cells.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// World position of cell (0, 0, 0)'s lowest corner.
    pub origin: DVec3,
    /// Cell size.
    pub h: f64,
    /// Cells along x, y and z.
    pub dims: [usize; 3],
}

impl Grid {
    /// Number of cells.
    pub fn len(&self) -> usize {
        self.dims[0] * self.dims[1] * self.dims[2]
    }

    /// True for a grid without cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Linear index of cell `(i, j, k)`.
    pub fn index(&self, i: usize, j: usize, k: usize) -> usize {
        i + self.dims[0] * (j + self.dims[1] * k)
    }

    /// Cell coordinates of a linear index.
    pub fn coords(&self, c: usize) -> [usize; 3] {
        let i = c % self.dims[0];
        let j = (c / self.dims[0]) % self.dims[1];
        [i, j, c / (self.dims[0] * self.dims[1])]
    }

    /// World position of a cell's centre.
    pub fn center(&self, c: usize) -> DVec3 {
        let [i, j, k] = self.coords(c);
        self.origin + (DVec3::new(i as f64, j as f64, k as f64) + 0.5) * self.h
    }

    /// The cell containing world point `p`, if it is in the grid.
    pub fn cell_of(&self, p: DVec3) -> Option<usize> {
        // Truncation is the floor on non-negative numbers (and needs no libm call).
        let q = (p - self.origin) / self.h;
        let ok = (0..3).all(|a| q[a] >= 0.0 && (q[a] as usize) < self.dims[a]);
        ok.then(|| self.index(q.x as usize, q.y as usize, q.z as usize))
    }

    /// Linear offsets of the 26 neighbours with their length in cells.
    pub fn neighbours(&self) -> [(isize, f64); 26] {
        let (sx, sy) = (self.dims[0] as isize, (self.dims[0] * self.dims[1]) as isize);
        let mut out = [(0isize, 0.0f64); 26];
        let mut n = 0;
        for dz in -1isize..=1 {
            for dy in -1isize..=1 {
                for dx in -1isize..=1 {
                    if dx == 0 && dy == 0 && dz == 0 {
                        continue;
                    }
                    let len = ((dx * dx + dy * dy + dz * dz) as f64).sqrt();
                    out[n] = (dx + dy * sx + dz * sy, len);
                    n += 1;
                }
            }
        }
        out
    }
}

/// The solid: which cells of the grid are inside the mesh.
#[derive(Clone, Debug)]
pub struct Solid {
    /// The grid.
    pub grid: Grid,
    /// Per cell: inside (shell or enclosed).
    pub inside: Vec<bool>,
    /// Per cell: the surface passes through it.
    pub shell: Vec<bool>,
    /// Closing radius in cells used to seal holes (0: the mesh was closed).
    pub closing: usize,
    /// True when no closing sealed the mesh and the solid is its shell alone.
    pub shell_only: bool,
}

impl Solid {
    /// Number of inside cells.
    pub fn count(&self) -> usize {
        self.inside.iter().filter(|&&b| b).count()
    }
}

/// The grid for `mesh`: `resolution` cells along the bounding box's longest side (at
/// least 8), padded by `PAD` cells. `None` for a mesh without finite extent.
pub fn grid_for(mesh: &Mesh, resolution: usize, pad: usize) -> Option<Grid> {
    let (lo, hi) = bounds(mesh)?;
    let ext = hi - lo;
    let longest = ext.max_element();
    if !(longest > 0.0 && longest.is_finite()) {
        return None;
    }
    let mut h = longest / resolution.max(8) as f64;
    loop {
        let dims = [0, 1, 2].map(|a| (ext[a] / h).ceil() as usize + 1 + 2 * pad);
        if dims.iter().product::<usize>() <= MAX_CELLS {
            let size = DVec3::new(dims[0] as f64, dims[1] as f64, dims[2] as f64) * h;
            let origin = (lo + hi) * 0.5 - size * 0.5;
            return Some(Grid { origin, h, dims });
        }
        h *= 1.25;
    }
}

/// Axis-aligned bounds of the vertices used by triangles.
pub fn bounds(mesh: &Mesh) -> Option<(DVec3, DVec3)> {
    let mut lo = DVec3::INFINITY;
    let mut hi = DVec3::NEG_INFINITY;
    for t in &mesh.triangles {
        for &i in t {
            let p = mesh.positions.get(i as usize)?.as_dvec3();
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    (lo.is_finite() && hi.is_finite()).then_some((lo, hi))
}

/// Signed volume enclosed by the triangles (divergence theorem, about the bounds'
/// centre); meaningful for closed, consistently oriented meshes.
pub fn signed_volume(mesh: &Mesh, centre: DVec3) -> f64 {
    let mut v = 0.0;
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| {
            mesh.positions
                .get(i as usize)
                .map_or(DVec3::ZERO, |p| p.as_dvec3() - centre)
        });
        v += a.dot(b.cross(c));
    }
    v / 6.0
}

/// The solid of `mesh` at `resolution` cells along its longest side (see the module
/// docs). `None` for a mesh without finite extent.
pub fn voxelize(mesh: &Mesh, resolution: usize) -> Option<Solid> {
    bounds(mesh)?;
    if open_edges(mesh) == 0 {
        let grid = grid_for(mesh, resolution, PAD)?;
        let shell = rasterize(mesh, &grid);
        let inside = fill(&grid, &shell, 0);
        return Some(Solid {
            grid,
            inside,
            shell,
            closing: 0,
            shell_only: false,
        });
    }
    // Open: a grid with room for the thickest closing. The closing that seals the hole is
    // the one whose volume jumps most over the previous one's (filling the inside);
    // closings past it only fill creases. No jump of a third: nothing was sealed.
    let grid = grid_for(mesh, resolution, PAD + CLOSINGS[CLOSINGS.len() - 1])?;
    let shell = rasterize(mesh, &grid);
    let count = |inside: &[bool]| inside.iter().filter(|&&b| b).count();
    let shell_cells = count(&shell);
    let mut best = (0usize, fill(&grid, &shell, 0), 1.0f64);
    let mut prev = count(&best.1).max(1) as f64;
    for c in CLOSINGS {
        let closed = fill(&grid, &shell, c);
        let v = count(&closed) as f64;
        let jump = v / prev;
        prev = v.max(1.0);
        if jump >= 4.0 / 3.0 && jump > best.2 {
            best = (c, closed, jump);
        }
    }
    let (closing, inside, _) = best;
    // Nothing but the shell (and what closings add to it at most): a sheet, left open.
    let shell_only = count(&inside) <= shell_cells + shell_cells / 4;
    Some(Solid {
        grid,
        inside,
        shell,
        closing,
        shell_only,
    })
}

/// Edges used by one triangle only, once vertices at the same position are one (UV
/// and normal seams split vertices without opening the surface). Sorting, not
/// hashing: vertices are welded by sorting their position bits, edges are counted as
/// runs of a sorted list (a hash map per edge cost a third of the skeleton's time on
/// a 200k-vertex mesh).
pub fn open_edges(mesh: &Mesh) -> usize {
    let key = |i: u32| {
        let p = mesh.positions[i as usize];
        (p.x.to_bits(), p.y.to_bits(), p.z.to_bits())
    };
    let mut order: Vec<u32> = (0..mesh.positions.len() as u32).collect();
    order.sort_unstable_by_key(|&i| key(i));
    let mut weld = vec![0u32; mesh.positions.len()];
    let mut id = 0u32;
    for (k, &i) in order.iter().enumerate() {
        if k > 0 && key(i) != key(order[k - 1]) {
            id += 1;
        }
        weld[i as usize] = id;
    }
    let mut edges: Vec<u64> = Vec::with_capacity(mesh.triangles.len() * 3);
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| weld.get(i as usize).copied().unwrap_or(u32::MAX));
        if a == b || b == c || a == c {
            continue;
        }
        for (x, y) in [(a, b), (b, c), (c, a)] {
            edges.push(((x.min(y) as u64) << 32) | x.max(y) as u64);
        }
    }
    edges.sort_unstable();
    edges.chunk_by(|x, y| x == y).filter(|run| run.len() == 1).count()
}

/// Marks every cell a triangle overlaps.
pub fn rasterize(mesh: &Mesh, grid: &Grid) -> Vec<bool> {
    let mut shell = vec![false; grid.len()];
    let h = grid.h;
    let half = 0.5 * h * (1.0 + 1e-9);
    let mut corners: Vec<f64> = Vec::new();
    let strides = [1, grid.dims[0], grid.dims[0] * grid.dims[1]];
    for t in &mesh.triangles {
        let Some(p) = tri_points(mesh, t, grid.origin) else {
            continue;
        };
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let lo = p[0].min(p[1]).min(p[2]);
        let hi = p[0].max(p[1]).max(p[2]);
        // The cell of coordinate x along axis a, clamped to the grid: truncation is the
        // floor on non-negative numbers, and negative ones (and NaN) give 0 either way.
        let cell = |x: f64, a: usize| ((x / h) as usize).min(grid.dims[a] - 1);
        let (c0, c1) = ([0, 1, 2].map(|a| cell(lo[a], a)), [0, 1, 2].map(|a| cell(hi[a], a)));
        let d = n.abs().max_position();
        let (a, b) = ((d + 1) % 3, (d + 2) % 3);
        let plane = n.dot(p[0]);
        let tilted = n[d].abs() > 1e-300;
        // The plane's coordinate along d over the column corners (xa, xb), computed once
        // per corner instead of once per column using it.
        let row = c1[a] - c0[a] + 2;
        if tilted {
            corners.clear();
            for xb in c0[b]..=c1[b] + 1 {
                for xa in c0[a]..=c1[a] + 1 {
                    corners.push((plane - n[a] * xa as f64 * h - n[b] * xb as f64 * h) / n[d]);
                }
            }
        }
        for ia in c0[a]..=c1[a] {
            for ib in c0[b]..=c1[b] {
                // The range of the triangle's plane over this column, in cells along d.
                let (mut dmin, mut dmax) = (lo[d], hi[d]);
                if tilted {
                    let (mut pmin, mut pmax) = (f64::INFINITY, f64::NEG_INFINITY);
                    let at = (ia - c0[a]) + row * (ib - c0[b]);
                    for v in [corners[at], corners[at + 1], corners[at + row], corners[at + row + 1]] {
                        pmin = pmin.min(v);
                        pmax = pmax.max(v);
                    }
                    dmin = dmin.max(pmin);
                    dmax = dmax.min(pmax);
                }
                if dmin > dmax {
                    continue;
                }
                // The column's first cell index and its centre's coordinates along a and
                // b (those of every cell in it).
                let column = ia * strides[a] + ib * strides[b];
                let mut centre = DVec3::ZERO;
                centre[a] = (ia as f64 + 0.5) * h;
                centre[b] = (ib as f64 + 0.5) * h;
                for id in cell(dmin, d)..=cell(dmax, d) {
                    let c = column + id * strides[d];
                    if shell[c] {
                        continue;
                    }
                    centre[d] = (id as f64 + 0.5) * h;
                    if tri_box_overlap([p[0] - centre, p[1] - centre, p[2] - centre], half) {
                        shell[c] = true;
                    }
                }
            }
        }
    }
    shell
}

fn tri_points(mesh: &Mesh, t: &[u32; 3], origin: DVec3) -> Option<[DVec3; 3]> {
    let mut out = [DVec3::ZERO; 3];
    for (k, &i) in t.iter().enumerate() {
        out[k] = mesh.positions.get(i as usize)?.as_dvec3() - origin;
    }
    Some(out)
}

/// Triangle (relative to the box centre) against the cube of half size `e`: the
/// separating-axis test of Akenine-Möller (2001) over the box axes, the triangle's
/// normal and the nine edge cross products.
#[inline]
pub fn tri_box_overlap(v: [DVec3; 3], e: f64) -> bool {
    let (lo, hi) = (v[0].min(v[1]).min(v[2]), v[0].max(v[1]).max(v[2]));
    if lo.max_element() > e || hi.min_element() < -e {
        return false;
    }
    let f = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
    let n = f[0].cross(f[1]);
    if n.dot(v[0]).abs() > e * (n.x.abs() + n.y.abs() + n.z.abs()) {
        return false;
    }
    // The nine axes `box axis × edge`: X × f = (0, −f.z, f.y), Y × f = (f.z, 0, −f.x),
    // Z × f = (−f.y, f.x, 0). Each has a zero component, so its dot products and
    // radius are sums of two terms (the same values as the full three-term sums).
    let (xs, ys, zs) = (v.map(|q| q.x), v.map(|q| q.y), v.map(|q| q.z));
    !f.iter().any(|fi| {
        axis_separates(-fi.z, fi.y, ys, zs, e)
            || axis_separates(fi.z, -fi.x, xs, zs, e)
            || axis_separates(-fi.y, fi.x, xs, ys, e)
    })
}

/// Whether the axis with components `ai` and `aj` (along two box axes; zero along the
/// third) separates the triangle, whose vertices have coordinates `qi` and `qj` along
/// those box axes, from the cube of half size `e`. A zero axis separates nothing.
#[inline(always)]
fn axis_separates(ai: f64, aj: f64, qi: [f64; 3], qj: [f64; 3], e: f64) -> bool {
    if ai == 0.0 && aj == 0.0 {
        return false;
    }
    let (p0, p1, p2) = (
        ai * qi[0] + aj * qj[0],
        ai * qi[1] + aj * qj[1],
        ai * qi[2] + aj * qj[2],
    );
    let r = e * (ai.abs() + aj.abs());
    p0.min(p1).min(p2) > r || p0.max(p1).max(p2) < -r
}

/// Inside cells: those the outside cannot reach from the border through cells off the
/// shell thickened by `closing` cells (then reclaiming `closing` cells back through
/// the plain shell). The grid's padding must exceed `closing` by at least 2.
pub fn fill(grid: &Grid, shell: &[bool], closing: usize) -> Vec<bool> {
    const FREE: u8 = 0;
    const WALL: u8 = 1;
    const OUT: u8 = 2;
    let as_state = |w: &bool| if *w { WALL } else { FREE };
    let mut state: Vec<u8> = if closing == 0 {
        shell.iter().map(as_state).collect()
    } else {
        dilate(grid, shell, closing).iter().map(as_state).collect()
    };
    // The border is outside; the flood runs over cells off the border, so every cell it
    // reaches has its six neighbours in the grid.
    let [nx, ny, nz] = grid.dims;
    let mut seeds: Vec<usize> = Vec::new();
    for k in 0..nz {
        for j in 0..ny {
            // Rows in the two outer layers in y or z whole, other rows their two ends.
            let outer = j.min(ny - 1 - j).min(k).min(nz - 1 - k) <= 1;
            let ends = [0, 1, nx - 2, nx - 1];
            let columns: &mut dyn Iterator<Item = usize> = if outer { &mut (0..nx) } else { &mut ends.into_iter() };
            for i in columns {
                let layer = i.min(nx - 1 - i).min(j).min(ny - 1 - j).min(k).min(nz - 1 - k);
                if layer > 1 {
                    continue;
                }
                let c = grid.index(i, j, k);
                if layer == 0 {
                    state[c] = OUT;
                } else if state[c] == FREE {
                    seeds.push(c);
                }
            }
        }
    }
    let steps = six(grid);
    flood_rows(grid, &mut state, seeds, FREE, OUT);
    if closing > 0 {
        // Reclaim: `closing` rounds of growth of the outside through non-shell cells,
        // from the outside cells next to the thickened wall.
        for (c, s) in state.iter_mut().enumerate() {
            if *s == WALL && !shell[c] {
                *s = FREE;
            }
        }
        let mut front: Vec<usize> = Vec::new();
        for k in 1..nz - 1 {
            for j in 1..ny - 1 {
                for i in 1..nx - 1 {
                    let c = grid.index(i, j, k);
                    if state[c] == OUT && steps.iter().any(|&s| state[(c as isize + s) as usize] == FREE) {
                        front.push(c);
                    }
                }
            }
        }
        for _ in 0..closing {
            let mut next = Vec::new();
            for &c in &front {
                for s in steps {
                    let m = (c as isize + s) as usize;
                    if state[m] == FREE {
                        state[m] = OUT;
                        next.push(m);
                    }
                }
            }
            front = next;
        }
    }
    state.iter().map(|&s| s != OUT).collect()
}

/// Turns every `free` cell 6-connected to a seed (through `free` cells) into `to`, a
/// row at a time (scanline fill): a popped seed grows into the whole run of `free`
/// cells along x, and the first cell of every `free` run next to it in the four
/// neighbouring rows becomes a seed. The cells reached are those of a cell-by-cell
/// flood; the rows are scanned as contiguous memory. Every cell that can be reached
/// must lie off the grid's border (its neighbours are in the grid).
fn flood_rows(grid: &Grid, state: &mut [u8], mut stack: Vec<usize>, free: u8, to: u8) {
    let sy = grid.dims[0] as isize;
    let sz = (grid.dims[0] * grid.dims[1]) as isize;
    while let Some(c) = stack.pop() {
        if state[c] != free {
            continue;
        }
        let (mut l, mut r) = (c, c);
        // Eight cells at a time while all eight are free, then one at a time.
        let all_free = |s: &[u8]| s.iter().all(|&x| x == free);
        while l >= 8 && all_free(&state[l - 8..l]) {
            l -= 8;
        }
        while state[l - 1] == free {
            l -= 1;
        }
        while state.get(r + 1..r + 9).is_some_and(all_free) {
            r += 8;
        }
        while state[r + 1] == free {
            r += 1;
        }
        state[l..=r].fill(to);
        for off in [-sy, sy, -sz, sz] {
            let a = (l as isize + off) as usize;
            push_run_starts(&state[a..=(r as isize + off) as usize], a, free, &mut stack);
        }
    }
}

/// Pushes `base + m` for the first cell `m` of every run of `free` cells in `row`.
/// Eight cells at a time where none of them is `free` (the usual case: rows already
/// filled or walled), one at a time elsewhere; the same cells as a plain scan.
fn push_run_starts(row: &[u8], base: usize, free: u8, stack: &mut Vec<usize>) {
    const ONES: u64 = 0x0101_0101_0101_0101;
    const HIGHS: u64 = 0x8080_8080_8080_8080;
    let pattern = u64::from(free) * ONES;
    let mut open = false;
    let mut m = 0;
    while m < row.len() {
        if let Some(chunk) = row.get(m..m + 8) {
            let mut bytes = [0u8; 8];
            bytes.copy_from_slice(chunk);
            // Zero bytes of `x` are the `free` cells (the exact has-a-zero-byte test).
            let x = u64::from_le_bytes(bytes) ^ pattern;
            if x.wrapping_sub(ONES) & !x & HIGHS == 0 {
                open = false;
                m += 8;
                continue;
            }
        }
        let end = (m + 8).min(row.len());
        for (k, &s) in row[m..end].iter().enumerate() {
            let f = s == free;
            if f && !open {
                stack.push(base + m + k);
            }
            open = f;
        }
        m = end;
    }
}

/// Linear offsets of the six face neighbours.
fn six(grid: &Grid) -> [isize; 6] {
    let sy = grid.dims[0] as isize;
    let sz = (grid.dims[0] * grid.dims[1]) as isize;
    [-1, 1, -sy, sy, -sz, sz]
}

/// Cells within Chebyshev distance `r` of a marked cell (three separable passes, each
/// a running count over a window of `2r + 1` cells).
fn dilate(grid: &Grid, marked: &[bool], r: usize) -> Vec<bool> {
    let mut cur = marked.to_vec();
    let strides = [1, grid.dims[0], grid.dims[0] * grid.dims[1]];
    for axis in 0..3 {
        let n = grid.dims[axis];
        let stride = strides[axis];
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        let mut next = vec![false; cur.len()];
        for ib in 0..grid.dims[b] {
            for ia in 0..grid.dims[a] {
                let base = ia * strides[a] + ib * strides[b];
                // Count of marked cells in [x - r, x + r].
                let mut count = (0..=r.min(n - 1)).filter(|&y| cur[base + y * stride]).count();
                for x in 0..n {
                    if count > 0 {
                        next[base + x * stride] = true;
                    }
                    if x + r + 1 < n && cur[base + (x + r + 1) * stride] {
                        count += 1;
                    }
                    if x >= r && cur[base + (x - r) * stride] {
                        count -= 1;
                    }
                }
            }
        }
        cur = next;
    }
    cur
}
