//! `set_keys`: writes a list of [`Key`]s onto an animCurve node's key
//! attributes (for tests, examples and the rig-file layer).

use sinew_core::{Error, Graph, NodeId, Plug, Value};

use super::curve::Key;
use super::nodes::tangent_index;

/// Sets the keys of the animCurve node `node` (replacing all existing keys).
///
/// Keys are in the node's plug units: times in frames (time curves) or driver
/// units, values in degrees for angular curves. `Key` angles are radians in
/// (time, plug value) space and are written to `keyInAngle`/`keyOutAngle` in
/// degrees; a weight of `None` removes that weight element (default handle).
/// Infinity and `weightedTangents` are left as they are.
pub fn set_keys(graph: &mut Graph, node: NodeId, keys: &[Key]) -> Result<(), Error> {
    let spec = graph
        .node_spec(node)
        .ok_or_else(|| Error::Program("set_keys: the node does not exist".into()))?
        .clone();
    let attr = |name: &str| {
        spec.find(name).map(|(a, _)| a).ok_or_else(|| Error::UnknownAttribute {
            node: graph.node_name(node).unwrap_or("?").to_string(),
            node_type: spec.name.clone(),
            attr: name.to_string(),
            suggestion: None,
        })
    };
    let names = [
        "keyTime",
        "keyValue",
        "keyInTangentType",
        "keyOutTangentType",
        "keyInAngle",
        "keyOutAngle",
        "keyInWeight",
        "keyOutWeight",
    ];
    let ids = names.map(attr);
    let mut attrs = Vec::with_capacity(ids.len());
    for id in ids {
        attrs.push(id?);
    }
    for &a in &attrs {
        for i in graph.elements(node, a) {
            graph.remove_element(node, a, i)?;
        }
    }
    for (i, key) in keys.iter().enumerate() {
        let i = i as u32;
        let plug = |k: usize| Plug::new(node, attrs[k]).at(i);
        graph.set(plug(0), Value::Float(key.time))?;
        graph.set(plug(1), Value::Float(key.value))?;
        graph.set(plug(2), Value::Enum(tangent_index(key.in_tangent)))?;
        graph.set(plug(3), Value::Enum(tangent_index(key.out_tangent)))?;
        if let Some(a) = key.in_angle {
            graph.set(plug(4), Value::Float(a.to_degrees()))?;
        }
        if let Some(a) = key.out_angle {
            graph.set(plug(5), Value::Float(a.to_degrees()))?;
        }
        if let Some(w) = key.in_weight {
            graph.set(plug(6), Value::Float(w))?;
        }
        if let Some(w) = key.out_weight {
            graph.set(plug(7), Value::Float(w))?;
        }
    }
    Ok(())
}
