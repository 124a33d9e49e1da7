//! The runtime view for game engines: a rig's skeleton as flat arrays, refreshed from a
//! compiled [`Instance`] each frame (ozz-animation's layout: joints parent-first with
//! parent indices; local TRS, model-space matrices, inverse binds and the skinning palette
//! as contiguous `f32` arrays ready to upload).
//!
//! - `joints`: every DAG node (`joint`, `transform`) in parent-first order; `parents[i]` is
//!   the index of joint `i`'s parent (`-1` for roots), always `< i`.
//! - Per frame ([`RuntimeView::update`]): `locals` (10 floats per joint: translation xyz,
//!   rotation quaternion xyzw, scale xyz; the decomposition of `parent⁻¹ · model`), `models`
//!   (16 floats per joint, column-major, the joint's `worldMatrix`).
//! - Skin (optional, one `skinCluster`): `skin_joints[k]` = joint index of influence `k`
//!   (`matrix[k]`), `inverse_binds` (16 floats per influence, `bindPreMatrix[k]`), and per
//!   frame `palette` (16 floats per influence, `models[skin_joints[k]] · inverse_binds[k]`,
//!   what a skinning shader multiplies vertices by).
//!
//! `update` allocates nothing: it reads handles resolved once in [`RuntimeView::new`].

use std::collections::HashMap;

use glam::{DMat4, Mat4};
use sinew_core::{Graph, Instance, PlugHandle, Program, Time, Value};

use super::bake::{dag_order, local_trs};

/// Flat skeleton arrays of a compiled rig (see the module docs).
pub struct RuntimeView {
    /// Joint (DAG node) names, parent-first.
    pub names: Vec<String>,
    /// Parent index per joint, `-1` for roots.
    pub parents: Vec<i32>,
    /// 10 floats per joint: `tx ty tz qx qy qz qw sx sy sz`.
    pub locals: Vec<f32>,
    /// 16 floats per joint: model-space (world) matrix, column-major.
    pub models: Vec<f32>,
    /// Joint index of each skin influence.
    pub skin_joints: Vec<u32>,
    /// 16 floats per influence: inverse bind matrix.
    pub inverse_binds: Vec<f32>,
    /// 16 floats per influence: `model · inverse bind`.
    pub palette: Vec<f32>,
    world_handles: Vec<PlugHandle>,
    world: Vec<DMat4>,
}

fn matrix(v: &Value) -> DMat4 {
    match v {
        Value::Matrix(m) => *m,
        _ => DMat4::IDENTITY,
    }
}

impl RuntimeView {
    /// Builds the view for `graph` compiled as `program`; `skin` names a `skinCluster`
    /// whose influences give the palette (its `matrix[k]` must come from DAG nodes).
    pub fn new(graph: &mut Graph, program: &Program, skin: Option<&str>) -> Result<Self, String> {
        let dag = dag_order(graph);
        let index: HashMap<_, _> = dag.iter().enumerate().map(|(i, &n)| (n, i)).collect();
        let names: Vec<String> = dag
            .iter()
            .map(|&n| graph.node_name(n).unwrap_or("").to_string())
            .collect();
        let parents = dag
            .iter()
            .map(|&n| graph.parent_of(n).and_then(|p| index.get(&p)).map_or(-1, |&p| p as i32))
            .collect();
        let world_handles = names
            .iter()
            .map(|n| program.handle(&format!("{n}.worldMatrix")).map_err(|e| e.to_string()))
            .collect::<Result<Vec<_>, _>>()?;
        let mut skin_joints = Vec::new();
        let mut inverse_binds = Vec::new();
        if let Some(sc) = skin {
            let id = graph.node_id(sc).map_err(|e| e.to_string())?;
            let attr = graph
                .node_spec(id)
                .and_then(|s| s.find("matrix"))
                .ok_or_else(|| format!("{sc} is not a skinCluster"))?
                .0;
            let count = graph.elements(id, attr).into_iter().max().map_or(0, |m| m + 1);
            for k in 0..count {
                let p = graph.plug(&format!("{sc}.matrix[{k}]")).map_err(|e| e.to_string())?;
                let j = graph
                    .source_of(p)
                    .and_then(|s| index.get(&s.node))
                    .ok_or_else(|| format!("{sc}.matrix[{k}] is not driven by a joint's worldMatrix"))?;
                skin_joints.push(*j as u32);
                let ibm = graph
                    .get_path(&format!("{sc}.bindPreMatrix[{k}]"))
                    .map_err(|e| e.to_string())?;
                inverse_binds.extend_from_slice(&matrix(&ibm).as_mat4().to_cols_array());
            }
        }
        let n = names.len();
        let s = skin_joints.len();
        Ok(RuntimeView {
            names,
            parents,
            locals: vec![0.0; n * 10],
            models: vec![0.0; n * 16],
            skin_joints,
            inverse_binds,
            palette: vec![0.0; s * 16],
            world_handles,
            world: vec![DMat4::IDENTITY; n],
        })
    }

    /// Number of joints.
    pub fn joint_count(&self) -> usize {
        self.names.len()
    }

    /// Evaluates `inst` at `time` and refreshes every per-frame array.
    pub fn update(&mut self, inst: &mut Instance, time: Time) -> Result<(), String> {
        inst.evaluate(time).map_err(|e| e.to_string())?;
        self.refresh(inst);
        Ok(())
    }

    /// Refreshes the per-frame arrays from an already evaluated instance.
    pub fn refresh(&mut self, inst: &Instance) {
        for (i, h) in self.world_handles.iter().enumerate() {
            self.world[i] = matrix(&inst.get(h));
        }
        for i in 0..self.world.len() {
            let parent = usize::try_from(self.parents[i]).ok().map(|p| self.world[p]);
            let (s, r, t) = local_trs(parent, self.world[i]);
            let l = &mut self.locals[i * 10..i * 10 + 10];
            l[..3].copy_from_slice(&t.to_array());
            l[3..7].copy_from_slice(&r.to_array());
            l[7..].copy_from_slice(&s.to_array());
            self.models[i * 16..i * 16 + 16].copy_from_slice(&self.world[i].as_mat4().to_cols_array());
        }
        for (k, &j) in self.skin_joints.iter().enumerate() {
            let ibm = Mat4::from_cols_slice(&self.inverse_binds[k * 16..k * 16 + 16]);
            let m = self.world[j as usize].as_mat4() * ibm;
            self.palette[k * 16..k * 16 + 16].copy_from_slice(&m.to_cols_array());
        }
    }
}
