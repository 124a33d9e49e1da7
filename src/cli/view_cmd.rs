//! `sinew view`: serves the browser viewer (the `sinew-view` crate) for a rig and
//! reloads it whenever the rig or a file it uses changes.
//!
//! Status lines (the address, one line per reload) go through the command's [`Output`]
//! like every command's results: a closed standard output ends the viewer quietly (exit
//! 0) at its next line, any other write error ends it with exit code 1.

use std::path::Path;
use std::sync::Arc;

use sinew_core::Registry;

use super::output::{CliError, Output};
use super::watch::FileWatcher;

/// Serves `rig` on `addr` until interrupted (or until standard output is closed); prints
/// the page's address first.
pub fn view(
    rig: &Path,
    addr: &str,
    open: bool,
    registry: &Arc<Registry>,
    out: &mut Output<'_>,
) -> Result<(), CliError> {
    let registry = registry.clone();
    let loader: sinew_view::Loader = Arc::new(move |p: &Path| crate::io::mesh_file::load_rig(p, &registry));
    let viewer = sinew_view::Viewer::start(sinew_view::ViewOptions {
        rig: rig.to_path_buf(),
        addr: addr.to_string(),
        loader,
    })?;
    let url = viewer.url();
    out.text(&format!(
        "sinew view: serving {} at {url} (Ctrl-C to stop)",
        rig.display()
    ))?;
    if open {
        open_browser(&url);
    }
    let mut watcher = FileWatcher::new()?;
    loop {
        watcher.set_files(&viewer.files());
        let Some(event_at) = watcher.wait() else {
            return Err("the file watcher stopped".into());
        };
        let report = viewer.reload(event_at);
        out.text(&report.to_string())?;
    }
}

fn open_browser(url: &str) {
    let opener = if cfg!(target_os = "macos") {
        "open"
    } else if cfg!(windows) {
        "explorer"
    } else {
        "xdg-open"
    };
    if std::process::Command::new(opener).arg(url).spawn().is_err() {
        eprintln!("could not start a browser ({opener}); open {url} yourself");
    }
}
