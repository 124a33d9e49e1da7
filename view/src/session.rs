//! The viewer's state: the loaded rig (lazy graph, compiled program and instance), what
//! it draws, the edits made in the page (re-applied after every reload), the last load
//! errors and evaluation errors, and the last profile.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use serde_json::{json, Value as Json};
use sinew_core::rig::typed::parse_plug_value;
use sinew_core::{
    CompileOptions, Diagnostics, Direction, Graph, Instance, LoadedRig, PlugHandle, ProfileTable, Profiler, Program,
    Time,
};

use crate::problems::{failing_nodes, Checks, Problem, ProblemKind};
use crate::scene::Scene;

/// Loads a rig file (the facade passes its loader, which resolves mesh files).
pub type Loader = Arc<dyn Fn(&Path) -> Result<LoadedRig, Diagnostics> + Send + Sync>;

/// Where the time of a reload went (milliseconds).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ReloadTimes {
    /// Whether the rig loaded (else its errors are shown over the last good scene).
    pub ok: bool,
    /// Reading, parsing and expanding the rig into a graph (the loader).
    pub load_ms: f64,
    /// Re-applying the page's edits and deciding what is drawn (meshes are evaluated once
    /// for their sizes).
    pub scene_ms: f64,
    /// Compiling the program for playback.
    pub compile_ms: f64,
    /// The whole reload.
    pub total_ms: f64,
}

fn ms_since(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// A loaded rig ready to draw.
struct Loaded {
    graph: Graph,
    program: Arc<Program>,
    instance: Instance,
    handles: Vec<Option<PlugHandle>>,
    /// What is checked after each frame (non-finite outputs, statuses).
    checks: Checks,
    scene: Scene,
    fps: f64,
    range: (f64, f64),
    files: Vec<PathBuf>,
}

/// The viewer's state (behind a mutex in the server).
pub struct Session {
    path: PathBuf,
    loader: Loader,
    loaded: Option<Loaded>,
    /// Edits made in the page, in order: (plug, value text).
    edits: Vec<(String, String)>,
    /// Bumped on every reload (the page re-fetches the scene).
    pub revision: u64,
    load_errors: Option<Diagnostics>,
    load_ms: f64,
    problems: Vec<Problem>,
    frame: f64,
    profile: Option<ProfileTable>,
}

fn compile(graph: &mut Graph, scene: &Scene) -> Result<(Arc<Program>, Vec<Option<PlugHandle>>), String> {
    let program = Arc::new(Program::compile(graph, &CompileOptions::default()).map_err(|e| e.to_string())?);
    let handles = scene.handles(&program);
    Ok((program, handles))
}

fn diag_json(d: &Diagnostics) -> Json {
    let errors: Vec<Json> = d
        .errors
        .iter()
        .map(|e| {
            json!({
                "file": e.span.file.display().to_string(), "line": e.span.line, "col": e.span.col,
                "message": e.message, "hint": e.hint, "text": e.render(),
            })
        })
        .collect();
    json!(errors)
}

impl Session {
    /// Loads `path`; a rig that fails to load gives a session that shows its errors.
    pub fn new(path: &Path, loader: Loader) -> Session {
        let mut s = Session {
            path: path.to_path_buf(),
            loader,
            loaded: None,
            edits: Vec::new(),
            revision: 0,
            load_errors: None,
            load_ms: 0.0,
            problems: Vec::new(),
            frame: 1.0,
            profile: None,
        };
        s.reload();
        s
    }

    /// The rig file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Files the loaded rig depends on (or just the rig file while it fails to load,
    /// plus the files its errors name).
    pub fn files(&self) -> Vec<PathBuf> {
        let mut v = sinew_core::rig_dependencies(&self.path);
        if let Some(l) = &self.loaded {
            v.extend(l.files.iter().cloned());
        }
        if let Some(d) = &self.load_errors {
            v.extend(d.files());
        }
        v.sort();
        v.dedup();
        v
    }

    /// Loads the rig again; on success the edits are re-applied and the scene replaced,
    /// on failure the last good scene stays and the errors are shown. Returns whether
    /// the load succeeded and where the time went.
    pub fn reload(&mut self) -> ReloadTimes {
        let started = Instant::now();
        let result = (self.loader)(&self.path);
        let load_ms = ms_since(started);
        self.revision += 1;
        let mut times = ReloadTimes {
            ok: false,
            load_ms,
            ..ReloadTimes::default()
        };
        match result
            .map_err(Some)
            .and_then(|rig| self.install(rig, &mut times).map_err(|_| None))
        {
            Ok(()) => {
                self.load_errors = None;
                self.load_ms = ms_since(started);
                times.ok = true;
            }
            Err(d) => {
                if let Some(d) = d {
                    self.load_errors = Some(d);
                }
            }
        }
        times.total_ms = ms_since(started);
        times
    }

    fn install(&mut self, rig: LoadedRig, times: &mut ReloadTimes) -> Result<(), String> {
        let started = Instant::now();
        let mut graph = rig.graph;
        let fps = rig.document.fps.unwrap_or(24.0);
        let range = rig.document.frames.unwrap_or((1.0, 48.0));
        let mut files = rig.files.clone();
        files.extend(rig.document.referenced_files());
        // Edits that no longer apply (a renamed node...) are dropped.
        let mut kept = Vec::new();
        for (plug, text) in std::mem::take(&mut self.edits) {
            let ok = graph
                .plug(&plug)
                .map_err(|e| e.to_string())
                .and_then(|p| Ok((p, parse_plug_value(&graph, p, &text)?)))
                .and_then(|(p, v)| graph.set(p, v).map_err(|e| e.to_string()));
            if ok.is_ok() {
                kept.push((plug, text));
            }
        }
        self.edits = kept;
        if self.loaded.is_none() {
            self.frame = range.0;
        }
        graph.set_time(Time::new(self.frame, fps));
        let scene = Scene::build(&mut graph);
        times.scene_ms = ms_since(started);
        let started = Instant::now();
        let (program, handles) = match compile(&mut graph, &scene) {
            Ok(x) => x,
            Err(e) => {
                self.load_errors = Some(Diagnostics {
                    errors: vec![sinew_core::Diagnostic::new(
                        sinew_core::rig::Span::new(&Arc::new(self.path.clone()), 1, 1),
                        format!("cannot compile the rig: {e}"),
                    )],
                });
                return Err(e);
            }
        };
        let instance = Instance::new(program.clone());
        let checks = Checks::new(&graph, &program);
        times.compile_ms = ms_since(started);
        self.profile = None;
        self.loaded = Some(Loaded {
            graph,
            program,
            instance,
            handles,
            checks,
            scene,
            fps,
            range,
            files,
        });
        Ok(())
    }

    /// The page's view of the session: scene, timeline, nodes, errors.
    pub fn scene_json(&self) -> Json {
        let errors = self.load_errors.as_ref().map(diag_json);
        let Some(l) = &self.loaded else {
            return json!({ "revision": self.revision, "rig": self.path.display().to_string(), "loadErrors": errors, "scene": null });
        };
        let g = &l.graph;
        let scene = l.scene.to_json();
        // What the page compares to keep its drawing when only values changed.
        let scene_key = {
            use std::hash::{Hash, Hasher};
            let mut h = std::collections::hash_map::DefaultHasher::new();
            scene.to_string().hash(&mut h);
            format!("{:016x}", h.finish())
        };
        let nodes: Vec<Json> = g
            .nodes()
            .into_iter()
            .map(|id| json!({ "name": g.node_name(id), "type": g.node_type(id) }))
            .collect();
        json!({
            "revision": self.revision,
            "rig": self.path.display().to_string(),
            "fps": l.fps, "start": l.range.0, "end": l.range.1, "frame": self.frame,
            "loadMs": self.load_ms,
            "loadErrors": errors,
            "scene": scene,
            "sceneKey": scene_key,
            "nodes": nodes,
            "edits": self.edits.iter().map(|(p, v)| json!([p, v])).collect::<Vec<_>>(),
        })
    }

    /// Evaluates the compiled program at `frame` and writes the frame into `out`;
    /// returns the evaluation time in microseconds. The problems of the frame are
    /// collected as well (see [`crate::problems`]): when a step fails, the lazy graph
    /// finds every other failing node too (only then, so playback pays nothing for it).
    pub fn frame(&mut self, frame: f64, out: &mut Vec<u8>) -> Option<f64> {
        let l = self.loaded.as_mut()?;
        self.frame = frame;
        let time = Time::new(frame, l.fps);
        let started = Instant::now();
        let result = l.instance.evaluate(time);
        let us = started.elapsed().as_secs_f64() * 1e6;
        self.problems.clear();
        if let Err(e) = result {
            l.graph.set_time(time);
            self.problems = failing_nodes(&mut l.graph);
            if self.problems.is_empty() {
                self.problems.push(Problem::from_error(&e));
            }
        }
        l.checks.scan(&l.instance, &mut self.problems);
        l.scene.write_frame(&l.instance, &l.handles, out);
        Some(us)
    }

    /// Problems of the last frame or edit: `[{node, kind, message}]` (kind `error`,
    /// `nonFinite` or `status`).
    pub fn eval_errors_json(&self) -> Json {
        json!(self.problems.iter().map(Problem::to_json).collect::<Vec<_>>())
    }

    /// A node's attributes from its spec, with current values, for the attribute panel.
    pub fn node_json(&mut self, name: &str) -> Result<Json, String> {
        let l = self.loaded.as_mut().ok_or("no rig loaded")?;
        let g = &mut l.graph;
        g.set_time(Time::new(self.frame, l.fps));
        let id = g.node_id(name).map_err(|e| e.to_string())?;
        let spec = g.node_spec(id).ok_or("stale node")?.clone();
        let mut attrs = Vec::new();
        for (i, a) in spec.attrs.iter().enumerate() {
            let indices: Vec<Option<u32>> = if a.multi {
                g.elements(id, sinew_core::AttrId(i as u16))
                    .into_iter()
                    .map(Some)
                    .collect()
            } else {
                vec![None]
            };
            for index in indices {
                let path = match index {
                    Some(k) => format!("{name}.{}[{k}]", a.name),
                    None => format!("{name}.{}", a.name),
                };
                let Ok(plug) = g.plug(&path) else { continue };
                let source = g.source_of(plug).map(|s| g.plug_name(s));
                let value = if a.ty.is_heavy() {
                    None
                } else {
                    g.get(plug).ok().map(|v| value_json(&v))
                };
                attrs.push(json!({
                    "plug": path, "name": a.name, "index": index, "type": a.ty.name(),
                    "input": a.direction == Direction::Input, "keyable": a.keyable,
                    "unit": format!("{:?}", a.unit), "enum": a.enum_names, "doc": a.doc,
                    "min": a.min, "max": a.max, "softMin": a.soft_min, "softMax": a.soft_max,
                    "custom": i >= spec.first_custom().index(),
                    "source": source, "value": value,
                    "editable": a.direction == Direction::Input && source.is_none() && !a.ty.is_heavy(),
                }));
            }
        }
        Ok(json!({
            "name": name, "type": spec.name, "doc": spec.doc,
            "parent": g.parent_of(id).and_then(|p| g.node_name(p)),
            "attrs": attrs,
        }))
    }

    /// Sets `plug` to `text` through the lazy graph, pulls what the page draws (only what
    /// depends on the plug recomputes), and sets the compiled instance to match. Returns
    /// the lazy work: computes, cutoffs and time.
    pub fn set(&mut self, plug_path: &str, text: &str) -> Result<Json, String> {
        let l = self.loaded.as_mut().ok_or("no rig loaded")?;
        let g = &mut l.graph;
        g.set_time(Time::new(self.frame, l.fps));
        let plug = g.plug(plug_path).map_err(|e| e.to_string())?;
        let value = parse_plug_value(g, plug, text)?;
        // Bring the graph up to date first, so the counters show this edit's work only.
        let mut scratch = Vec::new();
        l.scene.write_frame_lazy(g, &mut scratch);
        g.reset_stats();
        let started = Instant::now();
        g.set(plug, value.clone()).map_err(|e| e.to_string())?;
        self.problems = l.scene.write_frame_lazy(g, &mut scratch);
        let ms = started.elapsed().as_secs_f64() * 1e3;
        let stats = g.stats();
        let compiled = l
            .program
            .handle(plug_path)
            .map_err(|e| e.to_string())
            .and_then(|h| l.instance.set(&h, value).map_err(|e| e.to_string()));
        if compiled.is_err() {
            let (program, handles) = compile(g, &l.scene)?;
            l.instance = Instance::new(program.clone());
            l.checks = Checks::new(g, &program);
            l.program = program;
            l.handles = handles;
        }
        self.edits.retain(|(p, _)| p != plug_path);
        self.edits.push((plug_path.to_string(), text.to_string()));
        Ok(json!({ "computes": stats.computes, "cutoffs": stats.cutoffs, "ms": ms,
                   "errors": self.eval_errors_json() }))
    }

    /// Profiles the compiled evaluation over the rig's frame range (a fresh instance of
    /// the current program, so the first frame is a full evaluation).
    pub fn profile(&mut self, frames: Option<(f64, f64)>) -> Result<Json, String> {
        let l = self.loaded.as_ref().ok_or("no rig loaded")?;
        let (a, b) = frames.unwrap_or(l.range);
        let mut inst = Instance::new(l.program.clone());
        let mut profiler = Profiler::new(&l.program);
        let mut f = a;
        while f <= b {
            profiler
                .evaluate(&mut inst, Time::new(f, l.fps))
                .map_err(|e| format!("frame {f}: {e}"))?;
            f += 1.0;
        }
        let table = profiler.table(&l.program);
        let json = crate::profile_json(&table);
        self.profile = Some(table);
        Ok(json)
    }

    /// The DG around `center` as SVG (see [`crate::graph_svg`]).
    pub fn graph_svg(&self, center: &str, depth: usize) -> Result<String, String> {
        let l = self.loaded.as_ref().ok_or("no rig loaded")?;
        let nodes = |status: bool| -> Vec<&str> {
            self.problems
                .iter()
                .filter(|p| (p.kind == ProblemKind::Status) == status)
                .map(|p| p.node.as_str())
                .collect()
        };
        let (errors, warnings) = (nodes(false), nodes(true));
        let opts = crate::graph_svg::SvgOptions {
            center: Some(center),
            depth,
            profile: self.profile.as_ref(),
            errors: &errors,
            warnings: &warnings,
        };
        crate::graph_svg::render(&l.graph, &opts)
    }
}

/// A value as JSON for the attribute panel.
fn value_json(v: &sinew_core::Value) -> Json {
    use sinew_core::Value as V;
    match v {
        V::Bool(b) => json!(b),
        V::Int(i) | V::Enum(i) => json!(i),
        V::Float(x) if x.is_finite() => json!(x),
        V::Vec3(x) => json!(x.to_array()),
        V::Quat(q) => json!(q.to_array()),
        V::Matrix(m) => json!(m.to_cols_array()),
        other => json!(other.to_string()),
    }
}
