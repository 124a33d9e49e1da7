//! The float-in, float-out math nodes, one table row each: every row becomes
//! a [`KernelNode`] (the whole compute is `output = op(inputs)`, so compiled
//! programs run it straight over their slots), registered as Maya's unitless
//! node and its `...DL` twin ([`Flavor`]).
//!
//! Rules shared by every row (the per-row doc says what else applies):
//! a NaN result becomes 0 and an overflow saturates at `±f64::MAX`
//! ([`finite`]); angles are degrees on plugs (Maya's angle attributes).

use sinew_core::{finite, KernelNode, NodeSpec, Registry, ScalarOp, SpecError, Unit};

use super::Flavor;
use crate::math::arith::{safe_div, safe_pow};

/// One float attribute of a table row.
#[derive(Clone, Copy, Debug)]
pub struct FloatAttr {
    /// Maya's long name.
    pub name: &'static str,
    /// Maya's short name.
    pub short: &'static str,
    /// Default (inputs) or initial value (the output).
    pub default: f64,
    /// Unit in the unitless node ([`Unit::Degrees`] for Maya's angle attributes).
    pub unit: Unit,
    /// One line for `sinew nodes` and `docs/nodes.md`.
    pub doc: &'static str,
}

/// A float-in, float-out Maya math node: its attributes and its arithmetic.
#[derive(Clone, Copy, Debug)]
pub struct KernelRow {
    /// Maya's node type name (unitless flavor).
    pub name: &'static str,
    /// One line on what the node computes, with its degenerate cases.
    pub doc: &'static str,
    /// Inputs, in the order `op` reads them.
    pub inputs: &'static [FloatAttr],
    /// The output.
    pub output: FloatAttr,
    /// `output = op(inputs)`; pure and total.
    pub op: fn(&[f64]) -> f64,
}

const fn attr(name: &'static str, short: &'static str, default: f64, doc: &'static str) -> FloatAttr {
    FloatAttr {
        name,
        short,
        default,
        unit: Unit::None,
        doc,
    }
}

const fn angle(name: &'static str, short: &'static str, doc: &'static str) -> FloatAttr {
    FloatAttr {
        name,
        short,
        default: 0.0,
        unit: Unit::Degrees,
        doc,
    }
}

const INPUT: FloatAttr = attr("input", "i", 0.0, "the operand");
const OUTPUT: FloatAttr = attr("output", "o", 0.0, "the result");
const ANGLE_IN: FloatAttr = angle("input", "i", "an angle");
const ANGLE_OUT: FloatAttr = angle("output", "o", "the angle");
const INPUT1: FloatAttr = attr("input1", "i1", 0.0, "first operand");
const INPUT2: FloatAttr = attr("input2", "i2", 0.0, "second operand");

/// The argument `k` of a kernel (0 when absent: a kernel always gets its declared count).
#[inline(always)]
fn arg(x: &[f64], k: usize) -> f64 {
    x.get(k).copied().unwrap_or(0.0)
}

/// Round half up (`0.5 → 1`, `-0.5 → 0`, `-1.5 → -1`), Maya's `round` rule.
pub fn round_half_up(x: f64) -> f64 {
    let f = x.floor();
    // `x - floor(x)` is exact for every finite float, so ties are detected exactly.
    if x - f >= 0.5 {
        f + 1.0
    } else {
        f
    }
}

/// `x` wrapped into `[0, m)` (or `(m, 0]` for a negative `m`): `x - m·floor(x/m)`;
/// `m = 0` gives 0.
pub fn modulo(x: f64, m: f64) -> f64 {
    if m == 0.0 {
        return 0.0;
    }
    let r = x - m * (x / m).floor();
    // Rounding can land exactly on `m` for tiny negative `x`; that value is 0 modulo `m`.
    finite(if r == m { 0.0 } else { r })
}

/// `log_base(x)`; 0 where it has no real value (`x <= 0`, `base <= 0`, `base == 1`).
pub fn log_base(x: f64, base: f64) -> f64 {
    if x > 0.0 && base > 0.0 && base != 1.0 {
        finite(x.ln() / base.ln())
    } else {
        0.0
    }
}

/// `x` clamped to `[lo, hi]`, the `lo` test first (so `lo > hi` gives `lo` below
/// `lo` and `hi` otherwise, as sinew's `clamp`).
pub fn clamp_range(x: f64, lo: f64, hi: f64) -> f64 {
    let r = if x < lo {
        lo
    } else if x > hi {
        hi
    } else {
        x
    };
    finite(r)
}

/// Hermite smooth step: 0 at or below `left`, 1 at or above `right`,
/// `t²(3 - 2t)` between (`t = (x - left)/(right - left)`). A right edge below
/// the left edge is clamped to it (Maya's rule), which makes the step sharp:
/// 0 below `left`, 1 from `left` on.
pub fn smooth_step(x: f64, left: f64, right: f64) -> f64 {
    let right = if right < left { left } else { right };
    if x.is_nan() || left.is_nan() || right.is_nan() {
        return 0.0;
    }
    if x <= left && x < right {
        return 0.0;
    }
    if x >= right {
        return 1.0;
    }
    let t = ((x - left) / (right - left)).clamp(0.0, 1.0);
    finite(t * t * (3.0 - 2.0 * t))
}

/// `(1 - w)·a + w·b`: exactly `a` at `w = 0` and `b` at `w = 1`; `w` outside [0, 1] extrapolates.
pub fn lerp(a: f64, b: f64, w: f64) -> f64 {
    finite((1.0 - w) * a + w * b)
}

/// The weight `w` with `lerp(a, b, w) = v`: `(v - a)/(b - a)`; 0 when `a == b`.
pub fn inverse_lerp(a: f64, b: f64, v: f64) -> f64 {
    safe_div(v - a, b - a)
}

fn absolute(x: &[f64]) -> f64 {
    finite(arg(x, 0).abs())
}
fn negate(x: &[f64]) -> f64 {
    finite(-arg(x, 0))
}
fn floor(x: &[f64]) -> f64 {
    finite(arg(x, 0).floor())
}
fn ceil(x: &[f64]) -> f64 {
    finite(arg(x, 0).ceil())
}
fn round(x: &[f64]) -> f64 {
    finite(round_half_up(arg(x, 0)))
}
fn truncate(x: &[f64]) -> f64 {
    finite(arg(x, 0).trunc())
}
fn sin(x: &[f64]) -> f64 {
    finite(arg(x, 0).to_radians().sin())
}
fn cos(x: &[f64]) -> f64 {
    finite(arg(x, 0).to_radians().cos())
}
fn tan(x: &[f64]) -> f64 {
    finite(arg(x, 0).to_radians().tan())
}
fn asin(x: &[f64]) -> f64 {
    finite(finite(arg(x, 0)).clamp(-1.0, 1.0).asin().to_degrees())
}
fn acos(x: &[f64]) -> f64 {
    finite(finite(arg(x, 0)).clamp(-1.0, 1.0).acos().to_degrees())
}
fn atan(x: &[f64]) -> f64 {
    finite(arg(x, 0).atan().to_degrees())
}
fn atan2(x: &[f64]) -> f64 {
    // input1 is x, input2 is y (Maya: x = r cos a, y = r sin a).
    finite(finite(arg(x, 1)).atan2(finite(arg(x, 0))).to_degrees())
}
fn subtract(x: &[f64]) -> f64 {
    finite(arg(x, 0) - arg(x, 1))
}
fn divide(x: &[f64]) -> f64 {
    safe_div(arg(x, 0), arg(x, 1))
}
fn power(x: &[f64]) -> f64 {
    safe_pow(arg(x, 0), arg(x, 1))
}
fn log(x: &[f64]) -> f64 {
    log_base(arg(x, 0), arg(x, 1))
}
fn modulo_k(x: &[f64]) -> f64 {
    modulo(arg(x, 0), arg(x, 1))
}
fn clamp_k(x: &[f64]) -> f64 {
    clamp_range(arg(x, 0), arg(x, 1), arg(x, 2))
}
fn smooth_k(x: &[f64]) -> f64 {
    smooth_step(arg(x, 0), arg(x, 1), arg(x, 2))
}
fn lerp_k(x: &[f64]) -> f64 {
    lerp(arg(x, 0), arg(x, 1), arg(x, 2))
}
fn inverse_lerp_k(x: &[f64]) -> f64 {
    inverse_lerp(arg(x, 0), arg(x, 1), arg(x, 2))
}

/// Every float-in, float-out Maya math node (each also registered as its `...DL` twin).
pub const ROWS: &[KernelRow] = &[
    KernelRow {
        name: "absolute",
        doc: "output = |input|",
        inputs: &[INPUT],
        output: OUTPUT,
        op: absolute,
    },
    KernelRow {
        name: "negate",
        doc: "output = -input",
        inputs: &[INPUT],
        output: OUTPUT,
        op: negate,
    },
    KernelRow {
        name: "floor",
        doc: "output = the largest integer <= input",
        inputs: &[INPUT],
        output: OUTPUT,
        op: floor,
    },
    KernelRow {
        name: "ceil",
        doc: "output = the smallest integer >= input",
        inputs: &[INPUT],
        output: OUTPUT,
        op: ceil,
    },
    KernelRow {
        name: "round",
        doc: "output = input rounded to the nearest integer, halves up (0.5 -> 1, -0.5 -> 0)",
        inputs: &[INPUT],
        output: OUTPUT,
        op: round,
    },
    KernelRow {
        name: "truncate",
        doc: "output = the integer part of input (toward zero)",
        inputs: &[INPUT],
        output: OUTPUT,
        op: truncate,
    },
    KernelRow {
        name: "sin",
        doc: "output = sin(input), input an angle (degrees on the plug)",
        inputs: &[ANGLE_IN],
        output: OUTPUT,
        op: sin,
    },
    KernelRow {
        name: "cos",
        doc: "output = cos(input), input an angle (degrees on the plug)",
        inputs: &[ANGLE_IN],
        output: OUTPUT,
        op: cos,
    },
    KernelRow {
        name: "tan",
        doc: "output = tan(input), input an angle; at +-90 degrees the (huge, finite) value of tan at the nearest double",
        inputs: &[ANGLE_IN],
        output: OUTPUT,
        op: tan,
    },
    KernelRow {
        name: "asin",
        doc: "output = asin(input) as an angle in [-90, 90]; input clamped to [-1, 1]",
        inputs: &[INPUT],
        output: ANGLE_OUT,
        op: asin,
    },
    KernelRow {
        name: "acos",
        doc: "output = acos(input) as an angle in [0, 180]; input clamped to [-1, 1]",
        inputs: &[INPUT],
        output: ANGLE_OUT,
        op: acos,
    },
    KernelRow {
        name: "atan",
        doc: "output = atan(input) as an angle in (-90, 90)",
        inputs: &[INPUT],
        output: ANGLE_OUT,
        op: atan,
    },
    KernelRow {
        name: "atan2",
        doc: "output = the polar angle of (x = input1, y = input2) in (-180, 180]; (0, 0) gives 0",
        inputs: &[
            attr("input1", "i1", 0.0, "x, the value used for computing the angle"),
            attr("input2", "i2", 0.0, "y, the value used for computing the angle"),
        ],
        output: ANGLE_OUT,
        op: atan2,
    },
    KernelRow {
        name: "subtract",
        doc: "output = input1 - input2",
        inputs: &[INPUT1, INPUT2],
        output: OUTPUT,
        op: subtract,
    },
    KernelRow {
        name: "divide",
        doc: "output = input1 / input2; a zero divisor gives 0 (Maya reports an error)",
        inputs: &[
            attr("input1", "i1", 0.0, "the dividend"),
            attr("input2", "i2", 1.0, "the divisor"),
        ],
        output: OUTPUT,
        op: divide,
    },
    KernelRow {
        name: "power",
        doc: "output = input ^ exponent; 0 where there is no real result (negative base, fractional exponent; 0 to a negative power)",
        inputs: &[
            attr("input", "i", 0.0, "the base"),
            attr("exponent", "e", 2.0, "the exponent"),
        ],
        output: OUTPUT,
        op: power,
    },
    KernelRow {
        name: "log",
        doc: "output = the logarithm of input in base; 0 for input <= 0, base <= 0 or base = 1",
        inputs: &[
            attr("input", "i", 0.0, "the value whose logarithm is taken"),
            attr("base", "e", 2.0, "the base"),
        ],
        output: OUTPUT,
        op: log,
    },
    KernelRow {
        name: "modulo",
        doc: "output = input wrapped into [0, modulus) (into (modulus, 0] for a negative modulus); modulus 0 gives 0",
        inputs: &[
            attr("input", "i", 0.0, "the value to wrap around"),
            attr("modulus", "m", 1.0, "the modulus"),
        ],
        output: OUTPUT,
        op: modulo_k,
    },
    KernelRow {
        name: "clampRange",
        doc: "output = input clamped to [minimum, maximum] (minimum tested first when minimum > maximum)",
        inputs: &[
            INPUT,
            attr("minimum", "min", 0.0, "the lowest value allowed"),
            attr("maximum", "max", 1.0, "the highest value allowed"),
        ],
        output: OUTPUT,
        op: clamp_k,
    },
    KernelRow {
        name: "smoothStep",
        doc: "output = 0 at or below leftEdge, 1 at or above rightEdge, the Hermite t*t*(3-2t) between; rightEdge < leftEdge is clamped to leftEdge",
        inputs: &[
            INPUT,
            attr("leftEdge", "le", 0.0, "inputs at or below give 0"),
            attr("rightEdge", "re", 1.0, "inputs at or above give 1"),
        ],
        output: OUTPUT,
        op: smooth_k,
    },
    KernelRow {
        name: "lerp",
        doc: "output = (1 - weight) * input1 + weight * input2 (weight 0 gives input1, 1 gives input2; outside [0, 1] extrapolates)",
        inputs: &[
            INPUT1,
            INPUT2,
            attr("weight", "w", 0.0, "0 gives input1, 1 gives input2"),
        ],
        output: OUTPUT,
        op: lerp_k,
    },
    KernelRow {
        name: "inverseLerp",
        doc: "output = (interpolation - input1) / (input2 - input1), the weight lerp needs; input1 = input2 gives 0",
        inputs: &[
            INPUT1,
            INPUT2,
            attr("interpolation", "i", 0.0, "the interpolated value"),
        ],
        output: attr("output", "o", 0.0, "the weight of the interpolation"),
        op: inverse_lerp_k,
    },
];

/// The node type of `row` in `flavor`.
pub fn kernel_node(row: &KernelRow, flavor: Flavor) -> Result<KernelNode, SpecError> {
    let mut s = NodeSpec::builder(&flavor.type_name(row.name));
    s.doc(&flavor.doc(row.doc, row.name));
    let mut inputs = Vec::with_capacity(row.inputs.len());
    for a in row.inputs {
        let h = s.input(a.name, a.default);
        s.unit(h, flavor.unit(a.unit)).attr_doc(h, a.doc).short_name(h, a.short);
        inputs.push(h);
    }
    let out = s.output(row.output.name, row.output.default);
    s.unit(out, flavor.unit(row.output.unit))
        .attr_doc(out, row.output.doc)
        .short_name(out, row.output.short);
    KernelNode::new(s.build()?, &inputs, out, ScalarOp::Custom(row.op))
}

/// Registers every row in both flavors.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    for row in ROWS {
        for flavor in Flavor::BOTH {
            registry.register(kernel_node(row, flavor)?)?;
        }
    }
    Ok(())
}
