//! The volume method: mesh → solid ([`super::voxel`]) → distance transform
//! ([`super::distance`]) → per connected part, the level graph of the geodesic
//! distance from the part's thickest cell ([`super::levels`]) → a cleaned curve
//! graph ([`super::curve`]); separate parts are joined to the nearest point of the
//! parts before them by a bridge edge, largest part first.

use glam::DVec3;

use super::curve::{CleanupReport, CurveGraph};
use super::distance::squared_distances;
use super::levels::{components, level_graph};
use super::medial::detour_shortcuts;
use super::symmetry::{detect_mirror, Mirror};
use super::voxel::{voxelize, Grid, Solid};
use sinew_core::data::Mesh;

/// Tuning of the volume method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolumeParams {
    /// Cells along the bounding box's longest side.
    pub resolution: usize,
    /// Width of a distance band, in cells.
    pub band: f64,
    /// Terminal chains shorter than this × their junction's radius are pruned.
    pub prune_factor: f64,
    /// Junctions closer than this × their radius merge.
    pub merge_factor: f64,
    /// Smoothing passes over chain points.
    pub smooth_iterations: usize,
    /// Parts with fewer cells than this fraction of the largest part's get no joints.
    pub min_part_fraction: f64,
    /// Symmetry tolerance (see [`detect_mirror`]); `None` skips the detection.
    pub symmetry_tolerance: Option<f64>,
}

/// One connected part of the solid and what became of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PartReport {
    /// Cells of the part.
    pub cells: usize,
    /// Centroid of the part (world).
    pub centroid: DVec3,
    /// How the part entered the skeleton.
    pub fate: PartFate,
}

/// How a part entered the skeleton.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PartFate {
    /// The largest part: the skeleton grows from it.
    Main,
    /// Joined to the skeleton by a bridge from `from` (on the skeleton so far) to `to`
    /// (on the part), `gap` apart.
    Joined {
        /// Skeleton point the bridge starts at.
        from: DVec3,
        /// Part point the bridge ends at.
        to: DVec3,
        /// Bridge length.
        gap: f64,
    },
    /// Kept as a separate tree (joining was turned off).
    Separate,
    /// Too small for joints of its own; its vertices are weighted to the nearest bones.
    TooSmall,
}

/// What the volume method computed besides the graph.
#[derive(Clone, Debug)]
pub struct VolumeReport {
    /// The grid.
    pub grid: Grid,
    /// Inside cells.
    pub cells: usize,
    /// Closing radius (cells) used to seal holes; 0 when the mesh was closed.
    pub closing: usize,
    /// True when the mesh could not be sealed and its shell alone was used.
    pub shell_only: bool,
    /// Parts, largest first.
    pub parts: Vec<PartReport>,
    /// The mirror plane, when the solid is symmetric within the tolerance.
    pub mirror: Option<Mirror>,
    /// The mirror mismatch of the best plane tried (fraction of the volume).
    pub mirror_mismatch: f64,
    /// Clean-up counts, summed over parts.
    pub cleanup: CleanupReport,
}

/// The curve graph of `mesh` by the volume method; `None` when the mesh has no
/// finite extent or its solid no cell.
pub fn curve_graph(mesh: &Mesh, params: &VolumeParams, join: bool) -> Option<(CurveGraph, VolumeReport, Solid)> {
    let solid = voxelize(mesh, params.resolution)?;
    let grid = solid.grid;
    let d2 = squared_distances(&grid, &solid.inside);
    let comps = components(&grid, &solid.inside);
    let main_cells = comps.first()?.len();
    let total: usize = comps.iter().map(Vec::len).sum();
    let (mirror, mirror_mismatch) = match params.symmetry_tolerance {
        Some(tol) => detect_mirror(&solid, tol),
        None => (None, 1.0),
    };
    let mut graph = CurveGraph::default();
    let mut report = VolumeReport {
        grid,
        cells: total,
        closing: solid.closing,
        shell_only: solid.shell_only,
        parts: Vec::new(),
        mirror,
        mirror_mismatch,
        cleanup: CleanupReport::default(),
    };
    let mut member = vec![false; grid.len()];
    for (k, cells) in comps.iter().enumerate() {
        let centroid = cells.iter().map(|&c| grid.center(c as usize)).sum::<DVec3>() / cells.len() as f64;
        if k > 0 && (cells.len() as f64) < params.min_part_fraction * main_cells as f64 {
            report.parts.push(PartReport {
                cells: cells.len(),
                centroid,
                fate: PartFate::TooSmall,
            });
            continue;
        }
        let seed = seed_cell(&grid, &d2, cells, centroid, mirror.as_ref());
        for &c in cells {
            member[c as usize] = true;
        }
        let part = part_graph(&grid, &d2, &member, cells, seed, params, &mut report.cleanup);
        for &c in cells {
            member[c as usize] = false;
        }
        let fate = join_part(&mut graph, &part, k == 0, join);
        report.parts.push(PartReport {
            cells: cells.len(),
            centroid,
            fate,
        });
    }
    Some((graph, report, solid))
}

/// The cleaned curve graph of one part: its level graph with loops cut (where their
/// sides meet, farthest from the seed), spurs pruned, junctions merged and sunk into
/// the body, shortcuts replaced by medial paths, points smoothed and tips stretched to the surface.
fn part_graph(
    grid: &Grid,
    d2: &[f32],
    member: &[bool],
    cells: &[u32],
    seed: u32,
    params: &VolumeParams,
    cleanup: &mut CleanupReport,
) -> CurveGraph {
    let h = grid.h;
    let levels = level_graph(grid, member, d2, cells, seed, params.band);
    let mut reeb = CurveGraph::default();
    for c in &levels.clusters {
        let p = reeb.add(
            c.position,
            c.radius,
            c.cells as f64 * h * h * h,
            (c.max_distance - c.mean_distance).max(0.0),
        );
        reeb.geodesic[p as usize] = c.mean_distance;
    }
    // Edges in band order: a loop is cut where its two sides meet, farthest from the seed.
    let band = |k: u32| levels.clusters[k as usize].band;
    let cuts = reeb.spanning_forest(&levels.edges, |a, b, w| (band(a).max(band(b)), u32::MAX - w));
    cleanup.loops_cut += cuts.len();
    // The seed's band is a tip of the level graph: its chain to the first split is where
    // the distance started, not a limb.
    if let Some(first) = levels.clusters.iter().position(|c| c.band == 0) {
        cleanup.pruned += usize::from(reeb.remove_stub(first as u32));
    }
    cleanup.pruned += reeb.prune(params.prune_factor, 4);
    cleanup.merged += reeb.merge_junctions(params.merge_factor);
    cleanup.pruned += reeb.prune(params.prune_factor, 4);
    reeb.sink_junctions(4);
    detour_shortcuts(&mut reeb, grid, d2, member);
    reeb.smooth(params.smooth_iterations);
    reeb.stretch_tips();
    reeb
}

/// Adds a part's graph to the skeleton so far: as the main part, as a separate tree,
/// or joined by a bridge to the nearest point.
pub fn join_part(graph: &mut CurveGraph, part: &CurveGraph, first: bool, join: bool) -> PartFate {
    if first || !join || graph.live().next().is_none() {
        graph.append(part);
        return if first { PartFate::Main } else { PartFate::Separate };
    }
    match graph.attach(part) {
        Some((from, to, gap)) => PartFate::Joined { from, to, gap },
        None => PartFate::Separate,
    }
}

/// The part's thickest cell, ties (within 5%) broken by nearness to the part's
/// centroid; on a mirror plane's cells when there is one and the part crosses it.
fn seed_cell(grid: &Grid, d2: &[f32], cells: &[u32], centroid: DVec3, mirror: Option<&Mirror>) -> u32 {
    let on_plane = |c: u32| mirror.is_none_or(|m| m.distance(grid.center(c as usize)).abs() <= grid.h);
    let pool: Vec<u32> = {
        let v: Vec<u32> = cells.iter().copied().filter(|&c| on_plane(c)).collect();
        if v.is_empty() {
            cells.to_vec()
        } else {
            v
        }
    };
    let top = pool.iter().map(|&c| d2[c as usize]).fold(0.0f32, f32::max);
    let limit = top * 0.95 * 0.95;
    pool.iter()
        .copied()
        .filter(|&c| d2[c as usize] >= limit)
        .min_by(|&a, &b| {
            grid.center(a as usize)
                .distance_squared(centroid)
                .total_cmp(&grid.center(b as usize).distance_squared(centroid))
                .then(a.cmp(&b))
        })
        .unwrap_or(cells[0])
}
