//! Compiled value storage: a program's float slots in a dense `f64` array, every other
//! slot as a [`Value`].
//!
//! Slot ids are global (`0..len`). The compiler numbers the slots whose value is a float
//! first, so slot `s` is `floats[s]` when `s < floats.len()` and `values[s - floats.len()]`
//! otherwise. A float slot takes 8 bytes where a `Value` takes 136 (a matrix is stored
//! inline), so chains of scalar nodes stay in the first-level cache and their reads and
//! writes need no variant test. Which store a slot lives in only affects speed: a float
//! stored as a `Value` (a program loaded from an older binary) is read the same way.

use std::any::Any;

use crate::value::{AttrType, AttrValue, Value};

/// The float `x` as `T`, when `T` is `f64` (decided at compile time).
#[inline(always)]
fn float_as<T: AttrValue>(x: f64) -> Option<T> {
    let mut t = T::default();
    let slot = (&mut t as &mut dyn Any).downcast_mut::<f64>()?;
    *slot = x;
    Some(t)
}

/// Whether `T` is read from and written to float slots (decided at compile time).
#[inline(always)]
fn is_float<T: AttrValue>() -> bool {
    matches!(T::TYPE, AttrType::Float)
}

/// An instance's slot values (see the module documentation).
#[derive(Clone, Debug, Default)]
pub(crate) struct Slots {
    pub floats: Vec<f64>,
    pub values: Vec<Value>,
}

impl Slots {
    /// Storage for values in slot order: the leading run of floats goes to the dense array.
    pub(crate) fn from_values(all: Vec<Value>) -> Slots {
        let lead = Slots::leading_floats(&all);
        let mut rest = all.into_iter();
        let floats = rest.by_ref().take(lead).filter_map(|v| v.as_f64()).collect();
        Slots {
            floats,
            values: rest.collect(),
        }
    }

    /// How many of `all`, from the start, are floats: the dense store's length.
    pub(crate) fn leading_floats(all: &[Value]) -> usize {
        all.iter().take_while(|v| matches!(v, Value::Float(_))).count()
    }

    /// Every slot's value in slot order (floats as [`Value::Float`]).
    pub(crate) fn to_values(&self) -> Vec<Value> {
        self.floats
            .iter()
            .map(|&x| Value::Float(x))
            .chain(self.values.iter().cloned())
            .collect()
    }

    /// Number of slots.
    pub(crate) fn len(&self) -> usize {
        self.floats.len() + self.values.len()
    }

    /// Shared access.
    #[inline]
    pub(crate) fn view(&self) -> SlotsRef<'_> {
        SlotsRef {
            floats: &self.floats,
            values: &self.values,
        }
    }

    /// Mutable access.
    #[inline]
    pub(crate) fn view_mut(&mut self) -> SlotsMut<'_> {
        SlotsMut {
            floats: &mut self.floats,
            values: &mut self.values,
        }
    }
}

/// Shared access to slots.
#[derive(Clone, Copy)]
pub(crate) struct SlotsRef<'a> {
    pub floats: &'a [f64],
    pub values: &'a [Value],
}

impl<'a> SlotsRef<'a> {
    /// Slot `s` when it is stored as a `Value` (`None` for a float slot or past the end).
    #[inline(always)]
    pub(crate) fn value(self, s: u32) -> Option<&'a Value> {
        self.values.get((s as usize).wrapping_sub(self.floats.len()))
    }

    /// Slot `s` when it is a float slot.
    #[inline(always)]
    pub(crate) fn float(self, s: u32) -> Option<f64> {
        self.floats.get(s as usize).copied()
    }

    /// Slot `s` as a number (a float slot, or a number value); `None` otherwise.
    #[inline]
    pub(crate) fn number(self, s: u32) -> Option<f64> {
        match self.float(s) {
            Some(x) => Some(x),
            None => self.value(s)?.as_f64(),
        }
    }

    /// Slot `s` typed; `None` when it holds another type or is past the end.
    #[inline(always)]
    pub(crate) fn read<T: AttrValue>(self, s: u32) -> Option<T> {
        if is_float::<T>() {
            if let Some(x) = self.float(s) {
                return float_as(x);
            }
        }
        T::from_value(self.value(s)?)
    }

    /// Slot `s` typed, by reference; `None` as for [`SlotsRef::read`], and for values that
    /// are converted on reading.
    #[inline(always)]
    pub(crate) fn read_ref<T: AttrValue>(self, s: u32) -> Option<&'a T> {
        if is_float::<T>() {
            if let Some(x) = self.floats.get(s as usize) {
                return (x as &dyn Any).downcast_ref::<T>();
            }
        }
        T::as_ref(self.value(s)?)
    }
}

/// Mutable access to slots.
pub(crate) struct SlotsMut<'a> {
    pub floats: &'a mut [f64],
    pub values: &'a mut [Value],
}

impl SlotsMut<'_> {
    /// No slots (the storage of a lazy compute context).
    pub(crate) fn empty() -> SlotsMut<'static> {
        SlotsMut {
            floats: &mut [],
            values: &mut [],
        }
    }

    /// Shared access.
    #[inline(always)]
    pub(crate) fn view(&self) -> SlotsRef<'_> {
        SlotsRef {
            floats: self.floats,
            values: self.values,
        }
    }

    /// Slot `s` when it is stored as a `Value`.
    #[inline(always)]
    pub(crate) fn value_mut(&mut self, s: u32) -> Option<&mut Value> {
        let k = (s as usize).wrapping_sub(self.floats.len());
        self.values.get_mut(k)
    }

    /// Slot `s` when it is a float slot.
    #[inline(always)]
    pub(crate) fn float_mut(&mut self, s: u32) -> Option<&mut f64> {
        self.floats.get_mut(s as usize)
    }

    /// Stores `v` in slot `s`. A float slot takes only a float; anything else is ignored
    /// there (the compiler gives float slots to float attributes only).
    #[inline(always)]
    pub(crate) fn write<T: AttrValue>(&mut self, s: u32, v: T) {
        if is_float::<T>() {
            if let Some(x) = self.floats.get_mut(s as usize) {
                if let Some(f) = (&v as &dyn Any).downcast_ref::<f64>() {
                    *x = *f;
                }
                return;
            }
        }
        if let Some(slot) = self.value_mut(s) {
            v.write_into(slot);
        }
    }

    /// Stores an untyped value in slot `s`: a float slot takes only numbers. Returns
    /// `false`, changing nothing, when `s` is past the end or the value does not fit.
    pub(crate) fn set_value(&mut self, s: u32, v: Value) -> bool {
        if let Some(x) = self.float_mut(s) {
            return match v {
                Value::Float(f) => {
                    *x = f;
                    true
                }
                _ => false,
            };
        }
        match self.value_mut(s) {
            Some(slot) => {
                *slot = v;
                true
            }
            None => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DMat4, DVec3};

    fn sample() -> Slots {
        Slots::from_values(vec![
            Value::Float(1.5),
            Value::Float(-0.0),
            Value::Vec3(DVec3::new(1.0, 2.0, 3.0)),
            Value::Float(7.0),
            Value::Matrix(DMat4::IDENTITY),
        ])
    }

    #[test]
    fn the_leading_floats_are_dense_and_the_order_is_kept() {
        let s = sample();
        assert_eq!(s.floats.len(), 2);
        assert_eq!(s.values.len(), 3);
        assert_eq!(s.len(), 5);
        let back = s.to_values();
        assert_eq!(back.len(), 5);
        assert!(back[1].same_bits(&Value::Float(-0.0)));
        assert!(back[3].same_bits(&Value::Float(7.0)));
    }

    #[test]
    fn typed_reads_find_each_store() {
        let s = sample();
        let v = s.view();
        assert_eq!(v.read::<f64>(0), Some(1.5));
        assert_eq!(v.read_ref::<f64>(1).map(|x| x.to_bits()), Some((-0.0f64).to_bits()));
        assert_eq!(v.read::<DVec3>(2), Some(DVec3::new(1.0, 2.0, 3.0)));
        // A float stored as a value (after the leading run) reads the same way.
        assert_eq!(v.read::<f64>(3), Some(7.0));
        assert_eq!(v.read_ref::<DMat4>(4), Some(&DMat4::IDENTITY));
        assert_eq!(v.read::<DVec3>(0), None);
        assert_eq!(v.read::<f64>(2), None);
        assert_eq!(v.read::<f64>(5), None);
        assert_eq!(v.number(3), Some(7.0));
        assert!(v.value(5).is_none() && v.float(5).is_none());
    }

    #[test]
    fn writes_keep_each_slot_its_type() {
        let mut s = sample();
        let mut m = s.view_mut();
        m.write(0, 2.5f64);
        m.write(0, DVec3::ONE); // not a float: ignored
        m.write(2, DVec3::ZERO);
        assert!(!m.set_value(1, Value::Int(3)));
        assert!(m.set_value(1, Value::Float(4.0)));
        assert!(!m.set_value(9, Value::Float(4.0)));
        let v = s.view();
        assert_eq!(v.read::<f64>(0), Some(2.5));
        assert_eq!(v.read::<f64>(1), Some(4.0));
        assert_eq!(v.read::<DVec3>(2), Some(DVec3::ZERO));
    }
}
