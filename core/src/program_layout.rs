//! Slot layout: renumbering a compiled program's slots so that each dense array of
//! [`crate::slots`] starts with the slots a frame touches, in the order it first touches
//! them. An instance's frame then walks a compact prefix of its memory forward, which the
//! hardware prefetcher follows: it matters when many instances are evaluated one after
//! another and their slots do not stay in cache.

use crate::inactive::Guard;
use crate::program::{AttrBinding, Binding, CompiledTables, Step};
use crate::slots::{Class, Slots};

/// The new id of every slot (indexed by old id): by class first (the dense arrays stay
/// contiguous), then by the position of the first step of `frame` that reads or writes
/// it, then by old id.
pub(crate) fn touch_order(
    initial: &Slots,
    frame: &[&Step],
    attr_bindings: &[AttrBinding],
    tables: &CompiledTables,
) -> Vec<u32> {
    let n = initial.len();
    let mut first_touch = vec![u32::MAX; n];
    let mut buf = Vec::new();
    for (pos, step) in frame.iter().enumerate() {
        let spec = step.kind.spec();
        let Some(group) = spec.groups().get(step.group as usize) else {
            continue;
        };
        for a in group.inputs.iter().chain(&group.outputs) {
            let Some(ab) = attr_bindings.get((step.attr_base + a.0 as u32) as usize) else {
                continue;
            };
            for eb in tables.elems.iter().skip(ab.first as usize).take(ab.len as usize) {
                buf.clear();
                tables.slots_read(eb.binding, &mut buf);
                for &s in &buf {
                    if let Some(t) = first_touch.get_mut(s as usize) {
                        *t = (*t).min(pos as u32);
                    }
                }
            }
        }
    }
    // A counting sort by (class, first touch), stable in the old id: linear in the slots
    // and the frame's length (a comparison sort of a 100,000-joint chain's 1.9 million
    // slots took a tenth of its compile).
    let untouched = frame.len();
    let key = |s: usize| initial.class(s as u32) as usize * (untouched + 1) + (first_touch[s] as usize).min(untouched);
    let keys: Vec<usize> = (0..n).map(key).collect();
    let mut start = vec![0u32; (Class::Other as usize + 1) * (untouched + 1) + 1];
    for &k in &keys {
        start[k + 1] += 1;
    }
    for k in 1..start.len() {
        start[k] += start[k - 1];
    }
    let mut new_id = vec![0u32; n];
    for (old, &k) in keys.iter().enumerate() {
        new_id[old] = start[k];
        start[k] += 1;
    }
    new_id
}

/// What a renumbering rewrites.
pub(crate) struct Renumber<'a> {
    pub attr_bindings: &'a mut [AttrBinding],
    pub tables: &'a mut CompiledTables,
    pub initial: &'a mut Slots,
    /// Per-slot flags (dynamic, own input, pruned), permuted with the slots.
    pub flags: [&'a mut Vec<bool>; 3],
    pub guards: &'a mut [Guard],
}

impl Renumber<'_> {
    /// Moves every slot `s` to `new_id[s]` (a permutation of `0..len`), rewriting every
    /// reference to it. Steps hold slot ids in their kernels: rebuild them afterwards.
    pub(crate) fn apply(self, new_id: &[u32]) {
        let map = |s: u32| new_id.get(s as usize).copied().unwrap_or(s);
        let binding = |b: Binding| match b {
            Binding::Slot(s) => Binding::Slot(map(s)),
            Binding::Component(s, k) => Binding::Component(map(s), k),
            Binding::Assemble(x) => Binding::Assemble(x),
        };
        for ab in self.attr_bindings.iter_mut() {
            let head = (ab.len > 0).then(|| binding(ab.head));
            ab.set_head(head);
        }
        for e in &mut self.tables.elems {
            e.binding = binding(e.binding);
        }
        for asm in &mut self.tables.assemblies {
            asm.own = map(asm.own);
            for c in asm.comps.iter_mut().flatten() {
                c.0 = map(c.0);
            }
        }
        for g in self.guards.iter_mut() {
            g.binding = binding(g.binding);
        }
        *self.initial = self.initial.permuted(new_id);
        for flags in self.flags {
            let mut out = vec![false; flags.len()];
            for (s, &f) in flags.iter().enumerate() {
                if let Some(o) = out.get_mut(map(s as u32) as usize) {
                    *o = f;
                }
            }
            *flags = out;
        }
    }
}
