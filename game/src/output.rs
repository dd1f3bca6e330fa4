//! Output: standard output without panicking when the reader has gone away
//! (`lumen render | head -1`: `println!` panics on a broken pipe), and text files written
//! atomically.

use anyhow::{Context, Result};
use std::io::Write;
use std::path::Path;

/// Writes `text` to stdout; a closed pipe or other write error is ignored.
pub fn print(text: &str) {
    let mut out = std::io::stdout().lock();
    let _ = out.write_all(text.as_bytes()).and_then(|_| out.flush());
}

/// Writes `text` to `path` atomically (its folder created; a failed write leaves what
/// `path` held); errors name the path.
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    lumen::files::write_atomic(path, text.as_bytes())
        .with_context(|| format!("cannot write {}", path.display()))
}
