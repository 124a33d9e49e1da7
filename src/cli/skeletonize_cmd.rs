//! `sinew skeletonize`: a mesh file (`.obj`, `.gltf`, `.glb`) to an editable rig — joints
//! extracted from the mesh (named, parented, `translate` + `jointOrient`) and a bound
//! `skinCluster` carrying bone-heat weights.
//!
//! Output layout (the same as `sinew import`, see [`RigBuilder`]): `RIG.ron` holds the joint
//! hierarchy and every connection; its data sidecar `RIG.data.ron` holds the heavy nodes —
//! the `mesh` shape with the geometry inline and the `skinCluster` with its weights — so
//! `sinew check`, `eval` and `fmt` load the pair with the ordinary rig loader. A dense
//! mesh and its weights go to value files (`RIG.data/*.bin`, see
//! [`crate::io::rig_builder`]), which the plain core loader reads too.
//!
//! The skinCluster: `inputGeometry ← <mesh>.outMesh`, `matrix[i] ← joint_i.worldMatrix`,
//! `bindPreMatrix[i]` = the inverse of joint `i`'s rest world matrix (evaluated from the
//! written values, so the bind pose deforms the mesh to itself), `weightList` = bone-heat
//! weights (joint index `i` = skeleton joint `i`), `maxInfluences` as requested.

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use sinew_core::{Registry, Value};
use sinew_nodes::skeletonize::volume::PartFate;
use sinew_nodes::skeletonize::{
    bone_heat_weights_with_report, node::local_placement, skeletonize_detailed, Method, Skeleton, SkeletonDetails,
    SkeletonizeParams, Template, WeightParams,
};

use super::skeleton_preview as preview;

use crate::io::mesh_file::load_mesh;
use crate::io::rig_builder::RigBuilder;

/// Options of `sinew skeletonize`.
#[derive(Clone, Debug)]
pub struct SkeletonizeOptions {
    /// Extraction method: `auto` (default), `volume` or `silhouette`.
    pub method: Method,
    /// Volume cells (or, for the silhouette method, raster pixels) along the mesh's
    /// longest side (None: the library defaults, 96 cells and 256 pixels).
    pub resolution: Option<usize>,
    /// Bones per limb, from its base to its tip (None: the default, 3).
    pub joints_per_limb: Option<usize>,
    /// Bones per branch spaced evenly, no articulation search (None or 0: off).
    pub bones_per_branch: Option<usize>,
    /// A named skeleton to fit (`humanoid`, `quadruped`).
    pub template: Option<Template>,
    /// Detect a mirror plane and make the skeleton symmetric.
    pub symmetry: bool,
    /// Join separate parts of the mesh to the nearest part (off: one root per part).
    pub join_parts: bool,
    /// Joints per vertex in the weights (0 = unlimited).
    pub max_influences: usize,
    /// Compute bone-heat weights and write a skinCluster.
    pub weights: bool,
    /// Write a PNG preview (front and side views, dominant joint per vertex) here.
    pub preview: Option<std::path::PathBuf>,
}

impl Default for SkeletonizeOptions {
    fn default() -> Self {
        SkeletonizeOptions {
            method: Method::Auto,
            resolution: None,
            joints_per_limb: None,
            bones_per_branch: None,
            template: None,
            symmetry: true,
            join_parts: true,
            max_influences: WeightParams::default().max_influences,
            weights: true,
            preview: None,
        }
    }
}

/// Parses `--method`: `auto`, `volume` or `silhouette`.
pub fn parse_method(s: &str) -> Result<Method, String> {
    match s.to_ascii_lowercase().as_str() {
        "auto" => Ok(Method::Auto),
        "volume" => Ok(Method::Volume),
        "silhouette" => Ok(Method::Silhouette),
        _ => Err(format!("unknown method `{s}`; use auto, volume or silhouette")),
    }
}

/// Parses `--template`: `humanoid` (or `biped`) or `quadruped`.
pub fn parse_template(s: &str) -> Result<Template, String> {
    Template::parse(s).ok_or_else(|| format!("unknown template `{s}`; use humanoid or quadruped"))
}

/// The library parameters for `opts`.
fn params(opts: &SkeletonizeOptions) -> SkeletonizeParams {
    let d = SkeletonizeParams::default();
    let silhouette = opts.method == Method::Silhouette;
    SkeletonizeParams {
        method: opts.method,
        resolution: opts.resolution.filter(|_| !silhouette).unwrap_or(d.resolution),
        silhouette_resolution: opts
            .resolution
            .filter(|_| silhouette)
            .unwrap_or(d.silhouette_resolution),
        joints_per_limb: opts.joints_per_limb.unwrap_or(d.joints_per_limb).max(1),
        bones_per_branch: opts.bones_per_branch.filter(|&b| b > 0),
        template: opts.template,
        symmetry: opts.symmetry,
        join_parts: opts.join_parts,
        ..d
    }
}

/// One line per notable fact of the extraction: method, mirror plane, parts.
fn describe(d: &SkeletonDetails) -> String {
    let method = match d.method {
        Method::Silhouette => "silhouette (the mesh is flat, or asked for)",
        _ => "volume",
    };
    let mut s = format!("method: {method}");
    match &d.mirror {
        Some(m) => s.push_str(&format!(
            "; mirror plane through {:.3} with normal {:.3}: {} limb pairs named _L/_R",
            m.origin, m.normal, d.symmetry.pairs
        )),
        None => s.push_str("; no mirror plane (the mesh is not symmetric within the tolerance)"),
    }
    if let Some(v) = &d.volume {
        if v.parts.len() > 1 {
            let count = |f: fn(&PartFate) -> bool| v.parts.iter().filter(|p| f(&p.fate)).count();
            s.push_str(&format!(
                "\nparts: {} separate parts: {} joined to the nearest part by a bridge bone, {} kept as separate roots, {} too small for joints of their own (weighted to the nearest bones)",
                v.parts.len(),
                count(|f| matches!(f, PartFate::Joined { .. })),
                count(|f| matches!(f, PartFate::Separate)),
                count(|f| matches!(f, PartFate::TooSmall)),
            ));
        }
        if v.shell_only {
            s.push_str("\nnote: the mesh has holes too wide to seal; its shell alone was used");
        }
    }
    s
}

/// Number of branches: maximal joint paths between key joints (roots, ends, junctions),
/// i.e. the edges of the tree once joints with one parent and one child are collapsed.
pub fn branch_count(sk: &Skeleton) -> usize {
    let n = sk.len();
    let mut children = vec![0usize; n];
    for p in sk.parents.iter().flatten() {
        if let Some(c) = children.get_mut(*p) {
            *c += 1;
        }
    }
    let key = (0..n).filter(|&j| sk.parents[j].is_none() || children[j] != 1).count();
    key.saturating_sub(sk.roots().count())
}

/// Runs `sinew skeletonize`; returns the summary to print.
pub fn skeletonize_cmd(
    mesh_path: &Path,
    out: &Path,
    opts: &SkeletonizeOptions,
    registry: &Arc<Registry>,
) -> Result<String, String> {
    crate::cli::paths::check_rig_output(&[mesh_path], out)?;
    if let Some(p) = &opts.preview {
        if !p.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
            return Err(format!("{}: the preview is a PNG image; name it `*.png`", p.display()));
        }
        crate::cli::paths::check_outputs(&[mesh_path], &[out, p.as_path()])?;
    }
    let start = Instant::now();
    let mesh = load_mesh(mesh_path)?;
    let loaded = start.elapsed();
    let params = params(opts);
    let t0 = Instant::now();
    let details = skeletonize_detailed(&mesh, &params).map_err(|e| format!("{}: {e}", mesh_path.display()))?;
    let sk = &details.skeleton;
    let t_skeleton = t0.elapsed();
    let t1 = Instant::now();
    let weights = if opts.weights {
        let wp = WeightParams {
            max_influences: if opts.max_influences == 0 {
                sk.len()
            } else {
                opts.max_influences
            },
            ..WeightParams::default()
        };
        Some(bone_heat_weights_with_report(&mesh, sk, &wp).map_err(|e| format!("{}: {e}", mesh_path.display()))?)
    } else {
        None
    };
    let t_weights = t1.elapsed();

    let stem = out.file_stem().and_then(|s| s.to_str()).unwrap_or("rig").to_string();
    let mut rig = RigBuilder::new(&stem, 24.0);
    let (translates, orients) = local_placement(sk);
    let mut names: Vec<String> = Vec::with_capacity(sk.len());
    for j in 0..sk.len() {
        let name = rig.name(&sk.names[j], &format!("joint{j}"));
        let parent = sk.parents[j].map(|p| names[p].clone());
        let k = rig.add(&name, "joint", parent.as_deref(), false);
        rig.set(k, "translate", Value::Vec3(translates[j]));
        rig.set(k, "jointOrient", Value::Vec3(orients[j]));
        names.push(name);
    }
    let shape_name = format!("{stem}Shape");
    let shape = rig.name(&shape_name, "shape");
    let k = rig.add(&shape, "mesh", None, true);
    rig.set(k, "inMesh", Value::Mesh(Arc::new(mesh.clone())));
    let mut fallback = 0;
    if let Some((w, report)) = &weights {
        fallback = report.fallback_vertices;
        let sc = rig.name(&format!("{stem}_skinCluster"), "skinCluster");
        // Bind: the inverse of each joint's rest world matrix, evaluated from what we write.
        let mut g = rig.to_graph(registry)?;
        let mut bind = Vec::with_capacity(names.len());
        for n in &names {
            let path = format!("{n}.worldMatrix");
            match g.get_path(&path) {
                Ok(Value::Matrix(m)) if m.determinant().abs() > 0.0 && m.is_finite() => {
                    bind.push(Value::Matrix(m.inverse()))
                }
                Ok(other) => return Err(format!("internal error: {path} is {other}, not an invertible matrix")),
                Err(e) => return Err(format!("internal error: {path}: {e}")),
            }
        }
        let k = rig.add(&sc, "skinCluster", None, true);
        rig.connect(format!("{shape}.outMesh"), format!("{sc}.inputGeometry"));
        for (j, n) in names.iter().enumerate() {
            rig.connect(format!("{n}.worldMatrix"), format!("{sc}.matrix[{j}]"));
        }
        rig.set_multi(k, "bindPreMatrix", bind);
        rig.set(k, "weightList", Value::Weights(Arc::new(w.clone())));
        rig.set(k, "maxInfluences", Value::Int(opts.max_influences as i64));
    }
    // Check that what we write loads back before writing it.
    let mut g = rig
        .to_graph(registry)
        .map_err(|e| format!("internal error: the skeleton rig does not build: {e}"))?;
    for (j, n) in names.iter().enumerate() {
        if let Ok(Value::Matrix(m)) = g.get_path(&format!("{n}.worldMatrix")) {
            let d = m.w_axis.truncate().distance(sk.positions[j]);
            if d > 1e-6 * (1.0 + sk.positions[j].length()) {
                return Err(format!("internal error: joint {n} lands {d:e} away from the skeleton"));
            }
        }
    }
    drop(g);
    let data = write(&rig, registry, out)?;
    let roots: Vec<&str> = sk.roots().map(|j| names[j].as_str()).collect();
    let mut msg = format!(
        "{}: {} vertices, {} triangles -> {} joints, {} branches (root {})",
        mesh_path.display(),
        mesh.positions.len(),
        mesh.triangles.len(),
        sk.len(),
        branch_count(sk),
        roots.join(", "),
    );
    msg.push('\n');
    msg.push_str(&describe(&details));
    msg.push_str(&format!(
        "\ntime: load {:.1} ms, skeleton {:.1} ms, weights {}",
        ms(loaded),
        ms(t_skeleton),
        if opts.weights {
            format!("{:.1} ms", ms(t_weights))
        } else {
            "skipped (--no-weights)".into()
        },
    ));
    if fallback > 0 {
        msg.push_str(&format!(
            "\nnote: {fallback} vertices are on no proper triangle and got inverse-distance weights"
        ));
    }
    msg.push_str(&format!("\nwrote {} (data: {})", out.display(), data.display()));
    if let Some(path) = &opts.preview {
        let img = preview::render(&mesh, sk, weights.as_ref().map(|(w, _)| w), 480);
        preview::write_png(&img, path)?;
        msg.push_str(&format!(
            "\nwrote {} (front and side views, dominant joint per vertex)",
            path.display()
        ));
    }
    Ok(msg)
}

/// Writes `out`, its data sidecar `<stem>.data.ron` and value files (as
/// [`RigBuilder::write`], with this command's header lines); returns the sidecar path.
fn write(rig: &RigBuilder, registry: &Registry, out: &Path) -> Result<std::path::PathBuf, String> {
    let mut files = rig.to_files(registry, out)?;
    let header = |text: &str, first: &str| match text.split_once('\n') {
        Some((line, rest)) if line.starts_with("//") => format!("{first}\n{rest}"),
        _ => text.to_string(),
    };
    files.main = header(
        &files.main,
        "// Written by `sinew skeletonize`; the mesh and skin weights live in the data file used below.",
    );
    files.data = files.data.as_deref().map(|d| {
        header(
            d,
            "// Data of a `sinew skeletonize` rig: the mesh and the skinCluster with its weights.",
        )
    });
    files.write(out)
}

fn ms(d: std::time::Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::{eval, EvalRequest};
    use glam::{DVec3, Vec3};
    use sinew_nodes::skeletonize::shapes;

    fn obj_text(m: &sinew_core::Mesh) -> String {
        let mut s = String::from("# procedural test mesh\no body\n");
        for p in &m.positions {
            s.push_str(&format!("v {} {} {}\n", p.x, p.y, p.z));
        }
        for t in &m.triangles {
            s.push_str(&format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1));
        }
        s
    }

    fn tmp(name: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("sinew-skeletonize-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    /// Writes the humanoid as OBJ, runs the command, checks the rig and evaluates each
    /// joint's worldMatrix against the `skeletonize` node's `jointPositions` on the same mesh.
    #[test]
    fn humanoid_obj_to_checked_rig() {
        let registry = crate::default_registry().unwrap();
        let d = tmp("humanoid");
        let mesh = shapes::humanoid(12);
        let obj = d.join("body.obj");
        std::fs::write(&obj, obj_text(&mesh)).unwrap();
        let out = d.join("body.ron");
        let summary = skeletonize_cmd(&obj, &out, &SkeletonizeOptions::default(), &registry).unwrap();
        assert!(summary.contains("joints") && summary.contains("branches"), "{summary}");
        let check = crate::cli::rig_cmds::check(&out, &registry).unwrap();
        assert!(!check.contains("error"), "{check}");

        // The node on the mesh as loaded back from the OBJ (f32 text round trip).
        let loaded = load_mesh(&obj).unwrap();
        let mut g = sinew_core::Graph::new(registry.clone());
        g.add_node("skeletonize", "sk").unwrap();
        g.set_path("sk.inMesh", Value::Mesh(Arc::new(loaded.clone()))).unwrap();
        g.set_path("sk.computeWeights", Value::Bool(false)).unwrap();
        let Value::Vec3Array(pos) = g.get_path("sk.jointPositions").unwrap() else {
            panic!()
        };
        let Value::IntArray(par) = g.get_path("sk.jointParents").unwrap() else {
            panic!()
        };
        // Ends: 5 (head, hands, feet).
        let ends = (0..par.len())
            .filter(|&j| par.iter().filter(|&&p| p == j as i64).count() + usize::from(par[j] >= 0) == 1)
            .count();
        assert_eq!(ends, 5);

        // Joint names in the rig come from the skeleton, in order: read them back.
        let rig = crate::cli::rig_cmds::load(&out, &registry).unwrap();
        let mut graph = rig.graph;
        let joints: Vec<String> = graph
            .nodes()
            .into_iter()
            .filter(|&id| graph.node_type(id) == Some("joint"))
            .map(|id| graph.node_name(id).unwrap().to_string())
            .collect();
        assert_eq!(joints.len(), pos.len());
        // Compare the k-th joint in the file order with the node's jointPositions[k].
        let text = std::fs::read_to_string(&out).unwrap();
        let mut order: Vec<(usize, String)> = joints
            .iter()
            .map(|n| (text.find(&format!("\"{n}\": joint")).unwrap(), n.clone()))
            .collect();
        order.sort();
        for (k, (_, n)) in order.iter().enumerate() {
            let req = EvalRequest {
                frames: Some("1".into()),
                ..EvalRequest::new(&out, &[&format!("{n}.worldMatrix")])
            };
            let csv = eval(&req, &registry).unwrap();
            let last = csv.lines().last().unwrap();
            let nums: Vec<f64> = last.split(',').filter_map(|x| x.trim().parse().ok()).collect();
            assert!(nums.len() >= 16, "{csv}");
            let m = &nums[nums.len() - 16..];
            let p = DVec3::new(m[12], m[13], m[14]);
            assert!(p.distance(pos[k]) < 1e-6, "{n}: eval {p} vs node {}", pos[k]);
            let Value::Matrix(wm) = graph.get_path(&format!("{n}.worldMatrix")).unwrap() else {
                panic!()
            };
            assert!(wm.w_axis.truncate().distance(pos[k]) < 1e-9);
        }

        // Bound: the skinned mesh equals the rest mesh (bindPreMatrix = inverse rest world).
        let skin = graph
            .nodes()
            .into_iter()
            .find(|&id| graph.node_type(id) == Some("skinCluster"))
            .unwrap();
        let sname = graph.node_name(skin).unwrap().to_string();
        let Value::Mesh(skinned) = graph.get_path(&format!("{sname}.outputGeometry")).unwrap() else {
            panic!()
        };
        // The OBJ loader keeps the file's vertex order: the mesh as loaded is the mesh written.
        assert_eq!(loaded.positions, mesh.positions);
        assert_eq!(loaded.triangles, mesh.triangles);
        assert_eq!(skinned.positions.len(), loaded.positions.len());
        for (a, b) in skinned.positions.iter().zip(&loaded.positions) {
            assert!(a.distance(*b) < 1e-4, "{a} vs {b}");
        }
        // Moving the root moves the mesh.
        graph
            .set_path(&format!("{}.translate", order[0].1), Value::Vec3(pos[0] + DVec3::Y))
            .unwrap();
        let Value::Mesh(moved) = graph.get_path(&format!("{sname}.outputGeometry")).unwrap() else {
            panic!()
        };
        let shift = moved
            .positions
            .iter()
            .zip(&loaded.positions)
            .map(|(a, b)| (*a - *b).y)
            .sum::<f32>()
            / loaded.positions.len() as f32;
        assert!(shift > 0.2, "mean shift {shift}");
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn capsule_without_weights_and_bad_input() {
        let registry = crate::default_registry().unwrap();
        let d = tmp("capsule");
        let mesh = shapes::capsule(Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0), 0.3, 16);
        let obj = d.join("cap.obj");
        std::fs::write(&obj, obj_text(&mesh)).unwrap();
        let out = d.join("cap.ron");
        let opts = SkeletonizeOptions {
            bones_per_branch: Some(4),
            weights: false,
            resolution: Some(128),
            ..Default::default()
        };
        let summary = skeletonize_cmd(&obj, &out, &opts, &registry).unwrap();
        // The root in the middle, two branches of four bones: nine joints.
        assert!(summary.contains("9 joints, 2 branches"), "{summary}");
        crate::cli::rig_cmds::check(&out, &registry).unwrap();
        let text = std::fs::read_to_string(&out).unwrap();
        assert!(!text.contains("skinCluster"));
        assert!(text.starts_with("// Written by `sinew skeletonize`"), "{text}");
        // Errors: unknown extension, missing file, degenerate mesh.
        let e = skeletonize_cmd(&d.join("x.stl"), &out, &opts, &registry).unwrap_err();
        assert!(e.contains(".obj"), "{e}");
        assert!(skeletonize_cmd(&d.join("missing.obj"), &out, &opts, &registry).is_err());
        let flat = d.join("flat.obj");
        std::fs::write(&flat, "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").unwrap();
        let e = skeletonize_cmd(&flat, &out, &opts, &registry).unwrap_err();
        assert!(e.contains("degenerate"), "{e}");
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn arguments_parse() {
        use clap::Parser;
        let parse = |extra: &[&str]| {
            let mut args = vec!["sinew", "skeletonize", "a.obj", "-o", "r.ron"];
            args.extend_from_slice(extra);
            crate::cli::Cli::try_parse_from(args)
        };
        let cli = parse(&[
            "--resolution",
            "64",
            "--bones-per-branch",
            "2",
            "--max-influences",
            "3",
            "--no-weights",
        ]);
        assert!(cli.is_ok(), "{cli:?}");
        let cli = parse(&[
            "--method",
            "volume",
            "--joints-per-limb",
            "4",
            "--template",
            "quadruped",
            "--no-symmetry",
            "--separate-parts",
            "--preview",
            "p.png",
        ]);
        assert!(cli.is_ok(), "{cli:?}");
        let e = parse(&["--method", "voxels"]).unwrap_err().to_string();
        assert!(e.contains("auto, volume or silhouette"), "{e}");
        let e = parse(&["--template", "spider"]).unwrap_err().to_string();
        assert!(e.contains("humanoid or quadruped"), "{e}");
    }

    /// The bent procedural humanoid through the command with the humanoid template and
    /// a preview: biped joint names in the rig, a mirror plane reported, and a PNG whose
    /// mesh pixels carry joint colours.
    #[test]
    fn template_and_preview() {
        use sinew_nodes::skeletonize::bodies;
        let registry = crate::default_registry().unwrap();
        let d = tmp("template");
        let body = bodies::humanoid(true, 12);
        let obj = d.join("body.obj");
        std::fs::write(&obj, obj_text(&body.mesh)).unwrap();
        let out = d.join("body.ron");
        let png_path = d.join("body.png");
        let opts = SkeletonizeOptions {
            template: Some(Template::Humanoid),
            preview: Some(png_path.clone()),
            ..Default::default()
        };
        let summary = skeletonize_cmd(&obj, &out, &opts, &registry).unwrap();
        assert!(
            summary.contains("method: volume") && summary.contains("mirror plane"),
            "{summary}"
        );
        assert!(summary.contains("body.png"), "{summary}");
        let text = std::fs::read_to_string(&out).unwrap();
        for n in ["pelvis", "elbow_L", "elbow_R", "knee_L", "ankle_R", "head"] {
            assert!(text.contains(&format!("\"{n}\": joint")), "no {n} in the rig");
        }
        crate::cli::rig_cmds::check(&out, &registry).unwrap();
        let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png_path).unwrap()));
        let mut r = dec.read_info().unwrap();
        let mut buf = vec![0; r.output_buffer_size()];
        let info = r.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (960, 480));
        let px = |x: usize, y: usize| {
            let i = 3 * (y * 960 + x);
            [buf[i], buf[i + 1], buf[i + 2]]
        };
        assert_eq!(px(3, 3), preview::BACKGROUND);
        // Front view, 15 pixels right of the spine's line, at chest height (about 237
        // pixels a unit, the torso 35 pixels wide each side): the torso, coloured.
        let torso = px(255, 200);
        assert_ne!(torso, preview::BACKGROUND);
        assert!(torso.iter().max() != torso.iter().min(), "grey torso {torso:?}");
        // A preview must be a PNG and must not overwrite the input.
        let bad = SkeletonizeOptions {
            preview: Some(d.join("p.jpg")),
            ..opts.clone()
        };
        assert!(skeletonize_cmd(&obj, &out, &bad, &registry)
            .unwrap_err()
            .contains("PNG"));
        let _ = std::fs::remove_dir_all(&d);
    }

    /// Generalized winding number of a closed-ish mesh around `p` (solid angles,
    /// Van Oosterom & Strackee 1983): about 1 inside, 0 outside.
    fn winding_number(m: &sinew_core::Mesh, p: DVec3) -> f64 {
        let mut total = 0.0;
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize].as_dvec3() - p);
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let num = a.dot(b.cross(c));
            let den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
            total += 2.0 * num.atan2(den);
        }
        total / (4.0 * std::f64::consts::PI)
    }

    /// The real Fox (Khronos sample model): four separate leg chains, a head and a tail
    /// chain at the two ends of the body, every joint with children inside the mesh.
    #[test]
    fn fox_has_four_legs_a_head_and_a_tail() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/assets/gltf/Fox.glb");
        if !path.exists() {
            println!("skipping: {} is absent", path.display());
            return;
        }
        let mesh = load_mesh(&path).unwrap();
        let d = skeletonize_detailed(&mesh, &SkeletonizeParams::default()).unwrap();
        let sk = &d.skeleton;
        let children = |j: usize| sk.children(j).count();
        for j in (0..sk.len()).filter(|&j| children(j) > 0) {
            let w = winding_number(&mesh, sk.positions[j]);
            assert!(
                w > 0.5,
                "{} at {} is outside (winding number {w:.2})",
                sk.names[j],
                sk.positions[j]
            );
        }
        // The chain of a leaf up to the first junction or root.
        let chain = |leaf: usize| {
            let mut out = vec![leaf];
            let mut j = leaf;
            while let Some(p) = sk.parents[j] {
                if children(p) > 1 || sk.parents[p].is_none() {
                    break;
                }
                out.push(p);
                j = p;
            }
            out
        };
        let (lo, hi) = mesh
            .positions
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), p| {
                (l.min(p.as_dvec3()), h.max(p.as_dvec3()))
            });
        let height = hi.y - lo.y;
        // The body's long horizontal axis.
        let long = if hi.x - lo.x > hi.z - lo.z { DVec3::X } else { DVec3::Z };
        let mut leaves: Vec<usize> = (0..sk.len()).filter(|&j| children(j) == 0).collect();
        leaves.sort_by(|&a, &b| sk.positions[a].y.total_cmp(&sk.positions[b].y));
        let names = |js: &[usize]| {
            js.iter()
                .map(|&j| format!("{} {:.1}", sk.names[j], sk.positions[j]))
                .collect::<Vec<_>>()
        };
        assert!(leaves.len() >= 6, "leaves {:?}", names(&leaves));
        // Four feet near the ground, each on its own chain of at least three joints.
        let feet = &leaves[..4];
        let mut used = std::collections::HashSet::new();
        for &f in feet {
            assert!(sk.positions[f].y < lo.y + 0.2 * height, "feet {:?}", names(feet));
            let c = chain(f);
            assert!(c.len() >= 3, "leg chain {:?}", names(&c));
            for j in c {
                assert!(used.insert(j), "two legs share {}", sk.names[j]);
            }
        }
        // Two feet on each side, two in front and two behind.
        let mid = 0.5 * (lo + hi);
        let side = long.cross(DVec3::Y);
        let left = feet
            .iter()
            .filter(|&&f| (sk.positions[f] - mid).dot(side) > 0.0)
            .count();
        let front = feet
            .iter()
            .filter(|&&f| (sk.positions[f] - mid).dot(long) > 0.0)
            .count();
        assert_eq!((left, front), (2, 2), "feet {:?}", names(feet));
        // The leaves farthest along the long axis either way (head and tail) are not
        // feet and have chains of their own.
        let along = |j: usize| (sk.positions[j] - mid).dot(long);
        let rest = &leaves[4..];
        let ends = [
            rest.iter()
                .copied()
                .max_by(|&a, &b| along(a).total_cmp(&along(b)))
                .unwrap(),
            rest.iter()
                .copied()
                .min_by(|&a, &b| along(a).total_cmp(&along(b)))
                .unwrap(),
        ];
        let length = (hi - lo).dot(long);
        for e in ends {
            assert!(along(e).abs() > 0.3 * length, "head/tail {:?}", names(&[e]));
            assert!(chain(e).len() >= 2, "head/tail chain {:?}", names(&chain(e)));
        }
    }
}
