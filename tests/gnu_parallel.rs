//! The GNU parallel recipe of `docs/src/scale-out.md`, run as written except for what
//! only a real site has: the local host `:` stands for `host1,host2,host3`, a temporary
//! folder for `/shared`, and a small `spheres` render for `scene.glb --spp 4096`. Its
//! twelve shards, merged by the recipe's own `lumen merge` line, equal the single-process
//! render to 1e-6 (relative).
//!
//! Needs GNU parallel (Debian: `parallel`). `.ci/run` installs it and sets
//! `LUMEN_REQUIRE_PARALLEL=1`, which makes its absence a failure; elsewhere the test says
//! that it did not run.

use std::path::Path;
use std::process::Command;

fn load(path: &Path) -> image::Rgba32FImage {
    lumen::assets::image_io::load_rgba32f(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn the_documented_gnu_parallel_recipe_merges_into_the_single_render() {
    let found = Command::new("parallel").arg("--version").output();
    if !found.as_ref().is_ok_and(|o| o.status.success()) {
        assert!(
            std::env::var_os("LUMEN_REQUIRE_PARALLEL").is_none(),
            "LUMEN_REQUIRE_PARALLEL is set but GNU parallel is not installed"
        );
        eprintln!("not run: GNU parallel is not installed (Debian: parallel)");
        return;
    }
    let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/src/scale-out.md");
    let markdown = std::fs::read_to_string(&docs).expect("scale-out.md");
    let recipe = super::common::sh_block_after(&markdown, "**GNU parallel across hosts**", 0);
    let dir = tempfile::tempdir().expect("temp dir");
    let shared = dir.path().display().to_string();
    let small = "spheres --size 32x18 --spp 12 --max-bounces 2";
    let mut script = recipe.to_string();
    for (what, with) in [
        ("host1,host2,host3", ":"),
        ("scene.glb --spp 4096", small),
        ("/shared", shared.as_str()),
    ] {
        assert!(
            script.contains(what),
            "the recipe no longer has '{what}':\n{recipe}"
        );
        script = script.replace(what, with);
    }
    let lumen = Path::new(env!("CARGO_BIN_EXE_lumen"));
    let path = format!(
        "{}:{}",
        lumen.parent().expect("bin dir").display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let ran = Command::new("bash")
        .args(["-euo", "pipefail", "-c", &script])
        .current_dir(dir.path())
        .env("PATH", path)
        .env("HOME", dir.path())
        .output()
        .expect("bash runs");
    assert!(
        ran.status.success(),
        "the recipe failed:\n{script}\n{}\n{}",
        String::from_utf8_lossy(&ran.stdout),
        String::from_utf8_lossy(&ran.stderr)
    );
    let shared = dir.path();
    for i in 0..12 {
        let sidecar = shared.join(format!("ref.shard-{i}-of-12.exr.json"));
        assert!(sidecar.is_file(), "no {}", sidecar.display());
    }
    let single = Command::new(lumen)
        .arg("reference")
        .args(small.split(' '))
        .arg("--out")
        .arg(shared.join("single.exr"))
        .output()
        .expect("lumen runs");
    assert!(
        single.status.success(),
        "{}",
        String::from_utf8_lossy(&single.stderr)
    );
    let (a, b) = (
        load(&shared.join("single.exr")),
        load(&shared.join("ref.exr")),
    );
    assert_eq!(a.dimensions(), b.dimensions());
    let worst = a
        .pixels()
        .zip(b.pixels())
        .flat_map(|(p, q)| p.0.into_iter().zip(q.0).take(3))
        .map(|(x, y)| (x - y).abs() / x.abs().max(y.abs()).max(1e-6))
        .fold(0.0f32, f32::max);
    assert!(
        worst <= 1e-6,
        "the merged recipe differs from the single render by {worst:e} (relative)"
    );
}
