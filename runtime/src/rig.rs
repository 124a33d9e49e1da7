//! A compiled, immutable rig shared by its instances: the program, the joints
//! in parent-first order with parent indices, the skin clusters, and handle
//! resolution (done once, so frames do no string lookup).

use std::marker::PhantomData;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use sinew_core::{AttrType, AttrValue, CompileOptions, Graph, Instance, LoadedRig, NodeId, PlugHandle, Program, Value};

use crate::instance::RigInstance;
use crate::{glob_match, ErrorKind, LoadOptions, Result, RuntimeError};

/// The node type whose nodes are the rig's joints.
pub(crate) const JOINT_TYPE: &str = "joint";
/// The node type whose `palette` and `outputGeometry` the rig exposes.
pub(crate) const SKIN_TYPE: &str = "skinCluster";

static NEXT_RIG_ID: AtomicU64 = AtomicU64::new(1);

/// One joint: its node name and the index of its nearest joint ancestor.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Joint {
    /// The joint node's name.
    pub name: String,
    /// Index (in [`Rig::joints`]) of the nearest ancestor that is a joint; `None` for roots.
    /// Always smaller than this joint's own index.
    pub parent: Option<usize>,
}

pub(crate) struct Skin {
    pub name: String,
    pub palette: PlugHandle,
    pub geometry: PlugHandle,
}

pub(crate) struct RigInner {
    pub id: u64,
    pub name: String,
    pub fps: f64,
    pub program: Arc<Program>,
    pub joints: Vec<Joint>,
    pub parents: Vec<i32>,
    pub joint_world: Vec<PlugHandle>,
    pub skins: Vec<Skin>,
    /// An instance used only to check, when a handle is resolved, that the plug can be set.
    probe: Mutex<Option<Instance>>,
}

/// A compiled rig: immutable, cheap to clone (an `Arc`), shared by all its instances.
#[derive(Clone)]
pub struct Rig {
    pub(crate) inner: Arc<RigInner>,
}

impl std::fmt::Debug for Rig {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Rig")
            .field("name", &self.inner.name)
            .field("joints", &self.inner.joints.len())
            .field("skins", &self.inner.skins.len())
            .field("program", &self.inner.program)
            .finish()
    }
}

/// A settable input of a rig, typed: set it with [`RigInstance::set`].
pub struct InputHandle<T> {
    pub(crate) rig: u64,
    pub(crate) plug: PlugHandle,
    _t: PhantomData<fn(T)>,
}

impl<T> Clone for InputHandle<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for InputHandle<T> {}
impl<T> std::fmt::Debug for InputHandle<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "InputHandle({})", self.plug.attr_type())
    }
}

/// A settable input of any type (its type is [`AnyInput::attr_type`]), for
/// bindings that learn types at run time (the C API).
#[derive(Clone, Copy, Debug)]
pub struct AnyInput {
    pub(crate) rig: u64,
    pub(crate) plug: PlugHandle,
}

impl AnyInput {
    /// The value type this input takes.
    pub fn attr_type(&self) -> AttrType {
        self.plug.attr_type()
    }
}

/// Any plug of a rig (output or input), typed, read with [`RigInstance::get`].
pub struct OutputHandle<T> {
    pub(crate) rig: u64,
    pub(crate) plug: PlugHandle,
    _t: PhantomData<fn() -> T>,
}

impl<T> Clone for OutputHandle<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for OutputHandle<T> {}
impl<T> std::fmt::Debug for OutputHandle<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "OutputHandle({})", self.plug.attr_type())
    }
}

fn type_matches(want: AttrType, have: AttrType) -> bool {
    want == have || matches!((want, have), (AttrType::Int, AttrType::Enum))
}

/// Joints in parent-first (depth-first, graph order) order with the index of each one's nearest joint ancestor.
fn collect_joints(g: &Graph) -> Vec<Joint> {
    fn visit(g: &Graph, id: NodeId, parent: Option<usize>, out: &mut Vec<Joint>) {
        let mut me = parent;
        if g.node_type(id) == Some(JOINT_TYPE) {
            out.push(Joint {
                name: g.node_name(id).unwrap_or_default().to_string(),
                parent,
            });
            me = Some(out.len() - 1);
        }
        for c in g.children_of(id) {
            visit(g, c, me, out);
        }
    }
    let mut out = Vec::new();
    for id in g.nodes() {
        if g.parent_of(id).is_none() {
            visit(g, id, None, &mut out);
        }
    }
    out
}

impl Rig {
    /// Compiles a loaded RON rig.
    pub(crate) fn from_loaded(loaded: LoadedRig, options: &LoadOptions) -> Result<Rig> {
        let name = loaded.document.name.clone().unwrap_or_default();
        Rig::from_graph(loaded.graph, name, options)
    }

    /// Compiles a graph.
    pub(crate) fn from_graph(mut g: Graph, name: String, options: &LoadOptions) -> Result<Rig> {
        let fps = g.time().fps;
        let skin_names: Vec<String> = g
            .nodes()
            .into_iter()
            .filter(|&id| g.node_type(id) == Some(SKIN_TYPE))
            .filter_map(|id| g.node_name(id).map(str::to_string))
            .collect();
        if !options.cpu_skinning {
            for s in &skin_names {
                let plug = g
                    .plug(&format!("{s}.envelope"))
                    .map_err(|e| RuntimeError::core(ErrorKind::Compile, e))?;
                if g.source_of(plug).is_none() {
                    g.set(plug, Value::Float(0.0))
                        .map_err(|e| RuntimeError::core(ErrorKind::Compile, e))?;
                }
            }
        }
        let dynamic_inputs = resolve_dynamic(&g, &options.dynamic_inputs)?;
        let joints = collect_joints(&g);
        let observed = if options.prune {
            let mut paths: Vec<String> = joints.iter().map(|j| format!("{}.worldMatrix", j.name)).collect();
            for s in &skin_names {
                paths.push(format!("{s}.palette"));
                paths.push(format!("{s}.outputGeometry"));
            }
            paths.extend(options.outputs.iter().cloned());
            let plugs = paths
                .iter()
                .map(|p| g.plug(p).map_err(|e| RuntimeError::core(ErrorKind::Compile, e)))
                .collect::<Result<Vec<_>>>()?;
            Some(plugs)
        } else {
            None
        };
        let program = Program::compile(
            &g,
            &CompileOptions {
                dynamic_inputs,
                observed,
            },
        )
        .map_err(|e| RuntimeError::core(ErrorKind::Compile, e))?;
        Rig::assemble(name, fps, Arc::new(program), joints, skin_names)
    }

    /// Builds a rig around a program, resolving joint and skin handles.
    pub(crate) fn assemble(
        name: String,
        fps: f64,
        program: Arc<Program>,
        joints: Vec<Joint>,
        skins: Vec<String>,
    ) -> Result<Rig> {
        let handle = |path: String, ty: AttrType| -> Result<PlugHandle> {
            let h = program
                .handle(&path)
                .map_err(|e| RuntimeError::core(ErrorKind::Format, e))?;
            if h.attr_type() != ty {
                return Err(RuntimeError::new(
                    ErrorKind::Format,
                    format!("{path} is {}, expected {ty}", h.attr_type()),
                ));
            }
            Ok(h)
        };
        let joint_world = joints
            .iter()
            .map(|j| handle(format!("{}.worldMatrix", j.name), AttrType::Matrix))
            .collect::<Result<Vec<_>>>()?;
        let parents = joints
            .iter()
            .enumerate()
            .map(|(i, j)| match j.parent {
                Some(p) if p < i => Ok(p as i32),
                None => Ok(-1),
                Some(p) => Err(RuntimeError::new(
                    ErrorKind::Format,
                    format!("joint {i} has parent {p}, which does not come before it"),
                )),
            })
            .collect::<Result<Vec<_>>>()?;
        let skins = skins
            .into_iter()
            .map(|s| {
                Ok(Skin {
                    palette: handle(format!("{s}.palette"), AttrType::MatrixArray)?,
                    geometry: handle(format!("{s}.outputGeometry"), AttrType::Mesh)?,
                    name: s,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Rig {
            inner: Arc::new(RigInner {
                id: NEXT_RIG_ID.fetch_add(1, Ordering::Relaxed),
                name,
                fps: if fps > 0.0 && fps.is_finite() { fps } else { 24.0 },
                program,
                joints,
                parents,
                joint_world,
                skins,
                probe: Mutex::new(None),
            }),
        })
    }

    /// The rig's name (from its file).
    pub fn name(&self) -> &str {
        &self.inner.name
    }

    /// Frames per second of the rig's animation (24 unless the file says otherwise).
    pub fn fps(&self) -> f64 {
        self.inner.fps
    }

    /// The compiled program.
    pub fn program(&self) -> &Arc<Program> {
        &self.inner.program
    }

    /// The joints (every `joint` node), parent first.
    pub fn joints(&self) -> &[Joint] {
        &self.inner.joints
    }

    /// Number of joints.
    pub fn joint_count(&self) -> usize {
        self.inner.joints.len()
    }

    /// Parent index of each joint, `-1` for roots (the layout engines upload).
    pub fn parent_indices(&self) -> &[i32] {
        &self.inner.parents
    }

    /// The index of the joint named `name`.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.inner.joints.iter().position(|j| j.name == name)
    }

    /// Number of skin clusters (palettes / skinned meshes).
    pub fn skin_count(&self) -> usize {
        self.inner.skins.len()
    }

    /// The names of the skin clusters, by skin index.
    pub fn skin_names(&self) -> impl Iterator<Item = &str> {
        self.inner.skins.iter().map(|s| s.name.as_str())
    }

    /// A new instance with the rig's authored values (shares the program).
    pub fn instantiate(&self) -> RigInstance {
        RigInstance::new(self.clone())
    }

    /// Serializes the rig (program, joints, skins) for [`Runtime::load_rig_bytes`](crate::Runtime::load_rig_bytes).
    pub fn to_bytes(&self) -> Vec<u8> {
        crate::format::encode_rig(self)
    }

    /// Resolves a settable input, typed (`f64` for a float or a vec3 child
    /// such as `ctrl.translateX`, `DVec3`, `DMat4`, `i64` for int and enum, `bool`...).
    pub fn input<T: AttrValue>(&self, path: &str) -> Result<InputHandle<T>> {
        let any = self.input_any(path)?;
        if !type_matches(T::TYPE, any.attr_type()) {
            return Err(RuntimeError::new(
                ErrorKind::Input,
                format!("{path} is {} but the handle asks for {}", any.attr_type(), T::TYPE),
            ));
        }
        Ok(InputHandle {
            rig: any.rig,
            plug: any.plug,
            _t: PhantomData,
        })
    }

    /// Resolves a settable input of any type.
    pub fn input_any(&self, path: &str) -> Result<AnyInput> {
        let plug = self
            .inner
            .program
            .handle(path)
            .map_err(|e| RuntimeError::core(ErrorKind::NotFound, e))?;
        // Setting the current value back is harmless and tells whether the plug is settable.
        let mut probe = self.inner.probe.lock().unwrap_or_else(|p| p.into_inner());
        let inst = probe.get_or_insert_with(|| Instance::new(self.inner.program.clone()));
        let current = inst.get(&plug);
        inst.set(&plug, current)
            .map_err(|e| RuntimeError::new(ErrorKind::Input, format!("{path}: {e}")))?;
        Ok(AnyInput {
            rig: self.inner.id,
            plug,
        })
    }

    /// Resolves any plug for reading, typed.
    pub fn output<T: AttrValue>(&self, path: &str) -> Result<OutputHandle<T>> {
        let plug = self
            .inner
            .program
            .handle(path)
            .map_err(|e| RuntimeError::core(ErrorKind::NotFound, e))?;
        if !type_matches(T::TYPE, plug.attr_type()) {
            return Err(RuntimeError::new(
                ErrorKind::Input,
                format!("{path} is {} but the handle asks for {}", plug.attr_type(), T::TYPE),
            ));
        }
        Ok(OutputHandle {
            rig: self.inner.id,
            plug,
            _t: PhantomData,
        })
    }
}

/// Turns dynamic input paths and patterns into plugs of `g`.
fn resolve_dynamic(g: &Graph, patterns: &[String]) -> Result<Vec<sinew_core::Plug>> {
    let mut out = Vec::new();
    for pat in patterns {
        let Some((node_pat, attr)) = pat.split_once('.') else {
            return Err(RuntimeError::new(
                ErrorKind::NotFound,
                format!("dynamic input `{pat}` is not a plug path (write node.attribute)"),
            ));
        };
        if !node_pat.contains('*') {
            let plug = g.plug(pat).map_err(|e| RuntimeError::core(ErrorKind::NotFound, e))?;
            if g.source_of(plug).is_some()
                || g.source_of(sinew_core::Plug {
                    component: None,
                    ..plug
                })
                .is_some()
            {
                return Err(RuntimeError::new(
                    ErrorKind::Compile,
                    format!("dynamic input {pat} is driven by a connection; only unconnected inputs can be set"),
                ));
            }
            out.push(plug);
            continue;
        }
        let before = out.len();
        for id in g.nodes() {
            let Some(name) = g.node_name(id) else { continue };
            if !glob_match(node_pat, name) {
                continue;
            }
            let Ok(plug) = g.plug(&format!("{name}.{attr}")) else {
                continue;
            };
            let is_input = g
                .node_spec(id)
                .is_some_and(|s| s.attr(plug.attr).direction == sinew_core::Direction::Input);
            let driven = g.source_of(plug).is_some()
                || g.source_of(sinew_core::Plug {
                    component: None,
                    ..plug
                })
                .is_some();
            if is_input && !driven {
                out.push(plug);
            }
        }
        if out.len() == before {
            return Err(RuntimeError::new(
                ErrorKind::NotFound,
                format!("dynamic input pattern `{pat}` matches no unconnected input"),
            ));
        }
    }
    Ok(out)
}
