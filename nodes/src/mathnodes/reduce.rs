//! The list, comparison and logic nodes of the Maya math set: `sum`,
//! `multiply`, `average`, `min`, `max` over the multi `input[]`; `equal`,
//! `greaterThan`, `lessThan` (float operands, bool output); `and`, `or`,
//! `not` (bool operands). One generic node type per shape, parameterized by
//! its operation.

use sinew_core::{
    finite, ComputeContext, ComputeError, Input, MultiInput, NodeSpec, NodeType, Output, Registry, SpecError, Unit,
};

use super::Flavor;

/// How a list node folds its elements.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fold {
    /// `sum`: the sum.
    Sum,
    /// `multiply`: the product.
    Product,
    /// `average`: the mean.
    Average,
    /// `min`: the smallest element.
    Min,
    /// `max`: the largest element.
    Max,
}

impl Fold {
    /// Every fold with its Maya name and doc line.
    pub const ALL: [(Fold, &'static str, &'static str); 5] = [
        (Fold::Sum, "sum", "output = the sum of input[]"),
        (Fold::Product, "multiply", "output = the product of input[]"),
        (Fold::Average, "average", "output = the mean of input[]"),
        (
            Fold::Min,
            "min",
            "output = the smallest element of input[]; NaN elements are skipped",
        ),
        (
            Fold::Max,
            "max",
            "output = the largest element of input[]; NaN elements are skipped",
        ),
    ];

    /// Folds `items` (in index order); no element (for min/max: no element that
    /// is not NaN) gives 0.
    pub fn apply(self, items: impl Iterator<Item = f64>) -> f64 {
        let mut n = 0usize;
        let mut acc = match self {
            Fold::Sum | Fold::Average => 0.0,
            Fold::Product => 1.0,
            Fold::Min => f64::INFINITY,
            Fold::Max => f64::NEG_INFINITY,
        };
        for x in items {
            match self {
                Fold::Sum | Fold::Average => acc += x,
                Fold::Product => acc *= x,
                Fold::Min | Fold::Max if x.is_nan() => continue,
                Fold::Min => acc = acc.min(x),
                Fold::Max => acc = acc.max(x),
            }
            n += 1;
        }
        match (n, self) {
            (0, _) => 0.0,
            (_, Fold::Average) => finite(acc / n as f64),
            _ => finite(acc),
        }
    }
}

/// A list node (`sum`, `multiply`, `average`, `min`, `max`): `output = fold(input[])`.
///
/// Elements are taken in logical index order; sparse indices are fine. No
/// element gives 0 (also for `multiply`). NaN elements are skipped by `min`
/// and `max` and poison the others (a NaN result becomes 0). Overflow
/// saturates at `±f64::MAX`.
pub struct ListNode {
    spec: NodeSpec,
    fold: Fold,
    input: MultiInput<f64>,
    output: Output<f64>,
}

impl ListNode {
    /// The node type `fold` (Maya name `base`) in `flavor`.
    pub fn new(fold: Fold, base: &str, doc: &str, flavor: Flavor) -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder(&flavor.type_name(base));
        s.doc(&flavor.doc(doc, base));
        let input = s.multi_input("input", 0.0);
        let output = s.output("output", 0.0);
        s.unit(input, flavor.unit(Unit::None))
            .attr_doc(input, "the list of values");
        s.unit(output, flavor.unit(Unit::None)).attr_doc(output, "the result");
        s.maya_names(&[("input", "i"), ("output", "o")]);
        Ok(ListNode {
            spec: s.build()?,
            fold,
            input,
            output,
        })
    }
}

impl NodeType for ListNode {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let n = ctx.multi_len(self.input);
        let v = self
            .fold
            .apply((0..n).filter_map(|k| ctx.multi_at(self.input, k).map(|(_, x)| x)));
        ctx.set(self.output, v);
        Ok(())
    }
}

/// A comparison: `equal`, `greaterThan`, `lessThan`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compare {
    /// `|input1 - input2| <= epsilon`.
    Equal,
    /// `input1 > input2`.
    Greater,
    /// `input1 < input2`.
    Less,
}

impl Compare {
    /// Every comparison with its Maya name and doc line.
    pub const ALL: [(Compare, &'static str, &'static str); 3] = [
        (
            Compare::Equal,
            "equal",
            "output = |input1 - input2| <= epsilon; false when either is NaN",
        ),
        (
            Compare::Greater,
            "greaterThan",
            "output = input1 > input2; false when either is NaN",
        ),
        (
            Compare::Less,
            "lessThan",
            "output = input1 < input2; false when either is NaN",
        ),
    ];

    /// Whether `a (op) b` holds (`eps` only for `Equal`; a negative epsilon counts as 0).
    pub fn holds(self, a: f64, b: f64, eps: f64) -> bool {
        match self {
            Compare::Equal => (a - b).abs() <= eps.max(0.0) || a == b,
            Compare::Greater => a > b,
            Compare::Less => a < b,
        }
    }
}

/// A comparison node: `output = input1 (op) input2` as a bool.
pub struct CompareNode {
    spec: NodeSpec,
    op: Compare,
    input1: Input<f64>,
    input2: Input<f64>,
    epsilon: Option<Input<f64>>,
    output: Output<bool>,
}

impl CompareNode {
    /// The node type `op` (Maya name `base`) in `flavor`.
    pub fn new(op: Compare, base: &str, doc: &str, flavor: Flavor) -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder(&flavor.type_name(base));
        s.doc(&flavor.doc(doc, base));
        let unit = flavor.unit(Unit::None);
        let epsilon = (op == Compare::Equal).then(|| {
            let h = s.input("epsilon", 0.0);
            s.unit(h, unit).attr_doc(h, "the tolerance of the comparison");
            h
        });
        let input1 = s.input("input1", 0.0);
        let input2 = s.input("input2", 0.0);
        s.unit(input1, unit).attr_doc(input1, "first operand");
        s.unit(input2, unit).attr_doc(input2, "second operand");
        let output = s.output("output", false);
        s.attr_doc(output, "the result of the comparison");
        s.maya_names(&[("input1", "i1"), ("input2", "i2"), ("output", "o")]);
        if op == Compare::Equal {
            s.maya_names(&[("epsilon", "e")]);
        }
        Ok(CompareNode {
            spec: s.build()?,
            op,
            input1,
            input2,
            epsilon,
            output,
        })
    }
}

impl NodeType for CompareNode {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let eps = self.epsilon.map_or(0.0, |h| ctx.get(h));
        let v = self.op.holds(ctx.get(self.input1), ctx.get(self.input2), eps);
        ctx.set(self.output, v);
        Ok(())
    }
}

/// A logic operation: `and`, `or`, `not`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Logic {
    /// `input1 && input2`.
    And,
    /// `input1 || input2`.
    Or,
    /// `!input`.
    Not,
}

/// A logic node (`and`, `or`: `input1`, `input2`; `not`: `input`), bool in, bool out.
pub struct LogicNode {
    spec: NodeSpec,
    op: Logic,
    a: Input<bool>,
    b: Option<Input<bool>>,
    output: Output<bool>,
}

impl LogicNode {
    /// The node type of `op`.
    pub fn new(op: Logic) -> Result<Self, SpecError> {
        let (name, doc) = match op {
            Logic::And => ("and", "output = input1 and input2"),
            Logic::Or => ("or", "output = input1 or input2"),
            Logic::Not => ("not", "output = not input"),
        };
        let mut s = NodeSpec::builder(name);
        s.doc(doc);
        let (a, b) = if op == Logic::Not {
            (s.input("input", false), None)
        } else {
            (s.input("input1", false), Some(s.input("input2", false)))
        };
        let output = s.output("output", false);
        if op == Logic::Not {
            s.maya_names(&[("input", "i"), ("output", "o")]);
        } else {
            s.maya_names(&[("input1", "i1"), ("input2", "i2"), ("output", "o")]);
        }
        Ok(LogicNode {
            spec: s.build()?,
            op,
            a,
            b,
            output,
        })
    }
}

impl NodeType for LogicNode {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let a = ctx.get(self.a);
        let b = self.b.is_some_and(|h| ctx.get(h));
        let v = match self.op {
            Logic::And => a && b,
            Logic::Or => a || b,
            Logic::Not => !a,
        };
        ctx.set(self.output, v);
        Ok(())
    }
}

/// Registers the list and comparison nodes in both flavors, and the logic nodes.
pub fn register(registry: &mut Registry) -> Result<(), SpecError> {
    for flavor in Flavor::BOTH {
        for (fold, name, doc) in Fold::ALL {
            registry.register(ListNode::new(fold, name, doc, flavor)?)?;
        }
        for (op, name, doc) in Compare::ALL {
            registry.register(CompareNode::new(op, name, doc, flavor)?)?;
        }
    }
    for op in [Logic::And, Logic::Or, Logic::Not] {
        registry.register(LogicNode::new(op)?)?;
    }
    Ok(())
}
