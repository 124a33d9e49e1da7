//! Geometry inputs with their evaluator precomputed: a node reading a curve or surface
//! declares the input and an object output holding the validated evaluator, computed in its
//! own group from the geometry alone. An animated parameter then re-evaluates only the
//! query; the evaluator (and a curve's arc-length table) is rebuilt only when the geometry
//! changes. Invalid geometry is kept as its message and reported by the query.

use std::sync::Arc;

use sinew_core::{ComputeContext, ComputeError, Curve, Input, ObjectRef, Output, SpecBuilder, Surface};

use super::curve_eval::CurveEval;
use super::surface_eval::SurfaceEval;

/// What a cache output holds: the evaluator, `None` for geometry without control points, or
/// the validation message.
type Cached<T> = Result<Option<T>, String>;

/// A curve input and its evaluator output.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CurveIn {
    /// The curve.
    pub curve: Input<Arc<Curve>>,
    /// Its [`CurveEval`] (object).
    pub cache: Output<ObjectRef>,
    lengths: bool,
}

impl CurveIn {
    /// Declares input `name` and the object output `curveCache`, which depends on it alone;
    /// `lengths` builds the arc-length table too.
    pub fn declare(b: &mut SpecBuilder, name: &str, doc: &str, lengths: bool) -> Self {
        let curve = b.input(name, Arc::new(Curve::default()));
        let cache = b.output("curveCache", ObjectRef::default());
        b.attr_doc(curve, doc).attr_doc(
            cache,
            "the validated curve, ready to evaluate (rebuilt when the curve changes)",
        );
        b.affects(&[curve.id()], &[cache.id()]);
        CurveIn { curve, cache, lengths }
    }

    /// Computes the cache when asked; true when it did (the compute is then done).
    pub fn compute(&self, ctx: &mut ComputeContext<'_>) -> bool {
        if !ctx.wants(self.cache) {
            return false;
        }
        let c = ctx.get(self.curve);
        let value: Cached<CurveEval> = if c.points.is_empty() {
            Ok(None)
        } else {
            CurveEval::new(&c).map(|e| Some(if self.lengths { e.with_lengths() } else { e }))
        };
        ctx.set(self.cache, ObjectRef::new(value));
        true
    }

    /// The cache object (read it with [`curve_of`]).
    pub fn get(&self, ctx: &ComputeContext<'_>) -> ObjectRef {
        ctx.get_output(self.cache)
    }
}

/// The evaluator in a curve cache: `None` for a curve without points; an error naming `what`
/// for an invalid one.
pub(crate) fn curve_of<'a>(obj: &'a ObjectRef, what: &str) -> Result<Option<&'a CurveEval>, ComputeError> {
    match obj.downcast::<Cached<CurveEval>>() {
        Some(Ok(c)) => Ok(c.as_ref()),
        Some(Err(e)) => Err(ComputeError::new(format!("{what}: {e}"))),
        None => Ok(None),
    }
}

/// A surface input and its evaluator output.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SurfaceIn {
    /// The surface.
    pub surface: Input<Arc<Surface>>,
    /// Its [`SurfaceEval`] (object).
    pub cache: Output<ObjectRef>,
}

impl SurfaceIn {
    /// Declares input `name` and the object output `surfaceCache`, which depends on it alone.
    pub fn declare(b: &mut SpecBuilder, name: &str, doc: &str) -> Self {
        let surface = b.input(name, Arc::new(Surface::default()));
        let cache = b.output("surfaceCache", ObjectRef::default());
        b.attr_doc(surface, doc).attr_doc(
            cache,
            "the validated surface, ready to evaluate (rebuilt when the surface changes)",
        );
        b.affects(&[surface.id()], &[cache.id()]);
        SurfaceIn { surface, cache }
    }

    /// Computes the cache when asked; true when it did (the compute is then done).
    pub fn compute(&self, ctx: &mut ComputeContext<'_>) -> bool {
        if !ctx.wants(self.cache) {
            return false;
        }
        let s = ctx.get(self.surface);
        let value: Cached<SurfaceEval> = if s.points.is_empty() && s.count_u == 0 && s.count_v == 0 {
            Ok(None)
        } else {
            SurfaceEval::new(&s).map(Some)
        };
        ctx.set(self.cache, ObjectRef::new(value));
        true
    }

    /// The cache object (read it with [`surface_of`]).
    pub fn get(&self, ctx: &ComputeContext<'_>) -> ObjectRef {
        ctx.get_output(self.cache)
    }
}

/// The evaluator in a surface cache (see [`curve_of`]).
pub(crate) fn surface_of<'a>(obj: &'a ObjectRef, what: &str) -> Result<Option<&'a SurfaceEval>, ComputeError> {
    match obj.downcast::<Cached<SurfaceEval>>() {
        Some(Ok(c)) => Ok(c.as_ref()),
        Some(Err(e)) => Err(ComputeError::new(format!("{what}: {e}"))),
        None => Ok(None),
    }
}
