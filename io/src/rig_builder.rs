//! A rig under construction by an importer: nodes with attribute values, DAG parents and
//! connections, turned either into a [`Graph`] directly or into rig text split in two files:
//! the readable main rig and a *data sidecar* holding the nodes with heavy values.
//!
//! # The data sidecar (see `docs/rig-format.md`, "Imported rigs and their data file")
//! `sinew import model.glb -o model.ron` writes `model.ron` (header, the joint/transform
//! hierarchy with rest values, all connections) and `model.data.ron` (mesh, skinCluster,
//! blendShape and animation curve nodes with their arrays). The main rig pulls the data in
//! with `uses: [Use(file: "model.data.ron")]`, so any sinew command (`check`, `eval`,
//! `fmt`) loads the pair with the ordinary rig loader and no special support: connections
//! in the main file reach the data file's nodes by name.
//!
//! # Value files
//! A value of more than [`VALUE_FILE_NUMBERS`] numbers (a long take's animation keys, a
//! dense mesh, its weights) is written to a binary value file in the folder
//! `model.data/` ([`sinew_core::value_file`], exact to the bit) and referenced from the
//! sidecar as `keyValue: File("model.data/hip_rotate.keyValue.bin")`, which the core
//! loader reads. A 60,000-frame BVH take would otherwise be an 83 MB sidecar whose syntax
//! tree takes over a gigabyte to load; as value files it is 17 MB read at memory speed.

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;
use std::path::Path;
use std::sync::Arc;

use sinew_core::rig::doc::{print_ast, quote};
use sinew_core::rig::typed::write_value;
use sinew_core::{Graph, NodeId, Registry, Value};

/// An attribute value: one value, or the elements `0..n` of a multi attribute.
#[derive(Clone, Debug)]
pub enum AttrVal {
    /// A plain attribute.
    One(Value),
    /// Elements `0..n` of a multi attribute.
    Multi(Vec<Value>),
    /// Sparse elements `(index, value)` of a multi attribute, written as a RON map.
    Sparse(Vec<(u32, Value)>),
}

/// One node of a [`RigBuilder`].
#[derive(Clone, Debug)]
pub struct NodeRec {
    /// Unique node name (a rig identifier).
    pub name: String,
    /// Registered node type.
    pub type_name: String,
    /// DAG parent.
    pub parent: Option<String>,
    /// Custom attributes (Maya's `addAttr`), declared before the values.
    pub custom: Vec<sinew_core::AttrSpec>,
    /// Attribute values by attribute name, in writing order.
    pub values: Vec<(String, AttrVal)>,
    /// Whether the node goes to the data sidecar.
    pub heavy: bool,
}

/// Nodes, values and connections of a rig being built.
#[derive(Clone, Debug, Default)]
pub struct RigBuilder {
    /// Rig name.
    pub name: String,
    /// Frames per second.
    pub fps: f64,
    /// Frame range.
    pub frames: Option<(f64, f64)>,
    /// Nodes in creation order (parents before children).
    pub nodes: Vec<NodeRec>,
    /// Connections `(source plug, destination plug)`.
    pub connections: Vec<(String, String)>,
    used: HashSet<String>,
    next_suffix: HashMap<String, usize>,
}

/// Turns arbitrary text into a unique rig identifier (letters, digits, `_`, `:`; not
/// starting with a digit), recording it in `used`: the text itself, else `text_1`,
/// `text_2`, ... `next_suffix` remembers where each text's search stopped, so n nodes of
/// one name (a BVH whose joints are all called `j`) take O(n) work in all, not O(n²).
pub fn unique_name(
    used: &mut HashSet<String>,
    next_suffix: &mut HashMap<String, usize>,
    raw: &str,
    fallback: &str,
) -> String {
    let mut s: String = raw
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == ':' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() {
        s = fallback.to_string();
    }
    if s.starts_with(|c: char| c.is_ascii_digit()) {
        s.insert(0, '_');
    }
    let mut name = s.clone();
    if used.contains(&name) {
        let k = next_suffix.entry(s.clone()).or_insert(1);
        loop {
            name = format!("{s}_{k}");
            *k += 1;
            if !used.contains(&name) {
                break;
            }
        }
    }
    used.insert(name.clone());
    name
}

impl RigBuilder {
    /// An empty rig.
    pub fn new(name: &str, fps: f64) -> Self {
        RigBuilder {
            name: name.to_string(),
            fps,
            ..Default::default()
        }
    }

    /// Reserves a unique node name derived from `raw`.
    pub fn name(&mut self, raw: &str, fallback: &str) -> String {
        unique_name(&mut self.used, &mut self.next_suffix, raw, fallback)
    }

    /// Adds a node (its name must come from [`RigBuilder::name`]); returns its index.
    pub fn add(&mut self, name: &str, type_name: &str, parent: Option<&str>, heavy: bool) -> usize {
        self.used.insert(name.to_string());
        self.nodes.push(NodeRec {
            name: name.to_string(),
            type_name: type_name.to_string(),
            parent: parent.map(str::to_string),
            custom: Vec::new(),
            values: Vec::new(),
            heavy,
        });
        self.nodes.len() - 1
    }

    /// Sets a plain attribute of node `i`.
    pub fn set(&mut self, i: usize, attr: &str, v: Value) {
        self.nodes[i].values.push((attr.to_string(), AttrVal::One(v)));
    }

    /// Sets elements `0..n` of a multi attribute of node `i`.
    pub fn set_multi(&mut self, i: usize, attr: &str, v: Vec<Value>) {
        self.nodes[i].values.push((attr.to_string(), AttrVal::Multi(v)));
    }

    /// Sets sparse elements `(index, value)` of a multi attribute of node `i`.
    pub fn set_sparse(&mut self, i: usize, attr: &str, v: Vec<(u32, Value)>) {
        self.nodes[i].values.push((attr.to_string(), AttrVal::Sparse(v)));
    }

    /// Declares a custom attribute on node `i`.
    pub fn add_custom(&mut self, i: usize, attr: sinew_core::AttrSpec) {
        self.nodes[i].custom.push(attr);
    }

    /// Adds a connection.
    pub fn connect(&mut self, src: impl Into<String>, dst: impl Into<String>) {
        self.connections.push((src.into(), dst.into()));
    }

    /// Builds the graph directly (what loading the written files gives).
    pub fn to_graph(&self, registry: &Arc<Registry>) -> Result<Graph, String> {
        let mut g = Graph::new(registry.clone());
        g.reserve_nodes(self.nodes.len());
        let mut ids = Vec::with_capacity(self.nodes.len());
        for n in &self.nodes {
            let id = g
                .add_node(&n.type_name, &n.name)
                .map_err(|e| format!("node {}: {e}", n.name))?;
            for a in &n.custom {
                g.add_attr(id, a.clone())
                    .map_err(|e| format!("node {}: custom attribute {}: {e}", n.name, a.name))?;
            }
            ids.push(id);
        }
        // Plugs found on the node at hand (looking each path's node up by name, and a new
        // string per value, were most of the time here).
        let mut path = String::new();
        let mut set = |g: &mut Graph, id: NodeId, name: &str, attr: &str, index: Option<usize>, v: &Value| {
            let plug = match index {
                Some(k) => {
                    path.clear();
                    write!(path, "{attr}[{k}]").map_err(|e| e.to_string())?;
                    g.node_plug(id, &path)
                }
                None => g.node_plug(id, attr),
            };
            plug.and_then(|p| g.set(p, v.clone()))
                .map_err(|e| format!("{name}.{attr}: {e}"))
        };
        for (n, &id) in self.nodes.iter().zip(&ids) {
            if let Some(p) = &n.parent {
                let p = g.node_id(p).map_err(|e| e.to_string())?;
                g.set_parent(id, Some(p))
                    .map_err(|e| format!("parent of {}: {e}", n.name))?;
            }
            for (attr, v) in &n.values {
                match v {
                    AttrVal::One(v) => set(&mut g, id, &n.name, attr, None, v)?,
                    AttrVal::Multi(vs) => {
                        for (k, v) in vs.iter().enumerate() {
                            set(&mut g, id, &n.name, attr, Some(k), v)?;
                        }
                    }
                    AttrVal::Sparse(vs) => {
                        for (k, v) in vs {
                            set(&mut g, id, &n.name, attr, Some(*k as usize), v)?;
                        }
                    }
                }
            }
        }
        for (s, d) in &self.connections {
            g.connect_path(s, d).map_err(|e| format!("{s} -> {d}: {e}"))?;
        }
        g.set_time(sinew_core::Time::new(self.frames.map_or(0.0, |f| f.0), self.fps));
        Ok(g)
    }

    fn print_nodes(
        &self,
        registry: &Registry,
        heavy: bool,
        out: &mut String,
        mut files: Option<&mut ValueFiles>,
    ) -> Result<(), String> {
        let nodes: Vec<&NodeRec> = self.nodes.iter().filter(|n| n.heavy == heavy).collect();
        if nodes.is_empty() {
            return Ok(());
        }
        out.push_str("    nodes: {\n");
        for n in nodes {
            let ty = registry
                .get(&n.type_name)
                .ok_or_else(|| format!("unknown node type {}", n.type_name))?;
            let spec = ty.spec();
            let mut parts = Vec::new();
            if let Some(p) = &n.parent {
                let mut s = String::from("parent: ");
                quote(&mut s, p);
                parts.push(s);
            }
            if !n.custom.is_empty() {
                let mut s = String::from("attrs: ");
                print_ast(&mut s, &sinew_core::rig::write_attrs(&n.custom));
                parts.push(s);
            }
            for (attr, v) in &n.values {
                let a = spec
                    .find(attr)
                    .map(|(id, _)| spec.attr(id))
                    .or_else(|| n.custom.iter().find(|c| c.name == *attr));
                let mut s = format!("{attr}: ");
                let mut value = |s: &mut String, v: &Value, key: String| match files.as_deref_mut() {
                    Some(f) if f.wants(v) => f.reference(s, v, &key),
                    _ => print_ast(s, &write_value(v, a)),
                };
                match v {
                    AttrVal::One(v) => value(&mut s, v, format!("{}.{attr}", n.name)),
                    AttrVal::Multi(vs) => {
                        s.push('[');
                        for (k, v) in vs.iter().enumerate() {
                            if k > 0 {
                                s.push_str(", ");
                            }
                            value(&mut s, v, format!("{}.{attr}.{k}", n.name));
                        }
                        s.push(']');
                    }
                    AttrVal::Sparse(vs) => {
                        s.push('{');
                        for (k, (i, v)) in vs.iter().enumerate() {
                            if k > 0 {
                                s.push_str(", ");
                            }
                            let _ = write!(s, "{i}: ");
                            print_ast(&mut s, &write_value(v, a));
                        }
                        s.push('}');
                    }
                }
                parts.push(s);
            }
            out.push_str("        ");
            quote(out, &n.name);
            let one = parts.join(", ");
            if one.len() + n.name.len() + n.type_name.len() < 100 {
                let _ = writeln!(out, ": {}({one}),", n.type_name);
            } else {
                let _ = writeln!(out, ": {}(", n.type_name);
                for p in parts {
                    let _ = writeln!(out, "            {p},");
                }
                out.push_str("        ),\n");
            }
        }
        out.push_str("    },\n");
        Ok(())
    }

    /// The main rig text (using `data_file`, a path relative to it) and the data text, with
    /// every value inline (see [`RigBuilder::to_files`] for what importers write).
    pub fn to_texts(&self, registry: &Registry, data_file: &str) -> Result<(String, String), String> {
        self.texts(registry, data_file, None)
    }

    fn texts(
        &self,
        registry: &Registry,
        data_file: &str,
        mut files: Option<&mut ValueFiles>,
    ) -> Result<(String, String), String> {
        let mut main = String::from(
            "// Imported by `sinew import`; heavy arrays live in the data file used below.\nRig(\n    name: ",
        );
        quote(&mut main, &self.name);
        let _ = writeln!(main, ",\n    fps: {:?},", self.fps);
        if let Some((a, b)) = self.frames {
            let _ = writeln!(main, "    frames: ({a:?}, {b:?}),");
        }
        let has_heavy = self.nodes.iter().any(|n| n.heavy);
        if has_heavy {
            main.push_str("    uses: [\n        Use(file: ");
            quote(&mut main, data_file);
            main.push_str("),\n    ],\n");
        }
        self.print_nodes(registry, false, &mut main, files.as_deref_mut())?;
        if !self.connections.is_empty() {
            main.push_str("    connections: [\n");
            for (s, d) in &self.connections {
                main.push_str("        ");
                quote(&mut main, &format!("{s} -> {d}"));
                main.push_str(",\n");
            }
            main.push_str("    ],\n");
        }
        main.push_str(")\n");
        let mut data = String::from(
            "// Data sidecar of an imported rig (meshes, skin weights, blend shape targets, animation keys).\nRig(\n",
        );
        self.print_nodes(registry, true, &mut data, files)?;
        data.push_str(")\n");
        Ok((main, data))
    }

    /// What [`RigBuilder::write`] writes for the rig `out` (`<stem>.ron`): the main text,
    /// the data sidecar text (`<stem>.data.ron`) and the value files (see the module docs).
    pub fn to_files(&self, registry: &Registry, out: &Path) -> Result<RigFiles, String> {
        let stem = out.file_stem().and_then(|s| s.to_str()).unwrap_or("rig");
        let data_name = format!("{stem}.data.ron");
        let mut files = ValueFiles::new(format!("{stem}.data"));
        let (main, data) = self.texts(registry, &data_name, Some(&mut files))?;
        Ok(RigFiles {
            main,
            data: self.nodes.iter().any(|n| n.heavy).then_some(data),
            values: files.files,
            folder: files.folder,
        })
    }

    /// Writes `path`, its data sidecar (`<stem>.data.ron` next to it) and value files
    /// (`<stem>.data/*.bin`); returns the sidecar path.
    pub fn write(&self, registry: &Registry, path: &Path) -> Result<std::path::PathBuf, String> {
        self.to_files(registry, path)?.write(path)
    }
}

/// Heavy values with more numbers than this are written to value files (about 80 KB of
/// text); smaller ones (a short clip's keys, a low-poly mesh) stay inline in the data
/// sidecar, readable.
pub const VALUE_FILE_NUMBERS: usize = 4_096;

/// How many numbers a value holds (what its text would be made of).
fn number_count(v: &Value) -> usize {
    match v {
        Value::FloatArray(a) => a.len(),
        Value::IntArray(a) => a.len(),
        Value::Vec3Array(a) => 3 * a.len(),
        Value::MatrixArray(a) => 16 * a.len(),
        Value::Mesh(m) => 3 * (m.positions.len() + m.normals.len() + m.triangles.len()) + 2 * m.uvs.len(),
        Value::Weights(w) => w.offsets.len() + 2 * w.joints.len(),
        Value::Curve(c) => 3 * c.points.len() + c.knots.len(),
        Value::Surface(c) => 3 * c.points.len() + c.knots_u.len() + c.knots_v.len(),
        _ => 0,
    }
}

/// The value files of one written rig: large values by content (identical values, such as
/// the key times every curve of a BVH take shares, are written once).
struct ValueFiles {
    folder: String,
    files: Vec<(String, Vec<u8>)>,
    by_hash: std::collections::HashMap<u64, Vec<usize>>,
}

impl ValueFiles {
    fn new(folder: String) -> Self {
        ValueFiles {
            folder,
            files: Vec::new(),
            by_hash: Default::default(),
        }
    }

    fn wants(&self, v: &Value) -> bool {
        number_count(v) > VALUE_FILE_NUMBERS
    }

    /// Writes `File("<folder>/<key>.bin")` for `v` into `s`, recording the file.
    fn reference(&mut self, s: &mut String, v: &Value, key: &str) {
        let Some(bytes) = sinew_core::value_file::value_to_bytes(v) else {
            return print_ast(s, &write_value(v, None));
        };
        let hash = {
            use std::hash::{Hash, Hasher};
            let mut h = std::collections::hash_map::DefaultHasher::new();
            bytes.hash(&mut h);
            h.finish()
        };
        let same = self
            .by_hash
            .get(&hash)
            .and_then(|ks| ks.iter().find(|&&k| self.files[k].1 == bytes).copied());
        let k = same.unwrap_or_else(|| {
            let safe: String = key
                .chars()
                .map(|c| {
                    if c.is_ascii_alphanumeric() || "_.-".contains(c) {
                        c
                    } else {
                        '_'
                    }
                })
                .collect();
            self.files.push((format!("{}/{safe}.bin", self.folder), bytes));
            self.by_hash.entry(hash).or_default().push(self.files.len() - 1);
            self.files.len() - 1
        });
        s.push_str("File(");
        quote(s, &self.files[k].0);
        s.push(')');
    }
}

/// The texts and value files of a rig to write (see [`RigBuilder::to_files`]).
#[derive(Clone, Debug)]
pub struct RigFiles {
    /// The main rig text.
    pub main: String,
    /// The data sidecar text, when the rig has heavy nodes.
    pub data: Option<String>,
    /// Value files: path relative to the rig's folder, and bytes.
    pub values: Vec<(String, Vec<u8>)>,
    /// The folder of the value files, relative to the rig's folder.
    pub folder: String,
}

impl RigFiles {
    /// Writes the rig to `path`, the sidecar next to it and the value files into their
    /// folder (value files left there by an earlier import are removed first); returns the
    /// sidecar path.
    pub fn write(&self, path: &Path) -> Result<std::path::PathBuf, String> {
        let dir = path.parent().unwrap_or(Path::new(""));
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("rig");
        let data_path = path.with_file_name(format!("{stem}.data.ron"));
        let folder = dir.join(&self.folder);
        remove_value_files(&folder);
        if !self.values.is_empty() {
            std::fs::create_dir_all(&folder).map_err(|e| format!("cannot create {}: {e}", folder.display()))?;
        }
        for (rel, bytes) in &self.values {
            let p = dir.join(rel);
            std::fs::write(&p, bytes).map_err(|e| format!("cannot write {}: {e}", p.display()))?;
        }
        std::fs::write(path, &self.main).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        if let Some(data) = &self.data {
            std::fs::write(&data_path, data).map_err(|e| format!("cannot write {}: {e}", data_path.display()))?;
        }
        Ok(data_path)
    }
}

/// Removes the value files (`.bin` files starting with the value file header) in `folder`,
/// and the folder when that leaves it empty; anything else is left alone.
fn remove_value_files(folder: &Path) {
    let Ok(entries) = std::fs::read_dir(folder) else { return };
    for e in entries.flatten() {
        let p = e.path();
        let is_value_file = p.extension().is_some_and(|x| x == "bin")
            && std::fs::File::open(&p)
                .and_then(|mut f| {
                    let mut head = [0u8; 8];
                    std::io::Read::read_exact(&mut f, &mut head).map(|()| head)
                })
                .is_ok_and(|head| sinew_core::value_file::is_value_file(&head));
        if is_value_file {
            let _ = std::fs::remove_file(&p);
        }
    }
    let _ = std::fs::remove_dir(folder);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Suffixes count up per name and skip names already taken, whatever order they came in.
    #[test]
    fn unique_names_skip_taken_suffixes_in_order() {
        let mut b = RigBuilder::new("t", 24.0);
        b.add("j_2", "joint", None, false);
        let names: Vec<String> = (0..4).map(|_| b.name("j", "node")).collect();
        assert_eq!(names, ["j", "j_1", "j_3", "j_4"]);
        assert_eq!(b.name("9 lives", "node"), "_9_lives");
        assert_eq!(b.name("", "node"), "node");
        assert_eq!(b.name("", "node"), "node_1");
    }

    /// 20,000 nodes of one name get 20,000 distinct names (the search resumes where it
    /// stopped instead of trying every suffix from 1 again).
    #[test]
    fn many_equal_names_stay_distinct() {
        let mut b = RigBuilder::new("t", 24.0);
        let names: HashSet<String> = (0..20_000).map(|_| b.name("Bone", "node")).collect();
        assert_eq!(names.len(), 20_000);
        assert!(names.contains("Bone_19999"));
    }
}
