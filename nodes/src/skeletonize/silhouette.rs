//! The silhouette method: principal-axes view ([`Frame`]) → silhouette raster with
//! front and back depth ([`Raster`]) → outline loops grouped into parts → chordal
//! axis per part ([`super::chordal_axis`]) → mid-depth lift ([`super::depth`]) → a
//! curve graph, parts joined like the volume method's.
//!
//! One view cannot separate limbs that overlap in it, so this is the method for flat
//! meshes (cards, cut-outs, a star lying in a plane), where it is exact and fast; the
//! automatic choice uses it when the mesh is thinner than 2.5 volume cells.

use super::chordal_axis::{chordal_axis, AxisParams};
use super::curve::CurveGraph;
use super::depth::lift;
use super::extract::{SkeletonizeError, SkeletonizeParams};
use super::outline::parts;
use super::raster::{Frame, Raster};
use super::volume::{join_part, PartFate};
use sinew_core::data::Mesh;

/// The curve graph of `mesh`'s silhouette and the fate of each outline part.
pub fn silhouette_graph(
    mesh: &Mesh,
    params: &SkeletonizeParams,
) -> Result<(CurveGraph, Vec<PartFate>), SkeletonizeError> {
    let frame = Frame::principal(mesh, params.view_axis).ok_or(SkeletonizeError::Degenerate { extent: 0.0 })?;
    let raster = Raster::draw(
        mesh,
        &frame,
        params.silhouette_resolution.clamp(8, 4096),
        params.close_radius,
    )
    .ok_or(SkeletonizeError::Degenerate { extent: 0.0 })?;
    let px = raster.pixel;
    let all = parts(
        &raster,
        params.simplify_tolerance.max(0.0) * px,
        params.min_loop_area.max(0.0) * px * px,
    );
    if all.is_empty() {
        return Err(SkeletonizeError::NoInterior);
    }
    let axis_params = AxisParams {
        prune_factor: params.prune_factor,
        merge_factor: params.merge_factor,
        smooth_iterations: 3 * params.smooth_iterations,
    };
    let main_area = all[0].area;
    let mut graph = CurveGraph::default();
    let mut fates = Vec::new();
    for (k, part) in all.iter().enumerate() {
        if k > 0 && part.area < params.min_part_fraction * main_area {
            fates.push(PartFate::TooSmall);
            continue;
        }
        let axis = lift(
            &chordal_axis(part, &axis_params),
            &raster,
            &frame,
            3 * params.smooth_iterations,
        );
        let mut g = CurveGraph::default();
        let mut id = vec![u32::MAX; axis.points.len()];
        for br in &axis.branches {
            for w in br.windows(2) {
                let [a, b] = [w[0], w[1]].map(|i| {
                    let i = i as usize;
                    if id[i] == u32::MAX {
                        // Mass: a disc of the local half-width over about a pixel of axis.
                        let r = axis.radius[i];
                        id[i] = g.add(axis.points[i], r, std::f64::consts::PI * r * r * px, 0.0);
                    }
                    id[i]
                });
                g.link(a, b);
            }
        }
        if g.live().next().is_none() {
            fates.push(PartFate::TooSmall);
            continue;
        }
        let first = graph.live().next().is_none();
        fates.push(join_part(&mut graph, &g, first, params.join_parts));
    }
    Ok((graph, fates))
}
