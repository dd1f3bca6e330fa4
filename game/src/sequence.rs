//! A sharded sequence's part: the manifest of the frames one shard rendered (each frame's
//! file and checksum), checked frame by frame and joined by `lumen merge` into the
//! manifest of the whole sequence.

use crate::shard::fnv1a64;
use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The manifest's schema name.
pub const MANIFEST_SCHEMA: &str = "lumen-sequence/1";

/// The frames of a sequence (a shard's share, or the whole), beside which they lie.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// [`MANIFEST_SCHEMA`].
    pub schema: String,
    /// The `--out` pattern's file name; its `#`s stand for the frame number.
    pub pattern: String,
    /// The whole sequence's first and last frame (both included).
    pub frames_of: [u32; 2],
    /// Frames per second: frame k is posed at k / fps seconds.
    pub fps: f32,
    /// The frames, in order.
    pub frames: Vec<FrameEntry>,
}

/// One frame of a [`Manifest`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrameEntry {
    /// The frame number.
    pub frame: u32,
    /// The image's file name, in the manifest's folder.
    pub file: String,
    /// FNV-1a of the image's bytes, in hex.
    pub hash: String,
}

impl FrameEntry {
    /// The entry of frame `frame`, written to `path`: its name and checksum.
    pub fn of(path: &Path, frame: u32) -> Result<Self> {
        let bytes = std::fs::read(path).with_context(|| format!("{}", path.display()))?;
        Ok(Self {
            frame,
            file: path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default(),
            hash: format!("{:016x}", fnv1a64(&bytes)),
        })
    }
}

/// Where shard `index` of `count` of the sequence `pattern` writes its manifest: beside
/// the frames, named for the pattern without its `#`s (`seq/frame-####.png`, shard 1 of
/// 3 → `seq/frame.shard-1-of-3.json`; `frames` when nothing else is left of the name).
pub fn manifest_path(pattern: &Path, index: u32, count: u32) -> PathBuf {
    let stem = pattern
        .file_stem()
        .map(|s| s.to_string_lossy().replace('#', ""))
        .unwrap_or_default();
    let stem = stem.trim_matches(|c: char| "-_. ".contains(c));
    let stem = if stem.is_empty() { "frames" } else { stem };
    pattern.with_file_name(format!("{stem}.shard-{index}-of-{count}.json"))
}

/// Reads the manifest at `path`.
pub fn read(path: &Path) -> Result<Manifest> {
    let text = std::fs::read_to_string(path).with_context(|| format!("{}", path.display()))?;
    let manifest: Manifest = serde_json::from_str(&text)
        .with_context(|| format!("{}: not a sequence manifest", path.display()))?;
    if manifest.schema != MANIFEST_SCHEMA {
        bail!(
            "{}: manifest schema '{}', this lumen reads '{MANIFEST_SCHEMA}'",
            path.display(),
            manifest.schema
        );
    }
    Ok(manifest)
}

/// Checks that every frame the manifest at `path` lists lies beside it, whole: an error
/// names the first frame that is missing, truncated or corrupt.
pub fn check_frames(path: &Path, manifest: &Manifest) -> Result<()> {
    let folder = path.parent().unwrap_or(Path::new("."));
    for entry in &manifest.frames {
        let file = folder.join(&entry.file);
        let bytes = std::fs::read(&file).with_context(|| {
            format!(
                "frame {} ({}) is missing: render its shard again",
                entry.frame,
                file.display()
            )
        })?;
        let hash = format!("{:016x}", fnv1a64(&bytes));
        if hash != entry.hash {
            bail!(
                "frame {} ({}) is truncated or corrupt ({} bytes, checksum {hash}; {} says {}): render its shard again",
                entry.frame,
                file.display(),
                bytes.len(),
                path.display(),
                entry.hash
            );
        }
    }
    Ok(())
}

/// Joins the manifests of every shard of one sequence into the whole's: the frames in
/// order, each once, exactly `frames_of`. An error names the manifest at fault or the
/// frames missing.
pub fn join(parts: &[(PathBuf, Manifest)]) -> Result<Manifest> {
    let Some((first_path, first)) = parts.first() else {
        bail!("no sequence manifests to merge");
    };
    let [a, b] = first.frames_of;
    let mut seen: Vec<Option<FrameEntry>> = vec![None; (b.saturating_sub(a) + 1) as usize];
    for (path, m) in parts {
        if m.pattern != first.pattern || m.frames_of != first.frames_of || m.fps != first.fps {
            bail!(
                "{}: frames {:?} of {} at {} fps, {} frames {:?} of {} at {} fps",
                path.display(),
                m.frames_of,
                m.pattern,
                m.fps,
                first_path.display(),
                first.frames_of,
                first.pattern,
                first.fps
            );
        }
        for entry in &m.frames {
            let slot = entry
                .frame
                .checked_sub(a)
                .and_then(|i| seen.get_mut(i as usize))
                .with_context(|| {
                    format!(
                        "{}: frame {} is outside {a}..{b}",
                        path.display(),
                        entry.frame
                    )
                })?;
            if slot.is_some() {
                bail!("{}: frame {} twice", path.display(), entry.frame);
            }
            *slot = Some(entry.clone());
        }
    }
    let missing: Vec<String> = seen
        .iter()
        .enumerate()
        .filter(|(_, e)| e.is_none())
        .map(|(i, _)| (a + i as u32).to_string())
        .collect();
    if !missing.is_empty() {
        bail!(
            "frame(s) {} of {a}..{b} are in no manifest",
            missing.join(", ")
        );
    }
    Ok(Manifest {
        frames: seen.into_iter().flatten().collect(),
        ..first.clone()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn manifest(frames: &[u32]) -> Manifest {
        Manifest {
            schema: MANIFEST_SCHEMA.into(),
            pattern: "f-##.png".into(),
            frames_of: [2, 5],
            fps: 10.0,
            frames: frames
                .iter()
                .map(|&frame| FrameEntry {
                    frame,
                    file: format!("f-{frame:02}.png"),
                    hash: "0".into(),
                })
                .collect(),
        }
    }

    #[test]
    fn manifests_are_named_for_the_pattern() {
        let p = manifest_path(Path::new("seq/frame-####.png"), 1, 3);
        assert_eq!(p, Path::new("seq/frame.shard-1-of-3.json"));
        let p = manifest_path(Path::new("####.exr"), 0, 2);
        assert_eq!(p, Path::new("frames.shard-0-of-2.json"));
    }

    #[test]
    fn shares_join_in_order_and_gaps_and_repeats_are_named() {
        let a = (PathBuf::from("a.json"), manifest(&[4, 5]));
        let b = (PathBuf::from("b.json"), manifest(&[2, 3]));
        let whole = join(&[a.clone(), b.clone()]).unwrap();
        let order: Vec<u32> = whole.frames.iter().map(|e| e.frame).collect();
        assert_eq!(order, [2, 3, 4, 5]);
        let gap = (PathBuf::from("b.json"), manifest(&[2]));
        let e = join(&[a.clone(), gap]).unwrap_err().to_string();
        assert!(e.contains("frame(s) 3 of 2..5"), "{e}");
        let twice = (PathBuf::from("c.json"), manifest(&[3, 4]));
        let e = join(&[a.clone(), b, twice]).unwrap_err().to_string();
        assert!(e.contains("c.json: frame 3 twice"), "{e}");
        let outside = (PathBuf::from("d.json"), manifest(&[9]));
        let e = join(&[a, outside]).unwrap_err().to_string();
        assert!(e.contains("d.json: frame 9 is outside 2..5"), "{e}");
    }
}
