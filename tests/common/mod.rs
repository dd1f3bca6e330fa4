//! Helpers shared by the workspace tests.
#![allow(dead_code)]

use lumen::App;
use lumen::render::device::{Gpu, GpuRequest};

/// A headless GPU chosen as the environment says (Vulkan, then GL).
pub fn gpu() -> Gpu {
    Gpu::new(&GpuRequest::from_env().expect("GPU request"), None, None)
        .expect("a GPU adapter (install mesa-vulkan-drivers, or use GL)")
        .0
}

/// A headless app with `scene` (a built-in scene) spawned.
pub fn app_with(scene: &str) -> App {
    let mut app = App::headless().expect("a GPU adapter");
    let info = lumen_game::scenes::find(scene).expect("built-in scene");
    (info.build)(&mut app).expect("scene builds");
    app
}

/// Runs one compute dispatch and reads `output` back as vec4s.
pub fn run_compute(
    gpu: &Gpu,
    pipeline: &wgpu::ComputePipeline,
    bind_group: &wgpu::BindGroup,
    workgroups: u32,
    output: &wgpu::Buffer,
) -> Vec<[f32; 4]> {
    let readback = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: output.size(),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups(workgroups, 1, 1);
    }
    encoder.copy_buffer_to_buffer(output, 0, &readback, 0, output.size());
    gpu.queue.submit([encoder.finish()]);
    let slice = readback.slice(..);
    slice.map_async(wgpu::MapMode::Read, |r| r.expect("map"));
    gpu.device
        .poll(wgpu::PollType::Wait {
            submission_index: None,
            timeout: None,
        })
        .expect("poll");
    let data = slice.get_mapped_range().expect("mapped");
    bytemuck::cast_slice::<u8, [f32; 4]>(&data).to_vec()
}

/// A glTF quad's binary buffer: 4 positions (±`half`, ±`half`, 0) in bytes 0..48, their
/// texture coordinates (v down) in 48..80, and 6 `u16` indices (two triangles) in 80..92.
pub fn quad_buffer(half: f32) -> Vec<u8> {
    let positions: [[f32; 3]; 4] = [
        [-half, -half, 0.0],
        [half, -half, 0.0],
        [half, half, 0.0],
        [-half, half, 0.0],
    ];
    let uvs: [[f32; 2]; 4] = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];
    let indices: [u16; 6] = [0, 1, 2, 0, 2, 3];
    let mut bin: Vec<u8> = Vec::new();
    bin.extend(positions.iter().flatten().flat_map(|v| v.to_le_bytes()));
    bin.extend(uvs.iter().flatten().flat_map(|v| v.to_le_bytes()));
    bin.extend(indices.iter().flat_map(|v| v.to_le_bytes()));
    bin
}

/// Runs `lumen` with `args` in `dir` and asserts it succeeds (stderr in the message).
pub fn run_lumen<S: AsRef<std::ffi::OsStr>>(dir: &std::path::Path, args: &[S]) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_lumen"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("lumen runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A failed `lumen` run: non-zero exit, one line on stderr naming `needle`, no panic.
pub fn assert_clean_failure(out: &std::process::Output, needle: &str) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success(),
        "expected failure, got success; stderr: {err}"
    );
    assert!(!err.contains("panicked"), "panic: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "not one line: {err}");
    assert!(
        err.contains(needle),
        "stderr does not mention '{needle}': {err}"
    );
}

/// A memory line of `/proc/self/status` (`VmRSS`, `VmHWM`, …) in bytes.
pub fn process_memory(key: &str) -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.strip_prefix(key).is_some_and(|r| r.starts_with(':')))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<u64>().ok())
        })
        .unwrap_or_else(|| panic!("{key} in /proc/self/status"))
        * 1024
}

/// Luminance-like mean of the rgb of an HDR pixel.
pub fn lum(p: &image::Rgba<f32>) -> f32 {
    0.2126 * p.0[0] + 0.7152 * p.0[1] + 0.0722 * p.0[2]
}

/// An Xvfb server on a free display, stopped when dropped.
pub struct Xvfb {
    child: std::process::Child,
    /// `:N`, for `DISPLAY`.
    pub display: String,
}

impl Xvfb {
    /// Starts Xvfb (`apt-get install xvfb`) on a display it picks itself (`-displayfd`),
    /// so that tests running at the same time never collide.
    pub fn start() -> Xvfb {
        use std::io::BufRead;
        let mut child = std::process::Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "640x480x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("Xvfb (apt-get install xvfb) for the window tests");
        let mut line = String::new();
        if let Some(out) = child.stdout.take() {
            std::io::BufReader::new(out)
                .read_line(&mut line)
                .expect("Xvfb prints its display number");
        }
        let n: u32 = line.trim().parse().unwrap_or_else(|_| {
            let _ = child.kill();
            panic!("Xvfb did not start (it printed {line:?})")
        });
        Xvfb {
            child,
            display: format!(":{n}"),
        }
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Where world point `p` appeared in a `size` frame in the last frame, in pixels from
/// the top-left corner (fractional).
pub fn image_point(app: &App, p: glam::Vec3, size: (u32, u32)) -> glam::Vec2 {
    use glam::Vec4Swizzles;
    let camera = app
        .world()
        .resource::<lumen::render::extract::ExtractedFrame>()
        .camera
        .clone()
        .expect("camera");
    let clip = camera.clip_from_view * camera.view_from_world * p.extend(1.0);
    let ndc = clip.xy() / clip.w;
    glam::Vec2::new(
        (ndc.x * 0.5 + 0.5) * size.0 as f32,
        (0.5 - ndc.y * 0.5) * size.1 as f32,
    )
}

/// The pixel of a `size` frame where world point `p` appeared in the last frame.
pub fn pixel_of(app: &App, p: glam::Vec3, size: (u32, u32)) -> (u32, u32) {
    let q = image_point(app, p, size);
    (q.x as u32, q.y as u32)
}

/// The mean rgb of the (2·`half` + 1)² pixels of `img` around the image of world point
/// `p` in the last frame.
pub fn block_mean(app: &App, img: &image::Rgba32FImage, p: glam::Vec3, half: i32) -> glam::Vec3 {
    let (x, y) = pixel_of(app, p, img.dimensions());
    let mut sum = glam::Vec3::ZERO;
    for dy in -half..=half {
        for dx in -half..=half {
            let q = img
                .get_pixel((x as i32 + dx) as u32, (y as i32 + dy) as u32)
                .0;
            sum += glam::Vec3::new(q[0], q[1], q[2]);
        }
    }
    sum / ((2 * half + 1) * (2 * half + 1)) as f32
}

/// Panics unless every channel of the last frame's HDR image is finite.
pub fn assert_finite(app: &App) {
    let hdr = app.read_hdr_image().expect("hdr");
    let bad = hdr
        .pixels()
        .filter(|p| !p.0.iter().all(|v| v.is_finite()))
        .count();
    assert_eq!(bad, 0, "{bad} pixels are not finite");
}

/// No probes, ambient occlusion or screen-space reflections: only direct light and the
/// environment, for tests that look at one surface's own shading.
pub fn indirect_off(app: &mut App) {
    let mut q = app.world_mut().resource_mut::<lumen::quality::Quality>();
    q.gi.enabled = false;
    q.reflection_probes.enabled = false;
    q.ao.resolution = lumen::quality::AoResolution::Off;
    q.ssr.enabled = false;
}

/// A texture slot of `texture` sampled nearest at every level: texel-exact lookups.
pub fn nearest_slot(texture: lumen::scene::TextureHandle) -> lumen::scene::TextureSlot {
    use lumen::scene::{Filter, Sampler, TextureSlot};
    TextureSlot {
        sampler: Sampler {
            mag: Filter::Nearest,
            min: Filter::Nearest,
            mipmap: Filter::Nearest,
            ..Sampler::default()
        },
        ..TextureSlot::new(texture)
    }
}

/// What the plan of `report` decided for `pass`.
pub fn decision(
    report: &lumen::FrameReport,
    pass: lumen::render::graph::PassId,
) -> lumen::render::graph::Decision {
    report
        .plan
        .passes
        .iter()
        .find(|(id, _)| *id == pass)
        .map(|(_, d)| d.clone())
        .expect("the pass is in the plan")
}

/// meshoptimizer's attribute codec (`EXT_meshopt_compression` mode 0) in its plainest
/// legal form: each group of 16 byte deltas stored whole (header bits 3), zigzag-coded
/// against the previous element, from a zero baseline in the tail.
pub fn meshopt_attributes(data: &[u8], stride: usize) -> Vec<u8> {
    let count = data.len() / stride;
    let block_max = ((8192 / stride) & !15).min(256);
    let mut out = vec![0xa0];
    let mut last = vec![0u8; stride];
    let mut start = 0;
    while start < count {
        let block = block_max.min(count - start);
        let groups = block.div_ceil(16);
        for (k, previous) in last.iter_mut().enumerate() {
            out.extend(std::iter::repeat_n(0xffu8, groups.div_ceil(4)));
            let mut deltas = vec![0u8; groups * 16];
            for (i, delta) in deltas.iter_mut().take(block).enumerate() {
                let v = data[(start + i) * stride + k];
                let d = v.wrapping_sub(*previous) as i8;
                *delta = ((d << 1) ^ (d >> 7)) as u8;
                *previous = v;
            }
            out.extend(deltas);
        }
        start += block;
    }
    out.extend(vec![0u8; stride.max(32)]);
    out
}

/// The triangle codec (mode 1) in its plainest legal form: every triangle coded `0xff`
/// with all three indices explicit (zigzag deltas from the last, in varints).
pub fn meshopt_triangles(indices: &[u32]) -> Vec<u8> {
    let mut codes = vec![0xe1];
    let mut data = Vec::new();
    let mut last = 0u32;
    for triangle in indices.chunks(3) {
        codes.push(0xff);
        data.push(0xff);
        for &i in triangle {
            let d = i.wrapping_sub(last) as i32;
            let mut z = ((d << 1) ^ (d >> 31)) as u32;
            while z >= 0x80 {
                data.push((z & 0x7f) as u8 | 0x80);
                z >>= 7;
            }
            data.push(z as u8);
            last = i;
        }
    }
    [codes, data, vec![0u8; 16]].concat()
}

/// The views of [`quad_buffer`]'s `bin` (positions, texture coordinates, indices)
/// compressed by `EXT_meshopt_compression` into one stream: the packed bytes (buffer 0)
/// and the three buffer views, decoded into buffer 1. `corrupt` breaks the index
/// stream's header.
pub fn meshopt_quad(bin: &[u8], corrupt: bool) -> (Vec<u8>, Vec<serde_json::Value>) {
    let indices: Vec<u32> = bin[80..92]
        .chunks(2)
        .map(|c| u32::from(u16::from_le_bytes([c[0], c[1]])))
        .collect();
    let mut triangles = meshopt_triangles(&indices);
    if corrupt {
        triangles[0] = 0xe0;
    }
    let streams = [
        meshopt_attributes(&bin[..48], 12),
        meshopt_attributes(&bin[48..80], 8),
        triangles,
    ];
    let mut packed = Vec::new();
    let mut views = Vec::new();
    for (k, (stream, (offset, length, stride, count, mode))) in streams
        .iter()
        .zip([
            (0, 48, 12, 4, "ATTRIBUTES"),
            (48, 32, 8, 4, "ATTRIBUTES"),
            (80, 12, 2, 6, "TRIANGLES"),
        ])
        .enumerate()
    {
        let mut view = serde_json::json!({"buffer": 1, "byteOffset": offset, "byteLength": length,
            "extensions": {"EXT_meshopt_compression": {
                "buffer": 0, "byteOffset": packed.len(), "byteLength": stream.len(),
                "byteStride": stride, "count": count, "mode": mode}}});
        if k < 2 {
            view["byteStride"] = serde_json::json!(stride);
        }
        views.push(view);
        packed.extend_from_slice(stream);
    }
    (packed, views)
}

/// The `index`th (from 0) `sh` code block after `heading` in `markdown`: a recipe of the
/// docs, for a test to run as written.
pub fn sh_block_after<'a>(markdown: &'a str, heading: &str, index: usize) -> &'a str {
    let from = markdown
        .find(heading)
        .unwrap_or_else(|| panic!("the docs have no '{heading}'"));
    let mut rest = &markdown[from..];
    for _ in 0..index {
        let start = rest.find("```sh\n").expect("a sh block") + "```sh\n".len();
        let end = rest[start..].find("```").expect("the block's end");
        rest = &rest[start + end + 3..];
    }
    let start = rest.find("```sh\n").expect("a sh block") + "```sh\n".len();
    let end = rest[start..].find("```").expect("the block's end");
    &rest[start..start + end]
}

/// A small deterministic generator (xorshift) so that generated cases are the same on
/// every run.
pub struct Rng(pub u64);

impl Rng {
    /// A uniform number in [0, 1).
    pub fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    /// A unit direction, uniform on the sphere.
    pub fn dir(&mut self) -> glam::Vec3 {
        let z = self.next() * 2.0 - 1.0;
        let phi = self.next() * std::f32::consts::TAU;
        let r = (1.0 - z * z).max(0.0).sqrt();
        glam::Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    /// A point uniform in the box `lo..hi`.
    pub fn in_box(&mut self, lo: glam::Vec3, hi: glam::Vec3) -> glam::Vec3 {
        lo + (hi - lo) * glam::Vec3::new(self.next(), self.next(), self.next())
    }
}
