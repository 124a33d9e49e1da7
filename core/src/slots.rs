//! Compiled value storage: a program's slots in dense arrays by type (floats, vec3s,
//! matrices, bools, enums), every other slot as a [`Value`].
//!
//! Slot ids are global (`0..len`). The compiler numbers the slots by the type of their
//! value, floats first, then vec3s, matrices, bools, enums and the rest, so slot `s` lives
//! in the array of the class whose id range holds it. A `Value` takes 136 bytes (a matrix
//! is stored inline); in its own array a float takes 8, a vec3 24, a bool 1, so an
//! instance's frame touches a fraction of the memory and its reads and writes need no
//! variant test. Which array a slot lives in only affects speed: a value stored as a
//! `Value` (a program loaded from an older binary) reads the same.

use std::any::Any;

use glam::{DMat4, DVec3};

use crate::value::{AttrValue, Value};

/// `u` as `T`, when `T` is `U` (decided at compile time).
#[inline(always)]
fn cast<U: Copy + 'static, T: AttrValue>(u: U) -> Option<T> {
    let mut t = T::default();
    *(&mut t as &mut dyn Any).downcast_mut::<U>()? = u;
    Some(t)
}

/// `v` as `U`, when `T` is `U` (decided at compile time).
#[inline(always)]
fn uncast<T: AttrValue, U: Copy + 'static>(v: &T) -> Option<U> {
    (v as &dyn Any).downcast_ref::<U>().copied()
}

/// The dense classes, in slot-id order; [`Class::Other`] slots are `Value`s.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Class {
    Float,
    Vec3,
    Matrix,
    Bool,
    Enum,
    Other,
}

impl Class {
    /// The class a value is stored in.
    pub(crate) fn of(v: &Value) -> Class {
        match v {
            Value::Float(_) => Class::Float,
            Value::Vec3(_) => Class::Vec3,
            Value::Matrix(_) => Class::Matrix,
            Value::Bool(_) => Class::Bool,
            Value::Enum(_) => Class::Enum,
            _ => Class::Other,
        }
    }
}

/// Slots being filled class by class (see [`Slots::builder`]).
pub(crate) struct SlotsBuilder {
    slots: Slots,
    /// The id the next value of each class gets.
    next: [u32; 6],
    len: usize,
}

impl SlotsBuilder {
    /// Stores `v` in the next slot of its class and returns that slot's id. At most the
    /// count given to [`Slots::builder`] per class.
    pub(crate) fn push(&mut self, v: Value) -> u32 {
        let c = Class::of(&v);
        let id = self.next[c as usize];
        self.next[c as usize] += 1;
        let s = &mut self.slots;
        match v {
            Value::Float(x) => s.floats.push(x),
            Value::Vec3(x) => s.vec3s.push(x),
            Value::Matrix(x) => s.mats.push(x),
            Value::Bool(x) => s.bools.push(x),
            Value::Enum(x) => s.enums.push(x),
            v => s.values.push(v),
        }
        id
    }

    /// Number of slots (the sum of the counts).
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    /// The slots (every class filled to its count).
    pub(crate) fn finish(self) -> Slots {
        debug_assert!(self.next[..5].iter().zip(self.slots.base).all(|(&n, b)| n == b));
        self.slots
    }
}

/// An instance's slot values (see the module documentation).
#[derive(Clone, Debug, Default)]
pub(crate) struct Slots {
    pub floats: Vec<f64>,
    pub vec3s: Vec<DVec3>,
    pub mats: Vec<DMat4>,
    pub bools: Vec<bool>,
    pub enums: Vec<i64>,
    pub values: Vec<Value>,
    /// The first slot id of the vec3s, matrices, bools, enums and values.
    base: [u32; 5],
}

impl Slots {
    /// Storage for values in slot order: the leading floats, then the vec3s, matrices,
    /// bools and enums that follow each other in that order, go to the dense arrays.
    pub(crate) fn from_values(all: Vec<Value>) -> Slots {
        Slots::collect(all)
    }

    /// [`Slots::from_values`] without the intermediate vector: each value goes straight to
    /// its dense array while the classes come in class order, and to `values` from the
    /// first one out of order on.
    pub(crate) fn collect(all: impl IntoIterator<Item = Value>) -> Slots {
        let mut out = Slots::default();
        let mut class = Class::Float;
        let mut len = 0u32;
        for v in all {
            let c = Class::of(&v);
            if class != Class::Other && c != class {
                // Close the runs of the classes before `c` (or every run, when `c` comes
                // earlier in class order than the current one).
                let next = if c > class { c } else { Class::Other };
                for k in class as usize..next as usize {
                    out.base[k] = len;
                }
                class = next;
            }
            match (class, v) {
                (Class::Float, v) => out.floats.push(v.as_f64().unwrap_or(0.0)),
                (Class::Vec3, Value::Vec3(x)) => out.vec3s.push(x),
                (Class::Matrix, Value::Matrix(x)) => out.mats.push(x),
                (Class::Bool, Value::Bool(x)) => out.bools.push(x),
                (Class::Enum, Value::Enum(x)) => out.enums.push(x),
                (_, v) => out.values.push(v),
            }
            len += 1;
        }
        for k in class as usize..Class::Other as usize {
            out.base[k] = len;
        }
        out
    }

    /// Storage for `counts[c]` slots of each class `c` (indexed by `Class as usize`), filled
    /// by [`SlotsBuilder::push`]: slot ids are given class by class, so every value of a
    /// dense class lands in its dense array, never as a `Value`.
    pub(crate) fn builder(counts: [u32; 6]) -> SlotsBuilder {
        let mut next = [0u32; 6];
        for c in 1..6 {
            next[c] = next[c - 1] + counts[c - 1];
        }
        let mut slots = Slots::default();
        slots.base.copy_from_slice(&next[1..]);
        slots.floats.reserve_exact(counts[0] as usize);
        slots.vec3s.reserve_exact(counts[1] as usize);
        slots.mats.reserve_exact(counts[2] as usize);
        slots.bools.reserve_exact(counts[3] as usize);
        slots.enums.reserve_exact(counts[4] as usize);
        slots.values.reserve_exact(counts[5] as usize);
        let len = counts.iter().map(|&c| c as usize).sum();
        SlotsBuilder { slots, next, len }
    }

    /// The class of the value in slot `s` (of its array, or of the `Value` stored there).
    pub(crate) fn class(&self, s: u32) -> Class {
        let b = self.base;
        let dense = [Class::Float, Class::Vec3, Class::Matrix, Class::Bool, Class::Enum];
        let mut start = 0;
        for (k, c) in dense.into_iter().enumerate() {
            if s >= start && s < b[k] {
                return c;
            }
            start = b[k];
        }
        self.value(s).map_or(Class::Other, Class::of)
    }

    /// The slots with slot `s` moved to `new_id[s]` (a permutation of `0..len`).
    pub(crate) fn permuted(&self, new_id: &[u32]) -> Slots {
        let mut old_of = vec![0u32; new_id.len()];
        for (old, &new) in new_id.iter().enumerate() {
            if let Some(o) = old_of.get_mut(new as usize) {
                *o = old as u32;
            }
        }
        Slots::collect(old_of.into_iter().filter_map(|old| self.get(old)))
    }

    /// Every value stored as a `Value`, none in the dense arrays (what a program from an
    /// older binary, numbered without classes, amounts to).
    #[cfg(test)]
    pub(crate) fn all_values(values: Vec<Value>) -> Slots {
        Slots {
            values,
            ..Slots::default()
        }
    }

    /// Every slot's value in slot order.
    pub(crate) fn to_values(&self) -> Vec<Value> {
        (0..self.len() as u32).filter_map(|s| self.get(s)).collect()
    }

    /// Number of slots.
    pub(crate) fn len(&self) -> usize {
        self.base[4] as usize + self.values.len()
    }

    /// Bytes of slot storage (what each instance owns, besides heavy data it shares).
    pub(crate) fn bytes(&self) -> usize {
        use std::mem::size_of;
        self.floats.len() * size_of::<f64>()
            + self.vec3s.len() * size_of::<DVec3>()
            + self.mats.len() * size_of::<DMat4>()
            + self.bools.len()
            + self.enums.len() * size_of::<i64>()
            + self.values.len() * size_of::<Value>()
    }

    /// Index of slot `s` in the array of the class starting at `base` (past the end when
    /// `s` is in another class).
    #[inline(always)]
    fn at(s: u32, base: u32) -> usize {
        s.wrapping_sub(base) as usize
    }

    /// Slot `s` when it is stored as a `Value`.
    #[inline(always)]
    pub(crate) fn value(&self, s: u32) -> Option<&Value> {
        self.values.get(Self::at(s, self.base[4]))
    }

    /// Slot `s` when it is stored as a `Value`, mutably.
    #[inline(always)]
    pub(crate) fn value_mut(&mut self, s: u32) -> Option<&mut Value> {
        self.values.get_mut(Self::at(s, self.base[4]))
    }

    /// Slot `s` when it is a matrix slot.
    #[inline(always)]
    pub(crate) fn mat(&self, s: u32) -> Option<&DMat4> {
        self.mats.get(Self::at(s, self.base[1]))
    }

    /// Slot `s` when it is a matrix slot, mutably.
    #[inline(always)]
    pub(crate) fn mat_mut(&mut self, s: u32) -> Option<&mut DMat4> {
        self.mats.get_mut(Self::at(s, self.base[1]))
    }

    /// Slot `s` when it is a float slot.
    #[inline(always)]
    pub(crate) fn float(&self, s: u32) -> Option<f64> {
        self.floats.get(s as usize).copied()
    }

    /// The value of slot `s`, whatever its array; `None` past the end.
    pub(crate) fn get(&self, s: u32) -> Option<Value> {
        let b = self.base;
        if let Some(&x) = self.floats.get(s as usize) {
            return Some(Value::Float(x));
        }
        if let Some(&x) = self.vec3s.get(Self::at(s, b[0])) {
            return Some(Value::Vec3(x));
        }
        if let Some(&x) = self.mats.get(Self::at(s, b[1])) {
            return Some(Value::Matrix(x));
        }
        if let Some(&x) = self.bools.get(Self::at(s, b[2])) {
            return Some(Value::Bool(x));
        }
        if let Some(&x) = self.enums.get(Self::at(s, b[3])) {
            return Some(Value::Enum(x));
        }
        self.value(s).cloned()
    }

    /// Slot `s` as a number ([`Value::as_f64`]: a float, int, enum or bool, whatever its
    /// array); `None` otherwise. Float slots take the short path.
    #[inline]
    pub(crate) fn number(&self, s: u32) -> Option<f64> {
        match self.float(s) {
            Some(x) => Some(x),
            None => self.get(s)?.as_f64(),
        }
    }

    /// Lane `k` (0, 1, 2) of vec3 slot `s`.
    #[inline]
    pub(crate) fn lane(&self, s: u32, k: u8) -> Option<f64> {
        let v = self.read::<DVec3>(s)?;
        Some(v[(k as usize).min(2)])
    }

    /// Slot `s` typed; `None` when it holds another type or is past the end.
    #[inline(always)]
    pub(crate) fn read<T: AttrValue>(&self, s: u32) -> Option<T> {
        let b = self.base;
        let dense = match T::TYPE {
            crate::AttrType::Float => self.floats.get(s as usize).and_then(|&x| cast(x)),
            crate::AttrType::Vec3 => self.vec3s.get(Self::at(s, b[0])).and_then(|&x| cast(x)),
            crate::AttrType::Matrix => self.mats.get(Self::at(s, b[1])).and_then(|&x| cast(x)),
            crate::AttrType::Bool => self.bools.get(Self::at(s, b[2])).and_then(|&x| cast(x)),
            crate::AttrType::Enum | crate::AttrType::Int => self.enums.get(Self::at(s, b[3])).and_then(|&x| cast(x)),
            _ => None,
        };
        match dense {
            Some(v) => Some(v),
            None => T::from_value(self.value(s)?),
        }
    }

    /// Slot `s` typed, by reference; `None` as for [`Slots::read`], and for values that
    /// are converted on reading.
    #[inline(always)]
    pub(crate) fn read_ref<T: AttrValue>(&self, s: u32) -> Option<&T> {
        let b = self.base;
        let dense: Option<&dyn Any> = match T::TYPE {
            crate::AttrType::Float => self.floats.get(s as usize).map(|x| x as &dyn Any),
            crate::AttrType::Vec3 => self.vec3s.get(Self::at(s, b[0])).map(|x| x as &dyn Any),
            crate::AttrType::Matrix => self.mats.get(Self::at(s, b[1])).map(|x| x as &dyn Any),
            _ => None,
        };
        match dense.and_then(|x| x.downcast_ref::<T>()) {
            Some(v) => Some(v),
            None => T::as_ref(self.value(s)?),
        }
    }

    /// Stores `v` in slot `s`. A dense slot takes only its own type; anything else is
    /// ignored there (the compiler gives dense slots to attributes of that type only).
    #[inline(always)]
    pub(crate) fn write<T: AttrValue>(&mut self, s: u32, v: T) {
        /// Stores `v` into `slot` when `T` is `U`; `false` when there is no such slot.
        #[inline(always)]
        fn put<T: AttrValue, U: Copy + 'static>(slot: Option<&mut U>, v: &T) -> bool {
            match slot {
                Some(x) => {
                    if let Some(u) = uncast::<T, U>(v) {
                        *x = u;
                    }
                    true
                }
                None => false,
            }
        }
        let b = self.base;
        let stored = match T::TYPE {
            crate::AttrType::Float => put(self.floats.get_mut(s as usize), &v),
            crate::AttrType::Vec3 => put(self.vec3s.get_mut(Self::at(s, b[0])), &v),
            crate::AttrType::Matrix => put(self.mats.get_mut(Self::at(s, b[1])), &v),
            crate::AttrType::Bool => put(self.bools.get_mut(Self::at(s, b[2])), &v),
            crate::AttrType::Enum | crate::AttrType::Int => put(self.enums.get_mut(Self::at(s, b[3])), &v),
            _ => false,
        };
        if !stored {
            if let Some(slot) = self.value_mut(s) {
                v.write_into(slot);
            }
        }
    }

    /// Stores an untyped value in slot `s`: a dense slot takes only its own type (an int
    /// for an enum). Returns `false`, changing nothing, when `s` is past the end or the
    /// value does not fit.
    pub(crate) fn set_value(&mut self, s: u32, v: Value) -> bool {
        let b = self.base;
        let fits = |x: Option<()>| x.is_some();
        if (s as usize) < self.floats.len() {
            return fits(f64::from_value(&v).map(|x| self.floats[s as usize] = x));
        }
        if let Some(slot) = self.vec3s.get_mut(Self::at(s, b[0])) {
            return fits(DVec3::from_value(&v).map(|x| *slot = x));
        }
        if let Some(slot) = self.mats.get_mut(Self::at(s, b[1])) {
            return fits(DMat4::from_value(&v).map(|x| *slot = x));
        }
        if let Some(slot) = self.bools.get_mut(Self::at(s, b[2])) {
            return fits(bool::from_value(&v).map(|x| *slot = x));
        }
        if let Some(slot) = self.enums.get_mut(Self::at(s, b[3])) {
            return fits(i64::from_value(&v).map(|x| *slot = x));
        }
        match self.value_mut(s) {
            Some(slot) => {
                *slot = v;
                true
            }
            None => false,
        }
    }

    /// Sets lane `k` (0, 1, 2) of vec3 slot `s`; `false` when `s` is not a vec3.
    pub(crate) fn set_lane(&mut self, s: u32, k: u8, x: f64) -> bool {
        let k = (k as usize).min(2);
        if let Some(v) = self.vec3s.get_mut(Self::at(s, self.base[0])) {
            v[k] = x;
            return true;
        }
        match self.value_mut(s) {
            Some(Value::Vec3(v)) => {
                v[k] = x;
                true
            }
            _ => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Slots {
        Slots::from_values(vec![
            Value::Float(1.5),
            Value::Float(-0.0),
            Value::Vec3(DVec3::new(1.0, 2.0, 3.0)),
            Value::Matrix(DMat4::IDENTITY),
            Value::Bool(true),
            Value::Enum(4),
            Value::Int(9),
            Value::Float(7.0),
        ])
    }

    #[test]
    fn the_leading_runs_are_dense_and_the_order_is_kept() {
        let s = sample();
        assert_eq!(
            (
                s.floats.len(),
                s.vec3s.len(),
                s.mats.len(),
                s.bools.len(),
                s.enums.len(),
                s.values.len()
            ),
            (2, 1, 1, 1, 1, 2)
        );
        assert_eq!(s.len(), 8);
        let back = s.to_values();
        assert_eq!(back.len(), 8);
        assert!(back[1].same_bits(&Value::Float(-0.0)));
        assert!(back[5].same_bits(&Value::Enum(4)));
        assert!(back[6].same_bits(&Value::Int(9)));
        assert!(back[7].same_bits(&Value::Float(7.0)));
        assert_eq!(s.bytes(), 2 * 8 + 24 + 128 + 1 + 8 + 2 * std::mem::size_of::<Value>());
    }

    #[test]
    fn typed_reads_find_each_array() {
        let s = sample();
        assert_eq!(s.read::<f64>(0), Some(1.5));
        assert_eq!(s.read_ref::<f64>(1).map(|x| x.to_bits()), Some((-0.0f64).to_bits()));
        assert_eq!(s.read::<DVec3>(2), Some(DVec3::new(1.0, 2.0, 3.0)));
        assert_eq!(s.read_ref::<DMat4>(3), Some(&DMat4::IDENTITY));
        assert_eq!(s.read::<bool>(4), Some(true));
        assert_eq!(s.read::<i64>(5), Some(4));
        assert_eq!(s.read::<i64>(6), Some(9));
        // A float stored as a value (after the leading run) reads the same way.
        assert_eq!(s.read::<f64>(7), Some(7.0));
        assert_eq!(s.read::<DVec3>(0), None);
        assert_eq!(s.read::<f64>(2), None);
        assert_eq!(s.read::<bool>(5), None);
        assert_eq!(s.read::<f64>(8), None);
        assert_eq!(s.number(7), Some(7.0));
        // Numbers in the dense bool and enum arrays, as `Value::as_f64` reads them.
        assert_eq!(s.number(4), Some(1.0));
        assert_eq!(s.number(5), Some(4.0));
        assert_eq!(s.number(2), None);
        assert_eq!(s.lane(2, 1), Some(2.0));
        assert!(s.get(8).is_none());
    }

    #[test]
    fn writes_keep_each_slot_its_type() {
        let mut s = sample();
        s.write(0, 2.5f64);
        s.write(0, DVec3::ONE); // not a float: ignored
        s.write(2, DVec3::ZERO);
        s.write(4, false);
        s.write(5, 2i64);
        assert!(!s.set_value(1, Value::Int(3)));
        assert!(s.set_value(1, Value::Float(4.0)));
        assert!(s.set_value(5, Value::Int(3)));
        assert!(!s.set_value(3, Value::Float(4.0)));
        assert!(!s.set_value(9, Value::Float(4.0)));
        assert!(s.set_lane(2, 2, 8.0));
        assert!(!s.set_lane(0, 2, 8.0));
        assert_eq!(s.read::<f64>(0), Some(2.5));
        assert_eq!(s.read::<f64>(1), Some(4.0));
        assert_eq!(s.read::<DVec3>(2), Some(DVec3::new(0.0, 0.0, 8.0)));
        assert_eq!(s.read::<bool>(4), Some(false));
        assert!(s.get(5).is_some_and(|v| v.same_bits(&Value::Enum(3))));
    }
}
