//! The `sinew` command-line tool: argument parsing and one module per command.

mod frames;
mod nodes_cmd;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

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
            eprintln!("error: {message}");
            ExitCode::from(1)
        }
    }
}

fn execute(cli: Cli) -> Result<(), String> {
    let registry = crate::default_registry().map_err(|e| format!("internal error in a node plugin: {e}"))?;
    match cli.command {
        Command::Nodes { node_type, json } => {
            print!("{}", nodes_cmd::render(&registry, node_type.as_deref(), json)?);
            Ok(())
        }
    }
}
