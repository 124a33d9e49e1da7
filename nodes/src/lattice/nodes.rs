//! The `lattice` shape and the `ffd` deformer (Maya's lattice deformer: `lattice` +
//! `baseLattice` + `ffd`). The base lattice is any transform: connect its `worldMatrix` to
//! `ffd.baseLatticeMatrix`; the lattice's transform `worldMatrix` goes to
//! `ffd.deformedLatticeMatrix` and the shape's `latticeOutput` to `ffd.deformedLatticePoints`.
//!
//! `lattice`: `sDivisions`, `tDivisions`, `uDivisions` (int, 2, 5, 2: the lattice command's
//! default divisions; 2 to 32 each), `controlPoints` (vec3 array in the lattice's local space,
//! `s` fastest, `S·T·U` of them; empty = the undisturbed grid spanning `[−0.5, 0.5]³`) →
//! `latticeOutput` (object: the [`Lattice`]).
//!
//! `ffd` (besides the shared attributes): `deformedLatticePoints` (object),
//! `deformedLatticeMatrix`, `baseLatticeMatrix` (matrices), `local` (bool, false),
//! `localInfluenceS/T/U` (int, 2), `outsideLattice` (enum `inside`, `all`, `falloff`; default
//! `inside`), `outsideFalloffDist` (float, 1, in base-lattice units), `geomMatrix`.
//!
//! A vertex `p` (object space) goes to base-lattice coordinates
//! `l = baseLatticeMatrix⁻¹ · geomMatrix · p`, `stu = l + ½`, through the trivariate Bernstein
//! map [`evaluate`], and back by `geomMatrix⁻¹ · deformedLatticeMatrix`. `inside`: only vertices
//! inside the base lattice move; `all`: every vertex (the polynomial extended outside);
//! `falloff`: outside vertices within `outsideFalloffDist` of the lattice move by the
//! deformation at the nearest lattice point, faded linearly to 0 at that distance.

use std::cell::RefCell;
use std::sync::Arc;

use glam::{DMat4, Mat4, Vec3};
use sinew_core::{
    AttrId, ComputeContext, ComputeError, Input, NodeSpec, NodeType, ObjectRef, Output, SpecBuilder, SpecError,
};

use super::ffd::{evaluate, evaluate_lanes, Lattice, MAX_DIVISIONS, MAX_LANE_DIVISIONS};
use super::power::{inside, PowerLattice};
use crate::deformer::base::{
    deform_blocks, deform_map, deform_points, finite, finite_matrix, inverse, Affine, Block, BlockMap, Deformer,
    DeformerAttrs, Job, PointMap, LANES,
};

/// `outsideLattice` choices, by index.
pub const OUTSIDE_MODES: [&str; 3] = ["inside", "all", "falloff"];

/// The `lattice` shape node.
pub struct LatticeShape {
    spec: NodeSpec,
    divisions: [Input<i64>; 3],
    points: Input<Arc<Vec<glam::DVec3>>>,
    output: Output<ObjectRef>,
}

impl LatticeShape {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("lattice");
        s.doc("lattice shape: divisions and control points, output for an ffd deformer");
        let divisions = [
            s.input("sDivisions", 2i64),
            s.input("tDivisions", 5i64),
            s.input("uDivisions", 2i64),
        ];
        let points = s.input("controlPoints", Arc::new(Vec::<glam::DVec3>::new()));
        let output = s.output("latticeOutput", ObjectRef::default());
        // Maya's short names (node reference, lattice).
        for (id, short) in divisions.iter().map(|d| d.id()).zip(["sd", "td", "ud"]) {
            s.short_name(id, short);
        }
        s.short_name(output, "lo");
        s.attr_doc(
            points,
            "control points in lattice space, s fastest (empty = undisturbed)",
        )
        .attr_doc(output, "the lattice (connect to ffd.deformedLatticePoints)");
        for (h, axis) in divisions.iter().zip(["s", "t", "u"]) {
            s.attr_doc(
                *h,
                &format!("number of lattice points along {axis} (2 to {MAX_DIVISIONS})"),
            );
        }
        Ok(LatticeShape {
            spec: s.build()?,
            divisions,
            points,
            output,
        })
    }
}

impl NodeType for LatticeShape {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let mut div = [0usize; 3];
        for (d, (h, name)) in div
            .iter_mut()
            .zip(self.divisions.iter().zip(["sDivisions", "tDivisions", "uDivisions"]))
        {
            let v = ctx.get(*h);
            if !(2..=MAX_DIVISIONS as i64).contains(&v) {
                return Err(ComputeError::new(format!(
                    "lattice.{name} is {v}; give 2 to {MAX_DIVISIONS}"
                )));
            }
            *d = v as usize;
        }
        let mut lattice = Lattice::undisturbed(div);
        let points = ctx.get(self.points);
        if !points.is_empty() {
            if points.len() != lattice.points.len() {
                return Err(ComputeError::new(format!(
                    "lattice.controlPoints has {} points but {}×{}×{} divisions need {}",
                    points.len(),
                    div[0],
                    div[1],
                    div[2],
                    lattice.points.len()
                )));
            }
            if let Some(i) = points.iter().position(|p| !p.is_finite()) {
                return Err(ComputeError::new(format!("lattice.controlPoints[{i}] is not finite")));
            }
            lattice.points = points.iter().map(|p| p.as_vec3()).collect();
        }
        ctx.set(self.output, ObjectRef::new(lattice));
        Ok(())
    }
}

/// The ffd kernel of the `inside` and `all` modes, per block and per point (the same
/// operations, so both paths give the same bits).
struct FfdBlock<'a> {
    lattice: &'a Lattice,
    to: Affine,
    back: Affine,
    local: Option<[usize; 3]>,
    /// `all`: vertices outside the base lattice move too (the polynomial extended).
    all: bool,
}

impl BlockMap for FfdBlock<'_> {
    #[inline(always)]
    fn map_block(&self, b: &mut Block) {
        let mut stu = [[0.0f32; LANES]; 3];
        let mut keep = [false; LANES];
        for q in 0..LANES {
            let s = self.to.apply(Vec3::new(b[0][q], b[1][q], b[2][q])) + 0.5;
            keep[q] = !self.all && !inside(s);
            (stu[0][q], stu[1][q], stu[2][q]) = (s.x, s.y, s.z);
        }
        if !evaluate_lanes(self.lattice, &mut stu, self.local) {
            // Local mode with the block across windows: point by point.
            #[allow(clippy::needless_range_loop)] // one lane of each of the three arrays
            for q in 0..LANES {
                let o = self.map(0, Vec3::new(b[0][q], b[1][q], b[2][q]));
                (b[0][q], b[1][q], b[2][q]) = (o.x, o.y, o.z);
            }
            return;
        }
        for q in 0..LANES {
            let o = self.back.apply(Vec3::new(stu[0][q], stu[1][q], stu[2][q]));
            let o = if keep[q] {
                Vec3::new(b[0][q], b[1][q], b[2][q])
            } else {
                o
            };
            (b[0][q], b[1][q], b[2][q]) = (o.x, o.y, o.z);
        }
    }
}

impl PointMap for FfdBlock<'_> {
    #[inline(always)]
    fn map(&self, _: usize, p: Vec3) -> Vec3 {
        let stu = self.to.apply(p) + 0.5;
        if self.all || inside(stu) {
            self.back.apply(evaluate(self.lattice, stu, self.local))
        } else {
            p
        }
    }
}

/// The ffd kernel of the `inside` and `all` modes on the lattice's power form (the fast path:
/// see [`super::power`]), per block and per point (the same operations, so both paths give the
/// same bits).
struct FfdPower<'a> {
    power: &'a PowerLattice,
    to: Affine,
    /// `all`: vertices outside the base lattice move too (the polynomial extended).
    all: bool,
}

impl BlockMap for FfdPower<'_> {
    #[inline(always)]
    fn map_block(&self, b: &mut Block) {
        if !self.power.block(&self.to, self.all, b) {
            // Local mode with the block across windows: point by point.
            #[allow(clippy::needless_range_loop)] // one lane of each of the three arrays
            for q in 0..LANES {
                let o = self.map(0, Vec3::new(b[0][q], b[1][q], b[2][q]));
                (b[0][q], b[1][q], b[2][q]) = (o.x, o.y, o.z);
            }
        }
    }
}

impl PointMap for FfdPower<'_> {
    #[inline(always)]
    fn map(&self, _: usize, p: Vec3) -> Vec3 {
        let stu = self.to.apply(p) + 0.5;
        if self.all || inside(stu) {
            self.power.point(stu)
        } else {
            p
        }
    }
}

thread_local! {
    /// The power form of the lattice being deformed (its buffers reused frame to frame).
    static POWER: RefCell<PowerLattice> = RefCell::new(PowerLattice::default());
}

/// The `ffd` deformer.
pub struct Ffd {
    points: Input<ObjectRef>,
    deformed: Input<DMat4>,
    base: Input<DMat4>,
    local: Input<bool>,
    influence: [Input<i64>; 3],
    outside: Input<i64>,
    falloff: Input<f64>,
    geom: Input<DMat4>,
}

/// One frame of `ffd`.
pub struct FfdFrame {
    /// Per-frame parameter `lattice`.
    pub lattice: ObjectRef,
    /// Per-frame parameter `to`.
    pub to: Mat4,
    /// Per-frame parameter `back`.
    pub back: Mat4,
    /// Per-frame parameter `local`.
    pub local: Option<[usize; 3]>,
    /// Per-frame parameter `outside`.
    pub outside: i64,
    /// Per-frame parameter `falloff`.
    pub falloff: f32,
}

impl Deformer for Ffd {
    type Frame = FfdFrame;

    fn declare(s: &mut SpecBuilder, _base: &DeformerAttrs) -> (Self, Vec<AttrId>) {
        let points = s.input("deformedLatticePoints", ObjectRef::default());
        let deformed = s.input("deformedLatticeMatrix", DMat4::IDENTITY);
        let base = s.input("baseLatticeMatrix", DMat4::IDENTITY);
        let local = s.input("local", false);
        let influence = [
            s.input("localInfluenceS", 2i64),
            s.input("localInfluenceT", 2i64),
            s.input("localInfluenceU", 2i64),
        ];
        let outside = s.input_enum("outsideLattice", &OUTSIDE_MODES, 0);
        let falloff = s.input("outsideFalloffDist", 1.0);
        let geom = s.input("geomMatrix", DMat4::IDENTITY);
        s.attr_doc(points, "the lattice shape's latticeOutput")
            .attr_doc(deformed, "the lattice transform's world matrix")
            .attr_doc(base, "the base lattice's world matrix (the rest lattice)")
            .attr_doc(local, "each vertex uses only the lattice points of its window")
            .attr_doc(outside, "inside: only vertices in the lattice move; all; falloff")
            .attr_doc(falloff, "falloff distance outside the lattice (base lattice units)")
            .attr_doc(geom, "the deformed mesh's world matrix");
        // Maya's short names (node reference, Nodes/ffd.html). outsideLattice `ot`: the
        // stored reference pages stop before it; Maya-written scene files set `setAttr ".ot"
        // 1` on ffd nodes (Maya writes only non-default values: outsideLattice's default is
        // 0, outsideFalloffDist's 1, so `.ot` 1 is outsideLattice = all). outsideFalloffDist
        // has none here: its short name was found in neither.
        s.short_name(outside, "ot");
        s.short_name(points, "dlp")
            .short_name(deformed, "dlm")
            .short_name(base, "blm")
            .short_name(local, "lo")
            .short_name(influence[0], "lis")
            .short_name(influence[1], "lit")
            .short_name(influence[2], "liu");
        s.keyable(points, false);
        let mut ids = vec![
            points.id(),
            deformed.id(),
            base.id(),
            local.id(),
            outside.id(),
            falloff.id(),
            geom.id(),
        ];
        ids.extend(influence.iter().map(|h| h.id()));
        let me = Ffd {
            points,
            deformed,
            base,
            local,
            influence,
            outside,
            falloff,
            geom,
        };
        (me, ids)
    }

    fn prepare(&self, ty: &str, ctx: &ComputeContext<'_>) -> Result<FfdFrame, ComputeError> {
        let g = finite_matrix(ty, "geomMatrix", ctx.get(self.geom))?;
        let dlm = finite_matrix(ty, "deformedLatticeMatrix", ctx.get(self.deformed))?;
        let blm = finite_matrix(ty, "baseLatticeMatrix", ctx.get(self.base))?;
        let to = inverse(ty, "baseLatticeMatrix", blm)? * g;
        let back = inverse(ty, "geomMatrix", g)? * dlm;
        let local = if ctx.get(self.local) {
            let mut li = [0usize; 3];
            for (l, h) in li.iter_mut().zip(self.influence) {
                let v = ctx.get(h);
                if v < 1 {
                    return Err(ComputeError::new(format!(
                        "{ty}.localInfluence is {v}; give at least 1"
                    )));
                }
                *l = v.min(MAX_DIVISIONS as i64) as usize;
            }
            Some(li)
        } else {
            None
        };
        Ok(FfdFrame {
            lattice: ctx.get(self.points),
            to: to.as_mat4(),
            back: back.as_mat4(),
            local,
            outside: ctx.get(self.outside),
            falloff: finite(ty, "outsideFalloffDist", ctx.get(self.falloff))?.max(0.0) as f32,
        })
    }

    fn writes_every_vertex(&self, f: &FfdFrame) -> bool {
        // `deform` leaves the output alone only without a lattice (or fails on a bad one).
        f.lattice.downcast::<Lattice>().is_some()
    }

    fn deform(&self, ty: &str, f: &FfdFrame, job: Job<'_>) -> Result<(), ComputeError> {
        if f.lattice.is_empty() {
            return Ok(());
        }
        let Some(lattice) = f.lattice.downcast::<Lattice>() else {
            return Err(ComputeError::new(format!(
                "{ty}.deformedLatticePoints is not a lattice; connect lattice.latticeOutput"
            )));
        };
        let (to, back, local) = (Affine::new(f.to), Affine::new(f.back), f.local);
        let (pos, out, m, env) = (&job.input.positions, job.out, job.membership, job.envelope);
        if f.outside == 2 {
            let d = f.falloff;
            deform_points(pos, out, m, env, |_, p| {
                let stu = to.apply(p) + 0.5;
                if inside(stu) {
                    return back.apply(evaluate(lattice, stu, local));
                }
                let c = stu.clamp(Vec3::ZERO, Vec3::ONE);
                let dist = stu.distance(c);
                if dist >= d {
                    return p;
                }
                let moved = back.apply(stu - 0.5 + (evaluate(lattice, c, local) - (c - 0.5)));
                p + (moved - p) * (1.0 - dist / d)
            });
            return Ok(());
        }
        if PowerLattice::fits(lattice, local) {
            POWER.with(|cell| {
                let mut power = cell.borrow_mut();
                power.prepare(lattice, local, &back);
                let block = FfdPower {
                    power: &power,
                    to,
                    all: f.outside == 1,
                };
                let point = |p| block.map(0, p);
                if m.sparse.is_some() || !power.dense(&to, block.all, pos, out, env, &point) {
                    deform_blocks(pos, out, m, env, &block, &block);
                }
            });
            return Ok(());
        }
        let block = FfdBlock {
            lattice,
            to,
            back,
            local,
            all: f.outside == 1,
        };
        if lattice.divisions.iter().any(|&d| d > MAX_LANE_DIVISIONS) {
            deform_map(pos, out, m, env, &block);
        } else {
            // Every vertex active: blocks of LANES vertices.
            deform_blocks(pos, out, m, env, &block, &block);
        }
        Ok(())
    }
}
