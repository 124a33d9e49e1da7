//! The plugin API: the `NodeType` trait every node type implements, the
//! `Time` a node may read, and the `ComputeContext` through which `compute`
//! reads inputs and writes outputs by typed handles.
//!
//! The same `compute` runs in both evaluation modes: lazily from a
//! [`Graph`](crate::Graph) and from a compiled [`Program`](crate::Program).
//! The context hides which; that is what makes the two bit-identical.

use std::sync::Arc;

use crate::custom::CustomAffects;
use crate::error::{ComputeError, InputError};
use crate::graph::store::{AttrStore, Elem};
pub use crate::inactive::KnownInputs;
use crate::kernel::ScalarKernel;
use crate::mat_kernel::MatrixKernel;
use crate::program::{AttrBinding, Binding, CompiledTables, ElemBinding};
#[allow(unused_imports)] // for doc links
use crate::rig::expand::ExpandPhase;
use crate::rig::expand::{AuthoringField, ExpandContext};
use crate::slots::Slots;
use crate::spec::{AttrId, AttrSpec, Input, MultiInput, MultiOutput, NodeSpec, Output};
pub use crate::validate::{Problem, ValidateInputs};
use crate::value::{AttrValue, SharedData, Value};

/// A node type: its spec and its compute function.
///
/// Implementations must be pure: outputs depend only on the inputs of the
/// group being computed (and on time, for time-dependent nodes). A node must
/// only read inputs that affect the outputs it writes (see
/// [`SpecBuilder::affects`](crate::SpecBuilder::affects)).
pub trait NodeType: Send + Sync + 'static {
    /// The node type's spec (built once, when the plugin is created).
    fn spec(&self) -> &NodeSpec;

    /// Computes the outputs of the group `ctx` asks for.
    ///
    /// Writes to outputs outside that group are ignored, so a node with one
    /// group can simply compute everything.
    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError>;

    /// An optional fast path for trivial float nodes: when the node's whole
    /// compute is `output = op(inputs...)` over single float attributes,
    /// return that [`ScalarKernel`] (built once, with the spec) and implement
    /// `compute` as [`ScalarKernel::compute`]. A compiled program then runs
    /// the kernel directly over its slots. `compute` must give exactly what
    /// the kernel gives. The default is `None` (always call `compute`).
    fn scalar_kernel(&self) -> Option<&ScalarKernel> {
        None
    }

    /// An optional fast path for one compute group whose only output is a matrix computed
    /// by a pure function of three single matrix attributes (a world matrix from the
    /// parent's, an offset and the local one): return that [`MatrixKernel`] (built once,
    /// with the spec), and have `compute` call the same function for that group. A compiled
    /// program then runs the function directly over its matrix slots. The default is
    /// `None` (always call `compute`).
    fn matrix_kernel(&self) -> Option<&MatrixKernel> {
        None
    }

    /// For selector nodes (a blend at weight 0 or 1, a condition with fixed terms): the
    /// inputs that `compute` does not read given the inputs whose values are already known
    /// when a program is compiled (see [`KnownInputs`]). A compiled program then leaves out
    /// the steps that only feed those inputs (an FK/IK switch set to FK costs no IK solve).
    ///
    /// The contract: while every input read through `known` keeps the value it returned,
    /// no output bit of this node depends on the listed inputs. The program checks those
    /// values after each full evaluation and runs everything when one has changed. The
    /// default lists nothing.
    fn unread_inputs(&self, known: &KnownInputs<'_>) -> Vec<AttrId> {
        let _ = known;
        Vec::new()
    }

    /// Authoring fields this type accepts in rig files besides its attributes (see
    /// [`crate::rig::expand`]): compact declarations that [`NodeType::expand`] turns into
    /// connections, values and helper nodes at load. The default has none.
    fn authoring_fields(&self) -> &[AuthoringField] {
        &[]
    }

    /// Expands the authoring fields written on a node (called once per [`ExpandPhase`],
    /// only for nodes that wrote at least one): make connections and set values through
    /// `cx`, report errors with `cx.error` at the field's position. The default does nothing.
    fn expand(&self, cx: &mut ExpandContext<'_>) {
        let _ = cx;
    }

    /// Checks the node's input values for data that evaluation would refuse or silently
    /// get wrong (a weight table shorter than its mesh, unsorted keys, a knot vector of
    /// the wrong length), before any evaluation: `sinew check` and every rig load report
    /// each [`Problem`] at the position of the value the rig file wrote, with the
    /// numbers involved. `inputs` gives authored values, defaults and values arriving
    /// from static upstream data (see [`ValidateInputs`]). The default finds nothing.
    fn validate(&self, inputs: &ValidateInputs<'_>) -> Vec<Problem> {
        let _ = inputs;
        Vec::new()
    }

    /// Checks a value authored for input `attr` in a rig file beyond its type (an
    /// expression's syntax, say), so the loader reports a mistake at its place in the file
    /// (`file:line:col`, inside a string when [`InputError::offset`] is given) instead of
    /// at the first evaluation. `spec` is the node's own spec (custom attributes
    /// included). `compute` must still cope with any value (values also arrive through
    /// `set` and connections). The default accepts everything.
    fn check_input(&self, spec: &NodeSpec, attr: AttrId, value: &Value) -> Result<(), InputError> {
        let _ = (spec, attr, value);
        Ok(())
    }

    /// For node types whose compute reads or writes custom attributes (an expression node
    /// whose named inputs and outputs are custom attributes): given the custom attributes
    /// of a node (their ids start at `first`), which attributes affect each custom output
    /// and which custom outputs read the graph's time (see [`CustomAffects`]). `compute`
    /// then reaches them through [`ComputeContext::node_spec`] and handles made from their
    /// ids ([`Input::new`], [`Output::new`]).
    ///
    /// An error (a message naming the attribute and the fix) refuses the attributes. The
    /// default accepts custom inputs, which affect nothing (a rig's switches and dials that
    /// other nodes read through connections), and refuses custom outputs, which nothing
    /// would compute.
    fn custom_affects(&self, custom: &[AttrSpec], first: AttrId) -> Result<CustomAffects, String> {
        let _ = first;
        match custom.iter().find(|a| !a.is_input()) {
            Some(a) => Err(format!(
                "custom attribute {} is an output, but node type {} computes no custom outputs; make it an input",
                a.name,
                self.spec().name
            )),
            None => Ok(CustomAffects::default()),
        }
    }
}

/// The current time: a frame number and a frame rate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Time {
    /// The frame (may be fractional).
    pub frame: f64,
    /// Frames per second.
    pub fps: f64,
}

impl Time {
    /// A time at `frame` with `fps` frames per second.
    pub fn new(frame: f64, fps: f64) -> Self {
        Time { frame, fps }
    }

    /// The time in seconds (`frame / fps`; 0 when `fps` is not positive).
    pub fn seconds(&self) -> f64 {
        if self.fps > 0.0 {
            self.frame / self.fps
        } else {
            0.0
        }
    }
}

impl Default for Time {
    /// Frame 0 at 24 frames per second (Maya's default rate).
    fn default() -> Self {
        Time { frame: 0.0, fps: 24.0 }
    }
}

pub(crate) struct LazyIo<'a> {
    pub attrs: &'a mut [AttrStore],
    pub revision: u64,
    pub spec: &'a NodeSpec,
}

impl LazyIo<'_> {
    /// Element `k` of an attribute to write, a single attribute's element stored now if
    /// it was not yet (graph/store.rs); `None` past the end of a multi (nothing reads it).
    fn elem_mut(&mut self, id: AttrId, k: usize) -> Option<&mut Elem> {
        let a = self.spec.attrs.get(id.index())?;
        let store = self.attrs.get_mut(id.index())?;
        if k == 0 && !a.multi {
            store.ensure(0, || a.default.clone());
        }
        store.elems.get_mut(k)
    }
}

/// Bindings for a context that is not compiled (none: every access takes the slow path).
static NO_TABLES: CompiledTables = CompiledTables::EMPTY;

/// What `compute` sees: typed reads of inputs, typed writes of outputs, time.
///
/// In compiled mode `slots`, `attrs` and `tables` describe where the node's
/// attributes live; in lazy mode they are empty (so the inlined fast paths
/// fall through to the out-of-line lazy code) and `lazy` is set.
pub struct ComputeContext<'a> {
    pub(crate) slots: &'a mut Slots,
    pub(crate) attrs: &'a [AttrBinding],
    pub(crate) tables: &'a CompiledTables,
    pub(crate) lazy: Option<LazyIo<'a>>,
    pub(crate) node: &'a dyn NodeType,
    pub(crate) group: u16,
    pub(crate) time: Time,
}

impl<'a> ComputeContext<'a> {
    /// A context over a lazy graph node's attribute stores.
    pub(crate) fn lazy(
        no_slots: &'a mut Slots,
        attrs: &'a mut [AttrStore],
        revision: u64,
        node: &'a dyn NodeType,
        group: u16,
        time: Time,
    ) -> Self {
        ComputeContext {
            slots: no_slots,
            attrs: &[],
            tables: &NO_TABLES,
            lazy: Some(LazyIo {
                attrs,
                revision,
                spec: node.spec(),
            }),
            node,
            group,
            time,
        }
    }

    /// A context over compiled slots (`attrs` is the node's slice of attribute bindings).
    #[inline]
    pub(crate) fn compiled(
        slots: &'a mut Slots,
        attrs: &'a [AttrBinding],
        tables: &'a CompiledTables,
        node: &'a dyn NodeType,
        group: u16,
        time: Time,
    ) -> Self {
        ComputeContext {
            slots,
            attrs,
            tables,
            lazy: None,
            node,
            group,
            time,
        }
    }

    /// The spec of the node being computed: its type's, followed by the node's custom
    /// attributes ([`NodeSpec::custom_attrs`]), for node types that compute with them.
    #[inline]
    pub fn node_spec(&self) -> &'a NodeSpec {
        self.spec()
    }

    /// The spec of the node being computed.
    #[inline]
    fn spec(&self) -> &'a NodeSpec {
        match &self.lazy {
            Some(io) => io.spec,
            None => self.node.spec(),
        }
    }

    /// The current time (meaningful for time-dependent node types).
    #[inline]
    pub fn time(&self) -> Time {
        self.time
    }

    /// Whether this call computes the group containing `out`.
    #[inline]
    pub fn wants(&self, out: impl Into<AttrId>) -> bool {
        let id = out.into();
        match self.attrs.get(id.index()) {
            // Compiled bindings carry the group of outputs (`u16::MAX` for inputs, never a step's group).
            Some(b) => b.group == self.group,
            None => self.spec().group_of(id) == Some(self.group),
        }
    }

    fn read_elem(&self, id: AttrId, k: usize) -> Option<Value> {
        match &self.lazy {
            Some(io) => {
                let store = io.attrs.get(id.index())?;
                match store.elems.get(k) {
                    Some(e) => Some(e.value.clone()),
                    // A single attribute's element is stored once something is (graph/store.rs).
                    None if k == 0 => store.value(0, io.spec.attrs.get(id.index())?).cloned(),
                    None => None,
                }
            }
            None => Some(self.tables.resolve(self.slots, self.compiled_elem(id, k)?.binding)),
        }
    }

    /// The compiled binding of element `k` of an attribute (`None` past its end).
    #[inline]
    fn compiled_elem(&self, id: AttrId, k: usize) -> Option<&'a ElemBinding> {
        let b = self.attrs.get(id.index())?;
        if k >= b.len as usize {
            return None;
        }
        self.tables.elems.get(b.first as usize + k)
    }

    /// Reads element `k` of an attribute: a plain compiled slot inline, everything else out of line.
    #[inline(always)]
    fn read_with<T: AttrValue>(&self, id: AttrId, k: usize) -> Option<T> {
        if k == 0 {
            if let Some(b) = self.attrs.get(id.index()) {
                // `slot` is `u32::MAX` (out of range) unless the head element is a whole slot.
                if let Some(v) = self.slots.read::<T>(b.slot) {
                    return Some(v);
                }
            }
        }
        self.read_slow(id, k)
    }

    #[inline(never)]
    fn read_slow<T: AttrValue>(&self, id: AttrId, k: usize) -> Option<T> {
        match &self.lazy {
            Some(io) => io
                .attrs
                .get(id.index())?
                .elems
                .get(k)
                .and_then(|e| T::from_value(&e.value)),
            None => self.tables.read(self.slots, self.compiled_elem(id, k)?.binding),
        }
    }

    #[cold]
    #[inline(never)]
    fn fallback<T: AttrValue>(&self, id: AttrId) -> T {
        T::from_value(&self.spec().attr(id).default).unwrap_or_default()
    }

    /// Reads a single-valued input.
    #[inline]
    pub fn get<T: AttrValue>(&self, h: Input<T>) -> T {
        self.read_with(h.id(), 0).unwrap_or_else(|| self.fallback(h.id()))
    }

    /// Calls `f` with input `h`'s value by reference when it lives whole in a slot (no
    /// copy), else with a copy: for large values (matrices) on hot paths.
    #[inline]
    pub fn with_ref<T: AttrValue, R>(&self, h: Input<T>, f: impl FnOnce(&T) -> R) -> R {
        match self.slot_ref::<T>(h.id()) {
            Some(v) => f(v),
            None => f(&self.get(h)),
        }
    }

    /// [`ComputeContext::with_ref`] for an output of another group of this node.
    #[inline]
    pub fn with_output_ref<T: AttrValue, R>(&self, h: Output<T>, f: impl FnOnce(&T) -> R) -> R {
        match self.slot_ref::<T>(h.id()) {
            Some(v) => f(v),
            None => f(&self.get_output(h)),
        }
    }

    /// The value of a compiled single attribute bound to a whole slot, by reference.
    #[inline(always)]
    fn slot_ref<T: AttrValue>(&self, id: AttrId) -> Option<&T> {
        let b = self.attrs.get(id.index())?;
        self.slots.read_ref(b.slot)
    }

    /// Reads an output of another compute group of this node that the
    /// current group declared it depends on (`affects(&[that_output], ...)`),
    /// e.g. a precomputed curve in an `Object` output.
    #[inline]
    pub fn get_output<T: AttrValue>(&self, h: Output<T>) -> T {
        self.read_with(h.id(), 0).unwrap_or_else(|| self.fallback(h.id()))
    }

    /// Reads an input as an untyped value.
    pub fn get_value(&self, id: AttrId) -> Option<Value> {
        self.read_elem(id, 0)
    }

    /// Number of existing elements of a multi input.
    pub fn multi_len<T>(&self, h: MultiInput<T>) -> usize {
        self.elem_count(h.id())
    }

    fn elem_count(&self, id: AttrId) -> usize {
        match &self.lazy {
            Some(io) => io.attrs.get(id.index()).map_or(0, |a| a.elems.len()),
            None => self.attrs.get(id.index()).map_or(0, |b| b.len as usize),
        }
    }

    fn elem_index(&self, id: AttrId, k: usize) -> Option<u32> {
        match &self.lazy {
            Some(io) => io.attrs.get(id.index())?.elems.get(k).map(|e| e.index),
            None => self.compiled_elem(id, k).map(|e| e.index),
        }
    }

    /// The `k`-th existing element of a multi input (in index order) as
    /// `(logical index, value)`; `None` past the end.
    pub fn multi_at<T: AttrValue>(&self, h: MultiInput<T>, k: usize) -> Option<(u32, T)> {
        if self.lazy.is_none() {
            // Compiled: one lookup of the element gives both its index and its binding.
            let e = self.compiled_elem(h.id(), k)?;
            let v = self
                .tables
                .read(self.slots, e.binding)
                .unwrap_or_else(|| self.fallback(h.id()));
            return Some((e.index, v));
        }
        let idx = self.elem_index(h.id(), k)?;
        let v = self.read_with(h.id(), k).unwrap_or_else(|| self.fallback(h.id()));
        Some((idx, v))
    }

    /// The position among the existing elements of `id` of the one with logical index
    /// `index`: tried at position `index` first (dense indices, the common case), then
    /// searched.
    fn position_of(&self, id: AttrId, index: u32) -> Option<usize> {
        let n = self.elem_count(id);
        let guess = index as usize;
        if guess < n && self.elem_index(id, guess) == Some(index) {
            return Some(guess);
        }
        (0..n).find(|&k| self.elem_index(id, k) == Some(index))
    }

    /// The element with logical index `index` of a multi input, if it exists.
    pub fn get_at<T: AttrValue>(&self, h: MultiInput<T>, index: u32) -> Option<T> {
        let k = self.position_of(h.id(), index)?;
        self.read_with(h.id(), k)
    }

    /// Number of existing elements of a multi output (the ones something reads).
    pub fn multi_out_len<T>(&self, h: MultiOutput<T>) -> usize {
        self.elem_count(h.id())
    }

    /// Logical index of the `k`-th existing element of a multi output.
    pub fn multi_out_index<T>(&self, h: MultiOutput<T>, k: usize) -> Option<u32> {
        self.elem_index(h.id(), k)
    }

    /// Writes element `k` of an output: a compiled single element inline, everything else out of line.
    #[inline(always)]
    fn write<T: AttrValue>(&mut self, id: AttrId, k: usize, v: T) {
        if k == 0 {
            if let Some(b) = self.attrs.get(id.index()) {
                if b.group == self.group {
                    self.slots.write(b.slot, v);
                }
                // Outputs are always bound to whole slots: nothing else to write.
                return;
            }
        }
        self.write_slow(id, k, v);
    }

    #[inline(never)]
    fn write_slow<T: AttrValue>(&mut self, id: AttrId, k: usize, v: T) {
        let group = self.group;
        match &mut self.lazy {
            None => {
                let Some(b) = self.attrs.get(id.index()) else { return };
                if b.group != group || k >= b.len as usize {
                    return;
                }
                let binding = if k == 0 {
                    b.head
                } else {
                    self.tables
                        .elems
                        .get(b.first as usize + k)
                        .map_or(b.head, |e| e.binding)
                };
                if let Binding::Slot(s) = binding {
                    self.slots.write(s, v);
                }
            }
            Some(io) => {
                if io.spec.group_of(id) != Some(group) {
                    return;
                }
                let revision = io.revision;
                if let Some(e) = io.elem_mut(id, k) {
                    let mut v_new = e.value.clone();
                    v.write_into(&mut v_new);
                    let v = v_new;
                    if !e.value.same_bits(&v) {
                        e.value = v;
                        e.changed_at = revision;
                    }
                }
            }
        }
    }

    /// Writes a single-valued output.
    #[inline]
    pub fn set<T: AttrValue>(&mut self, h: Output<T>, v: T) {
        self.write(h.id(), 0, v);
    }

    /// Writes element `index` of a multi output (ignored when nothing reads that element).
    pub fn set_at<T: AttrValue>(&mut self, h: MultiOutput<T>, index: u32, v: T) {
        if let Some(k) = self.position_of(h.id(), index) {
            self.write(h.id(), k, v);
        }
    }

    /// Writes the `k`-th existing element (in index order, as [`Self::multi_out_index`] numbers
    /// them) of a multi output: what [`Self::set_at`] does for that element's logical index,
    /// without searching for its position. Ignored past the end.
    #[inline]
    pub fn set_elem<T: AttrValue>(&mut self, h: MultiOutput<T>, k: usize, v: T) {
        self.write(h.id(), k, v);
    }

    /// Every existing element of a multi input, in index order, as `(logical index, value)`,
    /// into `out` (cleared first): [`Self::multi_at`] for each `k`, with the attribute looked
    /// up once.
    pub fn multi_read_into<T: AttrValue>(&self, h: MultiInput<T>, out: &mut Vec<(u32, T)>) {
        out.clear();
        if self.lazy.is_none() {
            let Some(b) = self.attrs.get(h.id().index()) else {
                return;
            };
            let first = b.first as usize;
            let Some(elems) = self.tables.elems.get(first..first + b.len as usize) else {
                return;
            };
            out.extend(elems.iter().map(|e| {
                let v = self
                    .tables
                    .read(self.slots, e.binding)
                    .unwrap_or_else(|| self.fallback(h.id()));
                (e.index, v)
            }));
            return;
        }
        let n = self.elem_count(h.id());
        out.extend((0..n).filter_map(|k| self.multi_at(h, k)));
    }

    /// Mutable access to shared data on an output, reusing its buffer when no
    /// one else holds it (copy-on-write). Returns `None` when the output is not
    /// in the group being computed.
    pub fn data_mut<D: SharedData>(&mut self, h: Output<Arc<D>>) -> Option<&mut D> {
        let id = h.id();
        if self.spec().group_of(id) != Some(self.group) {
            return None;
        }
        let slot: &mut Value = match &mut self.lazy {
            Some(io) => {
                let revision = io.revision;
                let e = io.elem_mut(id, 0)?;
                e.changed_at = revision;
                &mut e.value
            }
            None => {
                let b = self.attrs.get(id.index())?;
                let s = match self.tables.elems.get(b.first as usize)?.binding {
                    Binding::Slot(s) => s,
                    _ => return None,
                };
                self.slots.value_mut(s)?
            }
        };
        if D::arc_mut(slot).is_none() {
            *slot = D::wrap(Arc::new(D::default()));
        }
        D::arc_mut(slot).map(Arc::make_mut)
    }
}
