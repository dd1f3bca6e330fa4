//! Skinning and morph targets on the GPU: a two-bone bar bent 90° puts its tip where the
//! joint matrices say (in the G-buffer and in the sun's shadow), a morph weight of 0.5
//! moves a glTF quad halfway and turns a quad's normals halfway, and the Fox in its Walk
//! pose stays inside its bounds.

use crate::common;

use glam::Mat4;
use lumen::app::FrameTarget;
use lumen::assets::gltf::load_gltf;
use lumen::prelude::*;
use lumen::scene::{MeshData, Vertex};
use serde_json::json;
use std::path::{Path, PathBuf};

/// Half the bar's width (m).
const HALF_WIDTH: f32 = 0.2;

/// A 2 m square bar standing on y = 0, in rings of four vertices every 0.5 m: rings at
/// y ≤ 0.5 m follow joint 0, the ring at 1 m both joints equally, rings above joint 1.
fn bar() -> (MeshData, Vec<[u32; 4]>, Vec<[f32; 4]>) {
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let mut vertices = Vec::new();
    let (mut joints, mut weights) = (Vec::new(), Vec::new());
    for ring in 0..5 {
        let y = ring as f32 * 0.5;
        for (x, z) in corners {
            let n = Vec3::new(x, 0.0, z).normalize();
            vertices.push(Vertex::new(
                [x * HALF_WIDTH, y, z * HALF_WIDTH],
                n.into(),
                [0.0; 2],
                [1.0, 0.0, 0.0, 1.0],
            ));
            joints.push([0, 1, 0, 0]);
            weights.push(match ring {
                0 | 1 => [1.0, 0.0, 0.0, 0.0],
                2 => [0.5, 0.5, 0.0, 0.0],
                _ => [0.0, 1.0, 0.0, 0.0],
            });
        }
    }
    let mut indices = Vec::new();
    for ring in 0..4u32 {
        for side in 0..4u32 {
            let (a, b) = (ring * 4 + side, ring * 4 + (side + 1) % 4);
            indices.extend([a, b + 4, b, a, a + 4, b + 4]);
        }
    }
    // Caps: the bottom faces down, the top up.
    indices.extend([0, 1, 2, 0, 2, 3, 16, 18, 17, 16, 19, 18]);
    (MeshData { vertices, indices }, joints, weights)
}

/// The bar (red) on a white floor under a sun straight above, seen from above and in
/// front; joint 1 (at y = 1 m) turned `bend` radians about z. Returns the app and the
/// bar's entity.
fn bent_bar(bend: f32) -> (App, Entity) {
    let mut app = App::headless().expect("a GPU adapter");
    app.keep_target(FrameTarget::GBuffer0);
    app.keep_target(FrameTarget::Motion);
    let (mesh, joints, weights) = bar();
    let handle = app
        .add_deformable_mesh(mesh, joints, weights, Vec::new())
        .expect("bar");
    let floor = app
        .add_mesh(lumen::assets::procedural::plane(6.0, 6.0))
        .expect("floor");
    let world = app.world_mut();
    let root = world.spawn(Transform::IDENTITY).id();
    let elbow = world
        .spawn((
            Transform::from_xyz(0.0, 1.0, 0.0).with_rotation(Quat::from_rotation_z(bend)),
            ChildOf(root),
        ))
        .id();
    let bar = world
        .spawn((
            Mesh3d(handle),
            Material::new(Vec3::new(1.0, 0.0, 0.0), 0.0, 0.8),
            // Ignored: a skinned mesh follows its joints only.
            Transform::from_xyz(50.0, 0.0, 0.0),
            SkinnedMesh {
                joints: vec![root, elbow],
                inverse_bind: vec![Mat4::IDENTITY, Mat4::from_translation(-Vec3::Y)].into(),
            },
        ))
        .id();
    world.spawn((
        Mesh3d(floor),
        Material::new(Vec3::splat(0.8), 0.0, 0.8),
        Transform::IDENTITY,
    ));
    world.spawn((
        DirectionalLight {
            cast_shadows: true,
            ..DirectionalLight::default()
        },
        ShadowSettings::directional(),
        Transform::from_xyz(0.0, 5.0, 0.0).looking_at(Vec3::ZERO, Vec3::Z),
    ));
    world.spawn((
        Camera {
            exposure: Exposure::Ev100(13.0),
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 6.0, 5.0).looking_at(Vec3::new(0.0, 0.5, 0.0), Vec3::Y),
    ));
    (app, bar)
}

const SIZE: (u32, u32) = (160, 120);

/// The columns the red bar covers in the G-buffer's base colour: (leftmost, rightmost).
fn bar_columns(app: &App) -> (u32, u32) {
    let base = app.read_target(FrameTarget::GBuffer0).expect("gbuffer");
    let red: Vec<u32> = base
        .enumerate_pixels()
        .filter(|(_, _, p)| p.0[0] > 0.5 && p.0[1] < 0.3)
        .map(|(x, _, _)| x)
        .collect();
    assert!(red.len() > 30, "{} bar pixels", red.len());
    (
        red.iter().copied().min().unwrap_or(0),
        red.iter().copied().max().unwrap_or(0),
    )
}

#[test]
fn a_bent_two_bone_bar_puts_its_tip_where_the_joint_matrices_say() {
    let (mut app, bar) = bent_bar(std::f32::consts::FRAC_PI_2);
    app.render_headless(SIZE).expect("frame");
    // The CPU twin of the deformation pass, with the joint matrices of this frame.
    let world = app.world();
    let skin = world.get::<SkinnedMesh>(bar).expect("skin");
    let matrices = skin.joint_matrices(|e| world.get::<GlobalTransform>(e).map(|g| g.0));
    let meshes = world.resource::<Meshes>();
    let handle = world.get::<Mesh3d>(bar).expect("mesh").0;
    let mesh = meshes.get(handle).expect("mesh data");
    let deformed = meshes
        .deformation(handle)
        .expect("deformation")
        .deformed_vertices(mesh, Some(&matrices), &[]);
    // The top ring (vertices 16..20) is now the bar's left end, at x = −1 m.
    for v in &deformed[16..20] {
        assert!((v.position[0] + 1.0).abs() < 1e-5, "{:?}", v.position);
        assert!((v.position[1] - 1.0).abs() <= HALF_WIDTH + 1e-5);
    }
    let leftmost = deformed
        .iter()
        .map(|v| common::image_point(&app, Vec3::from(v.position), SIZE).x)
        .fold(f32::INFINITY, f32::min);
    let (left, right) = bar_columns(&app);
    println!("bent bar: covered columns {left}..={right}, the tip's image at x = {leftmost:.2} px");
    assert!(
        (left as f32 - leftmost).abs() <= 1.0,
        "the drawn tip at column {left}, the joint matrices put it at {leftmost:.2}"
    );
    // Unbent, it stands within ±0.2 m of x = 0 (and its own transform, 50 m away, is
    // ignored).
    let (mut straight, _) = bent_bar(0.0);
    straight.render_headless(SIZE).expect("frame");
    let (l0, r0) = bar_columns(&straight);
    let centre = common::image_point(&straight, Vec3::ZERO, SIZE).x;
    assert!(
        (l0 as f32) > centre - 6.0 && (r0 as f32) < centre + 6.0,
        "{l0}..={r0}"
    );
    assert!(left + 8 < l0, "bent {left}, straight {l0}");

    // The arm's shadow falls on the floor under it (x < 0), not on the other side.
    let hdr = app.read_hdr_image().expect("hdr");
    let floor = |app: &App, img: &image::Rgba32FImage, x: f32| {
        common::block_mean(app, img, Vec3::new(x, 0.0, 0.0), 0).element_sum()
    };
    let (under_arm, open) = (floor(&app, &hdr, -0.6), floor(&app, &hdr, 0.6));
    let straight_hdr = straight.read_hdr_image().expect("hdr");
    let unbent = floor(&straight, &straight_hdr, -0.6);
    println!("floor at x = −0.6 m: {under_arm:.3} bent, {unbent:.3} straight; at +0.6 m {open:.3}");
    assert!(
        under_arm < 0.5 * open,
        "{under_arm} under the arm, {open} in the open"
    );
    assert!(unbent > 0.9 * open, "{unbent} unbent, {open} in the open");
}

/// A glTF with one 1 m quad facing +z (normals +z) whose single morph target moves every
/// vertex +1 m along x, a LINEAR weights animation from 0 (at 0 s) to 1 (at 2 s), and a
/// camera 4 m in front of it. `quantized`: the positions, normals, texture coordinates,
/// tangents and offsets are normalized 16- and 8-bit integers (KHR_mesh_quantization, required), each element
/// padded to 4 bytes; the positions ±0.5 m are then ±16384 / 32767.
fn write_morphing_quad(dir: &Path, quantized: bool) -> PathBuf {
    let quad = [
        [-0.5f32, -0.5, 0.0],
        [0.5, -0.5, 0.0],
        [0.5, 0.5, 0.0],
        [-0.5, 0.5, 0.0],
    ];
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut view = |bin: &mut Vec<u8>, bytes: Vec<u8>, stride: Option<usize>| {
        let mut v = json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len()});
        if let Some(stride) = stride {
            v["byteStride"] = json!(stride);
        }
        bin.extend(bytes);
        views.push(v);
        views.len() - 1
    };
    let floats =
        |values: &[f32]| -> Vec<u8> { values.iter().flat_map(|f| f.to_le_bytes()).collect() };
    let (positions, normals, offsets, types) = if quantized {
        let i16n = |v: f32| ((v * 32767.0).round() as i16).to_le_bytes();
        let padded = |p: [f32; 3]| [i16n(p[0]), i16n(p[1]), i16n(p[2]), [0, 0]].concat();
        (
            view(
                &mut bin,
                quad.iter().flat_map(|p| padded(*p)).collect(),
                Some(8),
            ),
            view(&mut bin, [0u8, 0, 127, 0].repeat(4), Some(4)),
            view(
                &mut bin,
                (0..4).flat_map(|_| padded([1.0, 0.0, 0.0])).collect(),
                Some(8),
            ),
            (5122, 5120),
        )
    } else {
        (
            view(&mut bin, floats(quad.as_flattened()), None),
            view(&mut bin, floats(&[0.0, 0.0, 1.0].repeat(4)), None),
            view(&mut bin, floats(&[1.0, 0.0, 0.0].repeat(4)), None),
            (5126, 5126),
        )
    };
    // Texture coordinates (u16 normalized when quantized) and tangents +x (i8 normalized).
    let uvs = [[0.0f32, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];
    let (uv_view, tangent_view) = if quantized {
        let u16n = |v: f32| ((v * 65535.0).round() as u16).to_le_bytes();
        let uv_bytes = uvs.iter().flat_map(|t| [u16n(t[0]), u16n(t[1])].concat());
        (
            view(&mut bin, uv_bytes.collect(), None),
            view(&mut bin, [127u8, 0, 0, 127].repeat(4), None),
        )
    } else {
        (
            view(&mut bin, floats(uvs.as_flattened()), None),
            view(&mut bin, floats(&[1.0, 0.0, 0.0, 1.0].repeat(4)), None),
        )
    };
    let times = view(&mut bin, floats(&[0.0, 2.0]), None);
    let weights = view(&mut bin, floats(&[0.0, 1.0]), None);
    let indices = view(
        &mut bin,
        [0u16, 1, 2, 0, 2, 3]
            .iter()
            .flat_map(|i| i.to_le_bytes())
            .collect(),
        None,
    );
    std::fs::write(dir.join("morph.bin"), &bin).expect("bin");
    let (size, half) = if quantized {
        (types.0, 16384.0)
    } else {
        (5126, 0.5)
    };
    let normalized = quantized;
    let mut gltf = json!({
        "asset": {"version": "2.0"},
        "buffers": [{"uri": "morph.bin", "byteLength": bin.len()}],
        "bufferViews": views,
        "accessors": [
            {"bufferView": positions, "componentType": size, "normalized": normalized,
             "count": 4, "type": "VEC3", "min": [-half, -half, 0.0], "max": [half, half, 0.0]},
            {"bufferView": offsets, "componentType": size, "normalized": normalized,
             "count": 4, "type": "VEC3"},
            {"bufferView": times, "componentType": 5126, "count": 2, "type": "SCALAR",
             "min": [0.0], "max": [2.0]},
            {"bufferView": weights, "componentType": 5126, "count": 2, "type": "SCALAR"},
            {"bufferView": indices, "componentType": 5123, "count": 6, "type": "SCALAR"},
            {"bufferView": normals, "componentType": types.1, "normalized": normalized,
             "count": 4, "type": "VEC3"},
            {"bufferView": uv_view, "componentType": if quantized { 5123 } else { 5126 },
             "normalized": normalized, "count": 4, "type": "VEC2"},
            {"bufferView": tangent_view, "componentType": types.1, "normalized": normalized,
             "count": 4, "type": "VEC4"}
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 5,
                                                   "TEXCOORD_0": 6, "TANGENT": 7}, "indices": 4,
                                    "targets": [{"POSITION": 1}]}],
                    "weights": [0.0]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.0, 0.0, 4.0]}],
        "scenes": [{"nodes": [0, 1]}],
        "animations": [{"channels": [{"sampler": 0, "target": {"node": 0, "path": "weights"}}],
                        "samplers": [{"input": 2, "output": 3, "interpolation": "LINEAR"}]}]
    });
    if quantized {
        gltf["extensionsUsed"] = json!(["KHR_mesh_quantization"]);
        gltf["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
    }
    let path = dir.join("morph.gltf");
    std::fs::write(&path, serde_json::to_string(&gltf).expect("json")).expect("gltf");
    path
}

#[test]
fn a_morph_weight_of_one_half_moves_a_gltf_quad_halfway() {
    for quantized in [false, true] {
        morph_quad_moves_halfway(quantized);
    }
}

/// The quad of [`write_morphing_quad`], its vertices as read, and its columns at weights
/// 0 and 0.5.
fn morph_quad_moves_halfway(quantized: bool) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = write_morphing_quad(dir.path(), quantized);
    let mut app = App::headless().expect("a GPU adapter");
    let summary = load_gltf(&mut app, &path).expect("loads");
    assert!(summary.warnings.is_empty(), "{:?}", summary.warnings);
    // Quantized, the vertices read back within the quantization step (1 / 32767 m) and
    // the normals exactly +z.
    let world = app.world_mut();
    let handle = world.query::<&Mesh3d>().single(world).expect("one mesh").0;
    let meshes = world.resource::<Meshes>();
    let mesh = meshes.get(handle).expect("mesh");
    for (v, corner) in
        mesh.vertices
            .iter()
            .zip([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
    {
        assert!(
            (v.position[0] - corner[0]).abs() < 1.0 / 32767.0
                && (v.position[1] - corner[1]).abs() < 1.0 / 32767.0
                && v.position[2] == 0.0,
            "quantized {quantized}: {:?}",
            v.position
        );
        assert_eq!(v.normal, [0.0, 0.0, 1.0], "quantized {quantized}");
        assert_eq!(v.tangent, [1.0, 0.0, 0.0, 1.0], "quantized {quantized}");
    }
    let read_uvs: Vec<[f32; 2]> = mesh.vertices.iter().map(|v| v.uv).collect();
    assert_eq!(read_uvs, [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]);
    let offsets = &meshes.deformation(handle).expect("morph targets").targets()[0].positions;
    assert_eq!(offsets, &vec![[1.0, 0.0, 0.0]; 4], "quantized {quantized}");
    let size = (128, 96);
    let columns = |app: &mut App, t: f32| {
        let world = app.world_mut();
        let mut players = world.query::<&mut AnimationPlayer>();
        let mut player = players.single_mut(world).expect("player");
        player.seek(t);
        player.pause();
        app.render_headless(size).expect("frame");
        let world = app.world_mut();
        let weights = world
            .query::<&MorphWeights>()
            .single(world)
            .expect("weights")
            .0
            .clone();
        let hdr = app.read_hdr_image().expect("hdr");
        let covered: Vec<u32> = hdr
            .enumerate_pixels()
            .filter(|(_, _, p)| p.0[3] > 0.5)
            .map(|(x, _, _)| x)
            .collect();
        let (l, r) = (
            covered.iter().copied().min().unwrap_or(0),
            covered.iter().copied().max().unwrap_or(0),
        );
        (weights, l, r)
    };
    let (w0, l0, r0) = columns(&mut app, 0.0);
    let (w1, l1, r1) = columns(&mut app, 1.0);
    assert_eq!(w0, [0.0]);
    assert_eq!(w1, [0.5]);
    // Halfway: the quad's left edge at x = 0 m, its right edge at x = 1 m.
    let at = |x: f32| common::image_point(&app, Vec3::new(x, 0.0, 0.0), size).x;
    println!(
        "morphed quad (quantized {quantized}): columns {l0}..={r0} at weight 0, {l1}..={r1} at 0.5 (x = 0 m at {:.1} px, 1 m at {:.1} px)",
        at(0.0),
        at(1.0)
    );
    assert!((l0 as f32 - at(-0.5)).abs() <= 1.0, "{l0} vs {}", at(-0.5));
    assert!((l1 as f32 - at(0.0)).abs() <= 1.0, "{l1} vs {}", at(0.0));
    assert!(
        (r1 as f32 + 1.0 - at(1.0)).abs() <= 1.0,
        "{r1} vs {}",
        at(1.0)
    );
}

#[test]
fn a_morphed_normal_turns_the_shading_normal() {
    // A 2 m quad facing the camera (+z) whose one morph target moves every normal by
    // (1, 0, −1): at weight w the normal is (w, 0, 1 − w), normalised in the shader. The
    // G-buffer's normal at the centre, at weights 0, 0.5 and 1.
    let corner = |x: f32, y: f32| {
        Vertex::new(
            [x, y, 0.0],
            [0.0, 0.0, 1.0],
            [0.5 + x / 2.0, 0.5 - y / 2.0],
            [1.0, 0.0, 0.0, 1.0],
        )
    };
    let mesh = MeshData {
        vertices: vec![
            corner(-1.0, -1.0),
            corner(1.0, -1.0),
            corner(1.0, 1.0),
            corner(-1.0, 1.0),
        ],
        indices: vec![0, 1, 2, 0, 2, 3],
    };
    let target = lumen::scene::MorphTarget {
        normals: vec![[1.0, 0.0, -1.0]; 4],
        ..Default::default()
    };
    let mut app = App::headless().expect("a GPU adapter");
    let handle = app
        .add_deformable_mesh(mesh, Vec::new(), Vec::new(), vec![target])
        .expect("quad");
    let world = app.world_mut();
    let quad = world
        .spawn((
            Mesh3d(handle),
            Material::new(Vec3::splat(0.5), 0.0, 0.5),
            Transform::IDENTITY,
            MorphWeights(vec![0.0]),
        ))
        .id();
    world.spawn((
        Camera::default(),
        Transform::from_xyz(0.0, 0.0, 3.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    let size = (32, 32);
    app.keep_target(FrameTarget::GBuffer1);
    for w in [0.0f32, 0.5, 1.0] {
        app.world_mut()
            .entity_mut(quad)
            .insert(MorphWeights(vec![w]));
        app.render_headless(size).expect("frame");
        let g1 = app.read_target(FrameTarget::GBuffer1).expect("gbuffer1");
        let p = g1.get_pixel(size.0 / 2, size.1 / 2).0;
        let normal = lumen::shading::encoding::oct_decode(Vec2::new(p[0], p[1]));
        let expected = Vec3::new(w, 0.0, 1.0 - w).normalize();
        println!("morph weight {w}: normal {normal}, expected {expected}");
        assert!(
            (normal - expected).length() < 0.01,
            "weight {w}: {normal} against {expected}"
        );
    }
}

#[test]
fn the_fox_walks_at_half_a_second_inside_its_bounds() {
    // Fox.glb (CC BY 4.0, see assets/README.md): one skinned mesh of 24 joints.
    let fox = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/models/Fox.glb");
    let mut app = App::headless().expect("a GPU adapter");
    let summary = load_gltf(&mut app, &fox).expect("the fox loads");
    assert!(summary.warnings.is_empty(), "{:?}", summary.warnings);
    let size = (128, 128);
    let render = |app: &mut App, clip: &str| {
        let world = app.world_mut();
        let mut players = world.query::<&mut AnimationPlayer>();
        let mut player = players.single_mut(world).expect("player");
        player.play_named(clip).expect("clip");
        player.seek(0.5);
        player.pause();
        app.render_headless(size).expect("frame");
        let hdr = app.read_hdr_image().expect("hdr");
        hdr.pixels().map(|p| p.0[3] > 0.5).collect::<Vec<bool>>()
    };
    let walk = render(&mut app, "Walk");
    // Every skinned vertex (the CPU twin of the pass, with this frame's joints) lies in
    // the bounding sphere that culling and shadow fitting used.
    let world = app.world_mut();
    let (entity, handle, skin) = world
        .query::<(Entity, &Mesh3d, &SkinnedMesh)>()
        .single(world)
        .map(|(e, m, s)| (e, m.0, s.clone()))
        .expect("one skinned mesh");
    let world = app.world();
    let matrices = skin.joint_matrices(|e| world.get::<GlobalTransform>(e).map(|g| g.0));
    let meshes = world.resource::<Meshes>();
    let deformed = meshes
        .deformation(handle)
        .expect("deformation")
        .deformed_vertices(meshes.get(handle).expect("mesh"), Some(&matrices), &[]);
    let frame = world.resource::<lumen::render::extract::ExtractedFrame>();
    let deformed_index = frame
        .deformed
        .instances
        .iter()
        .position(|d| d.entity == entity)
        .expect("the fox is deformed this frame") as u32;
    let caster = frame
        .casters
        .iter()
        .find(|c| c.deformed == Some(deformed_index))
        .expect("the fox casts a shadow");
    let outside = deformed
        .iter()
        .filter(|v| Vec3::from(v.position).distance(caster.center) > caster.radius * (1.0 + 1e-5))
        .count();
    let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for v in &deformed {
        lo = lo.min(Vec3::from(v.position));
        hi = hi.max(Vec3::from(v.position));
    }
    println!(
        "Fox Walk at 0.5 s: vertices span {lo:.3}..{hi:.3} m; bounding sphere {:.3} r {:.3} m",
        caster.center, caster.radius
    );
    assert_eq!(outside, 0, "{outside} skinned vertices outside the bounds");
    // Drawn: every covered pixel lies in the image of the sphere's box, and the Walk pose
    // differs from the Survey pose at the same time.
    let (mut x0, mut y0, mut x1, mut y1) = (f32::MAX, f32::MAX, f32::MIN, f32::MIN);
    for corner in 0..8 {
        let sign = |bit: i32| if corner & bit == 0 { -1.0 } else { 1.0 };
        let p = caster.center + Vec3::new(sign(1), sign(2), sign(4)) * caster.radius;
        let q = common::image_point(&app, p, size);
        (x0, y0, x1, y1) = (x0.min(q.x), y0.min(q.y), x1.max(q.x), y1.max(q.y));
    }
    let stray = walk
        .iter()
        .enumerate()
        .filter(|(i, c)| {
            let (x, y) = ((i % size.0 as usize) as f32, (i / size.0 as usize) as f32);
            **c && (x + 1.0 < x0 || x > x1 || y + 1.0 < y0 || y > y1)
        })
        .count();
    assert_eq!(
        stray, 0,
        "{stray} fox pixels outside the image of its bounds"
    );
    let covered = walk.iter().filter(|c| **c).count();
    assert!(covered > 200, "{covered} fox pixels");
    let survey = render(&mut app, "Survey");
    let differ = walk.iter().zip(&survey).filter(|(a, b)| a != b).count();
    println!("Walk covers {covered} px; {differ} px differ from Survey at 0.5 s");
    assert!(differ > covered / 20, "{differ} of {covered}");
}

#[test]
fn skinned_motion_reaches_the_motion_vectors() {
    let (mut app, bar) = bent_bar(60f32.to_radians());
    app.set_progressive_taa(true);
    common::indirect_off(&mut app);
    app.world_mut().resource_mut::<Quality>().aa.method = lumen::quality::AaMethod::Taa;
    app.render_headless(SIZE).expect("first frame");
    let elbow = app.world().get::<SkinnedMesh>(bar).expect("skin").joints[1];
    // A point on the arm's upper face (rest pose x = +0.2 m, y = 1.75 m), carried by
    // joint 1 alone, before and after the elbow turns from 60° to 90°.
    let on_arm = Vec3::new(HALF_WIDTH, 1.75, 0.0);
    let carried = |app: &App| {
        let world = app.world();
        let skin = world.get::<SkinnedMesh>(bar).expect("skin");
        let m = skin.joint_matrices(|e| world.get::<GlobalTransform>(e).map(|g| g.0));
        m[1].transform_point3(on_arm)
    };
    let before = carried(&app);
    app.world_mut().entity_mut(elbow).insert(
        Transform::from_xyz(0.0, 1.0, 0.0).with_rotation(Quat::from_rotation_z(90f32.to_radians())),
    );
    app.render_headless(SIZE).expect("second frame");
    let after = carried(&app);
    let expected = common::image_point(&app, after, SIZE) - common::image_point(&app, before, SIZE);
    let motion = app.read_target(FrameTarget::Motion).expect("motion");
    let (x, y) = common::pixel_of(&app, after, SIZE);
    let got = Vec2::new(motion.get_pixel(x, y).0[0], motion.get_pixel(x, y).0[1]);
    let floor = common::pixel_of(&app, Vec3::new(1.5, 0.0, 1.0), SIZE);
    let still = motion.get_pixel(floor.0, floor.1).0;
    println!(
        "arm point: motion {got:.2} px, expected {expected:.2} px; floor {:.3} px",
        Vec2::new(still[0], still[1])
    );
    assert!(expected.length() > 3.0, "{expected}");
    assert!(
        (got - expected).length() < 1.5,
        "motion {got} where the joints moved the arm by {expected}"
    );
    assert!(Vec2::new(still[0], still[1]).length() < 0.05, "{still:?}");
}
