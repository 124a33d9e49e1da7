//! Choosing, blending and range nodes: `condition`, `blendColors`, `clamp`, `setRange`.

use glam::DVec3;
use sinew_core::{AttrId, ComputeContext, ComputeError, Input, KnownInputs, NodeSpec, NodeType, Output, SpecError};

use super::{finite, finite3, node_type};

const RGB: [&str; 3] = ["R", "G", "B"];

/// Maya's `condition`: `outColor = colorIfTrue` when `firstTerm (op) secondTerm`
/// holds, else `colorIfFalse`.
///
/// `operation`: `equal`, `notEqual`, `greaterThan`, `greaterOrEqual`,
/// `lessThan`, `lessOrEqual` (Maya's order). Comparisons are exact (no
/// tolerance), as in Maya: compare against a threshold, not a computed value.
pub struct Condition {
    spec: NodeSpec,
    first: Input<f64>,
    second: Input<f64>,
    operation: Input<i64>,
    if_true: Input<DVec3>,
    if_false: Input<DVec3>,
    out: Output<DVec3>,
}

impl Condition {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("condition");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[
            ("firstTerm", "ft"),
            ("secondTerm", "st"),
            ("operation", "op"),
            ("colorIfTrue", "ct"),
            ("colorIfFalse", "cf"),
            ("outColor", "oc"),
        ]);
        s.doc("outColor = colorIfTrue if firstTerm (op) secondTerm else colorIfFalse; exact comparison");
        let first = s.input("firstTerm", 0.0);
        let second = s.input("secondTerm", 0.0);
        let operation = s.input_enum(
            "operation",
            &[
                "equal",
                "notEqual",
                "greaterThan",
                "greaterOrEqual",
                "lessThan",
                "lessOrEqual",
            ],
            0,
        );
        let if_true = s.input("colorIfTrue", DVec3::ZERO);
        let if_false = s.input("colorIfFalse", DVec3::ONE);
        let out = s.output("outColor", DVec3::ZERO);
        s.child_suffixes(if_true, RGB);
        s.child_suffixes(if_false, RGB);
        s.child_suffixes(out, RGB);
        Ok(Condition {
            spec: s.build()?,
            first,
            second,
            operation,
            if_true,
            if_false,
            out,
        })
    }

    fn run(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let holds = holds(ctx.get(self.operation), ctx.get(self.first), ctx.get(self.second));
        let v = if holds {
            ctx.get(self.if_true)
        } else {
            ctx.get(self.if_false)
        };
        ctx.set(self.out, v);
        Ok(())
    }

    /// The colour that known terms and operation do not choose.
    fn unread(&self, known: &KnownInputs<'_>) -> Vec<AttrId> {
        let (Some(op), Some(a), Some(b)) = (known.get(self.operation), known.get(self.first), known.get(self.second))
        else {
            return Vec::new();
        };
        vec![if holds(op, a, b) {
            self.if_false.id()
        } else {
            self.if_true.id()
        }]
    }
}
node_type!(Condition, unread);

/// Whether `a (operation) b` holds; unknown operations compare for equality.
fn holds(operation: i64, a: f64, b: f64) -> bool {
    match operation {
        1 => a != b,
        2 => a > b,
        3 => a >= b,
        4 => a < b,
        5 => a <= b,
        _ => a == b,
    }
}

/// Maya's `blendColors`: `output = color1 * blender + color2 * (1 - blender)`.
///
/// `blender` is not clamped (values outside [0, 1] extrapolate, as in Maya
/// when the attribute is driven). Overflow saturates at `±f64::MAX`. At exactly
/// 1 the output is `color1` and at exactly 0 `color2`, bit for bit (made finite),
/// without reading the other colour: a compiled program does not evaluate what
/// feeds it (see [`NodeType::unread_inputs`]).
pub struct BlendColors {
    spec: NodeSpec,
    color1: Input<DVec3>,
    color2: Input<DVec3>,
    blender: Input<f64>,
    output: Output<DVec3>,
}

impl BlendColors {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("blendColors");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[("color1", "c1"), ("color2", "c2"), ("blender", "b"), ("output", "op")]);
        s.doc("output = color1 * blender + color2 * (1 - blender)");
        let color1 = s.input("color1", DVec3::new(1.0, 0.0, 0.0));
        let color2 = s.input("color2", DVec3::new(0.0, 0.0, 1.0));
        let blender = s.input("blender", 0.5);
        let output = s.output("output", DVec3::ZERO);
        s.child_suffixes(color1, RGB);
        s.child_suffixes(color2, RGB);
        s.child_suffixes(output, RGB);
        s.attr_doc(blender, "1 gives color1, 0 gives color2");
        Ok(BlendColors {
            spec: s.build()?,
            color1,
            color2,
            blender,
            output,
        })
    }

    fn run(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let w = ctx.get(self.blender);
        // The end points read one colour only (the contract of `unread`).
        let v = if w == 1.0 {
            ctx.get(self.color1)
        } else if w == 0.0 {
            ctx.get(self.color2)
        } else {
            ctx.get(self.color1) * w + ctx.get(self.color2) * (1.0 - w)
        };
        ctx.set(self.output, finite3(v));
        Ok(())
    }

    /// The colour a known blender of exactly 0 or 1 leaves unread.
    fn unread(&self, known: &KnownInputs<'_>) -> Vec<AttrId> {
        match known.get(self.blender) {
            Some(1.0) => vec![self.color2.id()],
            Some(0.0) => vec![self.color1.id()],
            _ => Vec::new(),
        }
    }
}
node_type!(BlendColors, unread);

/// Maya's `clamp`: per component, `output = min` if `input < min`, else
/// `max` if `input > max`, else `input`.
///
/// When `min > max` the `min` test wins (the output is `min` for inputs
/// below it and `max` for the others above `max`), the same order Maya
/// applies. Defaults (all 0) clamp everything to 0.
pub struct Clamp {
    spec: NodeSpec,
    min: Input<DVec3>,
    max: Input<DVec3>,
    input: Input<DVec3>,
    output: Output<DVec3>,
}

impl Clamp {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("clamp");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[("min", "mn"), ("max", "mx"), ("input", "ip"), ("output", "op")]);
        s.doc("output = input clamped to [min, max], per component (min tested first)");
        let min = s.input("min", DVec3::ZERO);
        let max = s.input("max", DVec3::ZERO);
        let input = s.input("input", DVec3::ZERO);
        let output = s.output("output", DVec3::ZERO);
        for h in [min, max, input] {
            s.child_suffixes(h, RGB);
        }
        s.child_suffixes(output, RGB);
        Ok(Clamp {
            spec: s.build()?,
            min,
            max,
            input,
            output,
        })
    }

    fn run(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let (lo, hi, x) = (ctx.get(self.min), ctx.get(self.max), ctx.get(self.input));
        let c = |x: f64, lo: f64, hi: f64| {
            if x < lo {
                lo
            } else if x > hi {
                hi
            } else {
                x
            }
        };
        ctx.set(
            self.output,
            DVec3::new(c(x.x, lo.x, hi.x), c(x.y, lo.y, hi.y), c(x.z, lo.z, hi.z)),
        );
        Ok(())
    }
}
node_type!(Clamp);

/// Maya's `setRange`, per component:
/// `outValue = min + (v - oldMin) / (oldMax - oldMin) * (max - min)` with `v`
/// first clamped to the old range (Maya's node clamps: the output never
/// leaves `[min, max]`).
///
/// An empty old range (`oldMin == oldMax`) gives `min`. A reversed old range
/// (`oldMin > oldMax`) maps inversely and clamps to it the same way.
pub struct SetRange {
    spec: NodeSpec,
    value: Input<DVec3>,
    min: Input<DVec3>,
    max: Input<DVec3>,
    old_min: Input<DVec3>,
    old_max: Input<DVec3>,
    out: Output<DVec3>,
}

impl SetRange {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("setRange");
        // Maya's short names (see docs/rig-format.md, "Maya short names").
        s.maya_names(&[
            ("value", "v"),
            ("min", "n"),
            ("max", "m"),
            ("oldMin", "on"),
            ("oldMax", "om"),
            ("outValue", "o"),
        ]);
        s.doc("outValue = value mapped from [oldMin, oldMax] to [min, max], clamped; oldMin == oldMax gives min");
        let value = s.input("value", DVec3::ZERO);
        let min = s.input("min", DVec3::ZERO);
        let max = s.input("max", DVec3::ZERO);
        let old_min = s.input("oldMin", DVec3::ZERO);
        let old_max = s.input("oldMax", DVec3::ZERO);
        let out = s.output("outValue", DVec3::ZERO);
        Ok(SetRange {
            spec: s.build()?,
            value,
            min,
            max,
            old_min,
            old_max,
            out,
        })
    }

    fn run(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let v = ctx.get(self.value);
        let (lo, hi) = (ctx.get(self.min), ctx.get(self.max));
        let (olo, ohi) = (ctx.get(self.old_min), ctx.get(self.old_max));
        let mut r = DVec3::ZERO;
        for k in 0..3 {
            r[k] = set_range(v[k], lo[k], hi[k], olo[k], ohi[k]);
        }
        ctx.set(self.out, r);
        Ok(())
    }
}
node_type!(SetRange);

/// One component of [`SetRange`].
fn set_range(v: f64, lo: f64, hi: f64, olo: f64, ohi: f64) -> f64 {
    let span = ohi - olo;
    if span == 0.0 {
        return lo;
    }
    let t = ((v - olo) / span).clamp(0.0, 1.0);
    let t = if t.is_nan() { 0.0 } else { t };
    finite(lo + t * (hi - lo))
}
