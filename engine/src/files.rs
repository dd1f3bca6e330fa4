//! Checked file access. Every file Lumen reads goes through [`read`], and every file it
//! writes through [`write_atomic`]:
//!
//! - **Reads** refuse what is not a regular file (a device such as `/dev/zero`, a FIFO, a
//!   directory) by its type, before opening it, and refuse a file larger than its kind's
//!   cap ([`FileKind::cap`]) from its metadata. The read itself stops at the cap, so a file
//!   that grows while it is read cannot exceed it either.
//! - **Writes** go to a temporary file beside the target, which is flushed to the disk
//!   (`sync_all`) and then renamed over the target. A failed write (a full disk, a quota,
//!   a missing permission) is an error naming the file, the temporary file is removed, and
//!   whatever the target held before is untouched.

use crate::error::{Error, Result};
use crate::limits::{FileKind, bytes_text};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

/// Reads `path` as a file of `kind`: its bytes, or an error naming the file and why it was
/// not read (missing, not a regular file, larger than the cap).
pub fn read(path: &Path, kind: FileKind) -> Result<Vec<u8>> {
    read_capped(path, kind, kind.cap())
}

/// [`read`] with an explicit cap in bytes.
pub fn read_capped(path: &Path, kind: FileKind, cap: u64) -> Result<Vec<u8>> {
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if !meta.is_file() {
        return Err(Error::bad_file(
            path,
            format!(
                "not a regular file ({}): refused as {}",
                file_type(&meta),
                kind.name()
            ),
        ));
    }
    if meta.len() > cap {
        return Err(too_large(path, kind, meta.len(), cap));
    }
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut bytes = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
    file.take(cap.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| Error::io(path, e))?;
    if bytes.len() as u64 > cap {
        return Err(too_large(path, kind, bytes.len() as u64, cap));
    }
    Ok(bytes)
}

/// [`read`] of a UTF-8 text file.
pub fn read_text(path: &Path) -> Result<String> {
    String::from_utf8(read(path, FileKind::Text)?)
        .map_err(|_| Error::bad_file(path, "not UTF-8 text"))
}

fn too_large(path: &Path, kind: FileKind, size: u64, cap: u64) -> Error {
    Error::bad_file(
        path,
        format!(
            "{} is larger than the {} allowed for {} (the smaller of its ceiling and {})",
            bytes_text(size),
            bytes_text(cap),
            kind.name(),
            crate::limits::memory_budget()
        ),
    )
}

fn file_type(meta: &std::fs::Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    let t = meta.file_type();
    if t.is_dir() {
        "a directory"
    } else if t.is_char_device() {
        "a character device"
    } else if t.is_block_device() {
        "a block device"
    } else if t.is_fifo() {
        "a FIFO"
    } else if t.is_socket() {
        "a socket"
    } else {
        "not a file"
    }
}

/// Creates the parent directory of `path` if needed.
pub fn ensure_parent(path: &Path) -> Result<()> {
    match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => {
            std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))
        }
        _ => Ok(()),
    }
}

/// Writes `bytes` to `path` atomically: to a temporary file in the same folder (created if
/// needed), synced to the disk, then renamed over `path`. On failure the temporary file is
/// removed and `path` keeps what it held.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    ensure_parent(path)?;
    let temporary = temporary_beside(path)?;
    let written = std::fs::File::create(&temporary).and_then(|mut file| {
        file.write_all(bytes)?;
        file.sync_all()
    });
    let renamed = written.and_then(|()| std::fs::rename(&temporary, path));
    if let Err(e) = renamed {
        let _ = std::fs::remove_file(&temporary);
        return Err(Error::io(path, e));
    }
    Ok(())
}

/// `.NAME.PID.tmp` in `path`'s folder.
fn temporary_beside(path: &Path) -> Result<PathBuf> {
    let name = path
        .file_name()
        .ok_or_else(|| Error::InvalidArgument(format!("{}: not a file name", path.display())))?;
    let temporary = format!(".{}.{}.tmp", name.to_string_lossy(), std::process::id());
    Ok(path.with_file_name(temporary))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_directories_and_fifos_are_refused_by_type() {
        for path in ["/dev/zero", "/dev/null", "/"] {
            let e = read(Path::new(path), FileKind::Texture)
                .expect_err(path)
                .to_string();
            assert!(e.contains("not a regular file"), "{e}");
        }
    }

    #[test]
    fn files_over_the_cap_are_refused_before_reading() {
        let dir = tempfile::tempdir().expect("dir");
        let path = dir.path().join("f.bin");
        std::fs::write(&path, [7u8; 100]).expect("write");
        assert_eq!(
            read_capped(&path, FileKind::Buffer, 100)
                .map(|b| b.len())
                .ok(),
            Some(100)
        );
        let e = read_capped(&path, FileKind::Buffer, 99)
            .expect_err("over the cap")
            .to_string();
        assert!(e.contains("100 bytes is larger than the 99 bytes"), "{e}");
    }

    #[test]
    fn an_atomic_write_replaces_the_file_and_leaves_nothing_else() {
        let dir = tempfile::tempdir().expect("dir");
        let path = dir.path().join("sub/out.txt");
        write_atomic(&path, b"first").expect("write");
        write_atomic(&path, b"second").expect("rewrite");
        assert_eq!(std::fs::read(&path).ok().as_deref(), Some(&b"second"[..]));
        let names: Vec<_> = std::fs::read_dir(dir.path().join("sub"))
            .expect("dir")
            .filter_map(|e| e.ok())
            .map(|e| e.file_name())
            .collect();
        assert_eq!(names.len(), 1, "{names:?}");
    }

    #[test]
    fn a_failed_write_keeps_the_old_file() {
        let dir = tempfile::tempdir().expect("dir");
        // The target's folder is a file: nothing can be created in it.
        let blocker = dir.path().join("blocker");
        std::fs::write(&blocker, b"old").expect("write");
        assert!(write_atomic(&blocker.join("x.png"), b"new").is_err());
        // A target that is a directory cannot be replaced by a file.
        let target = dir.path().join("target");
        std::fs::create_dir(&target).expect("dir");
        assert!(write_atomic(&target, b"new").is_err());
        assert!(target.is_dir());
        let left = std::fs::read_dir(dir.path()).expect("dir").count();
        assert_eq!(left, 2, "a temporary file was left behind");
    }
}
