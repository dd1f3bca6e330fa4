//! Splitting work across processes and machines: which shard this process is (`--shard
//! I/N`, or the array index a batch engine puts in the environment), and the sidecar a
//! shard writes beside its part so that `lumen merge` can check that parts belong
//! together and are whole.

use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The sidecar's schema name.
pub const SIDECAR_SCHEMA: &str = "lumen-shard/1";

/// This process's shard, and where its index came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShardSpec {
    /// 0-based shard index.
    pub index: u32,
    /// Number of shards.
    pub count: u32,
    /// `--shard`, or the environment variable the index was read from.
    pub source: &'static str,
}

/// Parses `I/N` (0 ≤ I < N ≤ 1 000 000).
pub fn parse_shard(s: &str) -> std::result::Result<(u32, u32), String> {
    let (i, n) = s
        .split_once('/')
        .ok_or(format!("'{s}' is not I/N (e.g. 0/4)"))?;
    let number = |t: &str| {
        t.trim()
            .parse::<u32>()
            .map_err(|_| format!("'{t}' in '{s}' is not a whole number"))
    };
    let (i, n) = (number(i)?, number(n)?);
    if n == 0 || n > 1_000_000 {
        return Err(format!("{n} shards: the count must be 1..=1000000"));
    }
    if i >= n {
        return Err(format!(
            "shard {i} of {n}: the index counts from 0 to {}",
            n - 1
        ));
    }
    Ok((i, n))
}

/// The environment variables a batch engine sets for an array job's task.
struct Engine {
    /// The task's index.
    index: &'static str,
    /// The number of tasks; `None` when it comes from `--shards`.
    count: Option<&'static str>,
    /// The first index, where it may not be 0.
    min: Option<&'static str>,
    /// The step between indices, where it may not be 1 (`--array=0-15:4`).
    step: Option<&'static str>,
}

/// The batch engines, in the order they are tried.
const ENGINES: [Engine; 4] = [
    Engine {
        index: "SLURM_ARRAY_TASK_ID",
        count: Some("SLURM_ARRAY_TASK_COUNT"),
        min: Some("SLURM_ARRAY_TASK_MIN"),
        step: Some("SLURM_ARRAY_TASK_STEP"),
    },
    Engine {
        index: "JOB_COMPLETION_INDEX",
        count: None,
        min: None,
        step: None,
    },
    Engine {
        index: "AWS_BATCH_JOB_ARRAY_INDEX",
        count: Some("AWS_BATCH_JOB_ARRAY_SIZE"),
        min: None,
        step: None,
    },
    Engine {
        index: "HQ_TASK_ID",
        count: None,
        min: None,
        step: None,
    },
];

/// This process's shard: `--shard` (`flag`) wins; otherwise the first batch engine's
/// index found through `env` (Slurm's task ID less its minimum, over its step, with its
/// task count; an ID between two steps, as an irregular list like `--array=1,2,5` gives,
/// is an error;
/// Kubernetes' `JOB_COMPLETION_INDEX` and HyperQueue's `HQ_TASK_ID` with `--shards`
/// for the count; AWS Batch's array index and size). `None`: not sharded. An index that
/// is not a number, no count, or an index past the count is an error naming the variable.
pub fn resolve(
    flag: Option<(u32, u32)>,
    shards: Option<u32>,
    env: &dyn Fn(&str) -> Option<String>,
) -> Result<Option<ShardSpec>> {
    if let Some((index, count)) = flag {
        return Ok(Some(ShardSpec {
            index,
            count,
            source: "--shard",
        }));
    }
    for engine in ENGINES {
        let variable = engine.index;
        let Some(raw) = env(variable) else {
            continue;
        };
        let number = |name: &str, v: &str| -> Result<u32> {
            v.trim()
                .parse::<u32>()
                .with_context(|| format!("{name}={v:?} is not a whole number"))
        };
        let mut index = number(variable, &raw)?;
        if let Some((name, v)) = engine.min.and_then(|m| env(m).map(|v| (m, v))) {
            let min = number(name, &v)?;
            index = index
                .checked_sub(min)
                .with_context(|| format!("{variable}={raw} is below {name}={min}"))?;
        }
        if let Some((name, v)) = engine.step.and_then(|m| env(m).map(|v| (m, v))) {
            let step = number(name, &v)?.max(1);
            if index % step != 0 {
                bail!(
                    "{variable}={raw} is not on a step of {name}={step} from the first index: give --shard I/N"
                );
            }
            index /= step;
        }
        let count = match (engine.count.and_then(env), shards) {
            (_, Some(n)) => n,
            (Some(c), None) => number(engine.count.unwrap_or(variable), &c)?,
            (None, None) => bail!(
                "{variable}={raw} names this task, but not how many there are: give --shards N"
            ),
        };
        if count == 0 || index >= count {
            bail!("{variable}={raw} is shard {index}, but there are {count} shards");
        }
        return Ok(Some(ShardSpec {
            index,
            count,
            source: variable,
        }));
    }
    Ok(None)
}

/// The process environment, as [`resolve`] reads it.
pub fn process_env(name: &str) -> Option<String> {
    std::env::var(name).ok().filter(|v| !v.is_empty())
}

/// The 64-bit FNV-1a hash of `bytes` (Fowler, Noll, Vo): stable across machines and
/// builds, so parts hashed on different nodes compare. A checksum against truncation and
/// corruption, not a cryptographic hash.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The version a part is stamped with: the package version and the git revision the
/// binary was built from, so that parts of two builds of one version do not merge.
pub const LUMEN_VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (",
    env!("LUMEN_GIT_REVISION"),
    ")"
);

/// What a shard writes beside its part (`<part>.json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sidecar {
    /// [`SIDECAR_SCHEMA`].
    pub schema: String,
    /// What the part holds: `reference` (an EXR), `tradeoff` (JSON rows) or `sequence`
    /// (a manifest of frames).
    pub kind: String,
    /// The `lumen` version that wrote it.
    pub lumen_version: String,
    /// The scene's name (a built-in scene, or the file's stem).
    pub scene: String,
    /// What was rendered and how (scene options, size, samples, seed, …), as words.
    pub settings: String,
    /// FNV-1a of `settings` and the scene file's bytes, in hex: parts merge only with
    /// the same hash.
    pub scene_hash: String,
    /// The shard index (from 0).
    pub index: u32,
    /// The number of shards.
    pub count: u32,
    /// Where the index came from (`--shard` or an environment variable).
    pub index_source: String,
    /// The share of the work the shard did, `[first, end)`: sample indices per pixel (a
    /// reference) or rows (a tradeoff).
    pub share: [u32; 2],
    /// The random seed.
    pub seed: u64,
    /// Wall time the shard took (s).
    pub seconds: f64,
    /// The part's file name (beside the sidecar).
    pub part: String,
    /// FNV-1a of the part's bytes, in hex.
    pub part_hash: String,
}

/// The hash parts must share to merge: FNV-1a of `settings`, of the bytes of the scene's
/// file (`None` or a folder for a built-in scene), and of a `.gltf` file's buffers and
/// images beside it (`lumen::assets::gltf::external_files`), so that parts rendered from
/// different `.bin` or texture files do not merge; in hex. An unreadable file is an error
/// naming it.
pub fn scene_hash(settings: &str, scene_file: Option<&Path>) -> Result<String> {
    let read = |f: &Path| std::fs::read(f).with_context(|| format!("{}", f.display()));
    let mut bytes = settings.as_bytes().to_vec();
    if let Some(f) = scene_file.filter(|f| f.is_file()) {
        let file = read(f)?;
        bytes.extend(fnv1a64(&file).to_le_bytes());
        let base = f.parent().unwrap_or(Path::new("."));
        let external = f
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("gltf"))
            .then(|| lumen::assets::gltf::external_files(&file, base))
            .flatten()
            .unwrap_or_default();
        for path in external {
            bytes.extend(fnv1a64(&read(&path)?).to_le_bytes());
        }
    } else {
        bytes.extend(fnv1a64(&[]).to_le_bytes());
    }
    Ok(format!("{:016x}", fnv1a64(&bytes)))
}

/// What a shard finds of its part before it starts.
#[derive(Debug)]
pub enum PartState {
    /// Whole and made with the same settings, scene and shard count: the shard is done.
    Done(Box<Sidecar>),
    /// Whole but made with other settings: made again.
    OtherSettings,
    /// Missing, or broken (logged): made again.
    Absent,
}

/// What is left of `part` from an earlier run, checked against `settings`, `scene_hash`
/// and `count` shards. A part that exists but is broken or other is logged, to be made
/// again.
pub fn part_state(part: &Path, settings: &str, scene_hash: &str, count: u32) -> PartState {
    match check_part(part) {
        Ok(s)
            if s.settings == settings
                && s.scene_hash == scene_hash
                && s.count == count
                && s.lumen_version == LUMEN_VERSION =>
        {
            PartState::Done(Box::new(s))
        }
        Ok(_) => {
            log::warn!("{}: made with other settings: made again", part.display());
            PartState::OtherSettings
        }
        Err(e) => {
            if part.exists() {
                log::warn!("{e:#}: made again");
            }
            PartState::Absent
        }
    }
}

/// Writes the sidecar of `part` (just written) beside it, with the part's checksum.
#[allow(clippy::too_many_arguments)]
pub fn write_sidecar(
    part: &Path,
    kind: &str,
    scene: String,
    settings: String,
    scene_hash: String,
    spec: ShardSpec,
    share: std::ops::Range<u32>,
    seed: u64,
    seconds: f64,
) -> Result<Sidecar> {
    let sidecar = Sidecar {
        schema: SIDECAR_SCHEMA.into(),
        kind: kind.into(),
        lumen_version: LUMEN_VERSION.into(),
        scene,
        settings,
        scene_hash,
        index: spec.index,
        count: spec.count,
        index_source: spec.source.into(),
        share: [share.start, share.end],
        seed,
        seconds,
        part: part
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
        part_hash: format!(
            "{:016x}",
            fnv1a64(&std::fs::read(part).with_context(|| format!("{}", part.display()))?)
        ),
    };
    lumen::files::write_atomic(
        &sidecar_path(part),
        serde_json::to_string_pretty(&sidecar)?.as_bytes(),
    )?;
    Ok(sidecar)
}

/// Where shard `index` of `count` writes its part for the output `out`:
/// `<stem>.shard-<index>-of-<count>.<ext>` beside it.
pub fn part_path(out: &Path, index: u32, count: u32) -> PathBuf {
    let stem = out
        .file_stem()
        .map_or_else(|| "part".into(), |s| s.to_string_lossy().into_owned());
    let ext = out
        .extension()
        .map_or_else(|| "exr".into(), |e| e.to_string_lossy().into_owned());
    out.with_file_name(format!("{stem}.shard-{index}-of-{count}.{ext}"))
}

/// The sidecar path of a part.
pub fn sidecar_path(part: &Path) -> PathBuf {
    let mut name = part.as_os_str().to_owned();
    name.push(".json");
    PathBuf::from(name)
}

/// Reads the sidecar of `part` and checks the part against it: an error naming the part
/// when the sidecar is missing or unreadable, or when the part's bytes are not the ones
/// the sidecar hashed (truncated or corrupt).
pub fn check_part(part: &Path) -> Result<Sidecar> {
    let side = sidecar_path(part);
    let text = std::fs::read_to_string(&side)
        .with_context(|| format!("{}: no readable sidecar {}", part.display(), side.display()))?;
    let sidecar: Sidecar = serde_json::from_str(&text).with_context(|| {
        format!(
            "{}: its sidecar {} is not valid",
            part.display(),
            side.display()
        )
    })?;
    if sidecar.schema != SIDECAR_SCHEMA {
        bail!(
            "{}: sidecar schema '{}', this lumen reads '{SIDECAR_SCHEMA}'",
            part.display(),
            sidecar.schema
        );
    }
    let bytes =
        std::fs::read(part).with_context(|| format!("{}: cannot be read", part.display()))?;
    let hash = format!("{:016x}", fnv1a64(&bytes));
    if hash != sidecar.part_hash {
        bail!(
            "{}: truncated or corrupt ({} bytes, checksum {hash}; its sidecar says {})",
            part.display(),
            bytes.len(),
            sidecar.part_hash
        );
    }
    Ok(sidecar)
}

/// The first item (between `, ` and `; `) where two settings strings differ.
fn first_difference<'a>(a: &'a str, b: &'a str) -> (&'a str, &'a str) {
    let items = |s: &'a str| s.split([';', ',']).map(str::trim);
    items(a)
        .zip(items(b))
        .find(|(x, y)| x != y)
        .unwrap_or((a, b))
}

/// Checks that `parts` (with their sidecars) are every shard of one render: the same
/// version, scene hash and settings, one count, no index twice and none missing. Errors
/// name the part (or the missing indices).
pub fn check_together(parts: &[(PathBuf, Sidecar)]) -> Result<()> {
    let Some((first_path, first)) = parts.first() else {
        bail!("no parts to merge");
    };
    let mut seen: Vec<Option<&Path>> = vec![None; first.count as usize];
    for (path, s) in parts {
        let differs = if s.kind != first.kind {
            Some(format!(
                "a {} part, {} a {} part",
                s.kind,
                first_path.display(),
                first.kind
            ))
        } else if s.lumen_version != first.lumen_version {
            Some(format!(
                "written by lumen {} but {} by {}",
                s.lumen_version,
                first_path.display(),
                first.lumen_version
            ))
        } else if s.scene != first.scene {
            Some(format!(
                "a part of scene '{}', {} of '{}'",
                s.scene,
                first_path.display(),
                first.scene
            ))
        } else if s.scene_hash != first.scene_hash && s.settings == first.settings {
            Some(format!(
                "scene '{}' from another file than {} (hash {} against {})",
                s.scene,
                first_path.display(),
                s.scene_hash,
                first.scene_hash
            ))
        } else if s.settings != first.settings {
            let (mine, theirs) = first_difference(&s.settings, &first.settings);
            Some(format!(
                "other settings than {} ({mine} against {theirs})",
                first_path.display(),
            ))
        } else if s.count != first.count {
            Some(format!(
                "one of {} shards, {} one of {}",
                s.count,
                first_path.display(),
                first.count
            ))
        } else {
            None
        };
        if let Some(why) = differs {
            bail!("{}: {why}", path.display());
        }
        match seen.get_mut(s.index as usize) {
            Some(Some(other)) => bail!(
                "{}: shard {}/{} twice (also {})",
                path.display(),
                s.index,
                s.count,
                other.display()
            ),
            Some(slot) => *slot = Some(path),
            None => bail!("{}: shard {} of {}", path.display(), s.index, s.count),
        }
    }
    let missing: Vec<String> = seen
        .iter()
        .enumerate()
        .filter(|(_, p)| p.is_none())
        .map(|(i, _)| i.to_string())
        .collect();
    if !missing.is_empty() {
        bail!(
            "missing shard(s) {} of {} (have {})",
            missing.join(", "),
            first.count,
            parts.len()
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_parse_and_refuse_bad_forms() {
        assert_eq!(parse_shard("0/4"), Ok((0, 4)));
        assert_eq!(parse_shard("3/4"), Ok((3, 4)));
        assert!(parse_shard("4/4").unwrap_err().contains("from 0 to 3"));
        assert!(parse_shard("1/0").unwrap_err().contains("1..=1000000"));
        assert!(parse_shard("1-4").unwrap_err().contains("I/N"));
        assert!(parse_shard("a/4").unwrap_err().contains("'a'"));
    }

    #[test]
    fn the_index_comes_from_each_engine() {
        let env = |pairs: &'static [(&'static str, &'static str)]| {
            move |name: &str| {
                pairs
                    .iter()
                    .find(|(k, _)| *k == name)
                    .map(|(_, v)| v.to_string())
            }
        };
        let slurm = env(&[
            ("SLURM_ARRAY_TASK_ID", "6"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
            ("SLURM_ARRAY_TASK_MIN", "4"),
        ]);
        let got = resolve(None, None, &slurm).unwrap().unwrap();
        assert_eq!(
            (got.index, got.count, got.source),
            (2, 4, "SLURM_ARRAY_TASK_ID")
        );
        // `--array=0-15:4`: IDs 0, 4, 8, 12 are shards 0..4; an ID between steps (an
        // irregular list) is refused.
        let stepped = env(&[
            ("SLURM_ARRAY_TASK_ID", "8"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_STEP", "4"),
        ]);
        assert_eq!(resolve(None, None, &stepped).unwrap().unwrap().index, 2);
        let listed = env(&[
            ("SLURM_ARRAY_TASK_ID", "5"),
            ("SLURM_ARRAY_TASK_COUNT", "3"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
            ("SLURM_ARRAY_TASK_STEP", "2"),
        ]);
        assert_eq!(resolve(None, None, &listed).unwrap().unwrap().index, 2);
        let between = env(&[
            ("SLURM_ARRAY_TASK_ID", "2"),
            ("SLURM_ARRAY_TASK_COUNT", "3"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
            ("SLURM_ARRAY_TASK_STEP", "2"),
        ]);
        let e = resolve(None, None, &between).unwrap_err().to_string();
        assert!(e.contains("SLURM_ARRAY_TASK_STEP=2"), "{e}");
        let k8s = env(&[("JOB_COMPLETION_INDEX", "3")]);
        let got = resolve(None, Some(5), &k8s).unwrap().unwrap();
        assert_eq!(
            (got.index, got.count, got.source),
            (3, 5, "JOB_COMPLETION_INDEX")
        );
        assert!(
            resolve(None, None, &k8s)
                .unwrap_err()
                .to_string()
                .contains("--shards N")
        );
        let aws = env(&[
            ("AWS_BATCH_JOB_ARRAY_INDEX", "1"),
            ("AWS_BATCH_JOB_ARRAY_SIZE", "2"),
        ]);
        let got = resolve(None, None, &aws).unwrap().unwrap();
        assert_eq!((got.index, got.count), (1, 2));
        let hq = env(&[("HQ_TASK_ID", "7")]);
        let got = resolve(None, Some(8), &hq).unwrap().unwrap();
        assert_eq!((got.index, got.source), (7, "HQ_TASK_ID"));
        assert!(
            resolve(None, Some(4), &hq)
                .unwrap_err()
                .to_string()
                .contains("there are 4")
        );
        // The flag wins over the environment; nothing set is no shard.
        let got = resolve(Some((0, 2)), None, &slurm).unwrap().unwrap();
        assert_eq!(got.source, "--shard");
        assert_eq!(resolve(None, None, &env(&[])).unwrap(), None);
        let bad = env(&[("HQ_TASK_ID", "x")]);
        assert!(
            resolve(None, Some(2), &bad)
                .unwrap_err()
                .to_string()
                .contains("HQ_TASK_ID")
        );
    }

    #[test]
    fn a_gltf_files_buffers_and_images_are_in_the_scene_hash() {
        let dir = tempfile::tempdir().expect("temp dir");
        let gltf = dir.path().join("scene.gltf");
        std::fs::write(
            &gltf,
            r#"{"asset": {"version": "2.0"},
                "buffers": [{"uri": "mesh.bin", "byteLength": 4},
                            {"uri": "data:application/octet-stream;base64,AAAAAA==", "byteLength": 4}],
                "images": [{"uri": "leaf%20colour.png"}]}"#,
        )
        .expect("gltf");
        let bin = dir.path().join("mesh.bin");
        let png = dir.path().join("leaf colour.png");
        std::fs::write(&bin, [1, 2, 3, 4]).expect("bin");
        std::fs::write(&png, b"first").expect("png");
        let hash = || scene_hash("settings", Some(&gltf));
        let first = hash().expect("hash");
        assert_eq!(hash().expect("hash"), first, "the same files hash the same");
        std::fs::write(&bin, [1, 2, 3, 5]).expect("bin");
        let other_bin = hash().expect("hash");
        assert_ne!(other_bin, first, "another buffer");
        std::fs::write(&png, b"second").expect("png");
        assert_ne!(hash().expect("hash"), other_bin, "another image");
        std::fs::remove_file(&bin).expect("remove");
        let e = hash().unwrap_err().to_string();
        assert!(e.contains("mesh.bin"), "{e}");
        // A built-in scene hashes its settings alone.
        assert_ne!(
            scene_hash("settings", None).expect("hash"),
            scene_hash("other", None).expect("hash")
        );
    }

    #[test]
    fn fnv_matches_its_published_vectors() {
        assert_eq!(fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a64(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a64(b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn the_first_differing_setting_is_named() {
        assert_eq!(
            first_difference("a 1; 8 spp; seed 4", "a 1; 8 spp; seed 3"),
            ("seed 4", "seed 3")
        );
    }

    #[test]
    fn part_names_carry_the_shard() {
        let p = part_path(Path::new("out/ref.exr"), 2, 4);
        assert_eq!(p, Path::new("out/ref.shard-2-of-4.exr"));
        assert_eq!(sidecar_path(&p), Path::new("out/ref.shard-2-of-4.exr.json"));
    }
}
