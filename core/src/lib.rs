//! sinew-core: the dependency-graph engine of sinew.
//!
//! Values and attribute types ([`Value`], [`AttrType`]), node-type specs and
//! typed handles ([`NodeSpec`], [`Input`], [`Output`]), the plugin trait
//! ([`NodeType`]) and its [`ComputeContext`], the [`Registry`], the lazy
//! [`Graph`] (connections, plug-level cycle detection, push-dirty /
//! pull-evaluate with early cutoff) and the compiled [`Program`] with its
//! [`Instance`]s. The core knows no node type by name.

pub mod custom;
pub mod data;
pub mod error;
pub mod files;
pub mod graph;
pub mod inactive;
mod instance;
pub mod kernel;
pub mod mat_kernel;
pub mod node;
pub mod path;
pub mod profile;
pub mod program;
pub mod program_bin;
mod program_codec;
mod program_compile;
mod program_custom;
mod program_layout;
pub mod registry;
pub mod rig;
mod slots;
pub mod spec;
mod tape;
pub mod testing;
pub mod validate;
pub mod value;
pub mod value_file;

/// A hash map with a fast, randomly seeded hasher (foldhash) for maps filled once per node
/// or connection while loading and compiling.
pub(crate) type FastMap<K, V> = std::collections::HashMap<K, V, foldhash::fast::RandomState>;
/// The set of [`FastMap`].
pub(crate) type FastSet<K> = std::collections::HashSet<K, foldhash::fast::RandomState>;

pub use custom::{CustomAffects, CustomNode};
pub use data::{Curve, CurveForm, Mesh, Surface, Weights};
pub use error::{ComputeError, Error, InputError, Result, SpecError};
pub use graph::{EvalStats, Graph, NodeId, Plug, MAX_ELEMENT_INDEX};
pub use kernel::{finite, KernelNode, ScalarKernel, ScalarOp, MAX_KERNEL_INPUTS};
pub use mat_kernel::{MatrixFn, MatrixKernel};
pub use node::{ComputeContext, KnownInputs, NodeType, Time};
pub use profile::{ProfileRow, ProfileTable, Profiler, StepTiming};
pub use program::{evaluate_batch, CompileOptions, Instance, PlugHandle, Program};
pub use registry::Registry;
pub use rig::expand::{AuthoringField, ExpandContext, ExpandPhase, NamedWeights};
pub use rig::{
    format_rig_file, graph_eq, load_rig, load_rig_str, rig_dependencies, save_rig, to_dot, to_json, Diagnostic,
    Diagnostics, LoadedRig, RigDocument,
};
pub use spec::{
    AttrId, AttrSpec, ComputeGroup, DagLink, DagSpec, Direction, Input, MirrorRole, MultiInput, MultiOutput, NodeSpec,
    Output, SpecBuilder, StatusSpec, Unit,
};
pub use validate::{Problem, ValidateInputs};
pub use value::{AttrType, AttrValue, ObjectRef, SharedData, Value};
