//! Waiting for files to change, with the `notify` crate (inotify on Linux, FSEvents on
//! macOS, ReadDirectoryChangesW on Windows): used by `sinew check --watch` and
//! `sinew view`'s hot reload.
//!
//! The directories holding the files are watched (not the files), so editors that save
//! by writing a new file and renaming it over the old one are seen too; events for other
//! files in those directories are ignored.

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError};
use std::time::Duration;

use notify::{RecommendedWatcher, RecursiveMode, Watcher};

/// After the first event, how long to wait for more (an editor's save is often several
/// events) before reporting the change.
const SETTLE: Duration = Duration::from_millis(15);

fn absolute(p: &Path) -> PathBuf {
    sinew_core::rig::normalize(&std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf()))
}

/// Watches a set of files for changes.
pub struct FileWatcher {
    watcher: RecommendedWatcher,
    events: Receiver<notify::Result<notify::Event>>,
    files: HashSet<PathBuf>,
    dirs: HashSet<PathBuf>,
}

impl FileWatcher {
    /// A watcher over no files yet.
    pub fn new() -> Result<FileWatcher, String> {
        let (tx, events) = channel();
        let watcher = notify::recommended_watcher(move |e| {
            let _ = tx.send(e);
        })
        .map_err(|e| format!("cannot watch files: {e}"))?;
        Ok(FileWatcher {
            watcher,
            events,
            files: HashSet::new(),
            dirs: HashSet::new(),
        })
    }

    /// Watches exactly `files` from now on (missing files too: their creation counts).
    pub fn set_files(&mut self, files: &[PathBuf]) {
        self.files = files.iter().map(|f| absolute(f)).collect();
        let dirs: HashSet<PathBuf> = self
            .files
            .iter()
            .filter_map(|f| f.parent().map(Path::to_path_buf))
            .filter(|d| d.is_dir())
            .collect();
        for d in self.dirs.difference(&dirs) {
            let _ = self.watcher.unwatch(d);
        }
        for d in dirs.difference(&self.dirs.clone()) {
            let _ = self.watcher.watch(d, RecursiveMode::NonRecursive);
        }
        self.dirs = dirs;
    }

    fn relevant(&self, e: &notify::Result<notify::Event>) -> bool {
        match e {
            Ok(ev) => {
                !matches!(ev.kind, notify::EventKind::Access(_))
                    && ev.paths.iter().any(|p| self.files.contains(&absolute(p)))
            }
            Err(_) => false,
        }
    }

    /// Blocks until one of the files changes (then lets a burst of events settle).
    /// Returns `false` if the watcher stopped.
    pub fn wait(&self) -> bool {
        loop {
            match self.events.recv() {
                Ok(e) if self.relevant(&e) => break,
                Ok(_) => continue,
                Err(_) => return false,
            }
        }
        loop {
            match self.events.recv_timeout(SETTLE) {
                Ok(_) => continue,
                Err(RecvTimeoutError::Timeout) => return true,
                Err(RecvTimeoutError::Disconnected) => return false,
            }
        }
    }
}
