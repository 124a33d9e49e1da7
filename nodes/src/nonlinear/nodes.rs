//! The nonLinear node types: the handle shapes `deformBend`, `deformTwist`, `deformSquash`,
//! `deformFlare`, `deformSine`, `deformWave` (Maya's `deformFunc` shapes: they hold the
//! parameters and output `deformerData`), and the `nonLinear` deformer that applies one to a
//! mesh in the handle's space.
//!
//! `nonLinear` attributes (besides the shared ones): `deformerData` (object: connect the
//! handle shape's `deformerData`), `matrix` (the handle transform's world matrix: the
//! deformer axis is its Y axis, its origin the handle centre), `geomMatrix` (the mesh's world
//! matrix). Each vertex goes to handle space (`matrix⁻¹ · geomMatrix`), through the function,
//! and back. Handle shapes' parameters are in [`PARAMS`] with Maya's names and defaults
//! (angles in degrees); `highBound` below `lowBound`, `maxRadius` below `minRadius`, a zero
//! `wavelength` or a `maxExpandPos` outside (0, 1) are errors naming the attribute.

use glam::{DMat4, Mat4, Vec3};
use sinew_core::{
    AttrId, ComputeContext, ComputeError, Input, NodeSpec, NodeType, ObjectRef, Output, Registry, SpecBuilder,
    SpecError, Unit,
};

use super::funcs::{BendFn, FlareFn, Func, PointFn, SineFn, SquashFn, TwistFn, WaveFn};
use crate::deformer::base::{
    deform_map, finite, finite_matrix, handle_space, Affine, Deformer, DeformerAttrs, Job, PointMap,
};
use crate::deformer::DeformerNode;

/// A handle shape parameter: (attribute, default, whether it is an angle in degrees).
pub type Param = (&'static str, f64, bool);

/// Each handle shape's parameters: (node type, its parameters).
pub const PARAMS: [(&str, &[Param]); 6] = [
    (
        "deformBend",
        &[
            ("lowBound", -1.0, false),
            ("highBound", 1.0, false),
            ("curvature", 0.0, true),
        ],
    ),
    (
        "deformTwist",
        &[
            ("lowBound", -1.0, false),
            ("highBound", 1.0, false),
            ("startAngle", 0.0, true),
            ("endAngle", 0.0, true),
        ],
    ),
    (
        "deformSquash",
        &[
            ("lowBound", -1.0, false),
            ("highBound", 1.0, false),
            ("factor", 0.0, false),
            ("expand", 1.0, false),
            ("maxExpandPos", 0.5, false),
            ("startSmoothness", 0.0, false),
            ("endSmoothness", 0.0, false),
        ],
    ),
    (
        "deformFlare",
        &[
            ("lowBound", -1.0, false),
            ("highBound", 1.0, false),
            ("startFlareX", 1.0, false),
            ("startFlareZ", 1.0, false),
            ("endFlareX", 1.0, false),
            ("endFlareZ", 1.0, false),
            ("curve", 0.0, false),
        ],
    ),
    (
        "deformSine",
        &[
            ("lowBound", -1.0, false),
            ("highBound", 1.0, false),
            ("amplitude", 0.0, false),
            ("wavelength", 2.0, false),
            ("offset", 0.0, false),
            ("dropoff", 0.0, false),
        ],
    ),
    (
        "deformWave",
        &[
            ("minRadius", 0.0, false),
            ("maxRadius", 1.0, false),
            ("amplitude", 0.0, false),
            ("wavelength", 1.0, false),
            ("offset", 0.0, false),
            ("dropoff", 0.0, false),
            ("dropoffPosition", 0.0, false),
        ],
    ),
];

/// Maya's short names of the handle shapes' attributes, as Maya's node reference lists them
/// (`deformSquash`'s `factor` has none here: its short name was not in the reference at hand).
pub const SHORT_NAMES: [&[(&str, &str)]; 6] = [
    &[("lowBound", "lb"), ("highBound", "hb"), ("curvature", "cur")],
    &[
        ("lowBound", "lb"),
        ("highBound", "hb"),
        ("startAngle", "sa"),
        ("endAngle", "ea"),
    ],
    &[
        ("lowBound", "lb"),
        ("highBound", "hb"),
        ("startSmoothness", "ss"),
        ("endSmoothness", "es"),
        ("maxExpandPos", "mp"),
        ("expand", "exp"),
    ],
    &[
        ("lowBound", "lb"),
        ("highBound", "hb"),
        ("startFlareX", "sfx"),
        ("startFlareZ", "sfz"),
        ("endFlareX", "efx"),
        ("endFlareZ", "efz"),
        ("curve", "crv"),
    ],
    &[
        ("lowBound", "lb"),
        ("highBound", "hb"),
        ("amplitude", "amp"),
        ("wavelength", "wav"),
        ("offset", "off"),
        ("dropoff", "dr"),
    ],
    &[
        ("minRadius", "mnr"),
        ("maxRadius", "mxr"),
        ("amplitude", "amp"),
        ("wavelength", "wav"),
        ("offset", "off"),
        ("dropoff", "dr"),
        ("dropoffPosition", "dp"),
    ],
];

/// A handle shape node (`deformBend` ...): parameters in, `deformerData` out.
pub struct DeformFunc {
    spec: NodeSpec,
    kind: usize,
    params: Vec<Input<f64>>,
    data: Output<ObjectRef>,
}

impl DeformFunc {
    /// The handle shape `PARAMS[kind]`.
    pub fn new(kind: usize) -> Result<Self, SpecError> {
        let (name, params) = PARAMS[kind];
        let mut s = NodeSpec::builder(name);
        s.doc("nonLinear handle shape: its parameters as deformerData for a nonLinear deformer");
        let mut ins = Vec::new();
        for &(p, default, angle) in params {
            let h = s.input(p, default);
            if angle {
                s.unit(h, Unit::Degrees);
            }
            ins.push(h);
        }
        let data = s.output("deformerData", ObjectRef::default());
        s.maya_names(SHORT_NAMES[kind]);
        s.attr_doc(
            data,
            "the function and its parameters (connect to nonLinear.deformerData)",
        );
        Ok(DeformFunc {
            spec: s.build()?,
            kind,
            params: ins,
            data,
        })
    }

    fn func(&self, ctx: &ComputeContext<'_>) -> Result<Func, ComputeError> {
        let (ty, names) = PARAMS[self.kind];
        let mut v = [0.0f32; 8];
        for (k, (&h, &(name, _, angle))) in self.params.iter().zip(names).enumerate() {
            let x = finite(ty, name, ctx.get(h))?;
            v[k] = if angle { x.to_radians() } else { x } as f32;
        }
        let err = |m: String| Err(ComputeError::new(format!("{ty}.{m}")));
        if v[1] < v[0] {
            let (lo, hi) = (names[0].0, names[1].0);
            return err(format!("{hi} ({}) is below {lo} ({}); make {hi} >= {lo}", v[1], v[0]));
        }
        let [a, b, c, d, e, f, g, _] = v;
        Ok(match self.kind {
            0 => Func::Bend { lb: a, hb: b, k: c },
            1 => Func::Twist {
                lb: a,
                hb: b,
                a0: c,
                a1: d,
            },
            2 => {
                if !(e > 0.0 && e < 1.0) {
                    return err(format!(
                        "maxExpandPos is {e}; give a value between 0 and 1 (Maya: 0.01 to 0.99)"
                    ));
                }
                let factor = if c >= 0.0 { 1.0 + c } else { 1.0 / (1.0 - c) };
                Func::Squash {
                    lb: a,
                    hb: b,
                    f: factor,
                    expand: d,
                    m: e,
                    ss: f,
                    es: g,
                }
            }
            3 => Func::Flare {
                lb: a,
                hb: b,
                start: [c, d],
                end: [e, f],
                curve: g,
            },
            _ => {
                if d == 0.0 {
                    return err("wavelength is 0; give a non-zero wavelength".into());
                }
                if self.kind == 4 {
                    Func::Sine {
                        lb: a,
                        hb: b,
                        amplitude: c,
                        wavelength: d,
                        offset: e,
                        dropoff: f,
                    }
                } else {
                    if !(0.0..=1.0).contains(&g) {
                        return err(format!("dropoffPosition is {g}; give a value from 0 to 1"));
                    }
                    Func::Wave {
                        r0: a,
                        r1: b,
                        amplitude: c,
                        wavelength: d,
                        offset: e,
                        dropoff: f,
                        dropoff_position: g,
                    }
                }
            }
        })
    }
}

impl NodeType for DeformFunc {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let f = self.func(ctx)?;
        ctx.set(self.data, ObjectRef::new(f));
        Ok(())
    }
}

/// The `nonLinear` deformer.
pub struct NonLinear {
    data: Input<ObjectRef>,
    matrix: Input<DMat4>,
    geom: Input<DMat4>,
}

/// One frame of `nonLinear`: the function and the space changes.
pub struct NonLinearFrame {
    /// Per-frame parameter `func`.
    pub func: Option<Func>,
    /// Per-frame parameter `to`.
    pub to: Mat4,
    /// Per-frame parameter `back`.
    pub back: Mat4,
}

impl Deformer for NonLinear {
    type Frame = NonLinearFrame;

    fn declare(s: &mut SpecBuilder, _base: &DeformerAttrs) -> (Self, Vec<AttrId>) {
        // Maya's nonLinear short names (node reference, *nonLinear*).
        s.maya_names(&[("deformerData", "dd"), ("matrix", "ma")]);
        let data = s.input("deformerData", ObjectRef::default());
        let matrix = s.input("matrix", DMat4::IDENTITY);
        let geom = s.input("geomMatrix", DMat4::IDENTITY);
        s.attr_doc(data, "the handle shape's deformerData (deformBend, deformTwist ...)")
            .attr_doc(matrix, "the handle's world matrix (the deformer axis is its Y axis)")
            .attr_doc(geom, "the deformed mesh's world matrix");
        s.keyable(data, false);
        // Maya's short names (node reference, Nodes/nonLinear.html).
        s.short_name(data, "dd").short_name(matrix, "ma");
        (
            NonLinear { data, matrix, geom },
            vec![data.id(), matrix.id(), geom.id()],
        )
    }

    fn prepare(&self, ty: &str, ctx: &ComputeContext<'_>) -> Result<NonLinearFrame, ComputeError> {
        let data = ctx.get(self.data);
        let func = if data.is_empty() {
            None
        } else {
            Some(*data.downcast::<Func>().ok_or_else(|| {
                ComputeError::new(format!("{ty}.deformerData is not a handle shape's; connect deformBend.deformerData (or twist, squash, flare, sine, wave)"))
            })?)
        };
        let handle = finite_matrix(ty, "matrix", ctx.get(self.matrix))?;
        let geom = finite_matrix(ty, "geomMatrix", ctx.get(self.geom))?;
        let (to, back) = handle_space(ty, handle, geom)?;
        Ok(NonLinearFrame { func, to, back })
    }

    fn writes_every_vertex(&self, f: &NonLinearFrame) -> bool {
        // `deform` returns early, leaving the output as it is, exactly in these two cases.
        !matches!(f.func, None | Some(Func::Bend { k: 0.0, .. }))
    }

    fn deform(&self, _ty: &str, f: &NonLinearFrame, job: Job<'_>) -> Result<(), ComputeError> {
        let Some(func) = f.func else {
            return Ok(());
        };
        if let Func::Bend { k: 0.0, .. } = func {
            return Ok(());
        }
        let (to, back) = (Affine::new(f.to), Affine::new(f.back));
        let (pos, out, m, env) = (&job.input.positions, job.out, job.membership, job.envelope);
        let tau = std::f32::consts::TAU;
        macro_rules! run {
            ($f:expr) => {
                deform_map(pos, out, m, env, &InHandle { to, back, f: $f })
            };
        }
        match func {
            // Bend and twist skip the trigonometric range reduction when the frame's angles lie
            // in a short range (the usual case).
            Func::Bend { k, lb, hb } => match BendFn::new(k, lb, hb).near() {
                Some(f) => run!(f),
                None => run!(BendFn::new(k, lb, hb)),
            },
            Func::Twist { lb, hb, a0, a1 } => match TwistFn::new(lb, hb, a0, a1).near() {
                Some(f) => run!(f),
                None => run!(TwistFn::new(lb, hb, a0, a1)),
            },
            Func::Squash {
                lb,
                hb,
                f,
                expand,
                m,
                ss,
                es,
            } => run!(SquashFn::new(lb, hb, f, expand, m, ss, es)),
            Func::Flare {
                lb,
                hb,
                start,
                end,
                curve,
            } => run!(FlareFn::new(lb, hb, start, end, curve)),
            Func::Sine {
                lb,
                hb,
                amplitude,
                wavelength,
                offset,
                dropoff,
            } => {
                // The sine moves points along the handle's X axis by an amount that depends on
                // their handle-space height only: `p + X · shift(y)` (X the handle's X axis in
                // object space) rather than a round trip through handle space.
                let (t, b) = (f.to.to_cols_array(), f.back.to_cols_array());
                let map = AlongX {
                    height: [t[1], t[5], t[9], t[13]],
                    axis: Vec3::new(b[0], b[1], b[2]),
                    f: SineFn::new(lb, hb, amplitude, tau / wavelength, offset, dropoff),
                };
                deform_map(pos, out, m, env, &map)
            }
            Func::Wave {
                r0,
                r1,
                amplitude,
                wavelength,
                offset,
                dropoff,
                dropoff_position: 0.0,
            } => run!(WaveFn::new(r0, r1, amplitude, tau / wavelength, offset, dropoff)),
            Func::Wave {
                r0,
                r1,
                amplitude,
                wavelength,
                offset,
                dropoff,
                dropoff_position,
            } => run!(WaveFn::<true>::with_position(
                r0,
                r1,
                amplitude,
                tau / wavelength,
                offset,
                dropoff,
                dropoff_position
            )),
        }
        Ok(())
    }
}

/// A function in handle space, as a point map (inlined into the vertex loop).
struct InHandle<F> {
    to: Affine,
    back: Affine,
    f: F,
}

impl<F: PointFn> PointMap for InHandle<F> {
    #[inline(always)]
    fn map(&self, _: usize, p: Vec3) -> Vec3 {
        self.back.apply(self.f.apply(self.to.apply(p)))
    }
}

/// The sine as a point map: the handle-space height of a point (a row of `to`) gives its
/// shift along the handle's X axis in object space (`axis`, the first column of `back`).
struct AlongX {
    height: [f32; 4],
    axis: Vec3,
    f: SineFn,
}

impl PointMap for AlongX {
    #[inline(always)]
    fn map(&self, _: usize, p: Vec3) -> Vec3 {
        let h = &self.height;
        p + self.axis * self.f.shift(h[0] * p.x + h[1] * p.y + h[2] * p.z + h[3])
    }
}

/// Registers the handle shapes and `nonLinear`.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    for kind in 0..PARAMS.len() {
        registry.register(DeformFunc::new(kind)?)?;
    }
    registry.register(DeformerNode::<NonLinear>::new(
        "nonLinear",
        "bends, twists, squashes, flares or waves a mesh in the space of a handle (deformerData from deformBend ...)",
    )?)?;
    Ok(())
}
