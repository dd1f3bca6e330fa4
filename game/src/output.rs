//! Writing to standard output without panicking when the reader has gone away
//! (`lumen render | head -1`): `println!` panics on a broken pipe.

use std::io::Write;

/// Writes `text` to stdout; a closed pipe or other write error is ignored.
pub fn print(text: &str) {
    let mut out = std::io::stdout().lock();
    let _ = out.write_all(text.as_bytes()).and_then(|_| out.flush());
}
