//! Typed values that live on plugs: the `AttrType` tags, the `Value` enum and
//! the `AttrValue` trait that maps Rust types to them for typed handles.
//!
//! Small values (numbers, vectors, matrices) are stored inline; heavy data
//! (meshes, weights, curves, arrays) is held in an `Arc` so copies along
//! connections are cheap and writes are copy-on-write (`Arc::make_mut`).

use std::fmt;
use std::sync::Arc;

use glam::{DMat4, DQuat, DVec3};

use crate::data::{Curve, Mesh, Surface, Weights};

/// The type of an attribute: what kind of value its plugs carry.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AttrType {
    /// `true` / `false`.
    Bool,
    /// A 64-bit signed integer.
    Int,
    /// A 64-bit float.
    Float,
    /// A 3-vector of f64 (translate, rotate in degrees, scale, colours).
    Vec3,
    /// A rotation quaternion (x, y, z, w).
    Quat,
    /// A 4x4 f64 matrix.
    Matrix,
    /// One of a fixed list of named choices, stored as its index.
    Enum,
    /// A UTF-8 string.
    String,
    /// A triangle mesh (shared, copy-on-write).
    Mesh,
    /// A B-spline curve (shared, copy-on-write).
    Curve,
    /// A B-spline (NURBS) surface (shared, copy-on-write).
    Surface,
    /// Sparse skin weights (shared, copy-on-write).
    Weights,
    /// An array of floats (shared, copy-on-write).
    FloatArray,
    /// An array of integers (shared, copy-on-write).
    IntArray,
    /// An array of 3-vectors (shared, copy-on-write).
    Vec3Array,
    /// An array of matrices (shared, copy-on-write).
    MatrixArray,
    /// Plugin-defined immutable data (a precomputed curve, a spatial index...).
    /// Outputs only: it cannot be written in rig files.
    Object,
}

impl AttrType {
    /// All types, in declaration order.
    pub const ALL: [AttrType; 17] = [
        AttrType::Bool,
        AttrType::Int,
        AttrType::Float,
        AttrType::Vec3,
        AttrType::Quat,
        AttrType::Matrix,
        AttrType::Enum,
        AttrType::String,
        AttrType::Mesh,
        AttrType::Curve,
        AttrType::Surface,
        AttrType::Weights,
        AttrType::FloatArray,
        AttrType::IntArray,
        AttrType::Vec3Array,
        AttrType::MatrixArray,
        AttrType::Object,
    ];

    /// The lower-case name used in messages, `sinew nodes` and rig files.
    pub fn name(self) -> &'static str {
        match self {
            AttrType::Bool => "bool",
            AttrType::Int => "int",
            AttrType::Float => "float",
            AttrType::Vec3 => "vec3",
            AttrType::Quat => "quat",
            AttrType::Matrix => "matrix",
            AttrType::Enum => "enum",
            AttrType::String => "string",
            AttrType::Mesh => "mesh",
            AttrType::Curve => "curve",
            AttrType::Surface => "surface",
            AttrType::Weights => "weights",
            AttrType::FloatArray => "floatArray",
            AttrType::IntArray => "intArray",
            AttrType::Vec3Array => "vec3Array",
            AttrType::MatrixArray => "matrixArray",
            AttrType::Object => "object",
        }
    }

    /// Whether values of this type are held behind an `Arc`.
    pub fn is_heavy(self) -> bool {
        matches!(
            self,
            AttrType::String
                | AttrType::Mesh
                | AttrType::Curve
                | AttrType::Surface
                | AttrType::Weights
                | AttrType::FloatArray
                | AttrType::IntArray
                | AttrType::Vec3Array
                | AttrType::MatrixArray
                | AttrType::Object
        )
    }

    /// Whether a plug of type `self` may feed a plug of type `dst`.
    ///
    /// Types must match exactly, except that `int` and `enum` connect both ways.
    pub fn connects_to(self, dst: AttrType) -> bool {
        self == dst
            || matches!(
                (self, dst),
                (AttrType::Int, AttrType::Enum) | (AttrType::Enum, AttrType::Int)
            )
    }

    /// The zero / empty value of this type.
    pub fn zero(self) -> Value {
        match self {
            AttrType::Bool => Value::Bool(false),
            AttrType::Int => Value::Int(0),
            AttrType::Float => Value::Float(0.0),
            AttrType::Vec3 => Value::Vec3(DVec3::ZERO),
            AttrType::Quat => Value::Quat(DQuat::IDENTITY),
            AttrType::Matrix => Value::Matrix(DMat4::IDENTITY),
            AttrType::Enum => Value::Enum(0),
            AttrType::String => Value::String(Arc::from("")),
            AttrType::Mesh => Value::Mesh(Arc::default()),
            AttrType::Curve => Value::Curve(Arc::default()),
            AttrType::Surface => Value::Surface(Arc::default()),
            AttrType::Weights => Value::Weights(Arc::default()),
            AttrType::FloatArray => Value::FloatArray(Arc::default()),
            AttrType::IntArray => Value::IntArray(Arc::default()),
            AttrType::Vec3Array => Value::Vec3Array(Arc::default()),
            AttrType::MatrixArray => Value::MatrixArray(Arc::default()),
            AttrType::Object => Value::Object(ObjectRef::default()),
        }
    }
}

impl fmt::Display for AttrType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A value carried by a plug.
#[derive(Clone, Debug)]
pub enum Value {
    /// See [`AttrType::Bool`].
    Bool(bool),
    /// See [`AttrType::Int`].
    Int(i64),
    /// See [`AttrType::Float`].
    Float(f64),
    /// See [`AttrType::Vec3`].
    Vec3(DVec3),
    /// See [`AttrType::Quat`].
    Quat(DQuat),
    /// See [`AttrType::Matrix`].
    Matrix(DMat4),
    /// See [`AttrType::Enum`].
    Enum(i64),
    /// See [`AttrType::String`].
    String(Arc<str>),
    /// See [`AttrType::Mesh`].
    Mesh(Arc<Mesh>),
    /// See [`AttrType::Curve`].
    Curve(Arc<Curve>),
    /// See [`AttrType::Surface`].
    Surface(Arc<Surface>),
    /// See [`AttrType::Weights`].
    Weights(Arc<Weights>),
    /// See [`AttrType::FloatArray`].
    FloatArray(Arc<Vec<f64>>),
    /// See [`AttrType::IntArray`].
    IntArray(Arc<Vec<i64>>),
    /// See [`AttrType::Vec3Array`].
    Vec3Array(Arc<Vec<DVec3>>),
    /// See [`AttrType::MatrixArray`].
    MatrixArray(Arc<Vec<DMat4>>),
    /// See [`AttrType::Object`].
    Object(ObjectRef),
}

impl Value {
    /// The type tag of this value.
    pub fn attr_type(&self) -> AttrType {
        match self {
            Value::Bool(_) => AttrType::Bool,
            Value::Int(_) => AttrType::Int,
            Value::Float(_) => AttrType::Float,
            Value::Vec3(_) => AttrType::Vec3,
            Value::Quat(_) => AttrType::Quat,
            Value::Matrix(_) => AttrType::Matrix,
            Value::Enum(_) => AttrType::Enum,
            Value::String(_) => AttrType::String,
            Value::Mesh(_) => AttrType::Mesh,
            Value::Curve(_) => AttrType::Curve,
            Value::Surface(_) => AttrType::Surface,
            Value::Weights(_) => AttrType::Weights,
            Value::FloatArray(_) => AttrType::FloatArray,
            Value::IntArray(_) => AttrType::IntArray,
            Value::Vec3Array(_) => AttrType::Vec3Array,
            Value::MatrixArray(_) => AttrType::MatrixArray,
            Value::Object(_) => AttrType::Object,
        }
    }

    /// Bitwise identity: the equality used for early cutoff and for the
    /// "lazy equals compiled" guarantee. Floats compare by bits (so `NaN`
    /// equals the same `NaN` and `-0.0 != 0.0`); shared data compares by
    /// pointer first, then by content.
    pub fn same_bits(&self, other: &Value) -> bool {
        fn f(a: f64, b: f64) -> bool {
            a.to_bits() == b.to_bits()
        }
        fn fs(a: &[f64], b: &[f64]) -> bool {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| f(*x, *y))
        }
        fn f32s(a: &[f32], b: &[f32]) -> bool {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
        }
        fn v3(a: &[DVec3], b: &[DVec3]) -> bool {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| fs(&x.to_array(), &y.to_array()))
        }
        fn m4(a: &[DMat4], b: &[DMat4]) -> bool {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| fs(&x.to_cols_array(), &y.to_cols_array()))
        }
        fn f32s_vec3(a: &[glam::Vec3], b: &[glam::Vec3]) -> bool {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| f32s(&x.to_array(), &y.to_array()))
        }
        match (self, other) {
            (Value::Bool(a), Value::Bool(b)) => a == b,
            (Value::Int(a), Value::Int(b)) | (Value::Enum(a), Value::Enum(b)) => a == b,
            (Value::Float(a), Value::Float(b)) => f(*a, *b),
            (Value::Vec3(a), Value::Vec3(b)) => fs(&a.to_array(), &b.to_array()),
            (Value::Quat(a), Value::Quat(b)) => fs(&a.to_array(), &b.to_array()),
            (Value::Matrix(a), Value::Matrix(b)) => fs(&a.to_cols_array(), &b.to_cols_array()),
            (Value::String(a), Value::String(b)) => a == b,
            (Value::Mesh(a), Value::Mesh(b)) => {
                Arc::ptr_eq(a, b)
                    || (f32s_vec3(&a.positions, &b.positions)
                        && f32s_vec3(&a.normals, &b.normals)
                        && a.uvs.len() == b.uvs.len()
                        && a.uvs
                            .iter()
                            .zip(&b.uvs)
                            .all(|(x, y)| f32s(&x.to_array(), &y.to_array()))
                        && a.triangles == b.triangles)
            }
            (Value::Curve(a), Value::Curve(b)) => {
                Arc::ptr_eq(a, b)
                    || (a.degree == b.degree && a.form == b.form && v3(&a.points, &b.points) && fs(&a.knots, &b.knots))
            }
            (Value::Surface(a), Value::Surface(b)) => {
                Arc::ptr_eq(a, b)
                    || (a.degree_u == b.degree_u
                        && a.degree_v == b.degree_v
                        && a.form_u == b.form_u
                        && a.form_v == b.form_v
                        && a.count_u == b.count_u
                        && a.count_v == b.count_v
                        && v3(&a.points, &b.points)
                        && fs(&a.knots_u, &b.knots_u)
                        && fs(&a.knots_v, &b.knots_v))
            }
            (Value::Weights(a), Value::Weights(b)) => {
                Arc::ptr_eq(a, b) || (a.offsets == b.offsets && a.joints == b.joints && f32s(&a.weights, &b.weights))
            }
            (Value::FloatArray(a), Value::FloatArray(b)) => Arc::ptr_eq(a, b) || fs(a, b),
            (Value::IntArray(a), Value::IntArray(b)) => Arc::ptr_eq(a, b) || a == b,
            (Value::Vec3Array(a), Value::Vec3Array(b)) => Arc::ptr_eq(a, b) || v3(a, b),
            (Value::MatrixArray(a), Value::MatrixArray(b)) => Arc::ptr_eq(a, b) || m4(a, b),
            (Value::Object(a), Value::Object(b)) => a.ptr_eq(b),
            _ => false,
        }
    }

    /// Whether every float in this value is finite (heavy data is not inspected).
    pub fn is_finite(&self) -> bool {
        match self {
            Value::Float(x) => x.is_finite(),
            Value::Vec3(v) => v.is_finite(),
            Value::Quat(q) => q.is_finite(),
            Value::Matrix(m) => m.is_finite(),
            _ => true,
        }
    }

    /// Component `k` (0..3) of a vec3 value, or `None` for other types.
    pub fn component(&self, k: u8) -> Option<f64> {
        match self {
            Value::Vec3(v) if k < 3 => Some(v[k as usize]),
            _ => None,
        }
    }

    /// A float view of numeric values (`bool` as 0/1, ints and enums converted).
    pub fn as_f64(&self) -> Option<f64> {
        match *self {
            Value::Float(x) => Some(x),
            Value::Int(i) | Value::Enum(i) => Some(i as f64),
            Value::Bool(b) => Some(if b { 1.0 } else { 0.0 }),
            _ => None,
        }
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fn m(f: &mut fmt::Formatter<'_>, m: &DMat4) -> fmt::Result {
            let c = m.to_cols_array();
            write!(f, "(")?;
            for (i, x) in c.iter().enumerate() {
                if i > 0 {
                    write!(f, ", ")?;
                }
                write!(f, "{x}")?;
            }
            write!(f, ")")
        }
        match self {
            Value::Bool(b) => write!(f, "{b}"),
            Value::Int(i) | Value::Enum(i) => write!(f, "{i}"),
            Value::Float(x) => write!(f, "{x}"),
            Value::Vec3(v) => write!(f, "({}, {}, {})", v.x, v.y, v.z),
            Value::Quat(q) => write!(f, "({}, {}, {}, {})", q.x, q.y, q.z, q.w),
            Value::Matrix(x) => m(f, x),
            Value::String(s) => write!(f, "{s:?}"),
            Value::Mesh(mesh) => write!(
                f,
                "<mesh: {} vertices, {} triangles>",
                mesh.positions.len(),
                mesh.triangles.len()
            ),
            Value::Curve(c) => write!(f, "<curve: degree {}, {} points>", c.degree, c.points.len()),
            Value::Surface(c) => write!(
                f,
                "<surface: degree {}x{}, {}x{} points>",
                c.degree_u, c.degree_v, c.count_u, c.count_v
            ),
            Value::Weights(w) => write!(f, "<weights: {} vertices>", w.vertex_count()),
            Value::FloatArray(a) => write!(f, "{:?}", a.as_slice()),
            Value::IntArray(a) => write!(f, "{:?}", a.as_slice()),
            Value::Vec3Array(a) => write!(f, "<{} vec3>", a.len()),
            Value::MatrixArray(a) => write!(f, "<{} matrices>", a.len()),
            Value::Object(_) => write!(f, "<object>"),
        }
    }
}

/// Plugin-defined immutable data behind an `Arc`, compared by identity.
///
/// A node can precompute something expensive (an animation curve's segment
/// coefficients, a spatial index) into an `Object` output in one compute
/// group, and use it every frame from another group.
#[derive(Clone)]
pub struct ObjectRef(Option<Arc<dyn std::any::Any + Send + Sync>>);

impl ObjectRef {
    /// Wraps a value.
    pub fn new<T: std::any::Any + Send + Sync>(value: T) -> Self {
        ObjectRef(Some(Arc::new(value)))
    }

    /// The value as `T`, when it is one.
    pub fn downcast<T: std::any::Any + Send + Sync>(&self) -> Option<&T> {
        self.0.as_ref()?.downcast_ref::<T>()
    }

    /// Whether both refer to the same allocation (or are both empty).
    pub fn ptr_eq(&self, other: &ObjectRef) -> bool {
        match (&self.0, &other.0) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        }
    }

    /// Whether no value is held (the default).
    pub fn is_empty(&self) -> bool {
        self.0.is_none()
    }
}

impl Default for ObjectRef {
    /// The empty object.
    fn default() -> Self {
        ObjectRef(None)
    }
}

impl fmt::Debug for ObjectRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(if self.0.is_some() {
            "Object(..)"
        } else {
            "Object(empty)"
        })
    }
}

/// A Rust type that can be read from and written to plugs through typed handles.
pub trait AttrValue: Sized + Default + 'static {
    /// The attribute type this Rust type maps to.
    const TYPE: AttrType;
    /// Extracts the value, or `None` when the value has another type.
    fn from_value(v: &Value) -> Option<Self>;
    /// Wraps the value.
    fn into_value(self) -> Value;
    /// Stores the value into `slot`, in place when the slot already holds this type.
    #[inline]
    fn write_into(self, slot: &mut Value) {
        *slot = self.into_value();
    }
    /// The value inside `v` by reference, or `None` when `v` holds another type (or a
    /// type, such as an enum index, that is converted on reading).
    #[inline]
    fn as_ref(v: &Value) -> Option<&Self> {
        let _ = v;
        None
    }
}

macro_rules! attr_value {
    ($t:ty, $tag:ident, $var:ident) => {
        impl AttrValue for $t {
            const TYPE: AttrType = AttrType::$tag;
            #[inline]
            fn from_value(v: &Value) -> Option<Self> {
                match v {
                    Value::$var(x) => Some(x.clone()),
                    _ => None,
                }
            }
            #[inline]
            fn as_ref(v: &Value) -> Option<&Self> {
                match v {
                    Value::$var(x) => Some(x),
                    _ => None,
                }
            }
            #[inline]
            fn into_value(self) -> Value {
                Value::$var(self)
            }
            #[inline]
            fn write_into(self, slot: &mut Value) {
                match slot {
                    Value::$var(x) => *x = self,
                    other => replace_value(other, Value::$var(self)),
                }
            }
        }
    };
}

attr_value!(bool, Bool, Bool);
attr_value!(f64, Float, Float);
attr_value!(DVec3, Vec3, Vec3);
attr_value!(DQuat, Quat, Quat);
attr_value!(DMat4, Matrix, Matrix);
attr_value!(Arc<str>, String, String);
attr_value!(Arc<Mesh>, Mesh, Mesh);
attr_value!(Arc<Curve>, Curve, Curve);
attr_value!(Arc<Surface>, Surface, Surface);
attr_value!(Arc<Weights>, Weights, Weights);
attr_value!(Arc<Vec<f64>>, FloatArray, FloatArray);
attr_value!(Arc<Vec<i64>>, IntArray, IntArray);
attr_value!(Arc<Vec<DVec3>>, Vec3Array, Vec3Array);
attr_value!(Arc<Vec<DMat4>>, MatrixArray, MatrixArray);
attr_value!(ObjectRef, Object, Object);

impl AttrValue for i64 {
    const TYPE: AttrType = AttrType::Int;
    #[inline]
    fn from_value(v: &Value) -> Option<Self> {
        match *v {
            Value::Int(x) | Value::Enum(x) => Some(x),
            _ => None,
        }
    }
    #[inline]
    fn into_value(self) -> Value {
        Value::Int(self)
    }
    /// Keeps an enum slot an enum (an `i64` written to an enum output).
    #[inline]
    fn write_into(self, slot: &mut Value) {
        match slot {
            Value::Int(x) | Value::Enum(x) => *x = self,
            other => replace_value(other, Value::Int(self)),
        }
    }
}

/// Replaces a slot holding another variant (rare: the first write of an
/// output, or a type change), out of line so the in-place writes stay small.
#[cold]
#[inline(never)]
fn replace_value(slot: &mut Value, v: Value) {
    *slot = v;
}

/// Heavy data held behind an `Arc` that a node may mutate in place on its
/// output plug (copy-on-write), so per-frame deformers do not allocate.
pub trait SharedData: Clone + Default + 'static {
    /// The `Arc` inside `v`, when `v` holds this type.
    fn arc_mut(v: &mut Value) -> Option<&mut Arc<Self>>;
    /// Wraps a shared value.
    fn wrap(a: Arc<Self>) -> Value;
}

macro_rules! shared_data {
    ($t:ty, $var:ident) => {
        impl SharedData for $t {
            fn arc_mut(v: &mut Value) -> Option<&mut Arc<Self>> {
                match v {
                    Value::$var(a) => Some(a),
                    _ => None,
                }
            }
            fn wrap(a: Arc<Self>) -> Value {
                Value::$var(a)
            }
        }
    };
}

shared_data!(Mesh, Mesh);
shared_data!(Curve, Curve);
shared_data!(Surface, Surface);
shared_data!(Weights, Weights);
shared_data!(Vec<f64>, FloatArray);
shared_data!(Vec<i64>, IntArray);
shared_data!(Vec<DVec3>, Vec3Array);
shared_data!(Vec<DMat4>, MatrixArray);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_bits_distinguishes_signed_zero_and_matches_nan() {
        assert!(!Value::Float(0.0).same_bits(&Value::Float(-0.0)));
        assert!(Value::Float(f64::NAN).same_bits(&Value::Float(f64::NAN)));
        assert!(!Value::Float(1.0).same_bits(&Value::Int(1)));
    }

    #[test]
    fn zero_values_have_their_type() {
        for t in AttrType::ALL {
            assert_eq!(t.zero().attr_type(), t);
        }
    }

    #[test]
    fn int_and_enum_connect() {
        assert!(AttrType::Int.connects_to(AttrType::Enum));
        assert!(!AttrType::Float.connects_to(AttrType::Int));
    }
}
