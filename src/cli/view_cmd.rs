//! `sinew view`: serves the browser viewer (the `sinew-view` crate) for a rig and
//! reloads it whenever the rig or a file it uses changes.

use std::io::Write as _;
use std::path::Path;
use std::sync::Arc;

use sinew_core::Registry;

use super::watch::FileWatcher;

/// Serves `rig` on `addr` until interrupted; prints the page's address first.
pub fn view(rig: &Path, addr: &str, open: bool, registry: &Arc<Registry>) -> Result<(), String> {
    let registry = registry.clone();
    let loader: sinew_view::Loader = Arc::new(move |p: &Path| crate::io::mesh_file::load_rig(p, &registry));
    let viewer = sinew_view::Viewer::start(sinew_view::ViewOptions {
        rig: rig.to_path_buf(),
        addr: addr.to_string(),
        loader,
    })?;
    let url = viewer.url();
    // Status lines go out with write results ignored: a closed stdout must not stop the server.
    let say = |text: String| {
        let mut out = std::io::stdout().lock();
        let _ = writeln!(out, "{text}");
        let _ = out.flush();
    };
    say(format!(
        "sinew view: serving {} at {url} (Ctrl-C to stop)",
        rig.display()
    ));
    if open {
        open_browser(&url);
    }
    let mut watcher = FileWatcher::new()?;
    loop {
        watcher.set_files(&viewer.files());
        if !watcher.wait() {
            break;
        }
        let started = std::time::Instant::now();
        let ok = viewer.reload();
        say(format!(
            "reloaded {} in {:.1} ms{}",
            rig.display(),
            started.elapsed().as_secs_f64() * 1e3,
            if ok { "" } else { " (errors shown in the page)" }
        ));
    }
    viewer.wait();
    Ok(())
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
