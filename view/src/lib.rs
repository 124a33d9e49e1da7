//! sinew-view: the browser rig viewer behind `sinew view`.
//!
//! A small HTTP server ([`Viewer`], on `tiny_http`) serves a page with bundled three.js
//! (no network needed) and a JSON/binary API over one [`Session`]: the loaded rig, its
//! compiled program for playback, its lazy graph for edits. The browser draws; sinew
//! computes. [`scene`] decides what is drawn and packs frames, [`graph_svg`] lays out the
//! dependency graph (also for `sinew graph --svg/--html`). File watching lives in the
//! `sinew` facade, which calls [`Viewer::reload`] when a file the rig uses changes.

mod assets;
pub mod graph_svg;
pub mod scene;
mod server;
pub mod session;

pub use server::{ViewOptions, Viewer};
pub use session::{Loader, Session};

use serde_json::json;
use sinew_core::ProfileTable;

/// A profile table as JSON: per node and per type, count, total and mean (microseconds)
/// and share of the frame, sorted by total time.
pub fn profile_json(table: &ProfileTable) -> serde_json::Value {
    let rows = |rows: &[sinew_core::ProfileRow]| {
        rows.iter()
            .map(|r| {
                json!({
                    "name": r.name, "type": r.node_type, "count": r.count,
                    "totalUs": r.total.as_secs_f64() * 1e6, "meanUs": r.mean().as_secs_f64() * 1e6,
                    "share": table.share(r),
                })
            })
            .collect::<Vec<_>>()
    };
    json!({
        "frames": table.frames,
        "perFrameUs": table.per_frame().as_secs_f64() * 1e6,
        "nodes": rows(&table.nodes),
        "types": rows(&table.types),
    })
}
