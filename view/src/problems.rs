//! Problems of an evaluation, as markers on nodes: every node whose compute fails (not
//! only the first, where the compiled evaluation stops), every node with an output that
//! is not finite (NaN or infinite), and every node whose declared status output
//! ([`sinew_core::StatusSpec`], e.g. an IK that cannot reach its goal) reports a problem.
//!
//! Nothing here names a node type: outputs are scanned by value type, statuses come
//! from the specs.

use serde_json::{json, Value as Json};
use sinew_core::{AttrId, AttrType, Direction, Error, Graph, Instance, PlugHandle, Program, Value};

/// What kind of problem a node has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProblemKind {
    /// Its compute failed.
    Error,
    /// An output holds NaN or an infinity.
    NonFinite,
    /// Its status output names a problem (the node still produced its best answer).
    Status,
}

impl ProblemKind {
    fn name(self) -> &'static str {
        match self {
            ProblemKind::Error => "error",
            ProblemKind::NonFinite => "nonFinite",
            ProblemKind::Status => "status",
        }
    }
}

/// A problem marked on a node.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    /// The node (empty when the error names none).
    pub node: String,
    /// What kind.
    pub kind: ProblemKind,
    /// The message shown.
    pub message: String,
}

impl Problem {
    /// The problem of a failed evaluation.
    pub fn from_error(e: &Error) -> Problem {
        let (node, message) = match e {
            Error::Compute { node, message, .. } => (node.clone(), message.clone()),
            other => (String::new(), other.to_string()),
        };
        Problem {
            node,
            kind: ProblemKind::Error,
            message,
        }
    }

    /// As JSON for the page: `{node, kind, message}`.
    pub fn to_json(&self) -> Json {
        json!({ "node": self.node, "kind": self.kind.name(), "message": self.message })
    }
}

/// A status output to read after each evaluation.
struct StatusPlug {
    node: String,
    status: PlugHandle,
    message: Option<PlugHandle>,
    names: Vec<String>,
}

/// What is checked after each compiled evaluation of one program: the outputs of
/// numeric and geometric types (for non-finite values) and the declared statuses.
#[derive(Default)]
pub struct Checks {
    /// (node, attribute label, handle) of every scanned output.
    values: Vec<(String, String, PlugHandle)>,
    statuses: Vec<StatusPlug>,
}

/// Whether a value of `ty` can hold a non-finite number worth scanning.
fn scanned(ty: AttrType) -> bool {
    matches!(
        ty,
        AttrType::Float
            | AttrType::Vec3
            | AttrType::Quat
            | AttrType::Matrix
            | AttrType::Mesh
            | AttrType::Curve
            | AttrType::FloatArray
            | AttrType::Vec3Array
            | AttrType::MatrixArray
    )
}

/// Whether `v` holds a NaN or an infinity.
pub fn non_finite(v: &Value) -> bool {
    match v {
        Value::Float(x) => !x.is_finite(),
        Value::Vec3(x) => !x.is_finite(),
        Value::Quat(x) => !x.is_finite(),
        Value::Matrix(x) => !x.is_finite(),
        Value::Mesh(m) => !m.positions.iter().all(|p| p.is_finite()),
        Value::Curve(c) => !c.points.iter().all(|p| p.is_finite()),
        Value::FloatArray(a) => !a.iter().all(|x| x.is_finite()),
        Value::Vec3Array(a) => !a.iter().all(|x| x.is_finite()),
        Value::MatrixArray(a) => !a.iter().all(|x| x.is_finite()),
        _ => false,
    }
}

impl Checks {
    /// The checks for `program`, compiled from `graph` (plugs the program cannot read
    /// are left out).
    pub fn new(graph: &Graph, program: &Program) -> Checks {
        let mut checks = Checks::default();
        for id in graph.nodes() {
            let (Some(spec), Some(name)) = (graph.node_spec(id), graph.node_name(id)) else {
                continue;
            };
            for (i, a) in spec.attrs.iter().enumerate() {
                if a.direction != Direction::Output || !scanned(a.ty) {
                    continue;
                }
                let paths: Vec<String> = if a.multi {
                    graph
                        .elements(id, AttrId(i as u16))
                        .into_iter()
                        .map(|k| format!("{}[{k}]", a.name))
                        .collect()
                } else {
                    vec![a.name.clone()]
                };
                for attr in paths {
                    if let Ok(h) = program.handle(&format!("{name}.{attr}")) {
                        checks.values.push((name.to_string(), attr, h));
                    }
                }
            }
            if let Some(st) = spec.status {
                let status = spec.attr(st.status);
                let handle = |a: AttrId| program.handle(&format!("{name}.{}", spec.attr(a).name)).ok();
                if let Some(h) = handle(st.status) {
                    checks.statuses.push(StatusPlug {
                        node: name.to_string(),
                        status: h,
                        message: st.message.and_then(handle),
                        names: status.enum_names.clone(),
                    });
                }
            }
        }
        checks
    }

    /// The problems `instance` holds after an evaluation: non-finite outputs (one problem
    /// per node, naming its outputs) and statuses other than the first choice.
    pub fn scan(&self, instance: &Instance, out: &mut Vec<Problem>) {
        let mut last: Option<usize> = None;
        for (node, attr, h) in &self.values {
            if !non_finite(&instance.get(h)) {
                continue;
            }
            match last.filter(|&k| out[k].node == *node && out[k].kind == ProblemKind::NonFinite) {
                Some(k) => out[k].message.push_str(&format!(", {attr}")),
                None => {
                    out.push(Problem {
                        node: node.clone(),
                        kind: ProblemKind::NonFinite,
                        message: format!("not finite (NaN or infinite): {attr}"),
                    });
                    last = Some(out.len() - 1);
                }
            }
        }
        for s in &self.statuses {
            let code = match instance.get(&s.status) {
                Value::Enum(k) | Value::Int(k) => k,
                _ => 0,
            };
            if code == 0 {
                continue;
            }
            let name = usize::try_from(code)
                .ok()
                .and_then(|k| s.names.get(k))
                .cloned()
                .unwrap_or_else(|| format!("status {code}"));
            // The status's name, then the node's words (which may start with the name).
            let message = match s.message.as_ref().map(|m| instance.get(m)) {
                Some(Value::String(m)) if m.starts_with(name.as_str()) => m.to_string(),
                Some(Value::String(m)) if !m.is_empty() => format!("{name}: {m}"),
                _ => name,
            };
            out.push(Problem {
                node: s.node.clone(),
                kind: ProblemKind::Status,
                message,
            });
        }
    }
}

/// Every failing node of `graph` at its current time (see [`Graph::evaluate_each`]):
/// what to mark after a compiled evaluation stopped at its first failure.
pub fn failing_nodes(graph: &mut Graph) -> Vec<Problem> {
    graph.evaluate_each().iter().map(Problem::from_error).collect()
}
