//! Watching `shaders/` for edits: the viewer polls the files' modification times (twice
//! a second) rather than asking the OS for events, which works the same everywhere.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};

/// Polls the `.wgsl` files of a folder for changes.
pub struct ShaderWatcher {
    dir: PathBuf,
    stamp: Vec<(PathBuf, Option<SystemTime>)>,
    last_poll: Instant,
    interval: Duration,
}

fn stamp(dir: &Path) -> Vec<(PathBuf, Option<SystemTime>)> {
    let mut files: Vec<(PathBuf, Option<SystemTime>)> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "wgsl"))
        .map(|p| {
            let modified = std::fs::metadata(&p).and_then(|m| m.modified()).ok();
            (p, modified)
        })
        .collect();
    files.sort();
    files
}

impl ShaderWatcher {
    /// Watches `dir`, polling at most every `interval`.
    pub fn new(dir: PathBuf, interval: Duration) -> ShaderWatcher {
        ShaderWatcher {
            stamp: stamp(&dir),
            dir,
            last_poll: Instant::now(),
            interval,
        }
    }

    /// The watched folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// True when a `.wgsl` file was added, removed or modified since the last change seen.
    pub fn changed(&mut self) -> bool {
        if self.last_poll.elapsed() < self.interval {
            return false;
        }
        self.last_poll = Instant::now();
        let now = stamp(&self.dir);
        if now == self.stamp {
            return false;
        }
        self.stamp = now;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sees_edits_additions_and_removals_only() {
        let dir = tempfile::tempdir().expect("temp dir");
        let file = dir.path().join("a.wgsl");
        std::fs::write(&file, "// a").expect("write");
        let mut w = ShaderWatcher::new(dir.path().to_path_buf(), Duration::ZERO);
        assert!(!w.changed(), "nothing changed yet");
        std::fs::write(dir.path().join("notes.txt"), "x").expect("write");
        assert!(!w.changed(), "other files are ignored");
        let later = SystemTime::now() + Duration::from_secs(5);
        std::fs::File::options()
            .write(true)
            .open(&file)
            .and_then(|f| f.set_modified(later))
            .expect("touch");
        assert!(w.changed(), "an edit");
        assert!(!w.changed(), "seen once");
        std::fs::write(dir.path().join("b.wgsl"), "// b").expect("write");
        assert!(w.changed(), "an addition");
        std::fs::remove_file(&file).expect("remove");
        assert!(w.changed(), "a removal");
    }
}
