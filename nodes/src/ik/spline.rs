//! ikSpline: a joint chain laid along a curve, with roll, twist and stretch.
//!
//! Curves are evaluated by [`super::curve`].
//!
//! # Placement
//!
//! Joints start at arc length `offset` from the curve start (periodic curves wrap).
//! Without stretch each next joint is the first point further along the curve at
//! exactly the rest bone length (chord) from the previous one, so bones keep their
//! lengths and every joint lies on the curve; joints that run past the end of an open
//! curve continue straight along its end tangent (status Unreachable, `error` = the
//! chain length past the end). With `stretch`, joints sit at arc lengths
//! `offset + s * cumulative_rest_length` with `s = remaining_arc / chain_length`
//! (capped at `max_stretch`; shorter curves squash), and `bone_scale` reports each
//! bone's chord over its rest length.
//!
//! # Orientation
//!
//! Each joint aims its rest bone direction at the next joint with the minimal rotation
//! from its carried rest frame (a discrete parallel-transport frame: no twist beyond
//! what the curve's bending forces). Then `roll` spins the start joint about its bone
//! axis (carrying the whole chain), and `twist` is spread linearly: joint `i` of `n`
//! bones adds `twist / n` about its own bone axis, so the end joint carries
//! `roll + twist` in total. The end joint keeps its preferred rotation plus its twist
//! share (its axis is the last bone's).
//!
//! # Root
//!
//! With `root_on_curve` the start joint moves onto the curve: `root_translate` is the
//! start joint's new local translate (chain space is its parent space), for the plugin
//! to connect to `translate`. Without it the root stays and the curve is used as if
//! shifted rigidly so that its offset point sits on the root.
//!
//! The curve is given in world space (like Maya's `worldSpace[0]`) and mapped into
//! chain space before anything is measured.

use glam::{DQuat, DVec3};

use super::chain::{Chain, IkError, IkSolution, IkStatus, Prepared, EPS};
pub use super::curve::{ArcLengthTable, BSpline, Curve, CurveForm};
use super::rest_memo::RestMemo;

/// Spline IK settings (ikHandle offset, roll, twist and stretch).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SplineParams {
    /// Arc length along the curve where the start joint sits (Maya's 0–1 `offset` times the curve length).
    pub offset: f64,
    /// Rotation of the whole chain about the start joint's bone axis, radians.
    pub roll: f64,
    /// Twist added linearly from start (0) to end joint (`twist`), radians.
    pub twist: f64,
    /// Stretch (or squash) the bones so the chain spans the curve from `offset` to its end.
    pub stretch: bool,
    /// Cap on the stretch factor (`f64::INFINITY` = none).
    pub max_stretch: f64,
    /// Move the start joint onto the curve (see `SplineSolution::root_translate`).
    pub root_on_curve: bool,
}

impl Default for SplineParams {
    fn default() -> Self {
        SplineParams {
            offset: 0.0,
            roll: 0.0,
            twist: 0.0,
            stretch: false,
            max_stretch: f64::INFINITY,
            root_on_curve: true,
        }
    }
}

/// Spline IK result: rotations and stretch, plus the start joint's new translate.
#[derive(Clone, Debug, PartialEq)]
pub struct SplineSolution {
    /// Rotations, bone scales and status (`iterations` is 0).
    pub solution: IkSolution,
    /// The start joint's local translate (its rest translate unless `root_on_curve`).
    pub root_translate: DVec3,
    /// Per joint, the curve parameter it sits at, or `None` past the end of the curve.
    pub curve_params: Vec<Option<f64>>,
    /// Arc length of the curve in chain space.
    pub curve_length: f64,
}

/// ikSpline: lays the chain along `curve` (world space) and returns joint rotations.
pub fn solve_spline(chain: &Chain, curve: &Curve, params: &SplineParams) -> SplineSolution {
    let mut scratch = SplineScratch::default();
    let mut solution = IkSolution::empty();
    let (root_translate, curve_length) = solve_spline_into(chain, curve, params, &mut scratch, &mut solution, true);
    SplineSolution {
        solution,
        root_translate,
        curve_params: scratch.cparams,
        curve_length,
    }
}

/// Reusable buffers of [`solve_spline_into`] (refilled on every call; what is kept is a memo of a pure
/// function, so nothing carries over into results).
#[derive(Debug)]
pub(super) struct SplineScratch {
    prep: Prepared,
    /// The chains' rest data, the one thing kept from call to call (a memo of a pure function).
    rest: RestMemo,
    spline: BSpline,
    table: ArcLengthTable,
    pos: Vec<DVec3>,
    twist: Vec<f64>,
    /// Per joint the curve parameter it sits at (`SplineSolution::curve_params`).
    pub cparams: Vec<Option<f64>>,
}

impl Default for SplineScratch {
    fn default() -> Self {
        SplineScratch {
            prep: Prepared::default(),
            rest: RestMemo::default(),
            spline: BSpline::empty(),
            table: ArcLengthTable::empty(),
            pos: Vec::new(),
            twist: Vec::new(),
            cparams: Vec::new(),
        }
    }
}

/// [`solve_spline`] into reused buffers: the solution goes to `out` and the curve
/// parameters to `s.cparams`; returns `(root_translate, curve_length)`. Same results as
/// [`solve_spline`], bit for bit, except that without `want_length` the curve length is
/// summed only when the solve needs it (a periodic curve, a positive offset, stretch) and
/// is NaN otherwise (still 0 when the input is invalid).
pub(super) fn solve_spline_into(
    chain: &Chain,
    curve: &Curve,
    params: &SplineParams,
    s: &mut SplineScratch,
    out: &mut IkSolution,
    want_length: bool,
) -> (DVec3, f64) {
    let SplineScratch {
        prep,
        rest,
        spline,
        table,
        pos,
        twist,
        cparams,
    } = s;
    let mut fail = |e: IkError| {
        *out = IkSolution::invalid(chain, e);
        cparams.clear();
        cparams.resize(chain.joints.len(), None);
        (chain.joints.first().map_or(DVec3::ZERO, |j| j.translate), 0.0)
    };
    let rest = match rest.refill(prep, chain) {
        Ok(rest) => rest,
        Err(e) => return fail(e),
    };
    let finite = [params.offset, params.roll, params.twist].iter().all(|x| x.is_finite());
    if !finite || params.max_stretch.is_nan() {
        return fail(IkError::NonFinite("spline parameters"));
    }
    let n = prep.joints.len();
    if n < 2 {
        return fail(IkError::JointCount {
            needed: "at least 2",
            got: n,
        });
    }
    let to_chain = prep.to_chain;
    if let Err(msg) = spline.rebuild(curve, |q| to_chain.transform_point3(q)) {
        return fail(IkError::Curve(msg));
    }
    let spline = &*spline;
    // The samples first; their cumulative lengths only when something below reads them (the
    // chord placement reads the samples alone): the zero-length test needs them only when the
    // samples cannot tell (`longer_than`), an offset of 0 starts at the first sample.
    table.rebuild_points(spline);
    if !table.longer_than(EPS) {
        return fail(IkError::Curve("the curve has zero length".into()));
    }
    let lengths = &rest.lengths;
    let chain_len: f64 = lengths.iter().sum();
    let stretch = params.stretch && chain_len > EPS;
    if want_length || spline.is_periodic() || params.offset > 0.0 || stretch {
        table.fill_lengths();
    }
    let table = &*table;
    let total = if table.has_lengths() { table.total() } else { f64::NAN };
    let start_s = if spline.is_periodic() {
        params.offset.rem_euclid(total)
    } else if params.offset > 0.0 {
        params.offset.clamp(0.0, total)
    } else {
        // `offset.clamp(0.0, total)` for `offset <= 0` and a total above 0 (either zero's sign kept).
        params.offset.clamp(0.0, f64::INFINITY)
    };
    let t0 = table.param_at(start_s);
    let c0 = spline.point(t0);
    let shift = if params.root_on_curve {
        DVec3::ZERO
    } else {
        prep.joints[0].translate - c0
    };
    pos.clear();
    pos.push(c0 + shift);
    cparams.clear();
    cparams.push(Some(t0));
    let bone_scale = &mut out.bone_scale;
    bone_scale.clear();
    bone_scale.resize(n, 1.0);
    let mut overrun = 0.0;
    if stretch {
        let remaining = if spline.is_periodic() { total } else { total - start_s };
        let s = (remaining / chain_len).min(params.max_stretch.max(0.0));
        let mut acc = start_s;
        for (i, l) in lengths.iter().enumerate() {
            acc += l * s;
            let arc = if spline.is_periodic() {
                acc.rem_euclid(total)
            } else {
                acc.min(total)
            };
            let t = table.param_at(arc);
            let q = spline.point(t) + shift;
            bone_scale[i] = if *l > EPS { q.distance(pos[i]) / l } else { 1.0 };
            pos.push(q);
            cparams.push(Some(t));
        }
    } else {
        let mut t = t0;
        let mut off_curve = false;
        for l in lengths.iter() {
            let prev = pos[pos.len() - 1] - shift;
            let next = if off_curve {
                None
            } else {
                next_on_curve(spline, table, t, prev, *l)
            };
            match next {
                Some((tn, point)) => {
                    t = tn;
                    // The point `chord_root` evaluated at `tn`, when it did (the same bits).
                    pos.push(point.unwrap_or_else(|| spline.point(tn)) + shift);
                    cparams.push(Some(spline.normalize_param(tn)));
                }
                None => {
                    let (q, end) = extrapolate(spline, t, prev, *l, pos);
                    overrun += match end {
                        Some(end) if !off_curve => q.distance(end),
                        _ => *l,
                    };
                    off_curve = true;
                    pos.push(q + shift);
                    cparams.push(None);
                }
            }
        }
    }
    // The solved chain: the root on the curve, bones stretched (in place: `prep` is refilled
    // on every call).
    prep.joints[0].translate = pos[0];
    for i in 1..n {
        prep.joints[i].translate *= bone_scale[i - 1];
    }
    twist.clear();
    twist.resize(n, params.twist / (n - 1) as f64);
    twist[0] = params.roll;
    prep.rotations_from_positions_into(pos, DQuat::IDENTITY, DVec3::ZERO, Some(twist), n, &mut out.rotations);
    out.status = if overrun > 0.0 {
        IkStatus::Unreachable
    } else {
        IkStatus::Reached
    };
    out.iterations = 0;
    out.error = overrun;
    (pos[0], total)
}

/// First parameter after `t` whose curve point is exactly `len` from `from`; `None` if the
/// curve ends (or, periodic, loops once) first. With the parameter comes its curve point
/// `spline.point(parameter)` when [`chord_root`] evaluated it (else `None`).
///
/// The table's stored sample points bracket the crossing (no curve evaluation), then
/// [`chord_root`] pins it down.
pub(super) fn next_on_curve(
    spline: &BSpline,
    table: &ArcLengthTable,
    t: f64,
    from: DVec3,
    len: f64,
) -> Option<(f64, Option<DVec3>)> {
    if len <= EPS {
        return Some((t, None));
    }
    let (a, b) = spline.domain();
    let period = b - a;
    let (laps, base) = if spline.is_periodic() {
        (2, (t - a).div_euclid(period) * period)
    } else {
        (1, 0.0)
    };
    let mut lo = t;
    let mut f_lo = -len;
    let (params, points) = (table.params(), table.points());
    for lap in 0..laps {
        // The samples the scan would skip at the start of the first lap (`hi <= lo`) form a
        // prefix (the parameters increase): jump over it.
        let first = if lap == 0 {
            params.partition_point(|&s| s + base + lap as f64 * period <= lo)
        } else {
            0
        };
        for (&s, q) in params[first..].iter().zip(&points[first..]) {
            let hi = s + base + lap as f64 * period;
            if hi <= lo {
                continue;
            }
            if hi > t + period {
                return None;
            }
            let f_hi = q.distance(from) - len;
            if f_hi >= 0.0 {
                return Some(chord_root(spline, from, len, (lo, f_lo), (hi, f_hi)));
            }
            (lo, f_lo) = (hi, f_hi);
        }
    }
    None
}

/// A parameter in `[lo, hi]` where `|C(x) - from| = len`, given `f(lo) < 0 <= f(hi)` for
/// `f(x) = |C(x) - from| - len`: Illinois (modified regula falsi), which keeps the bracket
/// and converges superlinearly, falling back to bisection when a step leaves the bracket.
/// Stops when `|f|` is within a few ulps of `len` or the bracket cannot shrink; returns
/// the bracket end with `f >= 0` unless an interior point hit the tolerance. With the
/// parameter comes `spline.point(parameter)` when it was evaluated here (`None` for the
/// given `hi`, whose point is the caller's), so the caller need not evaluate it again.
fn chord_root(spline: &BSpline, from: DVec3, len: f64, lo: (f64, f64), hi: (f64, f64)) -> (f64, Option<DVec3>) {
    let tol = len * 4.0 * f64::EPSILON;
    let ((mut x0, mut f0), (mut x1, mut f1)) = (lo, hi);
    let mut p1 = None;
    if f1 <= tol {
        return (x1, p1);
    }
    let mut last_side = 0i8;
    for _ in 0..200 {
        let mut x = x1 - f1 * (x1 - x0) / (f1 - f0);
        if !(x > x0 && x < x1) {
            x = 0.5 * (x0 + x1);
            if x <= x0 || x >= x1 {
                break;
            }
        }
        let px = spline.point(x);
        let fx = px.distance(from) - len;
        if fx.abs() <= tol {
            return (x, Some(px));
        }
        if fx >= 0.0 {
            (x1, f1, p1) = (x, fx, Some(px));
            if last_side == 1 {
                f0 *= 0.5;
            }
            last_side = 1;
        } else {
            (x0, f0) = (x, fx);
            if last_side == -1 {
                f1 *= 0.5;
            }
            last_side = -1;
        }
    }
    (x1, p1)
}

/// Places a joint `len` from `prev` past the end of an open curve, on the line through
/// the curve's end along its end tangent; for periodic curves (no chord found within a
/// loop), along the tangent at `t`. Returns the joint and, for an open curve, the curve's end
/// point `spline.point(spline.domain().1)` it used (`None` for a periodic curve).
fn extrapolate(spline: &BSpline, t: f64, prev: DVec3, len: f64, pos: &[DVec3]) -> (DVec3, Option<DVec3>) {
    let back = if pos.len() >= 2 {
        pos[pos.len() - 1] - pos[pos.len() - 2]
    } else {
        DVec3::ZERO
    };
    let tangent_at = |t: f64| {
        spline
            .derivative(t)
            .try_normalize()
            .or_else(|| back.try_normalize())
            .unwrap_or(DVec3::X)
    };
    if spline.is_periodic() {
        return (prev + tangent_at(t) * len, None);
    }
    let end_t = spline.domain().1;
    let end = spline.point(end_t);
    let dir = tangent_at(end_t);
    // Solve |end + dir * x - prev| = len for the larger root x (prev is within len of the end).
    let q = end - prev;
    let b = q.dot(dir);
    let disc = (b * b - q.length_squared() + len * len).max(0.0);
    (end + dir * (-b + disc.sqrt()).max(0.0), Some(end))
}
