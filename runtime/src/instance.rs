//! One character's evaluation state ([`RigInstance`]): its own value slots
//! over the shared program, typed setters through pre-resolved handles,
//! evaluation (single or batched in parallel) and the engine-facing outputs.

use std::sync::Arc;

use glam::{DMat4, Mat4};
use rayon::prelude::*;
use sinew_core::{AttrValue, Instance, Mesh, Time, Value};

use crate::rig::{AnyInput, InputHandle, OutputHandle, Rig};
use crate::{ErrorKind, Result, RuntimeError};

/// One instance of a rig: owns only its slot values; the program is shared.
#[derive(Clone)]
pub struct RigInstance {
    rig: Rig,
    inst: Instance,
}

impl std::fmt::Debug for RigInstance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RigInstance").field("rig", &self.rig.name()).finish()
    }
}

fn foreign() -> RuntimeError {
    RuntimeError::new(ErrorKind::Input, "the handle belongs to another rig")
}

impl RigInstance {
    pub(crate) fn new(rig: Rig) -> Self {
        let inst = Instance::new(rig.inner.program.clone());
        RigInstance { rig, inst }
    }

    /// The rig this instance evaluates.
    pub fn rig(&self) -> &Rig {
        &self.rig
    }

    /// Sets an input (refused for NaN or infinite values; the instance is unchanged then).
    #[inline]
    pub fn set<T: AttrValue>(&mut self, h: &InputHandle<T>, value: T) -> Result<()> {
        if h.rig != self.rig.inner.id {
            return Err(foreign());
        }
        self.inst
            .set_typed(&h.plug, value)
            .map_err(|e| RuntimeError::new(ErrorKind::Input, e.to_string()))
    }

    /// Sets an input of any type (int values are accepted for enums and the reverse).
    pub fn set_value(&mut self, h: &AnyInput, value: Value) -> Result<()> {
        if h.rig != self.rig.inner.id {
            return Err(foreign());
        }
        self.inst
            .set(&h.plug, value)
            .map_err(|e| RuntimeError::new(ErrorKind::Input, e.to_string()))
    }

    /// Reads a plug (`None` for a handle of another rig).
    #[inline]
    pub fn get<T: AttrValue>(&self, h: &OutputHandle<T>) -> Option<T> {
        (h.rig == self.rig.inner.id)
            .then(|| self.inst.get_typed::<T>(&h.plug))
            .flatten()
    }

    /// Evaluates at `time`: the whole program on the first call and after a
    /// non-dynamic input was set, otherwise only the steps downstream of
    /// dynamic inputs and time.
    pub fn evaluate(&mut self, time: Time) -> Result<()> {
        self.inst
            .evaluate(time)
            .map_err(|e| RuntimeError::core(ErrorKind::Evaluate, e))
    }

    /// Evaluates at `frame` at the rig's frame rate.
    pub fn evaluate_frame(&mut self, frame: f64) -> Result<()> {
        self.evaluate(Time::new(frame, self.rig.fps()))
    }

    /// Evaluates every step regardless of what changed.
    pub fn evaluate_full(&mut self, time: Time) -> Result<()> {
        self.inst
            .evaluate_full(time)
            .map_err(|e| RuntimeError::core(ErrorKind::Evaluate, e))
    }

    /// The model-space (world) matrix of joint `i` (identity when out of range).
    #[inline]
    pub fn joint_matrix(&self, i: usize) -> DMat4 {
        self.rig
            .inner
            .joint_world
            .get(i)
            .and_then(|h| self.inst.get_typed::<DMat4>(h))
            .unwrap_or(DMat4::IDENTITY)
    }

    /// Writes the model-space matrices of the first `out.len()` joints (parent-first order).
    pub fn joint_matrices(&self, out: &mut [DMat4]) {
        for (o, h) in out.iter_mut().zip(&self.rig.inner.joint_world) {
            *o = self.inst.get_typed::<DMat4>(h).unwrap_or(DMat4::IDENTITY);
        }
    }

    /// [`RigInstance::joint_matrices`] converted to `f32` (what GPUs take).
    pub fn joint_matrices_f32(&self, out: &mut [Mat4]) {
        for (o, h) in out.iter_mut().zip(&self.rig.inner.joint_world) {
            *o = self.inst.get_typed::<DMat4>(h).unwrap_or(DMat4::IDENTITY).as_mat4();
        }
    }

    /// The skinning palette of skin `skin` (`matrix[i] · bindPreMatrix[i]`), shared, not copied.
    /// Drop it before the next evaluation, or that evaluation copies it.
    pub fn palette(&self, skin: usize) -> Option<Arc<Vec<DMat4>>> {
        let h = &self.rig.inner.skins.get(skin)?.palette;
        self.inst.get_typed::<Arc<Vec<DMat4>>>(h)
    }

    /// Writes the palette of skin `skin` as `f32` into `out` (cleared first); returns its length.
    pub fn palette_f32(&self, skin: usize, out: &mut Vec<Mat4>) -> usize {
        out.clear();
        if let Some(p) = self.palette(skin) {
            out.extend(p.iter().map(|m| m.as_mat4()));
        }
        out.len()
    }

    /// The deformed mesh of skin `skin` (positions and normals skinned on the CPU), shared.
    /// Drop it before the next evaluation, or that evaluation copies the mesh.
    pub fn skinned_mesh(&self, skin: usize) -> Option<Arc<Mesh>> {
        let h = &self.rig.inner.skins.get(skin)?.geometry;
        self.inst.get_typed::<Arc<Mesh>>(h)
    }

    /// Runs `f` on the deformed mesh of skin `skin` without keeping a reference to it.
    pub fn with_skinned_mesh<R>(&self, skin: usize, f: impl FnOnce(&Mesh) -> R) -> Option<R> {
        self.skinned_mesh(skin).map(|m| f(&m))
    }
}

/// Evaluates all `instances` at `time` in parallel on the current rayon pool
/// (wrap the call in `pool.install` to choose the threads). Every instance is
/// evaluated even when one fails; the error returned is the one of the
/// lowest-index failing instance. Results equal evaluating one by one, bit for bit.
pub fn evaluate_batch(instances: &mut [RigInstance], time: Time) -> Result<()> {
    let failed = instances
        .par_iter_mut()
        .enumerate()
        .filter_map(|(k, i)| i.evaluate(time).err().map(|e| (k, e)))
        .min_by_key(|(k, _)| *k);
    match failed {
        None => Ok(()),
        Some((k, e)) => Err(RuntimeError::new(e.kind, format!("instance {k}: {}", e.message))),
    }
}
