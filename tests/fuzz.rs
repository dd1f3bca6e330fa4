//! A mutation fuzzer of every loader, on stable Rust: a bounded loop of seeded mutations
//! (bit flips, interesting integers, inserted, deleted and spliced ranges; for JSON also
//! structured edits of its numbers, keys and arrays) over a corpus of seeds built from
//! `tests/data/` and `assets/`.
//!
//! - **Loaders**: glTF (JSON with its side files), GLB, Draco streams, OpenEXR, Radiance
//!   HDR, PNG and JPEG. Each loader is one test.
//! - **What fails the test**: a panic (caught, the input saved to
//!   `target/fuzz-crashes/`), an input that takes longer than [`HANG_SECONDS`] (the
//!   watchdog saves it and aborts the process), or a peak resident memory over
//!   [`MEMORY_LIMIT`] above what the process held when the loader's fuzzing began.
//! - **Duration**: `LUMEN_FUZZ_SECONDS` per loader (default 6 in the test suite). The long
//!   run is `LUMEN_FUZZ_SECONDS=600 cargo test --release --test fuzz -- --nocapture`.
//! - **Regressions**: every input that ever crashed a loader is kept in
//!   `tests/data/fuzz/<loader>/` and replayed first, asserting an error and no panic.

use crate::common;

use lumen::App;
use lumen::scene::{ColorSpace, EquirectImage};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// An input that runs longer than this is a hang.
const HANG_SECONDS: u64 = 10;
/// Peak resident memory of the fuzzing process, above what was resident when the loader's
/// fuzzing began, over this fails (bytes).
const MEMORY_LIMIT: u64 = 3 << 30;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Seconds per loader: `LUMEN_FUZZ_SECONDS`, default 6 (CI runs the suite in under 30 minutes).
fn budget() -> Duration {
    let seconds = std::env::var("LUMEN_FUZZ_SECONDS")
        .ok()
        .and_then(|s| s.parse::<u64>().ok())
        .unwrap_or(6);
    Duration::from_secs(seconds)
}

/// SplitMix64: a small, seeded, reproducible generator.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
}

/// Integers that find edge cases: zero, one, the signed and unsigned limits of 8, 16, 32
/// and 64 bits, and a few sizes that overflow when multiplied.
const INTERESTING: &[u64] = &[
    0,
    1,
    2,
    0x7F,
    0x80,
    0xFF,
    0x7FFF,
    0x8000,
    0xFFFF,
    0x7FFF_FFFF,
    0x8000_0000,
    0xFFFF_FFFF,
    0x1_0000_0000,
    0x4000_0000,
    u64::MAX,
    i64::MAX as u64,
    65536,
    46341,
];

/// One byte-level mutation of `data`; `other` is another seed to splice from.
fn mutate_bytes(data: &mut Vec<u8>, other: &[u8], rng: &mut Rng) {
    let len = data.len();
    match rng.below(8) {
        0 if len > 0 => {
            let i = rng.below(len);
            data[i] ^= 1 << rng.below(8);
        }
        1 if len > 0 => {
            let i = rng.below(len);
            data[i] = [0u8, 0xFF, 0x7F, 0x80, 1][rng.below(5)];
        }
        2 if len >= 4 => {
            let width = [2usize, 4, 8][rng.below(3)].min(len);
            let i = rng.below(len - width + 1);
            let v = INTERESTING[rng.below(INTERESTING.len())];
            let bytes = if rng.below(2) == 0 {
                v.to_le_bytes()
            } else {
                v.to_be_bytes()
            };
            data[i..i + width].copy_from_slice(&bytes[..width]);
        }
        3 => {
            let i = rng.below(len + 1);
            let n = 1 + rng.below(64);
            let fill: Vec<u8> = (0..n).map(|_| rng.next() as u8).collect();
            data.splice(i..i, fill);
        }
        4 if len > 1 => {
            let i = rng.below(len);
            let n = 1 + rng.below((len - i).min(256));
            data.drain(i..i + n);
        }
        5 if len > 1 => {
            let i = rng.below(len);
            let n = 1 + rng.below((len - i).min(256));
            let copy = data[i..i + n].to_vec();
            let at = rng.below(len + 1);
            data.splice(at..at, copy);
        }
        6 if !other.is_empty() && len > 0 => {
            let from = rng.below(other.len());
            let n = 1 + rng.below((other.len() - from).min(512));
            let at = rng.below(len);
            let end = (at + n).min(len);
            data.splice(at..end, other[from..from + n].iter().copied());
        }
        _ => {
            let cut = rng.below(len + 1);
            data.truncate(cut);
        }
    }
}

/// One structured mutation of a JSON document: a number replaced by an interesting value,
/// a key removed, an array element duplicated or removed, or a value's type changed.
fn mutate_json(value: &mut Value, rng: &mut Rng) {
    let count = count_nodes(value);
    let mut k = rng.below(count);
    let Some(target) = nth_node(value, &mut k) else {
        return;
    };
    match rng.below(6) {
        0 | 1 => {
            let numbers: [Value; 10] = [
                0.into(),
                (-1).into(),
                1.into(),
                4_294_967_295u64.into(),
                4_294_967_296u64.into(),
                u64::MAX.into(),
                i64::MIN.into(),
                1e308.into(),
                (-1e308).into(),
                1e-45.into(),
            ];
            *target = numbers[rng.below(numbers.len())].clone();
        }
        2 => {
            if let Value::Object(map) = target
                && !map.is_empty()
            {
                let key = map.keys().nth(rng.below(map.len())).cloned();
                if let Some(key) = key {
                    map.remove(&key);
                }
            }
        }
        3 => {
            if let Value::Array(items) = target
                && !items.is_empty()
            {
                let i = rng.below(items.len());
                let copy = items[i].clone();
                items.insert(i, copy);
            }
        }
        4 => {
            if let Value::Array(items) = target
                && !items.is_empty()
            {
                let i = rng.below(items.len());
                items.remove(i);
            }
        }
        _ => {
            let replacements = [
                Value::Null,
                Value::Bool(true),
                Value::String("x".into()),
                Value::Array(Vec::new()),
                Value::Object(serde_json::Map::new()),
            ];
            *target = replacements[rng.below(replacements.len())].clone();
        }
    }
}

/// Nodes of a JSON tree, the root included.
fn count_nodes(value: &Value) -> usize {
    1 + match value {
        Value::Array(items) => items.iter().map(count_nodes).sum(),
        Value::Object(map) => map.values().map(count_nodes).sum(),
        _ => 0,
    }
}

/// The `k`-th node in pre-order (`k` counts down as nodes are passed).
fn nth_node<'a>(value: &'a mut Value, k: &mut usize) -> Option<&'a mut Value> {
    if *k == 0 {
        return Some(value);
    }
    *k -= 1;
    match value {
        Value::Array(items) => items.iter_mut().find_map(|v| nth_node(v, k)),
        Value::Object(map) => map.values_mut().find_map(|v| nth_node(v, k)),
        _ => None,
    }
}

/// A mutated copy of a seed: 1 to 4 stacked mutations, structured ones for JSON seeds.
fn mutant(seeds: &[Vec<u8>], rng: &mut Rng) -> Vec<u8> {
    let seed = &seeds[rng.below(seeds.len())];
    let other = &seeds[rng.below(seeds.len())];
    let rounds = 1 + rng.below(4);
    if rng.below(2) == 0
        && let Ok(mut json) = serde_json::from_slice::<Value>(seed)
    {
        for _ in 0..rounds {
            mutate_json(&mut json, rng);
        }
        return serde_json::to_vec(&json).unwrap_or_default();
    }
    let mut data = seed.clone();
    for _ in 0..rounds {
        mutate_bytes(&mut data, other, rng);
    }
    data
}

/// Where crashing inputs are written.
fn crash_dir() -> PathBuf {
    repo().join("target/fuzz-crashes")
}

/// A watchdog: if one input runs longer than [`HANG_SECONDS`], it saves the input and
/// aborts the process with a message naming the file.
struct Watchdog {
    started_ms: Arc<AtomicU64>,
    current: Arc<std::sync::Mutex<Vec<u8>>>,
    epoch: Instant,
}

impl Watchdog {
    fn start(loader: &'static str) -> Watchdog {
        let started_ms = Arc::new(AtomicU64::new(u64::MAX));
        let current = Arc::new(std::sync::Mutex::new(Vec::new()));
        let epoch = Instant::now();
        let (s, c) = (started_ms.clone(), current.clone());
        std::thread::spawn(move || {
            loop {
                std::thread::sleep(Duration::from_millis(250));
                let start = s.load(Ordering::Relaxed);
                if start == u64::MAX {
                    continue;
                }
                let now = epoch.elapsed().as_millis() as u64;
                if now.saturating_sub(start) > HANG_SECONDS * 1000 {
                    let _ = std::fs::create_dir_all(crash_dir());
                    let path = crash_dir().join(format!("{loader}-hang.bin"));
                    if let Ok(input) = c.lock() {
                        let _ = std::fs::write(&path, &*input);
                    }
                    eprintln!(
                        "fuzz {loader}: an input ran over {HANG_SECONDS} s; saved as {}",
                        path.display()
                    );
                    std::process::abort();
                }
            }
        });
        Watchdog {
            started_ms,
            current,
            epoch,
        }
    }

    fn begin(&self, input: &[u8]) {
        if let Ok(mut c) = self.current.lock() {
            c.clear();
            c.extend_from_slice(input);
        }
        self.started_ms
            .store(self.epoch.elapsed().as_millis() as u64, Ordering::Relaxed);
    }

    fn end(&self) {
        self.started_ms.store(u64::MAX, Ordering::Relaxed);
    }
}

/// Replays `tests/data/fuzz/<loader>/`, then fuzzes `load` with mutants of `seeds` for the
/// time budget. `load` returns whether the input loaded (an error is a fine outcome).
fn fuzz(loader: &'static str, seeds: Vec<Vec<u8>>, load: impl Fn(&[u8]) -> bool) {
    assert!(!seeds.is_empty(), "{loader}: no seeds");
    let mut failures = Vec::new();
    let run = |input: &[u8], watchdog: &Watchdog| -> Result<bool, String> {
        watchdog.begin(input);
        let outcome = lumen::error::contain_panics(|| load(input));
        watchdog.end();
        outcome
    };
    // The tests before this one share the process: reset its peak to what is resident now
    // and count only the growth above that, so the limit measures this loader alone.
    std::fs::write("/proc/self/clear_refs", "5").expect("reset the peak RSS (Linux >= 4.0)");
    let baseline = common::process_memory("VmRSS");
    let watchdog = Watchdog::start(loader);
    // The regression corpus: every input that once crashed this loader.
    let corpus = repo().join("tests/data/fuzz").join(loader);
    let mut replayed = 0;
    if let Ok(entries) = std::fs::read_dir(&corpus) {
        for entry in entries.filter_map(|e| e.ok()) {
            let bytes = std::fs::read(entry.path()).expect("corpus file");
            replayed += 1;
            if let Err(panic) = run(&bytes, &watchdog) {
                failures.push(format!("{}: {panic}", entry.path().display()));
            }
        }
    }
    // The seeds run too; the glTF seeds include the broken-file fixtures, so only some load.
    let mut seeds_loaded = 0;
    for seed in &seeds {
        match run(seed, &watchdog) {
            Ok(true) => seeds_loaded += 1,
            Ok(false) => {}
            Err(panic) => failures.push(format!("a seed: {panic}")),
        }
    }
    assert!(seeds_loaded > 0, "{loader}: no seed loads");
    let mut rng = Rng(0x5EED ^ loader.len() as u64);
    let start = Instant::now();
    let (mut runs, mut loaded) = (0u64, 0u64);
    let mut slowest = Duration::ZERO;
    while start.elapsed() < budget() {
        let input = mutant(&seeds, &mut rng);
        let t = Instant::now();
        let outcome = run(&input, &watchdog);
        slowest = slowest.max(t.elapsed());
        runs += 1;
        match outcome {
            Ok(true) => loaded += 1,
            Ok(false) => {}
            Err(panic) => {
                std::fs::create_dir_all(crash_dir()).expect("crash dir");
                let path = crash_dir().join(format!("{loader}-{runs}.bin"));
                std::fs::write(&path, &input).expect("save crash");
                failures.push(format!("{}: {panic}", path.display()));
            }
        }
    }
    let peak = common::process_memory("VmHWM").saturating_sub(baseline);
    println!(
        "fuzz {loader}: {runs} inputs in {:.0} s ({loaded} loaded), {replayed} corpus files, {} seeds, slowest {:.2} s, peak RSS {} MiB above the {} MiB resident before, {} panics",
        start.elapsed().as_secs_f64(),
        seeds.len(),
        slowest.as_secs_f64(),
        peak >> 20,
        baseline >> 20,
        failures.len()
    );
    assert!(
        failures.is_empty(),
        "{loader}: {} panics (add each input to tests/data/fuzz/{loader}/):\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(
        peak < MEMORY_LIMIT,
        "{loader}: peak resident memory {} MiB above the {} MiB resident before",
        peak >> 20,
        baseline >> 20
    );
    assert!(runs > 0, "{loader}: no input ran");
}

/// The glTF seeds: every broken-file fixture that is JSON (except the 16384² texture,
/// slow to decode), and a glTF with an embedded texture.
fn gltf_seeds() -> Vec<Vec<u8>> {
    let dir = repo().join("tests/data/gltf");
    let mut seeds: Vec<Vec<u8>> = std::fs::read_dir(&dir)
        .expect("tests/data/gltf")
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| {
            p.extension().is_some_and(|e| e == "gltf")
                && !p.ends_with("huge_texture.gltf")
                && !p.to_string_lossy().contains("dev_zero")
        })
        .filter_map(|p| std::fs::read(p).ok())
        .collect();
    seeds.sort();
    seeds
}

/// A loader of glTF bytes written as `name` into a copy of `tests/data/gltf/` (so that
/// side files resolve), through `load_gltf` into a GPU-less app.
fn gltf_loader(name: &str) -> impl Fn(&[u8]) -> bool {
    let dir = tempfile::tempdir().expect("temp dir");
    for entry in std::fs::read_dir(repo().join("tests/data/gltf"))
        .expect("tests/data/gltf")
        .filter_map(|e| e.ok())
    {
        let name = entry.file_name();
        if name != "huge.png" {
            std::fs::copy(entry.path(), dir.path().join(&name)).expect("copy fixture");
        }
    }
    let path = dir.path().join(name);
    move |bytes: &[u8]| {
        let _keep = &dir;
        std::fs::write(&path, bytes).expect("write input");
        let mut app = App::new();
        lumen::assets::gltf::load_gltf(&mut app, &path).is_ok()
    }
}

/// A GLB container of `json` and `bin`.
fn glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |v: &[u8], fill: u8| {
        let mut v = v.to_vec();
        while !v.len().is_multiple_of(4) {
            v.push(fill);
        }
        v
    };
    let (json, bin) = (pad(json, b' '), pad(bin, 0));
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(&json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(&bin);
    out
}

/// The quad with its views compressed by `EXT_meshopt_compression` as a GLB: the packed
/// streams in the binary chunk (buffer 0), decoded into a placeholder (buffer 1).
fn meshopt_glb() -> Vec<u8> {
    let bin = common::quad_buffer(1.0);
    let (packed, views) = common::meshopt_quad(&bin, false);
    let json = serde_json::json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["EXT_meshopt_compression"],
        "extensionsRequired": ["EXT_meshopt_compression"],
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2}]}],
        "buffers": [
            {"byteLength": packed.len()},
            {"byteLength": bin.len(), "extensions": {"EXT_meshopt_compression": {"fallback": true}}}
        ],
        "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-1.0, -1.0, 0.0], "max": [1.0, 1.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ]
    });
    glb(&serde_json::to_vec(&json).expect("json"), &packed)
}

/// A small textured quad as a GLB (positions, UVs, indices and a 4×4 PNG in the binary
/// chunk).
fn textured_glb() -> Vec<u8> {
    let png = png_bytes(&image::DynamicImage::ImageRgba8(image::RgbaImage::from_fn(
        4,
        4,
        |x, y| image::Rgba([(x * 60) as u8, (y * 60) as u8, 128, 255]),
    )));
    let mut bin = common::quad_buffer(1.0);
    bin.extend([0, 0]);
    let png_offset = bin.len();
    bin.extend(&png);
    let json = serde_json::json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "images": [{"bufferView": 3, "mimeType": "image/png"}],
        "textures": [{"source": 0}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32},
            {"buffer": 0, "byteOffset": 80, "byteLength": 12},
            {"buffer": 0, "byteOffset": png_offset, "byteLength": png.len()}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-1.0, -1.0, 0.0], "max": [1.0, 1.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ]
    });
    glb(&serde_json::to_vec(&json).expect("json"), &bin)
}

fn png_bytes(image: &image::DynamicImage) -> Vec<u8> {
    let mut out = std::io::Cursor::new(Vec::new());
    image
        .write_to(&mut out, image::ImageFormat::Png)
        .expect("png");
    out.into_inner()
}

fn encoded(image: &image::DynamicImage, format: image::ImageFormat) -> Vec<u8> {
    let mut out = std::io::Cursor::new(Vec::new());
    image.write_to(&mut out, format).expect("encode");
    out.into_inner()
}

/// The JSON and binary chunks of a GLB file (a well-formed one: the seeds in `assets/`).
fn glb_chunks(bytes: &[u8]) -> (&[u8], &[u8]) {
    let word =
        |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes")) as usize;
    let json_len = word(12);
    let json = &bytes[20..20 + json_len];
    let bin_at = 20 + json_len;
    let bin_len = word(bin_at);
    (json, &bytes[bin_at + 8..bin_at + 8 + bin_len])
}

/// The Draco stream and the extension object of each Draco-compressed model in `assets/`.
fn draco_streams() -> Vec<(Vec<u8>, Value)> {
    ["assets/models/suzi.glb", "assets/models/bunny.glb"]
        .iter()
        .map(|name| {
            let bytes = std::fs::read(repo().join(name)).expect("model");
            let (json, bin) = glb_chunks(&bytes);
            let json: Value = serde_json::from_slice(json).expect("json");
            let ext =
                json["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]
                    .clone();
            let view = &json["bufferViews"][ext["bufferView"].as_u64().expect("view") as usize];
            let offset = view["byteOffset"].as_u64().unwrap_or(0) as usize;
            let length = view["byteLength"].as_u64().expect("length") as usize;
            (bin[offset..offset + length].to_vec(), ext)
        })
        .collect()
}

#[test]
fn fuzz_gltf() {
    fuzz("gltf", gltf_seeds(), gltf_loader("input.gltf"));
}

#[test]
fn fuzz_glb() {
    let mut seeds: Vec<Vec<u8>> = ["assets/models/suzi.glb", "assets/models/bunny.glb"]
        .iter()
        .map(|p| std::fs::read(repo().join(p)).expect("model"))
        .collect();
    seeds.push(textured_glb());
    let packed = meshopt_glb();
    let mut app = App::new();
    let path = tempfile::tempdir().expect("temp dir");
    std::fs::write(path.path().join("packed.glb"), &packed).expect("write");
    lumen::assets::gltf::load_gltf(&mut app, &path.path().join("packed.glb"))
        .expect("the meshopt seed loads");
    seeds.push(packed);
    fuzz("glb", seeds, gltf_loader("input.glb"));
}

#[test]
fn fuzz_draco() {
    let streams = draco_streams();
    let extension = streams[0].1.clone();
    let seeds = streams.into_iter().map(|(bytes, _)| bytes).collect();
    fuzz("draco", seeds, move |bytes: &[u8]| {
        lumen::assets::draco::decode_primitive(&extension, |_| Some(bytes)).is_ok()
    });
}

#[test]
fn fuzz_meshopt() {
    // The three codecs on mutants of the quad's streams (and of each other's).
    let bin = common::quad_buffer(1.0);
    let indices: Vec<u32> = [0, 1, 2, 0, 2, 3].into();
    let seeds = vec![
        common::meshopt_attributes(&bin[..48], 12),
        common::meshopt_triangles(&indices),
        vec![
            0xd1, 0x00, 0x04, 0xcd, 0x01, 0x04, 0x07, 0x98, 0x1f, 0x00, 0x00, 0x00, 0x00,
        ],
    ];
    use lumen::assets::meshopt::*;
    fuzz("meshopt", seeds, |bytes: &[u8]| {
        let a = decode_vertex_buffer(bytes, 4, 12).is_ok();
        let t = decode_index_buffer(bytes, 6, 2).is_ok();
        let i = decode_index_sequence(bytes, 6, 4).is_ok();
        a || t || i
    });
}

#[test]
fn fuzz_exr() {
    let small = image::DynamicImage::ImageRgb32F(image::Rgb32FImage::from_fn(16, 8, |x, y| {
        image::Rgb([x as f32 * 0.5, y as f32 * 2.0, 1e4])
    }));
    let seeds = vec![
        encoded(&small, image::ImageFormat::OpenExr),
        std::fs::read(repo().join("assets/hdri/sky.exr")).expect("sky.exr"),
        std::fs::read(repo().join("assets/hdri/studio.exr")).expect("studio.exr"),
    ];
    fuzz("exr", seeds, |bytes: &[u8]| {
        EquirectImage::decode(bytes, Path::new("input.exr")).is_ok()
    });
}

#[test]
fn fuzz_hdr() {
    let image = |w: u32, h: u32| {
        image::DynamicImage::ImageRgb32F(image::Rgb32FImage::from_fn(w, h, |x, y| {
            image::Rgb([x as f32 * 0.25, y as f32, 3.0])
        }))
    };
    // Radiance run-length encoding applies to scanlines 8 to 32767 texels wide.
    let seeds = vec![
        encoded(&image(16, 8), image::ImageFormat::Hdr),
        encoded(&image(4, 2), image::ImageFormat::Hdr),
    ];
    fuzz("hdr", seeds, |bytes: &[u8]| {
        EquirectImage::decode(bytes, Path::new("input.hdr")).is_ok()
    });
}

#[test]
fn fuzz_png_and_jpeg() {
    let rgba = image::DynamicImage::ImageRgba8(image::RgbaImage::from_fn(12, 9, |x, y| {
        image::Rgba([(x * 20) as u8, (y * 25) as u8, 90, (x * y) as u8])
    }));
    let gray16 = image::DynamicImage::ImageLuma16(image::ImageBuffer::from_fn(7, 5, |x, y| {
        image::Luma([(x * 9000 + y * 300) as u16])
    }));
    let seeds = vec![
        png_bytes(&rgba),
        png_bytes(&gray16),
        encoded(
            &image::DynamicImage::ImageRgb8(rgba.to_rgb8()),
            image::ImageFormat::Jpeg,
        ),
        std::fs::read(repo().join("tests/data/gltf/tiny.png")).expect("tiny.png"),
        std::fs::read(repo().join("tests/data/ktx2/quadrants_etc1s.ktx2")).expect("ktx2"),
        std::fs::read(repo().join("tests/data/ktx2/quadrants_uastc_zstd.ktx2")).expect("ktx2"),
    ];
    fuzz("image", seeds, |bytes: &[u8]| {
        let mut warnings = Vec::new();
        lumen::assets::texture_io::decode(bytes, ColorSpace::Srgb, 256, &mut warnings, "input")
            .is_ok()
    });
}
