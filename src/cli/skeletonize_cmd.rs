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
#[path = "skeletonize_cmd_tests.rs"]
mod tests;
