//! The compiled binary form of a [`Program`]: `Program::to_bytes` and
//! `Program::from_bytes`, so an engine loads a rig's schedule in microseconds
//! instead of parsing and compiling RON.
//!
//! Layout (all integers little-endian; `varint` = unsigned LEB128):
//!
//! ```text
//! header   "SINEWPRG" | format version u32 | flags u32 (0) | payload length u64 | FNV-1a 64 of payload
//! payload  node types   name, attribute count, group count, spec fingerprint (u64)
//!          nodes        name, type index, attribute base, custom attributes (see `program_custom`)
//!          attributes   first element, element count   (head binding and group are derived)
//!          elements     index, binding, driven flag (connected as a whole)
//!          assemblies   own slot, three optional component sources
//!          shared data  heavy values (strings, meshes, weights, curves, arrays), each stored once
//!          slots        initial values (small values inline, common constants as one byte, heavy by index)
//!          dynamic / own-input / pruned slot bitsets, steps (node, group), frame steps
//!          guarded schedule  0, or 1 | its frame steps | guards (binding, small value)
//! ```
//!
//! Node types are stored by name and resolved through the [`Registry`] given
//! to `from_bytes`; a type whose attributes changed since the program was
//! written (different fingerprint) is refused with a message saying to
//! recompile. Floats are stored as their exact bits, so a loaded program
//! evaluates bit-identically to the one that was saved. `Object` values
//! (plugin caches) are stored empty: they are outputs that the first
//! evaluation of an instance (always a full one) recomputes.
//!
//! Decoding never panics and validates every invariant evaluation relies on: every
//! length is checked against the bytes left before allocating, every index (slot,
//! assembly, node, group, step) is range-checked, every slot's value is type-checked
//! against the attributes bound to it, outputs are bound to whole slots, each
//! attribute's elements are in increasing index order within
//! [`MAX_ELEMENT_INDEX`], input values are finite, each node
//! group has at most one step, meshes, weights and curves are valid. Corrupt or foreign
//! bytes give an [`Error::Program`](crate::Error::Program) naming the problem. The
//! `fuzz/` target `load_program_bytes` checks this with mutated programs whose checksum
//! is recomputed.

use std::collections::HashMap;
use std::sync::Arc;

use crate::error::Result;
use crate::graph::MAX_ELEMENT_INDEX;
use crate::inactive::Guard;
use crate::program::{
    frame_schedule, Assembly, AttrBinding, Binding, CompiledTables, ElemBinding, GuardedSchedule, NodeEntry, Program,
    Step,
};
use crate::program_codec::{err, Reader, Writer, V_SHARED};
use crate::registry::Registry;
use crate::slots::Slots;
use crate::spec::{AttrId, Direction, NodeSpec};
use crate::value::{AttrType, Value};

/// The first eight bytes of every compiled program.
pub const MAGIC: &[u8; 8] = b"SINEWPRG";
/// The format version written by this build; other versions are refused.
pub const FORMAT_VERSION: u32 = 4;
const HEADER_LEN: usize = 8 + 4 + 4 + 8 + 8;

/// FNV-1a, 64 bit: the payload checksum and the spec fingerprint (stable across builds).
pub(crate) fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// A fingerprint of what a compiled program relies on in a node type's spec:
/// its name, attributes (name, type, direction, multi) in order and group count.
fn spec_fingerprint(spec: &NodeSpec) -> u64 {
    let mut w = Writer::default();
    w.str(&spec.name);
    w.varint(spec.attrs.len() as u64);
    for a in &spec.attrs {
        w.str(&a.name);
        w.str(a.ty.name());
        w.u8(matches!(a.direction, Direction::Output) as u8);
        w.u8(a.multi as u8);
    }
    w.varint(spec.groups().len() as u64);
    fnv1a(&w.buf)
}

/// The address of the `Arc` behind a heavy value (its identity, for sharing).
fn heavy_ptr(v: &Value) -> Option<usize> {
    Some(match v {
        Value::String(a) => Arc::as_ptr(a) as *const u8 as usize,
        Value::Mesh(a) => Arc::as_ptr(a) as usize,
        Value::Curve(a) => Arc::as_ptr(a) as usize,
        Value::Surface(a) => Arc::as_ptr(a) as usize,
        Value::Weights(a) => Arc::as_ptr(a) as usize,
        Value::FloatArray(a) => Arc::as_ptr(a) as usize,
        Value::IntArray(a) => Arc::as_ptr(a) as usize,
        Value::Vec3Array(a) => Arc::as_ptr(a) as usize,
        Value::MatrixArray(a) => Arc::as_ptr(a) as usize,
        _ => return None,
    })
}

impl Program {
    /// Serializes the compiled program (see the [module docs](crate::program_bin)
    /// for the layout). Load it back with [`Program::from_bytes`].
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut w = Writer::default();
        // Node types, each once.
        let mut type_index: HashMap<&str, u32> = HashMap::new();
        let mut types: Vec<&NodeSpec> = Vec::new();
        for n in &self.nodes {
            let spec = n.base.spec();
            type_index.entry(spec.name.as_str()).or_insert_with(|| {
                types.push(spec);
                (types.len() - 1) as u32
            });
        }
        w.varint(types.len() as u64);
        for spec in &types {
            w.str(&spec.name);
            w.varint(spec.attrs.len() as u64);
            w.varint(spec.groups().len() as u64);
            w.buf.extend_from_slice(&spec_fingerprint(spec).to_le_bytes());
        }
        w.varint(self.nodes.len() as u64);
        for n in &self.nodes {
            w.str(&n.name);
            w.varint(type_index.get(n.base.spec().name.as_str()).copied().unwrap_or(0) as u64);
            w.varint(n.attr_base as u64);
            w.custom_attrs(n.kind.spec().custom_attrs());
        }
        w.varint(self.attr_bindings.len() as u64);
        for ab in &self.attr_bindings {
            w.varint(ab.first as u64);
            w.varint(ab.len as u64);
        }
        w.varint(self.tables.elems.len() as u64);
        for e in &self.tables.elems {
            w.varint(e.index as u64);
            w.binding(e.binding);
            w.u8(e.driven as u8);
        }
        w.varint(self.tables.assemblies.len() as u64);
        for a in &self.tables.assemblies {
            w.varint(a.own as u64);
            for c in &a.comps {
                match c {
                    None => w.u8(0),
                    Some((s, None)) => {
                        w.u8(1);
                        w.varint(*s as u64);
                    }
                    Some((s, Some(k))) => {
                        w.u8(2);
                        w.varint(*s as u64);
                        w.u8(*k);
                    }
                }
            }
        }
        // Heavy data, each allocation once (instances and slots share it after loading too).
        let mut shared_index: HashMap<usize, u32> = HashMap::new();
        let mut shared: Vec<&Value> = Vec::new();
        let initial = self.initial.to_values();
        let slot_shared: Vec<Option<u32>> = initial
            .iter()
            .map(|v| {
                heavy_ptr(v).map(|p| {
                    *shared_index.entry(p).or_insert_with(|| {
                        shared.push(v);
                        (shared.len() - 1) as u32
                    })
                })
            })
            .collect();
        w.varint(shared.len() as u64);
        for v in &shared {
            w.shared(v);
        }
        w.varint(initial.len() as u64);
        for (v, sh) in initial.iter().zip(&slot_shared) {
            if let Some(i) = sh {
                w.u8(V_SHARED);
                w.varint(*i as u64);
                continue;
            }
            w.small(v);
        }
        w.bits(&self.dynamic_slot);
        w.bits(&self.own_input_slot);
        w.bits(&self.pruned_slot);
        w.varint(self.steps.len() as u64);
        for s in &self.steps {
            w.varint(s.node as u64);
            w.varint(s.group as u64);
        }
        w.varint(self.frame_steps.len() as u64);
        for &f in &self.frame_steps {
            w.varint(f as u64);
        }
        match &self.guarded {
            None => w.u8(0),
            Some(g) => {
                w.u8(1);
                w.varint(g.frame_steps.len() as u64);
                for &f in &g.frame_steps {
                    w.varint(f as u64);
                }
                w.varint(g.guards.len() as u64);
                for guard in &g.guards {
                    w.binding(guard.binding);
                    w.small(&guard.value);
                }
            }
        }
        let payload = w.buf;
        let mut out = Vec::with_capacity(HEADER_LEN + payload.len());
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        out.extend_from_slice(&0u32.to_le_bytes());
        out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
        out.extend_from_slice(&fnv1a(&payload).to_le_bytes());
        out.extend_from_slice(&payload);
        out
    }

    /// Loads a program written by [`Program::to_bytes`], resolving node types
    /// by name in `registry`. Corrupt, truncated or foreign bytes, an unknown
    /// node type or one whose attributes changed give an error (never a panic).
    pub fn from_bytes(bytes: &[u8], registry: &Registry) -> Result<Program> {
        let payload = check_header(bytes)?;
        decode_payload(payload, registry)
    }
}

fn check_header(bytes: &[u8]) -> Result<&[u8]> {
    if bytes.len() < 8 || &bytes[..8] != MAGIC {
        return Err(err(
            "not a sinew compiled program (missing the SINEWPRG header); write it with Program::to_bytes",
        ));
    }
    if bytes.len() < HEADER_LEN {
        return Err(err(format!("truncated header ({} bytes)", bytes.len())));
    }
    let u32_at = |o: usize| u32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]);
    let u64_at = |o: usize| {
        let mut a = [0u8; 8];
        a.copy_from_slice(&bytes[o..o + 8]);
        u64::from_le_bytes(a)
    };
    let version = u32_at(8);
    if version != FORMAT_VERSION {
        return Err(err(format!(
            "format version {version}, but this build reads version {FORMAT_VERSION}; recompile the rig with this version"
        )));
    }
    if u32_at(12) != 0 {
        return Err(err("unknown flags in the header"));
    }
    let len = u64_at(16);
    let payload = &bytes[HEADER_LEN..];
    if payload.len() as u64 != len {
        return Err(err(format!(
            "the header announces {len} payload bytes but {} follow (truncated or padded file)",
            payload.len()
        )));
    }
    if fnv1a(payload) != u64_at(24) {
        return Err(err("checksum mismatch: the bytes are corrupt"));
    }
    Ok(payload)
}

fn decode_payload(payload: &[u8], registry: &Registry) -> Result<Program> {
    let mut r = Reader { buf: payload, pos: 0 };
    // Node types.
    let n = r.count(11, "node types")?;
    let mut types = Vec::with_capacity(n);
    for _ in 0..n {
        let name = r.str("node type name")?;
        let attr_count = r.varint("attribute count")?;
        let group_count = r.varint("group count")?;
        let fingerprint = r.u64("spec fingerprint")?;
        let kind = registry.get(name).ok_or_else(|| {
            err(format!(
                "node type `{name}` is not registered{}; register the plugin that provides it before loading",
                registry
                    .suggest(name)
                    .map(|s| format!(" (did you mean `{s}`?)"))
                    .unwrap_or_default()
            ))
        })?;
        let spec = kind.spec();
        if spec.attrs.len() as u64 != attr_count
            || spec.groups().len() as u64 != group_count
            || spec_fingerprint(spec) != fingerprint
        {
            return Err(err(format!(
                "node type `{name}` changed since the program was compiled (its attributes or compute groups differ); recompile the rig"
            )));
        }
        types.push(kind.clone());
    }
    // Nodes.
    let n = r.count(3, "nodes")?;
    let mut nodes = Vec::with_capacity(n);
    let mut node_index = crate::FastMap::with_capacity_and_hasher(n, Default::default());
    for i in 0..n {
        let name = r.str("node name")?;
        let t = r.u32v("node type index")? as usize;
        let base = types
            .get(t)
            .cloned()
            .ok_or_else(|| r.fail(&format!("node type index {t} out of range")))?;
        let attr_base = r.u32v("attribute base")?;
        let custom = r.custom_attrs()?;
        let kind = crate::custom::node_type_with(&base, &custom)
            .map_err(|e| r.fail(&format!("custom attributes of node `{name}`: {}", e.message)))?;
        if node_index.insert(name.to_string(), i as u32).is_some() {
            return Err(r.fail(&format!("node name `{name}` appears twice")));
        }
        nodes.push(NodeEntry {
            name: name.to_string(),
            kind,
            base,
            attr_base,
        });
    }
    // Attribute bindings (head and group are filled in once elements are known).
    let n = r.count(2, "attributes")?;
    let mut attr_bindings = Vec::with_capacity(n);
    for _ in 0..n {
        let first = r.u32v("first element")?;
        let len = r.u32v("element count")?;
        attr_bindings.push(AttrBinding {
            first,
            len,
            ..AttrBinding::default()
        });
    }
    let n = r.count(4, "elements")?;
    let mut elems = Vec::with_capacity(n);
    for _ in 0..n {
        let index = r.u32v("element index")?;
        let binding = r.binding()?;
        let driven = match r.u8("element driven flag")? {
            0 => false,
            1 => true,
            t => return Err(r.fail(&format!("bad element driven flag {t}"))),
        };
        elems.push(ElemBinding { index, binding, driven });
    }
    let n = r.count(4, "assemblies")?;
    let mut assemblies = Vec::with_capacity(n);
    for _ in 0..n {
        let own = r.u32v("assembly slot")?;
        let mut comps = [None; 3];
        for c in &mut comps {
            *c = match r.u8("assembly component")? {
                0 => None,
                1 => Some((r.u32v("component slot")?, None)),
                2 => Some((r.u32v("component slot")?, Some(r.u8("component lane")?))),
                t => return Err(r.fail(&format!("unknown assembly component tag {t}"))),
            };
        }
        assemblies.push(Assembly { own, comps });
    }
    let n = r.count(2, "shared data")?;
    let mut shared = Vec::with_capacity(n);
    for _ in 0..n {
        shared.push(r.shared()?);
    }
    let n = r.count(1, "slots")?;
    let mut initial = Vec::with_capacity(n);
    for _ in 0..n {
        initial.push(r.value(&shared)?);
    }
    let dynamic_slot = r.bits("dynamic slots")?;
    let own_input_slot = r.bits("own input slots")?;
    let pruned_slot = r.bits("pruned slots")?;
    let n = r.count(2, "steps")?;
    let mut step_keys = Vec::with_capacity(n);
    for _ in 0..n {
        let node = r.u32v("step node")?;
        let group = r.u32v("step group")?;
        step_keys.push((node, group));
    }
    let n = r.count(1, "frame steps")?;
    let mut frame_steps = Vec::with_capacity(n);
    for _ in 0..n {
        frame_steps.push(r.u32v("frame step")?);
    }
    let guarded = match r.u8("guarded schedule flag")? {
        0 => None,
        1 => {
            let n = r.count(1, "guarded frame steps")?;
            let mut steps = Vec::with_capacity(n);
            for _ in 0..n {
                steps.push(r.u32v("guarded frame step")?);
            }
            let n = r.count(3, "guards")?;
            let mut guards = Vec::with_capacity(n);
            for _ in 0..n {
                let binding = r.binding()?;
                let value = r.value(&[])?;
                guards.push(Guard { binding, value });
            }
            Some((steps, guards))
        }
        t => return Err(r.fail(&format!("bad guarded schedule flag {t}"))),
    };
    if r.pos != payload.len() {
        return Err(r.fail("trailing bytes after the program"));
    }

    // Validation: everything evaluation and `handle` index must be in range and well typed.
    let slots = initial.len();
    if dynamic_slot.len() != slots || own_input_slot.len() != slots || pruned_slot.len() != slots {
        return Err(err("slot flag tables do not match the slot count"));
    }
    let tables = CompiledTables { elems, assemblies };
    let slot_ok = |s: u32| (s as usize) < slots;
    let slot_ty = |s: u32| initial.get(s as usize).map(|v| v.attr_type());
    for (i, a) in tables.assemblies.iter().enumerate() {
        let bad_comp = a.comps.iter().flatten().any(|&(s, k)| match k {
            None => !matches!(
                slot_ty(s),
                Some(AttrType::Float | AttrType::Int | AttrType::Enum | AttrType::Bool)
            ),
            Some(k) => k >= 3 || slot_ty(s) != Some(AttrType::Vec3),
        });
        if slot_ty(a.own) != Some(AttrType::Vec3) || bad_comp {
            return Err(err(format!("assembly {i} refers to a missing or mistyped slot")));
        }
    }
    let mut expected_base = 0u64;
    for node in &nodes {
        let spec = node.kind.spec();
        if node.attr_base as u64 != expected_base {
            return Err(err(format!("node `{}` has a wrong attribute base", node.name)));
        }
        expected_base += spec.attrs.len() as u64;
        for (a, aspec) in spec.attrs.iter().enumerate() {
            let Some(ab) = attr_bindings.get_mut(node.attr_base as usize + a) else {
                return Err(err("attribute table shorter than the nodes need"));
            };
            let end = ab.first as u64 + ab.len as u64;
            if end > tables.elems.len() as u64 || (!aspec.multi && ab.len > 1) {
                return Err(err(format!("`{}.{}` has a bad element range", node.name, aspec.name)));
            }
            let group = spec.group_of(AttrId(a as u16)).unwrap_or(u16::MAX);
            if (aspec.direction == Direction::Output) != (group != u16::MAX) {
                return Err(err(format!("`{}.{}` has no compute group", node.name, aspec.name)));
            }
            ab.group = group;
            let elems = &tables.elems[ab.first as usize..end as usize];
            // Nodes rely on elements in increasing index order (the last has the largest
            // index) and on indices within the limit (they may size arrays by them).
            if let Some(w) = elems.windows(2).find(|w| w[0].index >= w[1].index) {
                return Err(err(format!(
                    "`{}.{}` lists element {} after element {}; elements must be in increasing index order",
                    node.name, aspec.name, w[1].index, w[0].index
                )));
            }
            if let Some(e) = elems
                .iter()
                .find(|e| e.index > MAX_ELEMENT_INDEX || (!aspec.multi && e.index != 0))
            {
                return Err(err(format!(
                    "`{}.{}` has element index {}, out of range",
                    node.name, aspec.name, e.index
                )));
            }
            for e in elems {
                let ok = match e.binding {
                    Binding::Slot(s) => slot_ty(s).is_some_and(|t| t == aspec.ty || t.connects_to(aspec.ty)),
                    Binding::Component(s, k) => {
                        k < 3 && slot_ty(s) == Some(AttrType::Vec3) && aspec.ty == AttrType::Float
                    }
                    Binding::Assemble(x) => (x as usize) < tables.assemblies.len() && aspec.ty == AttrType::Vec3,
                };
                if !ok {
                    return Err(err(format!(
                        "`{}.{}[{}]` is bound to a missing or mistyped slot",
                        node.name, aspec.name, e.index
                    )));
                }
                if aspec.direction == Direction::Output && !matches!(e.binding, Binding::Slot(s) if slot_ok(s)) {
                    return Err(err(format!(
                        "output `{}.{}` is not bound to a slot",
                        node.name, aspec.name
                    )));
                }
            }
            ab.set_head(
                tables
                    .elems
                    .get(ab.first as usize)
                    .filter(|_| ab.len > 0)
                    .map(|e| e.binding),
            );
        }
    }
    if expected_base != attr_bindings.len() as u64 {
        return Err(err("attribute table does not match the nodes"));
    }
    // Input values are finite, as the graph keeps them.
    if let Some(k) = (0..slots).find(|&k| own_input_slot[k] && !initial[k].is_finite()) {
        return Err(err(format!("input slot {k} holds a non-finite value")));
    }
    let mut steps = Vec::with_capacity(step_keys.len());
    let mut seen_steps = std::collections::HashSet::with_capacity(step_keys.len());
    for (node, group) in step_keys {
        if !seen_steps.insert((node, group)) {
            return Err(err(format!("node {node} group {group} has two steps")));
        }
        let Some(entry) = nodes.get(node as usize) else {
            return Err(err(format!("step refers to node {node}, out of range")));
        };
        let spec = entry.kind.spec();
        if group as usize >= spec.groups().len() {
            return Err(err(format!(
                "step of `{}` refers to group {group}, out of range",
                entry.name
            )));
        }
        steps.push(Step::new(
            entry.kind.clone(),
            node,
            entry.attr_base,
            group as u16,
            &attr_bindings,
        ));
    }
    if let Some(&f) = frame_steps.iter().find(|&&f| f as usize >= steps.len()) {
        return Err(err(format!("frame step {f} out of range")));
    }
    let guarded = match guarded {
        None => None,
        Some((guarded_steps, guards)) => {
            if let Some(&f) = guarded_steps.iter().find(|&&f| f as usize >= steps.len()) {
                return Err(err(format!("guarded frame step {f} out of range")));
            }
            for g in &guards {
                let reads = match g.binding {
                    Binding::Slot(s) => slot_ty(s),
                    Binding::Component(s, k) => {
                        (k < 3 && slot_ty(s) == Some(AttrType::Vec3)).then_some(AttrType::Float)
                    }
                    Binding::Assemble(x) => ((x as usize) < tables.assemblies.len()).then_some(AttrType::Vec3),
                };
                if reads != Some(g.value.attr_type()) {
                    return Err(err("a guard refers to a missing or mistyped slot"));
                }
            }
            Some((guarded_steps, guards))
        }
    };
    let initial = Slots::from_values(initial);
    let floats = initial.floats.len();
    Ok(Program {
        id: crate::program::next_program_id(),
        guarded: guarded.map(|(steps_of, guards)| GuardedSchedule::new(&steps, steps_of, guards, floats)),
        frame_schedule: frame_schedule(&steps, &frame_steps, floats),
        steps,
        frame_steps,
        attr_bindings,
        tables,
        initial,
        dynamic_slot,
        own_input_slot,
        pruned_slot,
        nodes,
        node_index,
    })
}
