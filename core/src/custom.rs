//! Custom attributes (Maya's `addAttr`): attributes a single node carries besides its
//! type's, declared in rig files (`attrs: { "footRoll": float(..) }`) or with
//! [`Graph::add_attr`](crate::Graph::add_attr).
//!
//! A node keeps its type's spec shared until it gets a custom attribute; then it gets its
//! own spec: the type's attributes, unchanged and in the same order (so the plugin's
//! typed handles and compute groups stay valid), followed by the custom ones. The node's
//! type is then a [`CustomNode`] that holds that spec and forwards everything else to the
//! registered type. Custom inputs affect nothing by default; they are plugs like any
//! other (set, connected from and to, compiled into slots, resolved by handles). A node
//! type whose compute reads or writes custom attributes (an expression node) opts in with
//! [`NodeType::custom_affects`], which may also declare
//! custom *outputs*.

use std::sync::Arc;

use crate::error::{InputError, SpecError};
use crate::kernel::ScalarKernel;
use crate::mat_kernel::MatrixKernel;
use crate::node::{ComputeContext, KnownInputs, NodeType};
use crate::spec::{AttrId, AttrSpec, Direction, MirrorRole, NodeSpec, SpecBuilder, Unit};
use crate::value::{AttrType, Value};
use crate::ComputeError;

/// What a node type's custom attributes affect (see
/// [`NodeType::custom_affects`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CustomAffects {
    /// `(input, output)` pairs: the output is a custom output; the input is one of the
    /// type's inputs or a custom input (or another group's output).
    pub affects: Vec<(AttrId, AttrId)>,
    /// Custom outputs that read the graph's time.
    pub time_outputs: Vec<AttrId>,
}

/// The value types a custom attribute may have.
pub const CUSTOM_TYPES: [AttrType; 8] = [
    AttrType::Float,
    AttrType::Int,
    AttrType::Bool,
    AttrType::Enum,
    AttrType::Vec3,
    AttrType::Matrix,
    AttrType::String,
    AttrType::FloatArray,
];

impl AttrSpec {
    /// A custom input attribute named `name` whose type is `default`'s (an
    /// [`Value::Enum`] makes an enum: give its names with [`AttrSpec::with_enum`]). Not
    /// keyable (Maya's `addAttr` default), no short name, no range, not multi.
    pub fn custom(name: &str, default: Value) -> AttrSpec {
        let ty = default.attr_type();
        AttrSpec {
            name: name.to_string(),
            ty,
            direction: Direction::Input,
            default,
            keyable: false,
            multi: false,
            children: (ty == AttrType::Vec3).then(|| ["X", "Y", "Z"].map(|s| format!("{name}{s}"))),
            enum_names: Vec::new(),
            unit: Unit::None,
            doc: String::new(),
            mirror: MirrorRole::None,
            short_name: None,
            child_short_names: None,
            min: None,
            max: None,
            soft_min: None,
            soft_max: None,
        }
    }

    /// With hard limits (float and int attributes): setting a value outside is refused.
    pub fn with_range(mut self, min: Option<f64>, max: Option<f64>) -> Self {
        self.min = min;
        self.max = max;
        self
    }

    /// With soft limits (a UI's slider range; not enforced).
    pub fn with_soft_range(mut self, min: Option<f64>, max: Option<f64>) -> Self {
        self.soft_min = min;
        self.soft_max = max;
        self
    }

    /// With the names of an enum's choices, by index.
    pub fn with_enum(mut self, names: &[&str]) -> Self {
        self.enum_names = names.iter().map(|s| s.to_string()).collect();
        self
    }

    /// With a short name (an alias accepted wherever the attribute is named).
    pub fn with_short_name(mut self, short: &str) -> Self {
        self.short_name = Some(short.to_string());
        self
    }

    /// With a one-line description.
    pub fn with_doc(mut self, doc: &str) -> Self {
        self.doc = doc.to_string();
        self
    }

    /// Keyable (shown in channel-box listings) or not.
    pub fn with_keyable(mut self, keyable: bool) -> Self {
        self.keyable = keyable;
        self
    }

    /// A multi (array) attribute, `name[i]`, each element starting at the default.
    pub fn with_multi(mut self, multi: bool) -> Self {
        self.multi = multi;
        self
    }

    /// An output (only for node types that compute custom outputs).
    pub fn as_output(mut self) -> Self {
        self.direction = Direction::Output;
        self
    }

    /// With the names of a vec3's children (default `nameX nameY nameZ`).
    pub fn with_children(mut self, children: [&str; 3]) -> Self {
        self.children = Some(children.map(str::to_string));
        self
    }

    /// With a mirror role (vec3: `Translate`, `WorldVector` or `LocalVector`).
    pub fn with_mirror(mut self, role: MirrorRole) -> Self {
        self.mirror = role;
        self
    }

    /// Checks a custom attribute declaration on its own (its name against the node's other
    /// attributes is checked when the node's spec is built). The message says what to fix.
    pub fn validate_custom(&self) -> Result<(), String> {
        let name = &self.name;
        let mut chars = name.chars();
        let valid = chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && chars.all(|c| c.is_ascii_alphanumeric() || c == '_');
        if !valid {
            return Err(format!(
                "custom attribute name {name:?} must be an identifier (letters, digits, '_', not starting with a digit)"
            ));
        }
        if matches!(name.as_str(), "parent" | "attrs") {
            return Err(format!("{name:?} is reserved in rig files; choose another name"));
        }
        if !CUSTOM_TYPES.contains(&self.ty) {
            let names: Vec<&str> = CUSTOM_TYPES.iter().map(|t| t.name()).collect();
            return Err(format!(
                "a custom attribute cannot be a {}; use one of {}",
                self.ty,
                names.join(", ")
            ));
        }
        let default_ty = self.default.attr_type();
        if default_ty != self.ty && !(self.ty == AttrType::Enum && default_ty == AttrType::Int) {
            return Err(format!(
                "{name}: default is a {default_ty} but the attribute is a {}",
                self.ty
            ));
        }
        if !self.default.is_finite() {
            return Err(format!("{name}: the default is not finite"));
        }
        if self.multi && matches!(self.ty, AttrType::String | AttrType::FloatArray) {
            return Err(format!("{name}: a {} cannot be multi", self.ty));
        }
        let numeric = matches!(self.ty, AttrType::Float | AttrType::Int);
        for (what, lo, hi) in [
            ("min/max", self.min, self.max),
            ("softMin/softMax", self.soft_min, self.soft_max),
        ] {
            if (lo.is_some() || hi.is_some()) && !numeric {
                return Err(format!(
                    "{name}: {what} apply to float and int attributes, not {}",
                    self.ty
                ));
            }
            if lo.is_some_and(|x| !x.is_finite()) || hi.is_some_and(|x| !x.is_finite()) {
                return Err(format!("{name}: {what} must be finite"));
            }
            if let (Some(lo), Some(hi)) = (lo, hi) {
                if lo > hi {
                    return Err(format!("{name}: {what} are reversed ({lo} > {hi})"));
                }
            }
        }
        if let Some(x) = self.default.as_f64().filter(|_| numeric) {
            if let Some(reason) = self.out_of_range(x) {
                return Err(format!("{name}: default {x} {reason}"));
            }
        }
        match self.ty {
            AttrType::Enum => {
                if self.enum_names.is_empty() {
                    return Err(format!("{name}: an enum needs at least one name"));
                }
                for (i, n) in self.enum_names.iter().enumerate() {
                    if n.is_empty() || self.enum_names[..i].iter().any(|m| m.eq_ignore_ascii_case(n)) {
                        return Err(format!("{name}: enum names must be non-empty and distinct ({n:?})"));
                    }
                }
                let d = self.default.as_f64().unwrap_or(0.0) as i64;
                if d < 0 || d as usize >= self.enum_names.len() {
                    return Err(format!(
                        "{name}: default index {d} is not one of the {} choices (0..{})",
                        self.enum_names.len(),
                        self.enum_names.len() - 1
                    ));
                }
            }
            _ if !self.enum_names.is_empty() => return Err(format!("{name}: only enums have names")),
            _ => {}
        }
        if self.children.is_some() != (self.ty == AttrType::Vec3) {
            return Err(format!("{name}: only vec3 attributes have children"));
        }
        let mirror_ok = match self.ty {
            AttrType::Vec3 => matches!(
                self.mirror,
                MirrorRole::None | MirrorRole::Translate | MirrorRole::WorldVector | MirrorRole::LocalVector
            ),
            _ => self.mirror == MirrorRole::None,
        };
        if !mirror_ok {
            return Err(format!(
                "{name}: a custom {} cannot mirror as {:?} (vec3 attributes may mirror as a translate, a world vector or a local vector)",
                self.ty, self.mirror
            ));
        }
        Ok(())
    }

    /// Whether two declarations say the same (defaults and limits compared bit for bit).
    pub fn same_decl(&self, o: &AttrSpec) -> bool {
        let bits = |x: Option<f64>| x.map(f64::to_bits);
        self.name == o.name
            && self.short_name == o.short_name
            && self.ty == o.ty
            && self.direction == o.direction
            && self.default.same_bits(&o.default)
            && self.keyable == o.keyable
            && self.multi == o.multi
            && self.children == o.children
            && self.child_short_names == o.child_short_names
            && self.enum_names == o.enum_names
            && self.unit == o.unit
            && self.doc == o.doc
            && self.mirror == o.mirror
            && [self.min, self.max, self.soft_min, self.soft_max].map(bits)
                == [o.min, o.max, o.soft_min, o.soft_max].map(bits)
    }

    /// Why `x` is outside this attribute's hard limits, if it is.
    pub fn out_of_range(&self, x: f64) -> Option<String> {
        match (self.min, self.max) {
            (Some(lo), Some(hi)) if x < lo || x > hi => Some(format!("is outside [{lo}, {hi}]")),
            (Some(lo), None) if x < lo => Some(format!("is below the minimum {lo}")),
            (None, Some(hi)) if x > hi => Some(format!("is above the maximum {hi}")),
            _ => None,
        }
    }
}

impl NodeSpec {
    /// This (node type's) spec with `custom` attributes appended, grouped as `affects`
    /// says (custom outputs only; custom inputs that `affects` does not name affect
    /// nothing). The type's attributes, ids and compute groups are unchanged. Fails when
    /// a custom attribute is invalid, its name (or short name) is already taken, or
    /// `affects` names something else than a custom output as an output.
    pub fn with_custom(&self, custom: &[AttrSpec], affects: &CustomAffects) -> Result<NodeSpec, SpecError> {
        let err = |message: String| SpecError {
            node_type: self.name.clone(),
            message,
        };
        let base = &self.attrs[..self.custom_start as usize];
        for a in custom {
            a.validate_custom().map_err(err)?;
            let taken = |n: &str| {
                self.find(n)
                    .filter(|(id, _)| id.0 < self.custom_start)
                    .map(|(id, _)| self.attr(id).name.clone())
            };
            for n in a.short_name.iter().chain(std::iter::once(&a.name)) {
                if let Some(owner) = taken(n) {
                    return Err(err(format!(
                        "{n:?} is already an attribute of {} ({owner}); choose another name",
                        self.name
                    )));
                }
            }
        }
        let first = base.len() as u16;
        for &(i, o) in &affects.affects {
            let custom_out = o.0 >= first
                && custom
                    .get((o.0 - first) as usize)
                    .is_some_and(|a| a.direction == Direction::Output);
            if !custom_out || i.index() >= base.len() + custom.len() {
                return Err(err(format!(
                    "custom affects must name a custom output as output ({} -> {})",
                    i.0, o.0
                )));
            }
        }
        let mut b: SpecBuilder = NodeSpec::builder(&self.name);
        b.explicit = true;
        b.custom_start = Some(first);
        b.doc(&self.doc);
        b.attrs = base.to_vec();
        b.attrs.extend(custom.iter().cloned());
        for g in self.groups() {
            for &o in &g.outputs {
                b.affects.extend(g.inputs.iter().map(|&i| (i, o)));
                if g.time_dependent {
                    b.time_outputs.push(o);
                }
            }
        }
        b.affects.extend(affects.affects.iter().copied());
        b.time_outputs.extend(affects.time_outputs.iter().copied());
        b.time_dependent = !b.time_outputs.is_empty();
        b.dag = self.dag.clone();
        let spec = b.build()?;
        if spec.groups()[..self.groups().len()] != self.groups()[..] {
            return Err(err(
                "custom attributes would change the type's compute groups; custom outputs need their own inputs".into(),
            ));
        }
        Ok(spec)
    }
}

/// The type of a node with custom attributes: the node's own spec (the registered type's
/// attributes followed by the custom ones) and the registered type for everything else.
pub struct CustomNode {
    base: Arc<dyn NodeType>,
    spec: NodeSpec,
}

impl CustomNode {
    /// The node type of a node of type `base` with `custom` attributes, grouped as `base`'s
    /// [`NodeType::custom_affects`] says.
    pub fn new(base: Arc<dyn NodeType>, custom: &[AttrSpec]) -> Result<CustomNode, SpecError> {
        let bspec = base.spec();
        let affects = base
            .custom_affects(custom, AttrId(bspec.attrs.len() as u16))
            .map_err(|message| SpecError {
                node_type: bspec.name.clone(),
                message,
            })?;
        let spec = bspec.with_custom(custom, &affects)?;
        Ok(CustomNode { base, spec })
    }

    /// The registered node type.
    pub fn base(&self) -> &Arc<dyn NodeType> {
        &self.base
    }
}

impl NodeType for CustomNode {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        self.base.compute(ctx)
    }

    fn scalar_kernel(&self) -> Option<&ScalarKernel> {
        // A kernel is bound to a node with one group; custom outputs add groups.
        (self.spec.groups().len() == self.base.spec().groups().len())
            .then(|| self.base.scalar_kernel())
            .flatten()
    }

    fn matrix_kernel(&self) -> Option<&MatrixKernel> {
        self.base.matrix_kernel()
    }

    fn unread_inputs(&self, known: &KnownInputs<'_>) -> Vec<AttrId> {
        self.base.unread_inputs(known)
    }

    fn custom_affects(&self, custom: &[AttrSpec], first: AttrId) -> Result<CustomAffects, String> {
        self.base.custom_affects(custom, first)
    }

    fn check_input(&self, spec: &NodeSpec, attr: AttrId, value: &Value) -> Result<(), InputError> {
        // Custom attributes come after the type's own, whose ids are unchanged.
        if attr.index() < self.base.spec().attrs.len() {
            self.base.check_input(spec, attr, value)
        } else {
            Ok(())
        }
    }
}

/// The node type of a node of type `base` with `custom` attributes: `base` itself when
/// there are none.
pub(crate) fn node_type_with(base: &Arc<dyn NodeType>, custom: &[AttrSpec]) -> Result<Arc<dyn NodeType>, SpecError> {
    if custom.is_empty() {
        return Ok(base.clone());
    }
    Ok(Arc::new(CustomNode::new(base.clone(), custom)?))
}
