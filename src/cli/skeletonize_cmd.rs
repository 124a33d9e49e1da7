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
use sinew_nodes::skeletonize::{
    bone_heat_weights_with_report, node::local_placement, skeletonize, Skeleton, SkeletonizeParams, WeightParams,
};

use crate::io::mesh_file::load_mesh;
use crate::io::rig_builder::RigBuilder;

/// Options of `sinew skeletonize`.
#[derive(Clone, Debug)]
pub struct SkeletonizeOptions {
    /// Silhouette raster resolution (pixels along the longer side).
    pub resolution: Option<usize>,
    /// Bones per branch (None or 0: joints where branches turn).
    pub bones_per_branch: Option<usize>,
    /// Joints per vertex in the weights (0 = unlimited).
    pub max_influences: usize,
    /// Compute bone-heat weights and write a skinCluster.
    pub weights: bool,
}

impl Default for SkeletonizeOptions {
    fn default() -> Self {
        SkeletonizeOptions {
            resolution: None,
            bones_per_branch: None,
            max_influences: WeightParams::default().max_influences,
            weights: true,
        }
    }
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
    let start = Instant::now();
    let mesh = load_mesh(mesh_path)?;
    let loaded = start.elapsed();
    let params = SkeletonizeParams {
        resolution: opts.resolution.unwrap_or(SkeletonizeParams::default().resolution),
        bones_per_branch: opts.bones_per_branch.filter(|&b| b > 0),
        ..SkeletonizeParams::default()
    };
    let t0 = Instant::now();
    let sk = skeletonize(&mesh, &params).map_err(|e| format!("{}: {e}", mesh_path.display()))?;
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
        Some(bone_heat_weights_with_report(&mesh, &sk, &wp).map_err(|e| format!("{}: {e}", mesh_path.display()))?)
    } else {
        None
    };
    let t_weights = t1.elapsed();

    let stem = out.file_stem().and_then(|s| s.to_str()).unwrap_or("rig").to_string();
    let mut rig = RigBuilder::new(&stem, 24.0);
    let (translates, orients) = local_placement(&sk);
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
        branch_count(&sk),
        roots.join(", "),
    );
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
        let cli = crate::cli::Cli::try_parse_from([
            "sinew",
            "skeletonize",
            "a.obj",
            "-o",
            "r.ron",
            "--resolution",
            "64",
            "--bones-per-branch",
            "2",
            "--max-influences",
            "3",
            "--no-weights",
        ]);
        assert!(cli.is_ok(), "{cli:?}");
    }
}
