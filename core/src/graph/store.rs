//! Per-node storage of the lazy graph: one `AttrStore` per attribute, holding
//! its elements (at most one, index 0, for a single attribute; any number for a
//! multi), each with its value, its change stamp and its connections.
//!
//! A single attribute's element exists only once something was stored in it (a set, a
//! connection at either end, a computed value): until then it reads as the attribute's
//! default, unconnected, never changed. A joint has 18 attributes and a loaded chain
//! touches 5 of them, so most of a graph is defaults that take no room.

use crate::graph::Plug;
use crate::spec::AttrSpec;
use crate::value::Value;

/// The elements of one attribute, sorted by logical index.
pub(crate) type Elems = thin_vec::ThinVec<Elem>;

/// One plug's state in the lazy graph.
#[derive(Clone, Debug)]
pub(crate) struct Elem {
    /// Logical index (0 for single attributes).
    pub index: u32,
    /// Current value: set by hand, copied from the source, or computed.
    pub value: Value,
    /// Revision at which `value` last changed.
    pub changed_at: u64,
    /// The plug's connections, boxed: most plugs have none, and a graph holds one element
    /// per attribute of every node (40 bytes less per element, 17% of a joint's storage).
    links: Option<Box<Links>>,
}

/// The connections at one plug (see [`Elem::links_mut`]).
#[derive(Clone, Debug, Default)]
pub(crate) struct Links {
    /// Whole-plug source connection (inputs only).
    pub source: Option<Plug>,
    /// Per-component sources of a vec3 input (`translateX` driven alone), boxed: rare,
    /// and three plugs would make every connected plug's links twice as large.
    pub comp_sources: Option<Box<[Option<Plug>; 3]>>,
    /// Plugs this plug feeds (whole or component connections from it).
    pub dests: Vec<Plug>,
}

impl Links {
    /// Records that this plug feeds `dst`, with room for exactly one at first (most
    /// plugs feed one; a first push would make room for four).
    pub fn add_dest(&mut self, dst: Plug) {
        if self.dests.is_empty() {
            self.dests.reserve_exact(1);
        }
        self.dests.push(dst);
    }
}

impl Elem {
    pub fn new(index: u32, value: Value) -> Self {
        Elem {
            index,
            value,
            changed_at: 0,
            links: None,
        }
    }

    /// Whole-plug source connection (inputs only).
    pub fn source(&self) -> Option<Plug> {
        self.links.as_ref()?.source
    }

    /// Per-component sources of a vec3 input (`translateX` driven alone).
    pub fn comp_sources(&self) -> Option<&[Option<Plug>; 3]> {
        self.links.as_ref()?.comp_sources.as_deref()
    }

    /// Plugs this plug feeds (whole or component connections from it).
    pub fn dests(&self) -> &[Plug] {
        self.links.as_ref().map_or(&[], |l| &l.dests)
    }

    /// The plug's connections, made empty when it has none yet.
    pub fn links_mut(&mut self) -> &mut Links {
        self.links.get_or_insert_with(Default::default)
    }

    /// The plug's connections, when it has any.
    pub fn links_if_any(&mut self) -> Option<&mut Links> {
        self.links.as_deref_mut()
    }

    /// Whether anything drives this plug (whole or any component).
    pub fn is_driven(&self) -> bool {
        self.source().is_some() || self.comp_sources().is_some_and(|c| c.iter().any(|s| s.is_some()))
    }
}

/// The elements of one attribute, sorted by logical index.
#[derive(Clone, Debug, Default)]
pub(crate) struct AttrStore {
    pub elems: Elems,
    /// The attribute's position in the graph's topological order (`order.rs`): every
    /// dependency edge goes from a lower to a higher position. Given by
    /// `Graph::place_new_node` when the node is added.
    pub ord: u64,
}

impl AttrStore {
    /// Position of the element with logical index `index`.
    pub fn find(&self, index: u32) -> Option<usize> {
        self.elems.binary_search_by_key(&index, |e| e.index).ok()
    }

    /// Whether element `index` is a single attribute's element not stored yet (it reads
    /// as the attribute's default).
    pub fn is_absent_single(&self, index: u32, attr: &AttrSpec) -> bool {
        index == 0 && !attr.multi && self.elems.is_empty()
    }

    /// The value of element `index`: the stored one, or the default of a single
    /// attribute's absent element; `None` for a multi's missing element.
    pub fn value<'a>(&'a self, index: u32, attr: &'a AttrSpec) -> Option<&'a Value> {
        match self.find(index) {
            Some(k) => Some(&self.elems[k].value),
            None => self.is_absent_single(index, attr).then_some(&attr.default),
        }
    }

    /// Position of element `index` among the elements as [`AttrStore::refs`] lists them:
    /// a single attribute's absent element is at 0.
    pub fn position(&self, index: u32, attr: &AttrSpec) -> Option<usize> {
        self.find(index)
            .or_else(|| self.is_absent_single(index, attr).then_some(0))
    }

    /// Every element as code that needs all of them reads it (compiling, listing), a
    /// single attribute's absent element as its default (no connection), without copying
    /// any value.
    pub fn refs<'a>(&'a self, attr: &'a AttrSpec) -> impl Iterator<Item = ElemRef<'a>> + 'a {
        let absent = self.is_absent_single(0, attr);
        let stored = self.elems.iter().map(|e| ElemRef {
            index: e.index,
            value: &e.value,
            source: e.source(),
        });
        stored.chain(absent.then_some(ElemRef {
            index: 0,
            value: &attr.default,
            source: None,
        }))
    }

    /// Position of the element `index`, inserting it with `value` when missing.
    /// Returns `(position, created)`.
    pub fn ensure(&mut self, index: u32, value: impl FnOnce() -> Value) -> (usize, bool) {
        match self.elems.binary_search_by_key(&index, |e| e.index) {
            Ok(k) => (k, false),
            Err(k) => {
                // Room for exactly one at first: most attributes hold one element (a first
                // push would make room for four); later pushes grow as usual (amortized).
                if self.elems.is_empty() {
                    self.elems.reserve_exact(1);
                }
                self.elems.insert(k, Elem::new(index, value()));
                (k, true)
            }
        }
    }
}

/// An element as [`AttrStore::refs`] gives it.
pub(crate) struct ElemRef<'a> {
    /// Logical index (0 for single attributes).
    pub index: u32,
    /// The stored value, or the attribute's default for an absent element.
    pub value: &'a Value,
    /// Whole-plug source connection.
    pub source: Option<Plug>,
}

/// Dirty/verification state of one compute group of one node.
#[derive(Clone, Copy, Debug)]
pub(crate) struct GroupState {
    /// Something upstream changed since the last verification.
    pub dirty: bool,
    /// Must compute on the next pull, whatever the inputs say.
    pub force: bool,
    /// Revision at which the group was last verified or computed.
    pub verified_at: u64,
}

impl Default for GroupState {
    fn default() -> Self {
        GroupState {
            dirty: true,
            force: true,
            verified_at: 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An element is its value (136 bytes: a matrix inline), index, stamp and one pointer
    /// to its connections: 156 bytes, 160 aligned (it was 200 with the connections inline).
    #[test]
    fn an_element_holds_its_connections_behind_one_pointer() {
        assert_eq!(std::mem::size_of::<Value>(), 136);
        assert!(std::mem::size_of::<Elem>() <= 160, "{}", std::mem::size_of::<Elem>());
    }

    /// An attribute that stores no element costs its store alone: a pointer and its
    /// position in the topological order (a joint has 18 attributes; a loaded chain's
    /// joints store 5 elements).
    #[test]
    fn an_attribute_without_elements_is_two_words() {
        assert_eq!(std::mem::size_of::<AttrStore>(), 16);
        assert!(std::mem::size_of::<Links>() <= 56, "{}", std::mem::size_of::<Links>());
    }
}
