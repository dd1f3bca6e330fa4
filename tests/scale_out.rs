//! Scale-out: a reference split into shards and merged equals the single-process render;
//! parts that do not belong together are refused by name; a shard whose part exists is
//! skipped and a truncated part is found; the shard index comes from a batch engine's
//! environment; a sequence split three ways holds the frames of the whole one.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A small, quick reference: 48×32, 8 paths per pixel, 2 bounces.
const REFERENCE: [&str; 9] = [
    "reference",
    "spheres",
    "--size",
    "48x32",
    "--spp",
    "8",
    "--max-bounces",
    "2",
    "--seed=3",
];

fn lumen(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_lumen"));
    command.args(args).current_dir(dir);
    for var in [
        "SLURM_ARRAY_TASK_ID",
        "SLURM_ARRAY_TASK_COUNT",
        "SLURM_ARRAY_TASK_MIN",
        "SLURM_ARRAY_TASK_STEP",
        "JOB_COMPLETION_INDEX",
        "AWS_BATCH_JOB_ARRAY_INDEX",
        "AWS_BATCH_JOB_ARRAY_SIZE",
        "HQ_TASK_ID",
    ] {
        command.env_remove(var);
    }
    command.envs(env.iter().copied());
    command.output().expect("lumen runs")
}

fn ok(out: &Output) -> String {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn reference(dir: &Path, extra: &[&str], env: &[(&str, &str)]) -> Output {
    let args: Vec<&str> = REFERENCE
        .iter()
        .copied()
        .chain(extra.iter().copied())
        .collect();
    lumen(dir, &args, env)
}

fn part(dir: &Path, i: u32) -> PathBuf {
    dir.join(format!("ref.shard-{i}-of-4.exr"))
}

fn merge(dir: &Path, parts: &[PathBuf]) -> Output {
    let mut args: Vec<String> = vec!["merge".into()];
    args.extend(parts.iter().map(|p| p.to_string_lossy().into_owned()));
    args.extend(["--out".into(), "merged.exr".into()]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    lumen(dir, &args, &[])
}

fn load(path: &Path) -> image::Rgba32FImage {
    lumen::assets::image_io::load_rgba32f(path).expect("an EXR")
}

#[test]
fn four_shards_merge_into_the_single_render_and_bad_parts_are_named() {
    let dir = tempfile::tempdir().expect("temp dir");
    let d = dir.path();
    ok(&reference(d, &["--out", "full.exr"], &[]));
    for i in 0..4 {
        let shard = format!("{i}/4");
        let text = ok(&reference(d, &["--shard", &shard, "--out", "ref.exr"], &[]));
        assert!(
            text.contains(&format!("samples {}..{}", i * 2, i * 2 + 2)),
            "{text}"
        );
    }
    let parts: Vec<PathBuf> = (0..4).map(|i| part(d, i)).collect();
    let text = ok(&merge(d, &parts));
    println!("{text}");
    assert!(text.contains("8.0 effective samples per pixel"), "{text}");
    let (full, merged) = (load(&d.join("full.exr")), load(&d.join("merged.exr")));
    assert_eq!(full.dimensions(), merged.dimensions());
    // Each part stores its mean as f32: the merge differs from the single render by that
    // rounding at most (a few units in the last place).
    let (mut worst, mut identical) = (0.0f32, 0usize);
    for (a, b) in full.pixels().zip(merged.pixels()) {
        for c in 0..3 {
            let e = (a.0[c] - b.0[c]).abs() / a.0[c].abs().max(1e-6);
            worst = worst.max(e);
        }
        identical += usize::from(a == b);
    }
    println!(
        "merge against the single render: worst relative difference {worst:.2e}, {identical} of {} pixels bit-identical",
        full.pixels().len()
    );
    assert!(worst <= 1e-6, "{worst}");

    // Parts that do not belong together: each a one-line error naming the part.
    let refuse = |out: Output, needle: &str| common::assert_clean_failure(&out, needle);
    refuse(merge(d, &parts[..3]), "missing shard(s) 3 of 4");
    refuse(
        merge(
            d,
            &[
                parts[0].clone(),
                parts[1].clone(),
                parts[1].clone(),
                parts[3].clone(),
            ],
        ),
        "twice",
    );
    let other = d.join("other");
    std::fs::create_dir_all(&other).expect("dir");
    let mut seeded: Vec<&str> = REFERENCE[..8].to_vec();
    seeded.extend(["--seed=4", "--shard", "2/4", "--out", "other/ref.exr"]);
    ok(&lumen(d, &seeded, &[]));
    let mut mixed = parts.clone();
    mixed[2] = other.join("ref.shard-2-of-4.exr");
    refuse(merge(d, &mixed), "other settings");
    let args = [
        "reference",
        "furnace",
        "--size",
        "48x32",
        "--spp",
        "8",
        "--max-bounces",
        "2",
        "--seed=3",
        "--shard",
        "2/4",
        "--out",
        "other/ref.exr",
    ];
    ok(&lumen(d, &args, &[]));
    refuse(merge(d, &mixed), "a part of scene 'furnace'");
    // A part stamped by another build (version and git revision) is refused.
    let sidecar = d.join("ref.shard-2-of-4.exr.json");
    let text = std::fs::read_to_string(&sidecar).expect("sidecar");
    let mut stamped: serde_json::Value = serde_json::from_str(&text).expect("json");
    stamped["lumen_version"] = "0.0.0 (another build)".into();
    std::fs::write(&sidecar, stamped.to_string()).expect("sidecar");
    refuse(merge(d, &parts), "written by lumen 0.0.0 (another build)");
    std::fs::write(&sidecar, text).expect("sidecar");

    // Resuming: a part that exists is skipped, left as it was (bytes and time); a
    // truncated one is found, then redone.
    let stamp = |p: &std::path::Path| {
        let meta = std::fs::metadata(p).expect("part");
        (
            std::fs::read(p).expect("part"),
            meta.modified().expect("time"),
        )
    };
    let before = stamp(&parts[1]);
    let again = ok(&reference(d, &["--shard", "1/4", "--out", "ref.exr"], &[]));
    assert!(again.contains("skipped"), "{again}");
    assert!(
        stamp(&parts[1]) == before,
        "a skipped part was written again"
    );
    let bytes = std::fs::read(&parts[1]).expect("part");
    std::fs::write(&parts[1], &bytes[..bytes.len() / 2]).expect("truncate");
    refuse(merge(d, &parts), "truncated or corrupt");
    let redone = ok(&reference(d, &["--shard", "1/4", "--out", "ref.exr"], &[]));
    assert!(!redone.contains("skipped"), "{redone}");
    ok(&merge(d, &parts));
}

#[test]
fn the_shard_index_comes_from_the_batch_engine() {
    let dir = tempfile::tempdir().expect("temp dir");
    let d = dir.path();
    /// The environment, the extra arguments, and the variable the index must come from.
    type Case<'a> = (&'a [(&'a str, &'a str)], &'a [&'a str], &'a str);
    let cases: [Case; 4] = [
        (
            &[
                ("SLURM_ARRAY_TASK_ID", "5"),
                ("SLURM_ARRAY_TASK_COUNT", "4"),
                ("SLURM_ARRAY_TASK_MIN", "3"),
            ],
            &[],
            "SLURM_ARRAY_TASK_ID",
        ),
        (
            &[("JOB_COMPLETION_INDEX", "2")],
            &["--shards", "4"],
            "JOB_COMPLETION_INDEX",
        ),
        (
            &[
                ("AWS_BATCH_JOB_ARRAY_INDEX", "2"),
                ("AWS_BATCH_JOB_ARRAY_SIZE", "4"),
            ],
            &[],
            "AWS_BATCH_JOB_ARRAY_INDEX",
        ),
        (&[("HQ_TASK_ID", "2")], &["--shards", "4"], "HQ_TASK_ID"),
    ];
    for (env, extra, source) in cases {
        let _ = std::fs::remove_file(part(d, 2));
        let args: Vec<&str> = ["--out", "ref.exr"].iter().chain(extra).copied().collect();
        let text = ok(&reference(d, &args, env));
        assert!(
            text.contains(&format!("shard 2/4 (index from {source})")),
            "{text}"
        );
        let sidecar: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(d.join("ref.shard-2-of-4.exr.json")).expect("sidecar"),
        )
        .expect("json");
        assert_eq!(sidecar["index_source"], source);
        assert_eq!(sidecar["index"], 2);
        assert_eq!(sidecar["share"], serde_json::json!([4, 6]));
    }
    // An index without a count is refused, naming the variable.
    let out = reference(d, &["--out", "ref.exr"], &[("HQ_TASK_ID", "1")]);
    common::assert_clean_failure(&out, "HQ_TASK_ID");
}

#[test]
fn a_sequence_split_three_ways_holds_the_frames_of_the_whole() {
    let dir = tempfile::tempdir().expect("temp dir");
    let d = dir.path();
    // Fox.glb (CC BY 4.0, see assets/README.md), posed at k / 10 s of its first clip.
    let fox = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/models/Fox.glb");
    let file = fox.to_str().expect("utf-8");
    let render = |out: &str, shard: Option<&str>| {
        let mut args = vec![
            "render",
            file,
            "--size",
            "32x24",
            "--frames",
            "0..4",
            "--fps",
            "10",
            "--out",
            out,
            // Each posed frame captures its probes again; 2 along the longest side are enough.
            "--gi-density",
            "2",
        ];
        if let Some(s) = shard {
            args.extend(["--shard", s]);
        }
        ok(&lumen(d, &args, &[]))
    };
    render("whole/f-##.png", None);
    for s in ["0/3", "1/3", "2/3"] {
        render("split/f-##.png", Some(s));
    }
    let names = |sub: &str| {
        let mut v: Vec<String> = std::fs::read_dir(d.join(sub))
            .expect("dir")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    assert_eq!(
        names("whole"),
        ["f-00.png", "f-01.png", "f-02.png", "f-03.png", "f-04.png"]
    );
    // Beside its frames, each shard writes the manifest of them, and its sidecar.
    let mut expected = names("whole");
    for i in 0..3 {
        expected.push(format!("f.shard-{i}-of-3.json"));
        expected.push(format!("f.shard-{i}-of-3.json.json"));
    }
    expected.sort();
    assert_eq!(names("split"), expected);
    for n in names("whole") {
        let a = image::open(d.join("whole").join(&n))
            .expect("png")
            .to_rgba8();
        let b = image::open(d.join("split").join(&n))
            .expect("png")
            .to_rgba8();
        assert!(
            a == b,
            "{n} differs between the whole and the split sequence"
        );
    }
    // The merge checks every frame of every shard and lists the whole sequence.
    let manifests: Vec<String> = (0..3)
        .map(|i| format!("split/f.shard-{i}-of-3.json"))
        .collect();
    let merge = |manifests: &[String]| {
        let mut args = vec!["merge"];
        args.extend(manifests.iter().map(String::as_str));
        args.extend(["--out", "split/all.json"]);
        lumen(d, &args, &[])
    };
    let text = ok(&merge(&manifests));
    assert!(text.contains("frames 0..4, 5 frames, each whole"), "{text}");
    let all: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("split/all.json")).expect("json"))
            .expect("json");
    let listed: Vec<u64> = all["frames"]
        .as_array()
        .expect("frames")
        .iter()
        .map(|f| f["frame"].as_u64().expect("frame"))
        .collect();
    assert_eq!(listed, [0, 1, 2, 3, 4]);
    // A shard whose frames are all whole does nothing when run again.
    let text = render("split/f-##.png", Some("1/3"));
    assert!(text.contains("already done"), "{text}");
    // A missing shard and a damaged frame are each named.
    common::assert_clean_failure(&merge(&manifests[..2]), "missing shard(s) 2 of 3");
    let frame = d.join("split/f-02.png");
    let bytes = std::fs::read(&frame).expect("png");
    std::fs::write(&frame, &bytes[..bytes.len() / 2]).expect("truncate");
    common::assert_clean_failure(&merge(&manifests), "frame 2 (");
    // Run again, the shard that holds it renders that frame again, and only that one.
    let text = render("split/f-##.png", Some("1/3"));
    assert!(
        text.contains("frame 1:") && !text.contains("frame 2:") && text.contains("f-02.png"),
        "{text}"
    );
    ok(&merge(&manifests));
    // A frame replaced by another whole image decodes, but its checksum is not the one
    // the manifest recorded: it is rendered again too.
    std::fs::copy(d.join("split/f-01.png"), &frame).expect("copy");
    let text = render("split/f-##.png", Some("1/3"));
    assert!(
        text.contains("frame 1:") && !text.contains("frame 2:") && text.contains("f-02.png"),
        "{text}"
    );
    ok(&merge(&manifests));
    // Run again with other settings, the shard renders all its frames again instead of
    // keeping those of the old ones.
    let text = ok(&lumen(
        d,
        &[
            "render",
            file,
            "--size",
            "24x16",
            "--frames",
            "0..4",
            "--fps",
            "10",
            "--out",
            "split/f-##.png",
            "--shard",
            "1/3",
        ],
        &[],
    ));
    assert!(!text.contains("skipped"), "{text}");
    for n in ["f-01.png", "f-02.png"] {
        let size = image::image_dimensions(d.join("split").join(n)).expect("png");
        assert_eq!(size, (24, 16), "{n}");
    }
}

#[test]
fn tradeoff_shards_join_into_the_rows_of_the_whole() {
    let dir = tempfile::tempdir().expect("temp dir");
    let d = dir.path();
    let args = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut v = vec![
            "tradeoff",
            "spheres",
            "--size",
            "32x18",
            "--spp",
            "4",
            "--frames",
            "1",
            "--only",
            "preset",
            "--gi-density",
            "2",
        ];
        v.extend(extra);
        v
    };
    ok(&lumen(d, &args(&["--json", "whole.json"]), &[]));
    for s in ["0/2", "1/2"] {
        let text = ok(&lumen(d, &args(&["--shard", s, "--json", "t.json"]), &[]));
        assert!(text.contains("tradeoff shard"), "{text}");
    }
    let parts = [d.join("t.shard-0-of-2.json"), d.join("t.shard-1-of-2.json")];
    let mut merge_args: Vec<String> = vec!["merge".into()];
    merge_args.extend(parts.iter().rev().map(|p| p.display().to_string()));
    merge_args.extend(["--out".into(), "joined.json".into()]);
    let merge_args: Vec<&str> = merge_args.iter().map(String::as_str).collect();
    ok(&lumen(d, &merge_args, &[]));
    let read = |name: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.join(name)).expect("json")).expect("json")
    };
    let (whole, joined) = (read("whole.json"), read("joined.json"));
    let key = |doc: &serde_json::Value| -> Vec<(String, String, f64)> {
        doc["rows"]
            .as_array()
            .expect("rows")
            .iter()
            .map(|r| {
                (
                    r["kind"].as_str().unwrap_or_default().to_string(),
                    r["setting"].as_str().unwrap_or_default().to_string(),
                    r["flip_mean"].as_f64().unwrap_or(f64::NAN),
                )
            })
            .collect()
    };
    println!("rows: {:?}", key(&joined));
    assert!(key(&whole).len() >= 3);
    // The same rows in the same order, with the same errors (the times are measured anew).
    assert_eq!(key(&joined), key(&whole));
    assert_eq!(joined["schema"], "lumen-tradeoff/1");
    assert!(joined.get("shard").is_none());
}
