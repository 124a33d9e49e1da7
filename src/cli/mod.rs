//! The `sinew` command-line tool: argument parsing and one module per command.

mod bake_cmd;
mod eval_cmd;
mod frames;
mod import_cmd;
mod nodes_cmd;
mod retarget_cmd;
mod rig_cmds;
mod skeletonize_cmd;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub use eval_cmd::{eval, parse_plug_value, EvalRequest, Format};
pub use frames::{parse_frames, FrameRange};

/// sinew: a Maya-style rig evaluator — check, evaluate and bake rigs written as RON text.
#[derive(Debug, Parser)]
#[command(name = "sinew", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// List the registered node types and their attributes.
    Nodes {
        /// Show only this node type.
        node_type: Option<String>,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
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
    /// Print a rig's node graph as Graphviz DOT (default) or JSON.
    Graph {
        /// The rig file.
        rig: PathBuf,
        /// Graphviz DOT output.
        #[arg(long, conflicts_with = "json")]
        dot: bool,
        /// JSON output.
        #[arg(long)]
        json: bool,
    },
    /// Evaluate a rig frame by frame and print plugs.
    Eval {
        /// The rig file.
        rig: PathBuf,
        /// Frames: START..=END, START..END or one frame (default: the rig's frame range).
        #[arg(long)]
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
        /// Output format.
        #[arg(long, value_enum, default_value_t = Format::Csv)]
        format: Format,
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
    Bake {
        /// The rig file.
        rig: PathBuf,
        /// Frames: START..=END, START..END or one frame (default: the rig's frame range).
        #[arg(long)]
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
    },
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
        /// Silhouette raster resolution in pixels along the longer side (default 256).
        #[arg(long)]
        resolution: Option<usize>,
        /// Bones per branch, spaced evenly (default: joints where branches turn).
        #[arg(long)]
        bones_per_branch: Option<usize>,
        /// Joints per vertex in the skin weights (0 = unlimited).
        #[arg(long, default_value_t = 4)]
        max_influences: usize,
        /// Skip the skin weights and the skinCluster.
        #[arg(long)]
        no_weights: bool,
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
    match execute(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!(
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

fn print(text: &str) {
    if text.ends_with('\n') {
        print!("{text}");
    } else if !text.is_empty() {
        println!("{text}");
    }
}

fn execute(cli: Cli) -> Result<(), String> {
    let registry = crate::default_registry().map_err(|e| format!("internal error in a node plugin: {e}"))?;
    match cli.command {
        Command::Nodes { node_type, json } => print(&nodes_cmd::render(&registry, node_type.as_deref(), json)?),
        Command::Check { rig, watch, max_runs } => {
            if watch {
                rig_cmds::watch(&rig, &registry, max_runs)?;
            } else {
                print(&rig_cmds::check(&rig, &registry)?);
            }
        }
        Command::Fmt { rigs, check } => print(&rig_cmds::fmt(&rigs, check, &registry)?),
        Command::Graph { rig, dot: _, json } => print(&rig_cmds::graph(&rig, json, &registry)?),
        Command::Eval {
            rig,
            frames,
            fps,
            print: plugs,
            set,
            format,
            lazy,
        } => {
            let req = EvalRequest {
                rig,
                frames,
                fps,
                print: plugs,
                set,
                format,
                lazy,
            };
            print(&eval(&req, &registry)?);
        }
        Command::Import {
            model,
            output,
            animation,
            fps,
            scale,
            strict,
        } => print(&import_cmd::import(
            &model,
            &output,
            &import_cmd::ImportFlags {
                animation: animation.as_deref(),
                fps,
                scale,
                strict,
            },
            &registry,
        )?),
        Command::Bake {
            rig,
            frames,
            fps,
            tolerance,
            output,
        } => print(&bake_cmd::bake_cmd(
            &rig,
            frames.as_deref(),
            fps,
            tolerance,
            &output,
            &registry,
        )?),
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
            print(&retarget_cmd::retarget_cmd(
                &mocap,
                &to,
                map.as_deref(),
                &output,
                &opts,
                &registry,
            )?)
        }
        Command::Skeletonize {
            mesh,
            output,
            resolution,
            bones_per_branch,
            max_influences,
            no_weights,
        } => {
            let opts = skeletonize_cmd::SkeletonizeOptions {
                resolution,
                bones_per_branch,
                max_influences,
                weights: !no_weights,
            };
            print(&skeletonize_cmd::skeletonize_cmd(&mesh, &output, &opts, &registry)?)
        }
    }
    Ok(())
}
