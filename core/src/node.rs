//! The plugin API: the `NodeType` trait every node type implements, the
//! `Time` a node may read, and the `ComputeContext` through which `compute`
//! reads inputs and writes outputs by typed handles.
//!
//! The same `compute` runs in both evaluation modes: lazily from a
//! [`Graph`](crate::Graph) and from a compiled [`Program`](crate::Program).
//! The context hides which; that is what makes the two bit-identical.

use std::sync::Arc;

use crate::error::ComputeError;
use crate::graph::store::AttrStore;
use crate::program::{AttrBinding, Binding, CompiledTables};
use crate::spec::{AttrId, Input, MultiInput, MultiOutput, NodeSpec, Output};
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
}

pub(crate) struct CompiledIo<'a> {
    pub slots: &'a mut [Value],
    pub attrs: &'a [AttrBinding],
    pub tables: &'a CompiledTables,
}

pub(crate) enum Io<'a> {
    Lazy(LazyIo<'a>),
    Compiled(CompiledIo<'a>),
}

/// What `compute` sees: typed reads of inputs, typed writes of outputs, time.
pub struct ComputeContext<'a> {
    pub(crate) io: Io<'a>,
    pub(crate) spec: &'a NodeSpec,
    pub(crate) group: u16,
    pub(crate) time: Time,
}

impl<'a> ComputeContext<'a> {
    /// The current time (meaningful for time-dependent node types).
    #[inline]
    pub fn time(&self) -> Time {
        self.time
    }

    /// Whether this call computes the group containing `out`.
    #[inline]
    pub fn wants(&self, out: impl Into<AttrId>) -> bool {
        self.spec.group_of(out.into()) == Some(self.group)
    }

    #[inline]
    fn read_elem(&self, id: AttrId, k: usize) -> Option<Value> {
        match &self.io {
            Io::Lazy(io) => io.attrs.get(id.index())?.elems.get(k).map(|e| e.value.clone()),
            Io::Compiled(io) => {
                let b = io.attrs.get(id.index())?;
                if k >= b.len as usize {
                    return None;
                }
                let e = io.tables.elems.get(b.first as usize + k)?;
                Some(io.tables.resolve(io.slots, e.binding))
            }
        }
    }

    #[inline(always)]
    fn read_with<T: AttrValue>(&self, id: AttrId, k: usize) -> Option<T> {
        // Fast paths avoid cloning the whole value for plain slots.
        if let (Io::Compiled(io), 0) = (&self.io, k) {
            let b = io.attrs.get(id.index())?;
            if b.len == 0 {
                return None;
            }
            return match b.head {
                Binding::Slot(s) => T::from_value(io.slots.get(s as usize)?),
                other => T::from_value(&io.tables.resolve(io.slots, other)),
            };
        }
        match &self.io {
            Io::Lazy(io) => io
                .attrs
                .get(id.index())?
                .elems
                .get(k)
                .and_then(|e| T::from_value(&e.value)),
            Io::Compiled(io) => {
                let b = io.attrs.get(id.index())?;
                if k >= b.len as usize {
                    return None;
                }
                let e = io.tables.elems.get(b.first as usize + k)?;
                match e.binding {
                    Binding::Slot(s) => T::from_value(io.slots.get(s as usize)?),
                    _ => T::from_value(&io.tables.resolve(io.slots, e.binding)),
                }
            }
        }
    }

    fn fallback<T: AttrValue>(&self, id: AttrId) -> T {
        T::from_value(&self.spec.attr(id).default).unwrap_or_default()
    }

    /// Reads a single-valued input.
    #[inline]
    pub fn get<T: AttrValue>(&self, h: Input<T>) -> T {
        self.read_with(h.id(), 0).unwrap_or_else(|| self.fallback(h.id()))
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
        match &self.io {
            Io::Lazy(io) => io.attrs.get(id.index()).map_or(0, |a| a.elems.len()),
            Io::Compiled(io) => io.attrs.get(id.index()).map_or(0, |b| b.len as usize),
        }
    }

    fn elem_index(&self, id: AttrId, k: usize) -> Option<u32> {
        match &self.io {
            Io::Lazy(io) => io.attrs.get(id.index())?.elems.get(k).map(|e| e.index),
            Io::Compiled(io) => {
                let b = io.attrs.get(id.index())?;
                if k >= b.len as usize {
                    return None;
                }
                io.tables.elems.get(b.first as usize + k).map(|e| e.index)
            }
        }
    }

    /// The `k`-th existing element of a multi input (in index order) as
    /// `(logical index, value)`; `None` past the end.
    pub fn multi_at<T: AttrValue>(&self, h: MultiInput<T>, k: usize) -> Option<(u32, T)> {
        let idx = self.elem_index(h.id(), k)?;
        let v = self.read_with(h.id(), k).unwrap_or_else(|| self.fallback(h.id()));
        Some((idx, v))
    }

    /// The element with logical index `index` of a multi input, if it exists.
    pub fn get_at<T: AttrValue>(&self, h: MultiInput<T>, index: u32) -> Option<T> {
        let n = self.elem_count(h.id());
        let k = (0..n).find(|&k| self.elem_index(h.id(), k) == Some(index))?;
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

    #[inline(always)]
    fn write<T: AttrValue>(&mut self, id: AttrId, k: usize, v: T) {
        match &mut self.io {
            Io::Compiled(io) => {
                let Some(b) = io.attrs.get(id.index()) else { return };
                if b.group != self.group || k >= b.len as usize {
                    return;
                }
                let binding = if k == 0 {
                    b.head
                } else {
                    io.tables.elems.get(b.first as usize + k).map_or(b.head, |e| e.binding)
                };
                if let Binding::Slot(s) = binding {
                    if let Some(slot) = io.slots.get_mut(s as usize) {
                        v.write_into(slot);
                    }
                }
            }
            Io::Lazy(io) => {
                if self.spec.group_of(id) != Some(self.group) {
                    return;
                }
                if let Some(e) = io.attrs.get_mut(id.index()).and_then(|a| a.elems.get_mut(k)) {
                    let mut v_new = e.value.clone();
                    v.write_into(&mut v_new);
                    let v = v_new;
                    if !e.value.same_bits(&v) {
                        e.value = v;
                        e.changed_at = io.revision;
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
        let n = self.elem_count(h.id());
        if let Some(k) = (0..n).find(|&k| self.elem_index(h.id(), k) == Some(index)) {
            self.write(h.id(), k, v);
        }
    }

    /// Mutable access to shared data on an output, reusing its buffer when no
    /// one else holds it (copy-on-write). Returns `None` when the output is not
    /// in the group being computed.
    pub fn data_mut<D: SharedData>(&mut self, h: Output<Arc<D>>) -> Option<&mut D> {
        let id = h.id();
        if self.spec.group_of(id) != Some(self.group) {
            return None;
        }
        let slot: &mut Value = match &mut self.io {
            Io::Lazy(io) => {
                let e = io.attrs.get_mut(id.index())?.elems.get_mut(0)?;
                e.changed_at = io.revision;
                &mut e.value
            }
            Io::Compiled(io) => {
                let b = io.attrs.get(id.index())?;
                let s = match io.tables.elems.get(b.first as usize)?.binding {
                    Binding::Slot(s) => s as usize,
                    _ => return None,
                };
                io.slots.get_mut(s)?
            }
        };
        if D::arc_mut(slot).is_none() {
            *slot = D::wrap(Arc::new(D::default()));
        }
        D::arc_mut(slot).map(Arc::make_mut)
    }
}
