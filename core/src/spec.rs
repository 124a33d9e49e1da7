//! Attribute and node-type specifications, declared once per node type by its
//! plugin, and the typed handles a plugin uses to read and write its plugs.
//!
//! A spec lists the attributes (name, type, direction, default, keyable,
//! multi, vec3 child names, enum names, unit) and which inputs affect which
//! outputs. From `affects` the spec derives *compute groups*: outputs that
//! depend on exactly the same inputs are computed together by one call of
//! the node's `compute`. Groups are what lets a node sit in a node-level loop
//! without a plug-level cycle (a joint's `parentInverseMatrix` does not wait
//! for its own `rotate`).

use std::collections::HashMap;
use std::marker::PhantomData;

use crate::error::SpecError;
use crate::value::{AttrType, AttrValue, Value};

/// Index of an attribute within its node type's spec.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct AttrId(pub u16);

impl AttrId {
    /// The index as `usize`.
    #[inline]
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Whether an attribute is read by the node (input) or written by it (output).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Direction {
    /// Set by hand or by a connection; read by `compute`.
    Input,
    /// Written by `compute`; may feed connections.
    Output,
}

/// What unit a float or vec3 attribute is in, for authoring and display.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Unit {
    /// A plain number.
    #[default]
    None,
    /// An angle in degrees (rotate, jointOrient...).
    Degrees,
    /// A length in scene units.
    Distance,
    /// Time in frames.
    Frames,
}

/// The declaration of one attribute.
#[derive(Clone, Debug)]
pub struct AttrSpec {
    /// The attribute's long name (Maya-style camelCase, e.g. `rotatePivot`).
    pub name: String,
    /// Value type of each plug of the attribute.
    pub ty: AttrType,
    /// Input or output.
    pub direction: Direction,
    /// The value a plug has before anything sets it.
    pub default: Value,
    /// Whether animators key it (shown in channel-box listings).
    pub keyable: bool,
    /// Whether this is a multi (array) attribute addressed as `name[i]`.
    pub multi: bool,
    /// Names of the three children of a vec3 attribute (`translateX`...).
    pub children: Option<[String; 3]>,
    /// The choices of an enum attribute, by index.
    pub enum_names: Vec<String>,
    /// Unit, for authoring and display.
    pub unit: Unit,
    /// One line on what the attribute is for.
    pub doc: String,
    /// How the value changes when a rig component is instantiated mirrored
    /// (see [`MirrorRole`]); `None` leaves it unchanged.
    pub mirror: MirrorRole,
    /// Maya's short name (`t` for `translate`, `jo` for `jointOrient`): accepted as an
    /// alias wherever an attribute is named (rig fields, plug paths, handles); files are
    /// always written with the long name. `None` when the attribute has no Maya
    /// counterpart. Declared with [`SpecBuilder::short_name`].
    pub short_name: Option<String>,
    /// Maya's short names of the three children of a vec3 attribute (`tx ty tz`), when the
    /// attribute has a short name.
    pub child_short_names: Option<[String; 3]>,
    /// Hard minimum of a float or int attribute: setting a smaller value is refused
    /// (Maya's `setAttr` without `-clamp`); values arriving through connections pass.
    pub min: Option<f64>,
    /// Hard maximum, as [`AttrSpec::min`].
    pub max: Option<f64>,
    /// Soft minimum: the slider range of a UI; not enforced.
    pub soft_min: Option<f64>,
    /// Soft maximum: the slider range of a UI; not enforced.
    pub soft_max: Option<f64>,
}

/// How an authored attribute value changes when a rig component is
/// instantiated mirrored across a plane (Maya's mirrorJoint, *behavior* mode).
///
/// Declared by plugins with [`SpecBuilder::mirror`]; the rig loader applies
/// it, so the core needs no attribute or node-type names. "Root" below means
/// a node whose DAG parent is not created by the same mirrored instance (or
/// that has no DAG hookup); "child" means its parent is mirrored with it.
/// `S` is the reflection across the plane and `D = -S` the 180-degree turn
/// about the plane's normal.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum MirrorRole {
    /// Unchanged (scale, weights, blend factors, twist...).
    #[default]
    None,
    /// A position in the parent's space (`translate`, pivots): reflected
    /// (`S t`) on a root, negated (`-t`) on a child. vec3.
    Translate,
    /// Euler angles in degrees in the node's rotate order (`rotate`), or a
    /// rotation quaternion: on a root *without* a `JointOrient` attribute the
    /// rotation becomes `D R`; otherwise unchanged. vec3 or quat.
    Rotate,
    /// A joint's orientation (Euler XYZ degrees, or a quaternion), applied
    /// after `Rotate` (`M = S RA R JO T`, row vectors): on a root it absorbs
    /// the mirror (`JO' = D JO`) so the rotate channels stay as authored;
    /// unchanged on a child. vec3 or quat.
    JointOrient,
    /// The enum holding the node's rotate order, in Maya's index order
    /// (xyz, yzx, zxy, xzy, yxz, zyx); read to interpret `Rotate`. Unchanged.
    RotateOrder,
    /// A direction or point in world space (a pole vector, a world up
    /// vector): reflected (`S v`) on every node. vec3.
    WorldVector,
    /// A vector in the node's own local frame (an aim or up vector): negated,
    /// because behavior mirroring turns every local axis around. vec3.
    LocalVector,
    /// A local transform matrix in the parent's space (`offsetParentMatrix`):
    /// `S M N` on a root, `N M N` on a child (`N` negates the local axes). matrix.
    Matrix,
}

impl AttrSpec {
    /// Whether this is an input.
    pub fn is_input(&self) -> bool {
        self.direction == Direction::Input
    }

    /// Index of the enum choice named `name` (case-insensitive).
    pub fn enum_index(&self, name: &str) -> Option<i64> {
        self.enum_names
            .iter()
            .position(|n| n.eq_ignore_ascii_case(name))
            .map(|i| i as i64)
    }
}

/// A set of outputs computed together, and the inputs they depend on.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ComputeGroup {
    /// Outputs written by one call of `compute` for this group.
    pub outputs: Vec<AttrId>,
    /// Inputs that affect them (what must be clean before computing). May
    /// include outputs of other groups of the same node (precomputed data).
    pub inputs: Vec<AttrId>,
    /// Whether the group reads the graph's time.
    pub time_dependent: bool,
}

/// The DAG (parenting) hookup of a node type: the child's `parent_matrix`
/// input is fed from the parent's `world_matrix` output.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DagSpec {
    /// The input that receives the parent's world matrix.
    pub parent_matrix: AttrId,
    /// The output that feeds children's `parent_matrix`.
    pub world_matrix: AttrId,
    /// Extra links made when parenting (see [`DagLink`]).
    pub links: Vec<DagLink>,
}

/// An extra connection made when a node is parented: the parent's attribute
/// `parent_attr` feeds this node's `child_input`, when the parent has that
/// attribute with a compatible type (and, if `parent_type` is given, only
/// when the parent is of that node type).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DagLink {
    /// Attribute name on the parent.
    pub parent_attr: String,
    /// Input on the child.
    pub child_input: AttrId,
    /// Only link when the parent has this node type.
    pub parent_type: Option<String>,
}
/// The outputs through which a node reports how its evaluation went, for tools that
/// show problems (the viewer marks the node): an enum output whose first choice (0)
/// means "fine" and whose other choices name a problem (an IK's `unreachable`), and
/// optionally a string output describing it. A value other than 0 is not an error:
/// evaluation goes on and the outputs hold the node's best answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StatusSpec {
    /// The enum output; choice 0 means the evaluation went as asked.
    pub status: AttrId,
    /// A string output with the problem in words, if the node has one.
    pub message: Option<AttrId>,
}

/// The specification of a node type.
#[derive(Clone, Debug)]
pub struct NodeSpec {
    /// The type name used in rig files (`multiplyDivide`).
    pub name: String,
    /// One line on what the node does.
    pub doc: String,
    /// Attributes in declaration order; `AttrId` indexes this list.
    pub attrs: Vec<AttrSpec>,
    /// Whether the node reads the graph's time (animation curves, `time`).
    pub time_dependent: bool,
    /// Parenting hookup, for transform-like nodes.
    pub dag: Option<DagSpec>,
    /// The outputs that report problems of the evaluation (see [`StatusSpec`]).
    pub status: Option<StatusSpec>,
    groups: Vec<ComputeGroup>,
    /// For each attribute: its group if it is an output; `u16::MAX` for inputs.
    group_of: Vec<u16>,
    /// For each input: the groups it affects.
    affected_groups: Vec<Vec<u16>>,
    by_name: HashMap<String, (AttrId, Option<u8>)>,
    by_short: HashMap<String, (AttrId, Option<u8>)>,
    /// Index of the first custom attribute (`attrs.len()` when the node has none; see
    /// [`NodeSpec::custom_attrs`]).
    pub(crate) custom_start: u16,
    /// The attributes with every input before the outputs it affects (the order a new
    /// node's attributes take in the graph's topological order; `graph/order.rs`).
    pub(crate) attr_order: Vec<AttrId>,
}

impl NodeSpec {
    /// Starts building a spec for the node type `name`.
    pub fn builder(name: &str) -> SpecBuilder {
        SpecBuilder {
            name: name.to_string(),
            doc: String::new(),
            attrs: Vec::new(),
            affects: Vec::new(),
            time_dependent: false,
            time_outputs: Vec::new(),
            dag: None,
            status: None,
            maya_names: Vec::new(),
            explicit: false,
            custom_start: None,
        }
    }

    /// The attribute with id `id`.
    ///
    /// # Panics
    /// Panics if `id` does not belong to this spec (a plugin bug, never user data).
    pub fn attr(&self, id: AttrId) -> &AttrSpec {
        &self.attrs[id.index()]
    }

    /// Looks up an attribute or a vec3 child by its long or Maya short name:
    /// `translate` and `t` give `(translate, None)`, `translateY` and `ty` give
    /// `(translate, Some(1))`.
    pub fn find(&self, name: &str) -> Option<(AttrId, Option<u8>)> {
        self.by_name.get(name).or_else(|| self.by_short.get(name)).copied()
    }

    /// All long names that [`NodeSpec::find`] accepts (attributes and vec3 children), for
    /// "did you mean" hints; short names are aliases and not listed.
    pub fn all_names(&self) -> impl Iterator<Item = &str> {
        self.by_name.keys().map(|s| s.as_str())
    }

    /// Whether `name` is a short name (an alias) rather than a long name.
    pub fn is_short_name(&self, name: &str) -> bool {
        !self.by_name.contains_key(name) && self.by_short.contains_key(name)
    }

    /// The compute groups of this node type.
    pub fn groups(&self) -> &[ComputeGroup] {
        &self.groups
    }

    /// The group an output belongs to (`None` for inputs).
    pub fn group_of(&self, id: AttrId) -> Option<u16> {
        match self.group_of.get(id.index()) {
            Some(&g) if g != u16::MAX => Some(g),
            _ => None,
        }
    }

    /// Whether group `g` reads the graph's time.
    pub fn group_time_dependent(&self, g: u16) -> bool {
        self.groups.get(g as usize).is_some_and(|x| x.time_dependent)
    }

    /// The groups an attribute affects: for an input, the groups that read it;
    /// for an output, the other groups of this node that read it.
    pub fn groups_affected_by(&self, id: AttrId) -> &[u16] {
        self.affected_groups
            .get(id.index())
            .map(|v| v.as_slice())
            .unwrap_or(&[])
    }

    /// Ids of all attributes.
    pub fn attr_ids(&self) -> impl Iterator<Item = AttrId> {
        (0..self.attrs.len() as u16).map(AttrId)
    }

    /// The custom attributes of a node (Maya's `addAttr`), after the type's own: empty
    /// for a node type's spec. Their ids start at [`NodeSpec::first_custom`].
    pub fn custom_attrs(&self) -> &[AttrSpec] {
        self.attrs.get(self.custom_start as usize..).unwrap_or(&[])
    }

    /// The id of the first custom attribute (the type's attribute count).
    pub fn first_custom(&self) -> AttrId {
        AttrId(self.custom_start)
    }

    /// Whether attribute `id` is a custom attribute.
    pub fn is_custom(&self, id: AttrId) -> bool {
        id.0 >= self.custom_start && id.index() < self.attrs.len()
    }
}

/// Builds a [`NodeSpec`]; each `input`/`output` call returns a typed handle
/// that the plugin keeps to read or write that attribute in `compute`.
#[derive(Debug)]
pub struct SpecBuilder {
    name: String,
    doc: String,
    pub(crate) attrs: Vec<AttrSpec>,
    pub(crate) affects: Vec<(AttrId, AttrId)>,
    pub(crate) time_dependent: bool,
    pub(crate) time_outputs: Vec<AttrId>,
    pub(crate) dag: Option<DagSpec>,
    pub(crate) status: Option<StatusSpec>,
    /// `(long, short)` pairs given to [`SpecBuilder::maya_names`], applied by `build`.
    maya_names: Vec<(String, String)>,
    /// Set for specs with custom attributes: `affects` and `time_outputs` are complete
    /// (no all-to-all default, no "every output reads time" default).
    pub(crate) explicit: bool,
    /// Where custom attributes start (`attrs.len()` unless set).
    pub(crate) custom_start: Option<u16>,
}

impl SpecBuilder {
    fn push(&mut self, name: &str, ty: AttrType, direction: Direction, default: Value, multi: bool) -> AttrId {
        let id = AttrId(self.attrs.len() as u16);
        let children = (ty == AttrType::Vec3).then(|| ["X", "Y", "Z"].map(|s| format!("{name}{s}")));
        self.attrs.push(AttrSpec {
            name: name.to_string(),
            ty,
            direction,
            default,
            keyable: direction == Direction::Input
                && matches!(
                    ty,
                    AttrType::Bool | AttrType::Int | AttrType::Float | AttrType::Vec3 | AttrType::Enum
                ),
            multi,
            children,
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
        });
        id
    }

    /// Sets the one-line description of the node type.
    pub fn doc(&mut self, doc: &str) -> &mut Self {
        self.doc = doc.to_string();
        self
    }

    /// Declares a single-valued input with a default.
    pub fn input<T: AttrValue>(&mut self, name: &str, default: T) -> Input<T> {
        Input::new(self.push(name, T::TYPE, Direction::Input, default.into_value(), false))
    }

    /// Declares an enum input with its choices and default index.
    pub fn input_enum(&mut self, name: &str, choices: &[&str], default: i64) -> Input<i64> {
        let id = self.push(name, AttrType::Enum, Direction::Input, Value::Enum(default), false);
        self.attrs[id.index()].enum_names = choices.iter().map(|s| s.to_string()).collect();
        Input::new(id)
    }

    /// Declares a multi (array) input; each element starts at `default`.
    pub fn multi_input<T: AttrValue>(&mut self, name: &str, default: T) -> MultiInput<T> {
        MultiInput::new(self.push(name, T::TYPE, Direction::Input, default.into_value(), true))
    }

    /// Declares a single-valued output; `initial` is its value before the first compute.
    pub fn output<T: AttrValue>(&mut self, name: &str, initial: T) -> Output<T> {
        Output::new(self.push(name, T::TYPE, Direction::Output, initial.into_value(), false))
    }

    /// Declares a multi (array) output; elements exist where something reads them.
    pub fn multi_output<T: AttrValue>(&mut self, name: &str, initial: T) -> MultiOutput<T> {
        MultiOutput::new(self.push(name, T::TYPE, Direction::Output, initial.into_value(), true))
    }

    fn attr_mut(&mut self, id: impl Into<AttrId>) -> Option<&mut AttrSpec> {
        self.attrs.get_mut(id.into().index())
    }

    /// Sets the one-line description of an attribute.
    pub fn attr_doc(&mut self, id: impl Into<AttrId>, doc: &str) -> &mut Self {
        if let Some(a) = self.attr_mut(id) {
            a.doc = doc.to_string();
        }
        self
    }

    /// Renames the children of a vec3 attribute by suffix (`["R", "G", "B"]`
    /// gives `colorIfTrueR`...), as Maya does for colour attributes.
    pub fn child_suffixes(&mut self, id: impl Into<AttrId>, suffixes: [&str; 3]) -> &mut Self {
        if let Some(a) = self.attr_mut(id) {
            let name = a.name.clone();
            a.children = Some(suffixes.map(|s| format!("{name}{s}")));
        }
        self
    }

    /// Sets the full names of the children of a vec3 attribute, for Maya
    /// attributes whose children do not follow the suffix rule
    /// (`inTranslate1` has children `inTranslateX1`...).
    pub fn child_names(&mut self, id: impl Into<AttrId>, names: [&str; 3]) -> &mut Self {
        if let Some(a) = self.attr_mut(id) {
            a.children = Some(names.map(|s| s.to_string()));
        }
        self
    }

    /// Marks an attribute as an angle in degrees (or another unit).
    pub fn unit(&mut self, id: impl Into<AttrId>, unit: Unit) -> &mut Self {
        if let Some(a) = self.attr_mut(id) {
            a.unit = unit;
        }
        self
    }

    /// Declares how the attribute's authored value is mirrored when a rig
    /// component is instantiated with `mirror:` (see [`MirrorRole`]).
    pub fn mirror(&mut self, id: impl Into<AttrId>, role: MirrorRole) -> &mut Self {
        if let Some(a) = self.attr_mut(id) {
            a.mirror = role;
        }
        self
    }

    /// Sets whether an input is keyable.
    pub fn keyable(&mut self, id: impl Into<AttrId>, keyable: bool) -> &mut Self {
        if let Some(a) = self.attr_mut(id) {
            a.keyable = keyable;
        }
        self
    }

    /// Declares Maya's short name of an attribute (`t` for `translate`). The children of a
    /// vec3 get `short` plus their long name's suffix in lower case (`tx ty tz`, `ctr ctg
    /// ctb` for `colorIfTrueR/G/B`); use [`SpecBuilder::child_short_names`] when Maya's
    /// do not follow that rule. A short name that collides with another attribute's long
    /// or short name makes [`SpecBuilder::build`] fail.
    pub fn short_name(&mut self, id: impl Into<AttrId>, short: &str) -> &mut Self {
        if let Some(a) = self.attr_mut(id) {
            a.short_name = Some(short.to_string());
            a.child_short_names = a.children.as_ref().and_then(|ch| {
                let suffix = |c: &String| {
                    c.strip_prefix(a.name.as_str())
                        .map(|s| format!("{short}{}", s.to_lowercase()))
                };
                Some([suffix(&ch[0])?, suffix(&ch[1])?, suffix(&ch[2])?])
            });
        }
        self
    }

    /// Sets (`Some`) or removes (`None`) Maya's short names of the children of a vec3
    /// attribute, after [`SpecBuilder::short_name`], when Maya's do not follow its suffix
    /// rule (`inTranslate1` is `it1`, its children `itx1 ity1 itz1`) or the children have
    /// no Maya counterpart.
    pub fn child_short_names(&mut self, id: impl Into<AttrId>, names: Option<[&str; 3]>) -> &mut Self {
        if let Some(a) = self.attr_mut(id) {
            a.child_short_names = names.map(|n| n.map(|s| s.to_string()));
        }
        self
    }

    /// Declares Maya's short names by long name, `(long, short)` pairs, resolved when the
    /// spec is built (so it may come right after [`NodeSpec::builder`]). A pair naming an
    /// attribute works as [`SpecBuilder::short_name`] (vec3 children get the derived
    /// names); a pair naming a vec3 child (`("inTranslateX1", "itx1")`) sets that child's
    /// short name, for children that do not follow the suffix rule. A long name the spec
    /// does not have makes [`SpecBuilder::build`] fail.
    pub fn maya_names(&mut self, pairs: &[(&str, &str)]) -> &mut Self {
        self.maya_names
            .extend(pairs.iter().map(|&(l, s)| (l.to_string(), s.to_string())));
        self
    }

    /// Applies the pairs of [`SpecBuilder::maya_names`]: attributes first, then children.
    fn apply_maya_names(&mut self) -> Result<(), String> {
        let pairs = std::mem::take(&mut self.maya_names);
        let mut children = Vec::new();
        for (long, short) in &pairs {
            match self.attrs.iter().position(|a| a.name == *long) {
                Some(i) => {
                    self.short_name(AttrId(i as u16), short);
                }
                None => children.push((long, short)),
            }
        }
        for (long, short) in children {
            let found = self.attrs.iter_mut().find_map(|a| {
                let k = a.children.as_ref()?.iter().position(|c| c == long)?;
                Some((a, k))
            });
            let Some((a, k)) = found else {
                return Err(format!(
                    "maya_names names {long:?}, which is not an attribute or a vec3 child"
                ));
            };
            let names = a.child_short_names.get_or_insert_with(Default::default);
            names[k] = short.clone();
        }
        for a in &self.attrs {
            if let Some(ch) = &a.child_short_names {
                if ch.iter().any(|c| c.is_empty()) {
                    return Err(format!(
                        "attribute {} has short names for some of its children only",
                        a.name
                    ));
                }
            }
        }
        Ok(())
    }

    /// The inputs declared so far, in declaration order (handy for "every input affects
    /// these outputs" when a node splits its outputs into several groups).
    pub fn input_ids(&self) -> Vec<AttrId> {
        (0..self.attrs.len())
            .filter(|&i| self.attrs[i].direction == Direction::Input)
            .map(|i| AttrId(i as u16))
            .collect()
    }

    /// Declares that each of `inputs` affects each of `outputs`.
    ///
    /// When a spec declares no `affects` at all, every input affects every output.
    pub fn affects(&mut self, inputs: &[AttrId], outputs: &[AttrId]) -> &mut Self {
        for &i in inputs {
            for &o in outputs {
                self.affects.push((i, o));
            }
        }
        self
    }

    /// Marks the node as reading the graph's time (every group, unless
    /// [`SpecBuilder::time_affects`] narrows it).
    pub fn time_dependent(&mut self) -> &mut Self {
        self.time_dependent = true;
        self
    }

    /// Marks the node as time-dependent, with time affecting only `outputs`:
    /// the other groups (e.g. a curve's precomputed segments) are not re-run
    /// when time changes.
    pub fn time_affects(&mut self, outputs: &[AttrId]) -> &mut Self {
        self.time_dependent = true;
        self.time_outputs.extend_from_slice(outputs);
        self
    }

    /// Declares the DAG hookup used by `parent` in rig files.
    pub fn dag(&mut self, parent_matrix: Input<glam::DMat4>, world_matrix: Output<glam::DMat4>) -> &mut Self {
        self.dag = Some(DagSpec {
            parent_matrix: parent_matrix.id(),
            world_matrix: world_matrix.id(),
            links: Vec::new(),
        });
        self
    }

    /// Declares the outputs that report how the node's evaluation went (see
    /// [`StatusSpec`]): `status` must be an enum output whose choice 0 means fine,
    /// `message` a string output.
    pub fn status(&mut self, status: Output<i64>, message: Option<Output<std::sync::Arc<str>>>) -> &mut Self {
        self.status = Some(StatusSpec {
            status: status.id(),
            message: message.map(|m| m.id()),
        });
        self
    }

    /// Adds a parenting link (after [`SpecBuilder::dag`]): when this node is
    /// parented under a node that has an attribute `parent_attr` of the same
    /// type, that attribute is connected into `child_input`.
    pub fn dag_link<T>(&mut self, parent_attr: &str, child_input: Input<T>) -> &mut Self {
        if let Some(d) = &mut self.dag {
            d.links.push(DagLink {
                parent_attr: parent_attr.to_string(),
                child_input: child_input.id(),
                parent_type: None,
            });
        }
        self
    }

    /// Like [`SpecBuilder::dag_link`], but only when the parent is of node type
    /// `parent_type` (Maya links `scale` to `inverseScale` only joint to joint).
    pub fn dag_link_from<T>(&mut self, parent_type: &str, parent_attr: &str, child_input: Input<T>) -> &mut Self {
        if let Some(d) = &mut self.dag {
            d.links.push(DagLink {
                parent_attr: parent_attr.to_string(),
                child_input: child_input.id(),
                parent_type: Some(parent_type.to_string()),
            });
        }
        self
    }

    /// Declares a multi enum input with its choices and default index.
    pub fn multi_input_enum(&mut self, name: &str, choices: &[&str], default: i64) -> MultiInput<i64> {
        let id = self.push(name, AttrType::Enum, Direction::Input, Value::Enum(default), true);
        self.attrs[id.index()].enum_names = choices.iter().map(|s| s.to_string()).collect();
        MultiInput::new(id)
    }

    /// Declares an enum output with its choices (written as an `i64` index).
    pub fn output_enum(&mut self, name: &str, choices: &[&str], initial: i64) -> Output<i64> {
        let id = self.push(name, AttrType::Enum, Direction::Output, Value::Enum(initial), false);
        self.attrs[id.index()].enum_names = choices.iter().map(|s| s.to_string()).collect();
        Output::new(id)
    }

    /// Finishes the spec: checks names and derives compute groups.
    pub fn build(mut self) -> Result<NodeSpec, SpecError> {
        if let Err(message) = self.apply_maya_names() {
            return Err(SpecError {
                node_type: self.name.clone(),
                message,
            });
        }
        let err = |message: String| SpecError {
            node_type: self.name.clone(),
            message,
        };
        if self.name.is_empty() || !self.name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(err(format!(
                "node type name {:?} must be a non-empty identifier",
                self.name
            )));
        }
        if self.attrs.len() >= u16::MAX as usize {
            return Err(err("too many attributes".into()));
        }
        let mut by_name = HashMap::new();
        let mut by_short = HashMap::new();
        for (i, a) in self.attrs.iter().enumerate() {
            let id = AttrId(i as u16);
            if a.default.attr_type() != a.ty && !(a.ty == AttrType::Enum && a.default.attr_type() == AttrType::Int) {
                return Err(err(format!(
                    "attribute {} default has type {} but the attribute is {}",
                    a.name,
                    a.default.attr_type(),
                    a.ty
                )));
            }
            let mut names = vec![(a.name.clone(), (id, None))];
            if let Some(ch) = &a.children {
                for (k, c) in ch.iter().enumerate() {
                    names.push((c.clone(), (id, Some(k as u8))));
                }
            }
            for (n, v) in names {
                if n.is_empty() || !n.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                    return Err(err(format!("attribute name {n:?} must be an identifier")));
                }
                if by_name.insert(n.clone(), v).is_some() {
                    return Err(err(format!("attribute name {n:?} is declared twice")));
                }
            }
            if a.child_short_names.is_some() && (a.short_name.is_none() || a.children.is_none()) {
                return Err(err(format!(
                    "attribute {} has child short names but no short name or no children",
                    a.name
                )));
            }
            let shorts =
                a.short_name
                    .iter()
                    .map(|s| (s.clone(), (id, None)))
                    .chain(a.child_short_names.iter().flat_map(|ch| {
                        ch.iter()
                            .enumerate()
                            .map(move |(k, c)| (c.clone(), (id, Some(k as u8))))
                    }));
            for (n, v) in shorts {
                if n.is_empty() || !n.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                    return Err(err(format!("short name {n:?} of {} must be an identifier", a.name)));
                }
                if by_short.insert(n.clone(), v).is_some() {
                    return Err(err(format!("short name {n:?} (of {}) is declared twice", a.name)));
                }
            }
        }
        // A short name may not be another attribute's long name (`find` tries long names
        // first, so the short one would never be reached); its own long name is fine
        // (Maya's `weight (w)`... and attributes whose two names are equal).
        for (n, &(id, k)) in &by_short {
            if let Some(&(other, ok)) = by_name.get(n) {
                if (other, ok) != (id, k) {
                    let owner = &self.attrs[id.index()].name;
                    return Err(err(format!(
                        "short name {n:?} of {owner} collides with the long name of {}",
                        self.attrs[other.index()].name
                    )));
                }
            }
        }
        let n = self.attrs.len();
        let is_out = |id: AttrId| self.attrs.get(id.index()).map(|a| a.direction == Direction::Output);
        for &(i, o) in &self.affects {
            if is_out(i).is_none() || is_out(o) != Some(true) || i == o {
                return Err(err(format!(
                    "affects must go from an input (or another output) to an output ({} -> {})",
                    i.0, o.0
                )));
            }
        }
        for &o in &self.time_outputs {
            if is_out(o) != Some(true) {
                return Err(err(format!(
                    "time_affects names attribute {} which is not an output",
                    o.0
                )));
            }
        }
        // inputs affecting each output
        let inputs: Vec<AttrId> = (0..n as u16)
            .map(AttrId)
            .filter(|&a| is_out(a) == Some(false))
            .collect();
        let outputs: Vec<AttrId> = (0..n as u16).map(AttrId).filter(|&a| is_out(a) == Some(true)).collect();
        let mut groups: Vec<ComputeGroup> = Vec::new();
        let mut group_of = vec![u16::MAX; n];
        for &o in &outputs {
            let mut ins: Vec<AttrId> = if self.affects.is_empty() && !self.explicit {
                inputs.clone()
            } else {
                self.affects
                    .iter()
                    .filter(|(_, out)| *out == o)
                    .map(|(i, _)| *i)
                    .collect()
            };
            ins.sort();
            ins.dedup();
            let timed = self.time_dependent
                && ((self.time_outputs.is_empty() && !self.explicit) || self.time_outputs.contains(&o));
            let g = match groups.iter().position(|g| g.inputs == ins && g.time_dependent == timed) {
                Some(g) => g,
                None => {
                    groups.push(ComputeGroup {
                        outputs: Vec::new(),
                        inputs: ins,
                        time_dependent: timed,
                    });
                    groups.len() - 1
                }
            };
            groups[g].outputs.push(o);
            group_of[o.index()] = g as u16;
        }
        // Output-to-output affects must not loop between groups.
        let group_deps = |g: usize| -> Vec<usize> {
            groups[g]
                .inputs
                .iter()
                .filter(|i| group_of[i.index()] != u16::MAX)
                .map(|i| group_of[i.index()] as usize)
                .collect()
        };
        for start in 0..groups.len() {
            let mut stack = group_deps(start);
            let mut seen = vec![false; groups.len()];
            while let Some(g) = stack.pop() {
                if g == start {
                    return Err(err(
                        "outputs affect each other in a loop; an output group cannot depend on itself".into(),
                    ));
                }
                if !std::mem::replace(&mut seen[g], true) {
                    stack.extend(group_deps(g));
                }
            }
        }
        let mut affected_groups = vec![Vec::new(); n];
        for (g, grp) in groups.iter().enumerate() {
            for i in &grp.inputs {
                affected_groups[i.index()].push(g as u16);
            }
        }
        if let Some(d) = &self.dag {
            let ok = self.attrs.get(d.parent_matrix.index()).map(|a| (a.ty, a.direction))
                == Some((AttrType::Matrix, Direction::Input))
                && self.attrs.get(d.world_matrix.index()).map(|a| (a.ty, a.direction))
                    == Some((AttrType::Matrix, Direction::Output));
            if !ok {
                return Err(err("dag hookup must name a matrix input and a matrix output".into()));
            }
        }
        if let Some(st) = &self.status {
            let is = |id: AttrId, ty: AttrType| {
                self.attrs.get(id.index()).map(|a| (a.ty, a.direction, a.multi)) == Some((ty, Direction::Output, false))
            };
            if !is(st.status, AttrType::Enum) || st.message.is_some_and(|m| !is(m, AttrType::String)) {
                return Err(err(
                    "status must name a single enum output (and a single string output for its message)".into(),
                ));
            }
        }
        let custom_start = self.custom_start.unwrap_or(self.attrs.len() as u16);
        let mut spec = NodeSpec {
            attr_order: Vec::new(),
            custom_start,
            name: self.name,
            doc: self.doc,
            attrs: self.attrs,
            time_dependent: self.time_dependent,
            dag: self.dag,
            status: self.status,
            groups,
            group_of,
            affected_groups,
            by_name,
            by_short,
        };
        spec.attr_order = crate::graph::attr_topological_order(&spec);
        Ok(spec)
    }
}

macro_rules! handle {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Debug)]
        pub struct $name<T> {
            id: AttrId,
            _t: PhantomData<fn() -> T>,
        }
        impl<T> Clone for $name<T> {
            fn clone(&self) -> Self {
                *self
            }
        }
        impl<T> Copy for $name<T> {}
        impl<T> $name<T> {
            /// Wraps an attribute id (normally done by [`SpecBuilder`]).
            pub const fn new(id: AttrId) -> Self {
                $name { id, _t: PhantomData }
            }
            /// The attribute id.
            #[inline]
            pub fn id(self) -> AttrId {
                self.id
            }
        }
        impl<T> From<$name<T>> for AttrId {
            fn from(h: $name<T>) -> AttrId {
                h.id
            }
        }
    };
}

handle!(
    /// Typed handle to a single-valued input attribute.
    Input
);
handle!(
    /// Typed handle to a multi (array) input attribute.
    MultiInput
);
handle!(
    /// Typed handle to a single-valued output attribute.
    Output
);
handle!(
    /// Typed handle to a multi (array) output attribute.
    MultiOutput
);

#[cfg(test)]
#[path = "spec_tests.rs"]
mod tests;
