//! sinew-runtime: sinew embedded in a game engine.
//!
//! Load a rig once ([`Runtime::load_rig`], from a RON file, RON text or the
//! compiled bytes of [`Rig::to_bytes`]), create as many [`RigInstance`]s as
//! there are characters (each owns only its value slots; the compiled
//! program is shared through an `Arc`), set inputs through handles resolved
//! once ([`Rig::input`]), evaluate one instance ([`RigInstance::evaluate`]) or
//! a batch in parallel ([`evaluate_batch`], rayon), and read joint
//! model-space matrices in parent-first order, skinning palettes and CPU
//! skinned meshes.
//!
//! ```no_run
//! use glam::DVec3;
//! use sinew_runtime::{LoadOptions, Runtime, Time};
//!
//! let runtime = Runtime::new()?;
//! let options = LoadOptions::default().dynamic("*_ctrl_*.translate");
//! let rig = runtime.load_rig_file("graphs/examples/arm.ron", &options)?;
//! let goal = rig.input::<DVec3>("arm_pole_ctrl_L.translate")?;
//! let mut characters: Vec<_> = (0..100).map(|_| rig.instantiate()).collect();
//! for (i, c) in characters.iter_mut().enumerate() {
//!     c.set(&goal, DVec3::new(0.4, 1.5, -0.5 - 0.01 * i as f64))?;
//! }
//! sinew_runtime::evaluate_batch(&mut characters, Time::new(1.0, 24.0))?;
//! let mut matrices = vec![glam::Mat4::IDENTITY; rig.joint_count()];
//! characters[0].joint_matrices_f32(&mut matrices);
//! # Ok::<(), sinew_runtime::RuntimeError>(())
//! ```
//!
//! The crate depends on `sinew-core` and `sinew-nodes` (without the
//! skeletonize feature) only: no CLI, no file watching, no JSON.

mod format;
mod instance;
mod rig;

use std::path::Path;
use std::sync::Arc;

pub use instance::{evaluate_batch, RigInstance};
pub use rig::{AnyInput, InputHandle, Joint, OutputHandle, Rig};
pub use sinew_core::{Mesh, Registry, Time, Value};

/// What went wrong, for programs (and the C API's status codes) to branch on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// The rig file could not be read or has errors (the message has file:line:col).
    Load,
    /// The graph could not be compiled (or a dynamic input is driven by a connection).
    Compile,
    /// Compiled bytes are corrupt, foreign, of another version or need an unregistered node type.
    Format,
    /// No such node, attribute or plug.
    NotFound,
    /// A value or handle of the wrong type, a plug that cannot be set, a non-finite value.
    Input,
    /// A node failed while evaluating.
    Evaluate,
}

/// An error from the runtime: a kind and a message that says what to do.
#[derive(Clone, Debug, thiserror::Error)]
#[error("{message}")]
pub struct RuntimeError {
    /// What went wrong.
    pub kind: ErrorKind,
    /// The full message.
    pub message: String,
}

impl RuntimeError {
    pub(crate) fn new(kind: ErrorKind, message: impl Into<String>) -> Self {
        RuntimeError {
            kind,
            message: message.into(),
        }
    }

    pub(crate) fn core(kind: ErrorKind, e: sinew_core::Error) -> Self {
        let kind = match e {
            sinew_core::Error::UnknownNode { .. }
            | sinew_core::Error::UnknownAttribute { .. }
            | sinew_core::Error::BadPlugPath { .. } => ErrorKind::NotFound,
            sinew_core::Error::Compute { .. } => ErrorKind::Evaluate,
            _ => kind,
        };
        RuntimeError::new(kind, e.to_string())
    }
}

/// Result with a [`RuntimeError`].
pub type Result<T, E = RuntimeError> = std::result::Result<T, E>;

/// How to compile a rig loaded from RON (compiled bytes carry these choices).
#[derive(Clone, Debug)]
pub struct LoadOptions {
    /// Inputs the game sets every frame, as plug paths (`"look_ctrl.translate"`).
    /// The node part may contain `*` wildcards (`"*_ctrl_*.translate"`); a
    /// wildcard skips plugs driven by connections, an exact path must be
    /// settable. Steps downstream of these run every frame; setting any other
    /// input makes the next evaluation of that instance run the whole program.
    pub dynamic_inputs: Vec<String>,
    /// Deform meshes on the CPU (default `true`). `false` sets every
    /// `skinCluster`'s unconnected `envelope` to 0 before compiling, so
    /// `outputGeometry` passes the rest mesh through and only the palette is
    /// computed, for engines that skin on the GPU.
    pub cpu_skinning: bool,
    /// Extra outputs the game reads with [`Rig::output`](crate::Rig::output)
    /// (exact plug paths). When `prune` is on, only these, the joints' world
    /// matrices and the skinClusters' outputs are computed.
    pub outputs: Vec<String>,
    /// Leave out of the schedule every step nothing observed needs (default
    /// `true`): unread inverse matrices, debug outputs, unused branches.
    pub prune: bool,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions {
            dynamic_inputs: Vec::new(),
            cpu_skinning: true,
            outputs: Vec::new(),
            prune: true,
        }
    }
}

impl LoadOptions {
    /// Adds a dynamic input path or pattern (see [`LoadOptions::dynamic_inputs`]).
    pub fn dynamic(mut self, pattern: impl Into<String>) -> Self {
        self.dynamic_inputs.push(pattern.into());
        self
    }

    /// Adds an output read with [`Rig::output`](crate::Rig::output) (see [`LoadOptions::outputs`]).
    pub fn output(mut self, path: impl Into<String>) -> Self {
        self.outputs.push(path.into());
        self
    }

    /// Sets [`LoadOptions::prune`].
    pub fn prune(mut self, on: bool) -> Self {
        self.prune = on;
        self
    }

    /// Sets [`LoadOptions::cpu_skinning`].
    pub fn cpu_skinning(mut self, on: bool) -> Self {
        self.cpu_skinning = on;
        self
    }
}

/// Where a rig comes from.
#[derive(Clone, Copy, Debug)]
pub enum RigSource<'a> {
    /// A RON rig file (component files are read relative to it).
    File(&'a Path),
    /// RON text; `path` names it in errors and anchors relative component paths.
    Text {
        /// The rig text.
        text: &'a str,
        /// A (possibly virtual) file path for messages and component lookup.
        path: &'a Path,
    },
    /// Bytes written by [`Rig::to_bytes`] (load options are baked in).
    Bytes(&'a [u8]),
}

/// The node types rigs may use. Cheap to clone; load rigs through it.
#[derive(Clone, Debug)]
pub struct Runtime {
    registry: Arc<Registry>,
}

impl Runtime {
    /// A runtime with sinew's standard node types.
    pub fn new() -> Result<Runtime> {
        let registry = sinew_nodes::registry()
            .map_err(|e| RuntimeError::new(ErrorKind::Load, format!("standard node types: {e}")))?;
        Ok(Runtime { registry })
    }

    /// A runtime with your own registry (standard types plus your plugins, say).
    pub fn with_registry(registry: Arc<Registry>) -> Runtime {
        Runtime { registry }
    }

    /// The node types.
    pub fn registry(&self) -> &Arc<Registry> {
        &self.registry
    }

    /// Loads and compiles a rig.
    pub fn load_rig(&self, source: RigSource<'_>, options: &LoadOptions) -> Result<Rig> {
        match source {
            RigSource::File(path) => {
                let loaded = sinew_core::load_rig(path, &self.registry)
                    .map_err(|d| RuntimeError::new(ErrorKind::Load, d.render()))?;
                Rig::from_loaded(loaded, options)
            }
            RigSource::Text { text, path } => {
                let loaded = sinew_core::load_rig_str(text, path, &self.registry)
                    .map_err(|d| RuntimeError::new(ErrorKind::Load, d.render()))?;
                Rig::from_loaded(loaded, options)
            }
            RigSource::Bytes(bytes) => format::decode_rig(bytes, &self.registry),
        }
    }

    /// Compiles a graph built or edited in code (for instance a rig with a
    /// skinCluster bound at load time). `name` names the rig; the frame rate is the graph's.
    pub fn compile_graph(&self, graph: sinew_core::Graph, name: &str, options: &LoadOptions) -> Result<Rig> {
        Rig::from_graph(graph, name.to_string(), options)
    }

    /// Loads a RON rig file.
    pub fn load_rig_file(&self, path: impl AsRef<Path>, options: &LoadOptions) -> Result<Rig> {
        self.load_rig(RigSource::File(path.as_ref()), options)
    }

    /// Loads a rig from RON text (component paths are relative to the current directory).
    pub fn load_rig_text(&self, text: &str, options: &LoadOptions) -> Result<Rig> {
        self.load_rig(
            RigSource::Text {
                text,
                path: Path::new("rig.ron"),
            },
            options,
        )
    }

    /// Loads a rig from the bytes of [`Rig::to_bytes`].
    pub fn load_rig_bytes(&self, bytes: &[u8]) -> Result<Rig> {
        self.load_rig(RigSource::Bytes(bytes), &LoadOptions::default())
    }
}

/// Whether `text` matches `pattern`, where `*` matches any run of characters.
pub(crate) fn glob_match(pattern: &str, text: &str) -> bool {
    let (p, t) = (pattern.as_bytes(), text.as_bytes());
    let (mut pi, mut ti) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while ti < t.len() {
        if pi < p.len() && p[pi] == b'*' {
            star = Some((pi, ti));
            pi += 1;
        } else if pi < p.len() && p[pi] == t[ti] {
            pi += 1;
            ti += 1;
        } else if let Some((sp, st)) = star {
            pi = sp + 1;
            ti = st + 1;
            star = Some((sp, st + 1));
        } else {
            return false;
        }
    }
    p[pi..].iter().all(|&c| c == b'*')
}

#[cfg(test)]
mod tests {
    use super::glob_match;

    #[test]
    fn glob() {
        assert!(glob_match("*_ctrl_*", "foot_ctrl_L"));
        assert!(glob_match("*", ""));
        assert!(glob_match("a*b*c", "aXXbYc"));
        assert!(!glob_match("a*b*c", "aXXbY"));
        assert!(glob_match("exact", "exact"));
        assert!(!glob_match("exact", "exactly"));
    }
}
