//! A real batch engine: a one-node Slurm cluster on localhost (munged, slurmctld, slurmd,
//! in a temporary folder, on ports 16817–16818) runs the Slurm recipe of
//! `docs/src/scale-out.md` as written (its `#SBATCH --array=0-3` script through `sbatch
//! --wait`, then its `lumen merge` line), but for a small `spheres` render in place of the
//! scene and the temporary folder in place of `/shared`; the merge equals the
//! single-process render. Every daemon is stopped when the test ends, passed or failed.
//!
//! Needs Debian's `slurm-wlm` and `munge` and root (the daemons run as root). `.ci/run`
//! installs them and sets `LUMEN_REQUIRE_SLURM=1`, which makes their absence a failure;
//! elsewhere the test says that it did not run and why.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Daemons started by the test, killed (and reaped) on drop.
struct Daemons(Vec<Child>);

impl Drop for Daemons {
    fn drop(&mut self) {
        for child in &mut self.0 {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

fn installed(program: &str) -> bool {
    ["/usr/sbin", "/usr/bin", "/usr/local/sbin", "/usr/local/bin"]
        .iter()
        .any(|d| Path::new(d).join(program).exists())
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

/// Polls `done` every 200 ms for up to `limit`.
fn wait_for(limit: Duration, mut done: impl FnMut() -> bool) -> bool {
    let start = Instant::now();
    while start.elapsed() < limit {
        if done() {
            return true;
        }
        std::thread::sleep(Duration::from_millis(200));
    }
    false
}

fn hostname() -> String {
    let out = Command::new("hostname")
        .arg("-s")
        .output()
        .expect("hostname");
    String::from_utf8_lossy(&out.stdout).trim().to_string()
}

/// Writes the munge key and `slurm.conf` into `dir` and starts the three daemons.
fn start_cluster(dir: &Path) -> Daemons {
    let key = dir.join("munge.key");
    let status = Command::new("mungekey")
        .args(["--create", "--keyfile"])
        .arg(&key)
        .status()
        .expect("mungekey runs");
    assert!(status.success(), "mungekey failed");
    let socket = dir.join("munge.socket");
    let host = hostname();
    let conf = format!(
        "ClusterName=lumentest\nSlurmctldHost={host}(127.0.0.1)\nSlurmUser=root\nSlurmdUser=root\n\
         AuthType=auth/munge\nCredType=cred/munge\nAuthInfo=socket={socket}\nMpiDefault=none\n\
         StateSaveLocation={d}/state\nSlurmdSpoolDir={d}/spool\n\
         SlurmctldPidFile={d}/slurmctld.pid\nSlurmdPidFile={d}/slurmd.pid\n\
         SlurmctldLogFile={d}/slurmctld.log\nSlurmdLogFile={d}/slurmd.log\n\
         ProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\n\
         JobAcctGatherType=jobacct_gather/none\nSchedulerType=sched/backfill\n\
         SelectType=select/cons_tres\nSelectTypeParameters=CR_Core\nReturnToService=2\n\
         SlurmctldPort=16817\nSlurmdPort=16818\n\
         NodeName={host} NodeAddr=127.0.0.1 CPUs=2 RealMemory=1000 State=UNKNOWN\n\
         PartitionName=lumen Nodes={host} Default=YES MaxTime=INFINITE State=UP\n",
        socket = socket.display(),
        d = dir.display()
    );
    std::fs::create_dir_all(dir.join("state")).expect("state dir");
    std::fs::create_dir_all(dir.join("spool")).expect("spool dir");
    std::fs::write(dir.join("slurm.conf"), conf).expect("slurm.conf");
    let spawn = |command: &mut Command| {
        command
            .env("SLURM_CONF", dir.join("slurm.conf"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("a daemon starts")
    };
    let mut daemons = Daemons(Vec::new());
    daemons.0.push(spawn(
        Command::new("munged")
            .args(["--foreground", "--force", "--socket"])
            .arg(&socket)
            .arg("--key-file")
            .arg(&key)
            .arg("--pid-file")
            .arg(dir.join("munged.pid"))
            .arg("--log-file")
            .arg(dir.join("munged.log"))
            .arg("--seed-file")
            .arg(dir.join("munged.seed")),
    ));
    assert!(
        wait_for(Duration::from_secs(10), || socket.exists()),
        "munged did not open its socket"
    );
    daemons
        .0
        .push(spawn(Command::new("slurmctld").args(["-D", "-c", "-i"])));
    daemons.0.push(spawn(
        Command::new("slurmd").args(["-D", "-c", "-N", &host]),
    ));
    let idle = wait_for(Duration::from_secs(60), || {
        Command::new("sinfo")
            .args(["-h", "-o", "%T"])
            .env("SLURM_CONF", dir.join("slurm.conf"))
            .output()
            .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "idle")
    });
    assert!(
        idle,
        "the node did not come up: {}",
        std::fs::read_to_string(dir.join("slurmctld.log")).unwrap_or_default()
    );
    daemons
}

fn lumen() -> &'static str {
    env!("CARGO_BIN_EXE_lumen")
}

fn load(path: &Path) -> image::Rgba32FImage {
    lumen::assets::image_io::load_rgba32f(path).expect("an EXR")
}

#[test]
fn a_slurm_array_job_renders_the_shards_that_merge_into_the_single_render() {
    let missing: Vec<&str> = [
        "munged",
        "mungekey",
        "slurmctld",
        "slurmd",
        "sbatch",
        "sinfo",
    ]
    .into_iter()
    .filter(|p| !installed(p))
    .collect();
    let required = std::env::var_os("LUMEN_REQUIRE_SLURM").is_some();
    if !missing.is_empty() || !is_root() {
        let why = if missing.is_empty() {
            "the daemons must run as root".to_string()
        } else {
            format!(
                "{} not installed (Debian: slurm-wlm, munge)",
                missing.join(", ")
            )
        };
        assert!(!required, "LUMEN_REQUIRE_SLURM is set but {why}");
        eprintln!("not run: {why}; .ci/run installs them and requires this test");
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let d = dir.path();
    let daemons = start_cluster(d);
    let work: PathBuf = d.join("work");
    std::fs::create_dir_all(&work).expect("work dir");
    // The recipe of docs/src/scale-out.md as written, but for what only a real site has:
    // a small `spheres` render for the scene, and the temporary folder for `/shared`.
    let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/src/scale-out.md");
    let markdown = std::fs::read_to_string(&docs).expect("scale-out.md");
    let small = "spheres --size 48x32 --spp 8 --max-bounces 2 --seed 5";
    let shared = work.display().to_string();
    let recipe = |index: usize| {
        let block = super::common::sh_block_after(&markdown, "**Slurm**", index);
        let mut script = block.to_string();
        for (what, with) in [
            ("scene.glb --size 1920x1080 --spp 4096", small),
            ("/shared", shared.as_str()),
        ] {
            if block.contains(what) {
                script = script.replace(what, with);
            }
        }
        assert!(
            !script.contains("/shared") && !script.contains("scene.glb"),
            "the recipe changed:\n{block}"
        );
        script
    };
    let batch = recipe(0);
    assert!(batch.contains("#SBATCH --array=0-3"), "{batch}");
    std::fs::write(work.join("reference.sh"), &batch).expect("script");
    // sbatch passes its environment on: `lumen` is found on the PATH.
    let path = format!(
        "{}:{}",
        Path::new(lumen()).parent().expect("bin dir").display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let start = Instant::now();
    let submitted = Command::new("timeout")
        .arg("300")
        .arg("sbatch")
        .args(["--wait", "--chdir"])
        .arg(&work)
        .arg(work.join("reference.sh"))
        .env("SLURM_CONF", d.join("slurm.conf"))
        .env("PATH", &path)
        .output()
        .expect("sbatch runs");
    let logs = || {
        (0..4)
            .map(|i| {
                std::fs::read_dir(&work)
                    .into_iter()
                    .flatten()
                    .flatten()
                    .filter(|e| {
                        e.file_name()
                            .to_string_lossy()
                            .ends_with(&format!("_{i}.out"))
                    })
                    .map(|e| std::fs::read_to_string(e.path()).unwrap_or_default())
                    .collect::<String>()
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert!(
        submitted.status.success(),
        "sbatch: {}\n{}",
        String::from_utf8_lossy(&submitted.stderr),
        logs()
    );
    println!(
        "Slurm ran the array of 4 shards in {:.1} s",
        start.elapsed().as_secs_f64()
    );
    for i in 0..4 {
        let sidecar: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(work.join(format!("ref.shard-{i}-of-4.exr.json")))
                .unwrap_or_else(|e| panic!("shard {i}: {e}\n{}", logs())),
        )
        .expect("json");
        assert_eq!(sidecar["index_source"], "SLURM_ARRAY_TASK_ID");
    }
    drop(daemons);
    let merge = recipe(1);
    let merged = Command::new("bash")
        .args(["-euo", "pipefail", "-c", &merge])
        .current_dir(&work)
        .env("PATH", &path)
        .output()
        .expect("bash runs");
    assert!(
        merged.status.success(),
        "{merge}\n{}",
        String::from_utf8_lossy(&merged.stderr)
    );
    let single = Command::new(lumen())
        .arg("reference")
        .args(small.split(' '))
        .arg("--out")
        .arg(work.join("single.exr"))
        .output()
        .expect("lumen runs");
    assert!(single.status.success());
    let (a, b) = (load(&work.join("single.exr")), load(&work.join("ref.exr")));
    let worst = a
        .pixels()
        .zip(b.pixels())
        .flat_map(|(p, q)| (0..3).map(move |c| (p.0[c] - q.0[c]).abs() / p.0[c].abs().max(1e-6)))
        .fold(0.0f32, f32::max);
    println!("merged against the single render: worst relative difference {worst:.2e}");
    assert!(worst <= 1e-6, "{worst}");
}
