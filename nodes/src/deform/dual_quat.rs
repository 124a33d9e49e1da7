//! Unit dual quaternions and the conversion of a skinning palette into the form dual
//! quaternion skinning (DQS) blends.
//!
//! **Scale and shear.** A palette matrix `M = [A | t]` is split by polar decomposition
//! `A = R · S` into a rotation `R` and a symmetric *stretch* `S` (scale and shear, in the
//! joint's bind space). `(R, t)` becomes a unit dual quaternion; `S` is kept beside it. A
//! vertex is deformed as `p' = DQ_blend(Σ wᵢ Sᵢ · p)`: the stretch matrices blend linearly
//! (like LBS) and the rigid parts blend as dual quaternions, so rigid rigs keep DQS's volume
//! preservation and scaled joints still scale. This is the approach of Kavan et al.
//! ("Geometric skinning with approximate dual quaternion blending", 2008, §4.2) and close to
//! what Maya's skinCluster does for scaled joints. A mirror (`det A < 0`) is folded into the
//! stretch (`A = R · (−S)`), so `R` is always a proper rotation.
//!
//! When every joint's stretch is the identity (within `1e-6`), [`DqPalette::has_stretch`] is
//! false and the kernels skip the stretch blend entirely.

use glam::{DMat3, DQuat, Mat3A, Mat4, Quat, Vec3, Vec3A, Vec4};

/// A dual quaternion `real + ε·dual`; unit when `|real| = 1` and `real · dual = 0`.
///
/// Quaternions are stored as `Vec4` `(x, y, z, w)` so that blending uses SIMD lanes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DualQuat {
    /// Rotation part.
    pub real: Vec4,
    /// Translation part: `0.5 · t · real` with `t` as a pure quaternion.
    pub dual: Vec4,
}

impl DualQuat {
    /// The identity transform.
    pub const IDENTITY: DualQuat = DualQuat {
        real: Vec4::new(0.0, 0.0, 0.0, 1.0),
        dual: Vec4::ZERO,
    };

    /// A rigid transform from a unit rotation and a translation.
    pub fn from_rotation_translation(rotation: Quat, translation: Vec3) -> Self {
        let real = Vec4::from(rotation);
        let t = Quat::from_xyzw(translation.x, translation.y, translation.z, 0.0);
        DualQuat {
            real,
            dual: Vec4::from(t * rotation) * 0.5,
        }
    }

    /// Divides both parts by `|real|`; `None` when `|real|` is (nearly) zero or not finite.
    #[inline]
    pub fn normalized(self) -> Option<Self> {
        let len = self.real.length();
        if len.is_nan() || len <= 1e-12 || len.is_infinite() {
            return None;
        }
        let inv = 1.0 / len;
        Some(DualQuat {
            real: self.real * inv,
            dual: self.dual * inv,
        })
    }

    /// Rotates a vector by the rotation part (assumes a unit dual quaternion).
    #[inline(always)]
    pub fn rotate(&self, v: Vec3A) -> Vec3A {
        let q = Vec3A::from_vec4(self.real);
        let w = self.real.w;
        v + 2.0 * q.cross(q.cross(v) + w * v)
    }

    /// The translation part (assumes a unit dual quaternion): `2 · dual · conj(real)`.
    #[inline(always)]
    pub fn translation(&self) -> Vec3A {
        let (r, d) = (Vec3A::from_vec4(self.real), Vec3A::from_vec4(self.dual));
        2.0 * (self.real.w * d - self.dual.w * r + r.cross(d))
    }

    /// Applies the rigid transform to a point (assumes a unit dual quaternion).
    #[inline(always)]
    pub fn transform_point(&self, p: Vec3A) -> Vec3A {
        self.rotate(p) + self.translation()
    }

    /// The rigid transform as a matrix (assumes a unit dual quaternion).
    pub fn to_mat4(&self) -> Mat4 {
        let q = Quat::from_vec4(self.real);
        Mat4::from_rotation_translation(q, self.translation().into())
    }
}

/// One palette entry prepared for DQS: the rigid part and the stretch (see module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DqJoint {
    /// Rigid part `(R, t)` as a unit dual quaternion.
    pub dq: DualQuat,
    /// Stretch `S` with `A = R · S` (identity for rigid joints).
    pub stretch: Mat3A,
}

/// Caller-owned scratch buffer holding a palette converted for DQS.
///
/// Reuse one per skin: [`DqPalette::update`] refills it without allocating once its capacity
/// covers the joint count.
#[derive(Clone, Debug, Default)]
pub struct DqPalette {
    joints: Vec<DqJoint>,
    has_stretch: bool,
}

impl DqPalette {
    /// An empty palette.
    pub fn new() -> Self {
        Self::default()
    }

    /// Converts `palette` (joint world × bindPreMatrix) into dual quaternions and stretches.
    pub fn update(&mut self, palette: &[Mat4]) {
        self.joints.clear();
        self.has_stretch = false;
        for m in palette {
            let j = split(m);
            let off = (j.stretch - Mat3A::IDENTITY).to_cols_array();
            if off.iter().any(|x| x.is_nan() || x.abs() > 1e-6) {
                self.has_stretch = true;
            }
            self.joints.push(j);
        }
    }

    /// The converted joints, in palette order.
    pub fn joints(&self) -> &[DqJoint] {
        &self.joints
    }

    /// Whether any joint carries scale, shear or a mirror.
    pub fn has_stretch(&self) -> bool {
        self.has_stretch
    }
}

/// Splits one palette matrix into its rigid dual quaternion and stretch.
///
/// Non-finite matrices give non-finite output (no panic); singular ones (a zero scale)
/// get an identity rotation and carry the whole 3×3 in the stretch.
pub fn split(m: &Mat4) -> DqJoint {
    let a = Mat3A::from_mat4(*m);
    let t = m.w_axis.truncate();
    let (r, s) = polar(a.as_dmat3());
    let q = DQuat::from_mat3(&r).normalize().as_quat();
    DqJoint {
        dq: DualQuat::from_rotation_translation(q, t),
        stretch: s.as_mat3().into(),
    }
}

/// Polar decomposition `a = r · s` with `r` a proper rotation, by scaled Newton iteration
/// (Higham 1986): `Q ← ½(γQ + γ⁻¹Q⁻ᵀ)`, converging quadratically.
fn polar(a: DMat3) -> (DMat3, DMat3) {
    let det = a.determinant();
    let scale = a.to_cols_array().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if !det.is_finite() || det.abs() <= 1e-12 * scale.powi(3) || scale == 0.0 {
        return (DMat3::IDENTITY, a);
    }
    let sign = det.signum();
    let mut q = a * sign;
    for _ in 0..32 {
        let qi = q.inverse().transpose();
        let fro = |m: &DMat3| m.to_cols_array().iter().map(|x| x * x).sum::<f64>().sqrt();
        let gamma = (fro(&qi) / fro(&q)).sqrt();
        let next = (q * gamma + qi * (1.0 / gamma)) * 0.5;
        let diff = fro(&(next - q));
        q = next;
        if diff <= 1e-14 {
            break;
        }
    }
    // Symmetric stretch; re-multiply by the sign to fold a mirror into it.
    let s = q.transpose() * a;
    (q, s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::EulerRot;

    #[test]
    fn rigid_round_trip() {
        let q = Quat::from_euler(EulerRot::XYZ, 0.3, -1.1, 2.0);
        let m = Mat4::from_rotation_translation(q, Vec3::new(1.0, -2.0, 3.0));
        let j = split(&m);
        assert!(j.dq.to_mat4().abs_diff_eq(m, 1e-5));
        assert!(j.stretch.abs_diff_eq(Mat3A::IDENTITY, 1e-5));
        let p = Vec3A::new(0.2, 0.7, -1.3);
        let expect = Vec3A::from(m.transform_point3(p.into()));
        assert!(j.dq.transform_point(p).abs_diff_eq(expect, 1e-5));
    }

    #[test]
    fn scaled_joint_splits_into_rotation_and_stretch() {
        // A = R · B S Bᵀ, with S = diag(2, 1, 0.5) in a rotated frame B: the polar factor
        // must recover R exactly and a symmetric stretch B S Bᵀ.
        let r = Quat::from_rotation_z(0.8);
        let b = Mat3A::from_quat(Quat::from_rotation_x(0.4));
        let s = b * Mat3A::from_diagonal(Vec3::new(2.0, 1.0, 0.5)) * b.transpose();
        let a = Mat3A::from_quat(r) * s;
        let m = Mat4::from_mat3a(a) * Mat4::IDENTITY;
        let j = split(&Mat4 {
            w_axis: Vec4::new(1.0, 2.0, 3.0, 1.0),
            ..m
        });
        assert!(Quat::from_vec4(j.dq.real).abs_diff_eq(r, 1e-5) || Quat::from_vec4(-j.dq.real).abs_diff_eq(r, 1e-5));
        assert!(j.stretch.abs_diff_eq(s, 1e-5));
        let mut pal = DqPalette::new();
        pal.update(&[Mat4::IDENTITY, m]);
        assert!(pal.has_stretch());
        pal.update(&[Mat4::IDENTITY]);
        assert!(!pal.has_stretch());
    }

    #[test]
    fn mirror_goes_into_the_stretch_and_singular_does_not_panic() {
        let m = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
        let j = split(&m);
        let back = Mat3A::from_quat(Quat::from_vec4(j.dq.real)) * j.stretch;
        assert!(back.abs_diff_eq(Mat3A::from_mat4(m), 1e-5));
        let z = split(&Mat4::from_scale(Vec3::ZERO));
        assert_eq!(z.dq.real, Vec4::W);
        let _ = split(&Mat4::from_cols_array(&[f32::NAN; 16]));
    }
}
