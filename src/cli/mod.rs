//! The `sinew` command-line tool: argument parsing and one module per command.
//!
//! Adding a command: give it a module with a function taking its arguments and an
//! [`Output`], returning `Result<(), CliError>` (or `Result<String, String>` for a short
//! summary that `execute` prints). Every command follows the rules in [`output`]: results
//! go through the `Output` (never `print!`/`println!`: they panic on a closed pipe), a
//! closed standard output ends the command quietly with exit code 0, any other write error
//! is reported with exit code 1, and files it writes are checked with
//! [`paths::check_outputs`] (no output may overwrite an input; rigs end in `.ron`).

mod bake_cmd;
mod corrective_cmd;
mod eval_cmd;
mod eval_format;
mod frames;
mod import_cmd;
mod nodes_cmd;
pub mod output;
pub mod paths;
mod profile_cmd;
mod retarget_cmd;
mod rig_cmds;
pub mod skeleton_preview;
mod skeletonize_cmd;
#[cfg(feature = "view")]
mod view_cmd;
mod watch;

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub use eval_cmd::{apply_overrides, eval, eval_to, parse_plug_value, EvalRequest, Format};
pub use eval_format::Json;
pub use frames::{parse_frames, resolve_timing, FrameRange, MAX_FRAME, MAX_FRAMES};
pub use nodes_cmd::{markdown as nodes_markdown, MARKDOWN_COMMAND};
pub use output::{CliError, Output};

/// sinew: a Maya-style rig evaluator — check, evaluate and bake rigs written as RON text.
#[derive(Debug, Parser)]
#[command(name = "sinew", version, about, long_about = None)]
pub struct Cli {
    /// The most nodes a rig may expand to, components included (default 250000): a guard
    /// against components that multiply without end.
    #[arg(long, global = true, value_name = "N")]
    max_nodes: Option<usize>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// List the registered node types and their attributes.
    Nodes {
        /// Show only this node type (with --rig: this node of the rig, custom attributes included).
        node_type: Option<String>,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
        /// Print every node type as Markdown (what `docs/nodes.md` holds).
        #[arg(long, conflicts_with_all = ["json", "node_type", "rig"])]
        markdown: bool,
        /// List the attributes of a node of this rig (NODE_TYPE names the node).
        #[arg(long, value_name = "RIG")]
        rig: Option<PathBuf>,
    },
    /// Validate a rig: a one-line summary, or every error as file:line:col.
    Check {
        /// The rig file.
        rig: PathBuf,
        /// Re-validate whenever the rig or a component file it uses changes.
        #[arg(long)]
        watch: bool,
        /// With --watch: stop after this many validations (for scripts and tests).
        #[arg(long, hide = true)]
        max_runs: Option<usize>,
    },
    /// Rewrite rigs in canonical form (stable order, defaults omitted).
    Fmt {
        /// Rig files.
        #[arg(required = true)]
        rigs: Vec<PathBuf>,
        /// Do not write; fail if a file is not canonical (for CI).
        #[arg(long)]
        check: bool,
    },
    /// Orient joints as Maya's Orient Joint: aim axis at the child joint, up axis toward a
    /// world axis, orientation into jointOrient; world positions kept. Rewrites the rig.
    OrientJoints {
        /// The rig file.
        rig: PathBuf,
        /// The local axis that points at the first child joint.
        #[arg(long, default_value = "x", value_parser = ["x", "y", "z"])]
        aim: String,
        /// The local axis that points toward --world-up.
        #[arg(long, default_value = "y", value_parser = ["x", "y", "z"])]
        up: String,
        /// The world direction for the up axis (x, y, z, -x, -y, -z; Maya's secondary axis orient).
        #[arg(long, default_value = "y", allow_hyphen_values = true)]
        world_up: String,
        /// Only these joints (comma-separated); default every joint.
        #[arg(long, value_delimiter = ',')]
        joints: Vec<String>,
        /// With --joints: their descendant joints too.
        #[arg(long)]
        children: bool,
        /// Write here instead of rewriting the rig.
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// Print a rig's node graph as Graphviz DOT (default), JSON, an SVG picture or an HTML page.
    Graph {
        /// The rig file.
        rig: PathBuf,
        /// Graphviz DOT output.
        #[arg(long, conflicts_with_all = ["json", "svg", "html"])]
        dot: bool,
        /// JSON output.
        #[arg(long, conflicts_with_all = ["svg", "html"])]
        json: bool,
        /// An SVG picture laid out by sinew (no Graphviz needed).
        #[arg(long, conflicts_with = "html")]
        svg: bool,
        /// A standalone HTML page with the picture, pan, zoom and node search.
        #[arg(long)]
        html: bool,
    },
    /// Serve a live viewer of the rig in the browser (reloads when the rig's files change).
    View {
        /// The rig file.
        rig: PathBuf,
        /// Port to listen on (0: any free port; the address is printed).
        #[arg(long, default_value_t = 8484)]
        port: u16,
        /// Address to listen on.
        #[arg(long, default_value = "127.0.0.1")]
        host: String,
        /// Open the page in the default browser.
        #[arg(long)]
        open: bool,
    },
    /// Time the compiled evaluation per node and node type; optionally write a Chrome trace.
    Profile {
        /// The rig file.
        rig: PathBuf,
        /// Frames: START..=END, START..END or one frame (default: the rig's frame range).
        #[arg(long, allow_hyphen_values = true)]
        frames: Option<String>,
        /// Frames per second (default: the rig's fps, else 24).
        #[arg(long)]
        fps: Option<f64>,
        /// Write a Chrome trace-event JSON of the first frames (Perfetto, chrome://tracing).
        #[arg(long)]
        trace: Option<PathBuf>,
        /// Node rows to print.
        #[arg(long, default_value_t = 30)]
        top: usize,
    },
    /// Evaluate a rig frame by frame and print plugs.
    Eval {
        /// The rig file.
        rig: PathBuf,
        /// Frames: START..=END, START..END or one frame (default: the rig's frame range).
        #[arg(long, allow_hyphen_values = true)]
        frames: Option<String>,
        /// Frames per second (default: the rig's fps, else 24).
        #[arg(long)]
        fps: Option<f64>,
        /// Plugs to print, comma-separated or repeated: node.attr, node.attr[2], node.attrX.
        #[arg(long, required = true)]
        print: Vec<String>,
        /// Override an input before evaluating: node.attr=value (RON syntax, e.g. (1, 2, 3)).
        #[arg(long)]
        set: Vec<String>,
        /// Override an input that a connection drives, for this run: the connection is
        /// removed and the value set (node.attr=value; try the FK side of a switch).
        #[arg(long)]
        set_driven: Vec<String>,
        /// Output format: csv, jsonl (whole values: meshes, weights, matrix arrays) or obj
        /// (one OBJ file per mesh plug and frame, into the --output folder).
        #[arg(long, value_enum, default_value_t = Format::Csv)]
        format: Format,
        /// With --format obj: the folder the OBJ files are written to.
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Evaluate lazily through the graph instead of the compiled schedule.
        #[arg(long)]
        lazy: bool,
    },
    /// Import a Maya ASCII (.ma), glTF (.gltf/.glb) or BVH file as a rig (RIG.ron plus its data file RIG.data.ron).
    Import {
        /// The scene, model or motion file.
        model: PathBuf,
        /// The rig file to write.
        #[arg(short, long)]
        output: PathBuf,
        /// glTF: the animation to import, by name or index (default: the first).
        #[arg(long)]
        animation: Option<String>,
        /// glTF: the rig's frame rate (default 30; playback is exact at any rate).
        #[arg(long)]
        fps: Option<f64>,
        /// Maya: multiply every length by this factor (0.01: centimetres to metres).
        #[arg(long)]
        scale: Option<f64>,
        /// Maya: fail when a node type or connection that changes the rig is skipped.
        #[arg(long)]
        strict: bool,
    },
    /// Evaluate a rig over frames and write a glTF (.glb or .gltf) with skeleton, skins, morphs and animation.
    ///
    /// Time: rig frame f is f / fps seconds of rig time (frame 0 = 0 s). The glTF gets one
    /// key per frame at (f - START) / fps seconds, so the clip starts at 0 s on the first
    /// baked frame: `--frames 1..=24 --fps 24` puts rig frame 1 at glTF time 0 and frame 24
    /// at 23/24 s. `sinew import` maps glTF time t to rig frame t * fps, so baking an
    /// imported clip over its own range (0..=N) keeps its timing.
    Bake {
        /// The rig file.
        rig: PathBuf,
        /// Frames: START..=END, START..END or one frame (default: the rig's frame range);
        /// frame START becomes glTF time 0.
        #[arg(long, allow_hyphen_values = true)]
        frames: Option<String>,
        /// Frames per second (default: the rig's fps, else 24).
        #[arg(long)]
        fps: Option<f64>,
        /// Remove keys that linear interpolation reproduces within this tolerance (0 keeps all).
        #[arg(long, default_value_t = 0.0)]
        tolerance: f64,
        /// The glTF file to write.
        #[arg(short, long)]
        output: PathBuf,
        /// Bake meshes deformed by deformers glTF cannot express (cluster, nonLinear, ffd,
        /// deltaMush, wire, wrap...) as one morph target per frame (else: a warning names what is lost).
        #[arg(long)]
        bake_deformers_as_morphs: bool,
    },
    /// Turn a mesh sculpted on the posed rig into a blendShape target before the skinning
    /// (Maya's invertShape) and write the rig with it.
    Corrective(corrective_cmd::CorrectiveArgs),
    /// Retarget a BVH take onto a rig's skeleton and bake the result to glTF.
    Retarget {
        /// The motion capture file (.bvh).
        mocap: PathBuf,
        /// The target rig.
        #[arg(long)]
        to: PathBuf,
        /// Joint map: a RON map { "SourceJoint": "targetJoint", .. } (default: by humanoid names).
        #[arg(long)]
        map: Option<PathBuf>,
        /// The glTF file to write.
        #[arg(short, long)]
        output: PathBuf,
        /// Plant the feet: while a source foot touches the ground, hold the target ankle still
        /// and solve hip, knee and ankle with two-bone IK (off by default).
        #[arg(long)]
        plant_feet: bool,
        /// With --plant-feet: a foot touches the ground within this height above the clip's
        /// lowest, in source leg lengths.
        #[arg(long, default_value_t = 0.08)]
        contact_height: f64,
        /// With --plant-feet: ... and when slower than this horizontally, in source leg lengths per second.
        #[arg(long, default_value_t = 0.3)]
        contact_speed: f64,
        /// With --plant-feet: contacts shorter than this many seconds are ignored.
        #[arg(long, default_value_t = 0.1)]
        min_contact: f64,
        /// With --plant-feet: seconds to blend into and out of each contact.
        #[arg(long, default_value_t = 0.1)]
        plant_blend: f64,
    },
    /// Extract a skeleton and bone-heat skin weights from a mesh and write an editable rig.
    Skeletonize {
        /// The mesh file (.obj, .gltf or .glb).
        mesh: PathBuf,
        /// The rig file to write (its heavy data goes to RIG.data.ron next to it).
        #[arg(short, long)]
        output: PathBuf,
        /// Extraction method: auto (volume, or silhouette for a flat mesh), volume, silhouette.
        #[arg(long, default_value = "auto", value_parser = skeletonize_cmd::parse_method)]
        method: sinew_nodes::skeletonize::Method,
        /// Volume cells along the mesh's longest side (default 96); with
        /// `--method silhouette`, raster pixels (default 256).
        #[arg(long)]
        resolution: Option<usize>,
        /// Bones per limb, from its base to its tip (default 3): more joints where the
        /// limb bends or thins.
        #[arg(long)]
        joints_per_limb: Option<usize>,
        /// Bones per branch, spaced evenly, instead of joints at bends (0 = off).
        #[arg(long)]
        bones_per_branch: Option<usize>,
        /// Fit a named skeleton: humanoid (the biped's joint names) or quadruped.
        #[arg(long, value_parser = skeletonize_cmd::parse_template)]
        template: Option<sinew_nodes::skeletonize::Template>,
        /// Keep the skeleton as extracted, without mirror symmetry.
        #[arg(long)]
        no_symmetry: bool,
        /// Give each separate part of the mesh its own root instead of joining it.
        #[arg(long)]
        separate_parts: bool,
        /// Joints per vertex in the skin weights (0 = unlimited).
        #[arg(long, default_value_t = 4)]
        max_influences: usize,
        /// Skip the skin weights and the skinCluster.
        #[arg(long)]
        no_weights: bool,
        /// Also write a PNG: front and side views, each vertex in its dominant joint's colour.
        #[arg(long)]
        preview: Option<PathBuf>,
    },
}

/// Runs the CLI with the given arguments; returns the process exit code.
pub fn run(args: impl IntoIterator<Item = std::ffi::OsString>) -> ExitCode {
    let cli = match Cli::try_parse_from(args) {
        Ok(c) => c,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::from(2)
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    let stdout = std::io::stdout();
    let terminal = stdout.is_terminal();
    let mut lock = std::io::BufWriter::new(stdout.lock());
    let mut out = Output::new(&mut lock).eager(terminal);
    let result = execute(cli, &mut out).and_then(|()| out.flush());
    match result {
        Ok(()) | Err(CliError::OutputClosed) => ExitCode::SUCCESS,
        Err(CliError::Failed(message)) => {
            // Standard error may be closed too: nothing more to do then.
            let _ = writeln!(
                std::io::stderr(),
                "{}",
                if message.contains(": error: ") {
                    message
                } else {
                    format!("error: {message}")
                }
            );
            ExitCode::from(1)
        }
    }
}

#[cfg(feature = "view")]
fn view(
    rig: &std::path::Path,
    addr: &str,
    open: bool,
    registry: &std::sync::Arc<sinew_core::Registry>,
    out: &mut Output<'_>,
) -> Result<(), CliError> {
    view_cmd::view(rig, addr, open, registry, &mut out.reborrow().eager(true))
}

/// The message of `sinew view` in a build without the viewer.
pub const VIEW_NOT_BUILT: &str =
    "this sinew was built without the viewer (the `view` feature); rebuild with default features: cargo build --release";

#[cfg(not(feature = "view"))]
fn view(
    _: &std::path::Path,
    _: &str,
    _: bool,
    _: &std::sync::Arc<sinew_core::Registry>,
    _: &mut Output<'_>,
) -> Result<(), CliError> {
    Err(VIEW_NOT_BUILT.into())
}

fn execute(cli: Cli, out: &mut Output<'_>) -> Result<(), CliError> {
    let registry = crate::default_registry().map_err(|e| format!("internal error in a node plugin: {e}"))?;
    if let Some(max_nodes) = cli.max_nodes {
        rig_cmds::set_load_limits(sinew_core::rig::LoadLimits { max_nodes });
    }
    match cli.command {
        Command::Nodes { markdown: true, .. } => out.text(&nodes_cmd::markdown(&registry))?,
        Command::Nodes {
            node_type, json, rig, ..
        } => match rig {
            Some(rig) => {
                let node = node_type.ok_or("--rig needs a node name: sinew nodes NODE --rig RIG.ron")?;
                let loaded = rig_cmds::load(&rig, &registry)?;
                out.text(&nodes_cmd::render_node(&loaded.graph, &node, json)?)?
            }
            None => out.text(&nodes_cmd::render(&registry, node_type.as_deref(), json)?)?,
        },
        Command::Check { rig, watch, max_runs } => {
            if watch {
                rig_cmds::watch(&rig, &registry, max_runs, &mut out.reborrow().eager(true))?;
            } else {
                out.text(&rig_cmds::check(&rig, &registry)?)?;
            }
        }
        Command::Fmt { rigs, check } => out.text(&rig_cmds::fmt(&rigs, check, &registry)?)?,
        Command::OrientJoints {
            rig,
            aim,
            up,
            world_up,
            joints,
            children,
            output,
        } => {
            let report = rig_cmds::orient_joints(
                &rig,
                rig_cmds::OrientArgs {
                    aim: &aim,
                    up: &up,
                    world_up: &world_up,
                    joints: &joints,
                    children,
                    output: output.as_deref(),
                },
                &registry,
            )?;
            out.text(&report)?
        }
        Command::Graph {
            rig,
            dot: _,
            json,
            svg,
            html,
        } => {
            let format = match (json, svg, html) {
                (true, _, _) => rig_cmds::GraphFormat::Json,
                (_, true, _) => rig_cmds::GraphFormat::Svg,
                (_, _, true) => rig_cmds::GraphFormat::Html,
                _ => rig_cmds::GraphFormat::Dot,
            };
            out.text(&rig_cmds::graph(&rig, format, &registry)?)?
        }
        Command::View { rig, port, host, open } => view(&rig, &format!("{host}:{port}"), open, &registry, out)?,
        Command::Profile {
            rig,
            frames,
            fps,
            trace,
            top,
        } => out.text(&profile_cmd::profile(
            &profile_cmd::ProfileRequest {
                rig,
                frames,
                fps,
                trace,
                top,
            },
            &registry,
        )?)?,
        Command::Eval {
            rig,
            frames,
            fps,
            print: plugs,
            set,
            set_driven,
            format,
            output,
            lazy,
        } => {
            let req = EvalRequest {
                rig,
                frames,
                fps,
                print: plugs,
                set,
                set_driven,
                format,
                output,
                lazy,
            };
            eval_to(&req, &registry, out)?;
        }
        Command::Import {
            model,
            output,
            animation,
            fps,
            scale,
            strict,
        } => out.text(&import_cmd::import(
            &model,
            &output,
            &import_cmd::ImportFlags {
                animation: animation.as_deref(),
                fps,
                scale,
                strict,
            },
            &registry,
        )?)?,
        Command::Bake {
            rig,
            frames,
            fps,
            tolerance,
            output,
            bake_deformers_as_morphs,
        } => out.text(&bake_cmd::bake_cmd(
            &rig,
            frames.as_deref(),
            fps,
            tolerance,
            &output,
            bake_deformers_as_morphs,
            &registry,
        )?)?,
        Command::Corrective(args) => out.text(&corrective_cmd::corrective(&args, &registry)?)?,
        Command::Retarget {
            mocap,
            to,
            map,
            output,
            plant_feet,
            contact_height,
            contact_speed,
            min_contact,
            plant_blend,
        } => {
            let opts = crate::io::retarget::RetargetOptions {
                plant_feet,
                contact_height,
                contact_speed,
                min_contact,
                blend: plant_blend,
                ..Default::default()
            };
            out.text(&retarget_cmd::retarget_cmd(
                &mocap,
                &to,
                map.as_deref(),
                &output,
                &opts,
                &registry,
            )?)?
        }
        Command::Skeletonize {
            mesh,
            output,
            method,
            resolution,
            joints_per_limb,
            bones_per_branch,
            template,
            no_symmetry,
            separate_parts,
            max_influences,
            no_weights,
            preview,
        } => {
            let opts = skeletonize_cmd::SkeletonizeOptions {
                method,
                resolution,
                joints_per_limb,
                bones_per_branch,
                template,
                symmetry: !no_symmetry,
                join_parts: !separate_parts,
                max_influences,
                weights: !no_weights,
                preview,
            };
            out.text(&skeletonize_cmd::skeletonize_cmd(&mesh, &output, &opts, &registry)?)?
        }
    }
    Ok(())
}
