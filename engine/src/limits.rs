//! Resource limits: how much memory Lumen lets one file or one frame take, so that a
//! hostile or careless input fails with a clear error instead of exhausting the machine.
//!
//! - **The memory budget** (bytes) is `LUMEN_MEMORY_BUDGET` when set (`4GiB`, `512MiB`,
//!   `1500000000`), else half of the host's available memory (`MemAvailable` in
//!   `/proc/meminfo`), else [`FALLBACK_BUDGET`]. A CPU adapter (lavapipe, llvmpipe)
//!   allocates its textures from the same memory, so the frame check uses it too.
//! - **A read cap per kind of file** ([`FileKind::cap`]): the smaller of the kind's own
//!   ceiling and the budget. A file larger than its cap is refused from its metadata,
//!   before any byte is read.

use crate::error::{Error, Result};

/// The environment variable that sets the memory budget.
pub const BUDGET_VAR: &str = "LUMEN_MEMORY_BUDGET";

/// The budget where neither [`BUDGET_VAR`] nor `/proc/meminfo` gives one: 4 GiB.
pub const FALLBACK_BUDGET: u64 = 4 << 30;

const MIB: u64 = 1 << 20;

/// What a file is read as. Each kind has a ceiling that no sane file of it reaches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// A glTF JSON document or a GLB container (JSON and binary chunk): 2 GiB.
    Model,
    /// A glTF buffer file: 2 GiB.
    Buffer,
    /// An encoded texture (PNG, JPEG): 512 MiB.
    Texture,
    /// An encoded environment image (OpenEXR, Radiance HDR): 2 GiB.
    Environment,
    /// A text file (a shader, a JSON report): 64 MiB.
    Text,
}

impl FileKind {
    /// Name used in messages.
    pub fn name(self) -> &'static str {
        match self {
            FileKind::Model => "a glTF file",
            FileKind::Buffer => "a glTF buffer",
            FileKind::Texture => "a texture",
            FileKind::Environment => "an environment image",
            FileKind::Text => "a text file",
        }
    }

    /// The kind's own ceiling in bytes.
    pub fn ceiling(self) -> u64 {
        match self {
            FileKind::Model | FileKind::Buffer | FileKind::Environment => 2048 * MIB,
            FileKind::Texture => 512 * MIB,
            FileKind::Text => 64 * MIB,
        }
    }

    /// The largest file of this kind read (bytes): the ceiling, or the memory budget if
    /// that is smaller.
    pub fn cap(self) -> u64 {
        self.ceiling().min(memory_budget().bytes)
    }
}

/// The memory budget and where it came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryBudget {
    /// Bytes.
    pub bytes: u64,
    /// Where the value came from, for messages.
    pub source: BudgetSource,
}

/// Where a [`MemoryBudget`] came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BudgetSource {
    /// [`BUDGET_VAR`].
    Variable,
    /// Half of the host's available memory.
    HostMemory,
    /// [`FALLBACK_BUDGET`].
    Fallback,
}

impl std::fmt::Display for MemoryBudget {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let from = match self.source {
            BudgetSource::Variable => format!("from {BUDGET_VAR}"),
            BudgetSource::HostMemory => format!("half the available memory; set {BUDGET_VAR}"),
            BudgetSource::Fallback => format!("the default; set {BUDGET_VAR}"),
        };
        write!(f, "{} ({from})", bytes_text(self.bytes))
    }
}

/// The memory budget: [`BUDGET_VAR`], else half of `MemAvailable`, else the fallback. An
/// unparsable [`BUDGET_VAR`] is ignored with a warning.
pub fn memory_budget() -> MemoryBudget {
    if let Ok(text) = std::env::var(BUDGET_VAR) {
        match parse_bytes(&text) {
            Ok(bytes) => {
                return MemoryBudget {
                    bytes,
                    source: BudgetSource::Variable,
                };
            }
            Err(e) => log::warn!("{BUDGET_VAR}={text}: {e}; ignored"),
        }
    }
    match std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|m| mem_available(&m))
    {
        Some(available) => MemoryBudget {
            bytes: available / 2,
            source: BudgetSource::HostMemory,
        },
        None => MemoryBudget {
            bytes: FALLBACK_BUDGET,
            source: BudgetSource::Fallback,
        },
    }
}

/// `MemAvailable` of a `/proc/meminfo` text, in bytes.
fn mem_available(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// Parses a byte count: a whole number with an optional unit `K`, `M`, `G`, `T` (powers of
/// 1024, with or without `iB`/`B`). Zero is refused.
pub fn parse_bytes(text: &str) -> Result<u64> {
    let t = text.trim();
    let split = t.find(|c: char| !c.is_ascii_digit()).unwrap_or(t.len());
    let (number, unit) = t.split_at(split);
    let bad =
        || Error::InvalidArgument(format!("'{text}' is not a byte count (e.g. 4GiB, 512MiB)"));
    let n: u64 = number.parse().map_err(|_| bad())?;
    let shift = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 0,
        "k" | "kb" | "kib" => 10,
        "m" | "mb" | "mib" => 20,
        "g" | "gb" | "gib" => 30,
        "t" | "tb" | "tib" => 40,
        _ => return Err(bad()),
    };
    let bytes = n.checked_mul(1 << shift).ok_or_else(bad)?;
    if bytes == 0 {
        return Err(Error::InvalidArgument(format!(
            "'{text}': the budget must be positive"
        )));
    }
    Ok(bytes)
}

/// `bytes` for a message: `1.5 GiB`, `300 MiB`, `12 KiB`, `17 bytes`.
pub fn bytes_text(bytes: u64) -> String {
    const UNITS: [(&str, u64); 3] = [("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)];
    for (unit, size) in UNITS {
        if bytes >= size {
            return format!("{:.1} {unit}", bytes as f64 / size as f64);
        }
    }
    format!("{bytes} bytes")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_counts_parse_with_binary_units() {
        assert_eq!(parse_bytes("1500").ok(), Some(1500));
        assert_eq!(parse_bytes("4GiB").ok(), Some(4 << 30));
        assert_eq!(parse_bytes("512 MiB").ok(), Some(512 << 20));
        assert_eq!(parse_bytes("2k").ok(), Some(2048));
        for bad in ["", "GiB", "-1G", "1.5G", "3 parsecs", "0", "99999999999T"] {
            assert!(parse_bytes(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn available_memory_is_read_from_meminfo() {
        let text = "MemTotal:       24000000 kB\nMemAvailable:   1000 kB\n";
        assert_eq!(mem_available(text), Some(1_024_000));
        assert_eq!(mem_available("MemTotal: 5 kB\n"), None);
    }

    #[test]
    fn caps_never_exceed_the_kind_ceiling() {
        for kind in [
            FileKind::Model,
            FileKind::Buffer,
            FileKind::Texture,
            FileKind::Environment,
            FileKind::Text,
        ] {
            assert!(kind.cap() <= kind.ceiling());
            assert!(kind.cap() > 0);
        }
        assert_eq!(bytes_text(3 << 29), "1.5 GiB");
        assert_eq!(bytes_text(17), "17 bytes");
    }
}
