//! Extraction: ECS components → plain, GPU-ready data for one frame.
//!
//! This is the only place the renderer reads the scene's components. Exposure is applied
//! here, in f32, to every light, emissive and background value before anything reaches a
//! 16-bit target (pre-exposure, docs/src/formulas.md#numerical-guards).

use crate::color::Tonemapper;
use crate::error::Error;
use crate::punctual::spot_scale_offset;
use crate::quality::Quality;
use crate::render::extract_deform::{DeformSources, DeformedFrame};
use crate::render::frame::{CaptureView, FrameErrors, FrameOutput};
use crate::render::gpu_types::{GpuInstance, GpuLight, GpuView};
use crate::render::jitter::Jitter;
use crate::render::shadow_views::{
    CameraForShadows, ShadowView, directional_views, frustum_planes, point_views,
    sphere_in_frustum, spot_view,
};
use crate::scene::{
    Background, Camera, Cascades, DirectionalLight, Environment, EnvironmentSource,
    GlobalTransform, Material, Mesh3d, MeshHandle, Meshes, NotShadowCaster, NotShadowReceiver,
    PointLight, ShadowSettings, SpotLight, Transmission,
};
use bevy_ecs::prelude::*;
use glam::{Mat3, Mat4, Vec3};

/// The camera as the passes need it.
#[derive(Clone, Debug, PartialEq)]
pub struct ExtractedCamera {
    /// World-space position in metres.
    pub position: Vec3,
    /// View from world.
    pub view_from_world: Mat4,
    /// Clip from view (reversed Z), without the frame's jitter.
    pub clip_from_view: Mat4,
    /// Linear exposure multiplier applied to luminance.
    pub exposure: f32,
    /// The EV100 equivalent of `exposure`.
    pub ev100: f32,
    /// Tone mapper.
    pub tonemapper: Tonemapper,
    /// Lens settings after clamping (docs/src/formulas.md#numerical-guards).
    pub lens: crate::scene::Lens,
    /// Focal length (m), from the field of view and the sensor height.
    pub focal_length_m: f32,
    /// Vertical field of view (rad) and aspect ratio.
    pub fov_y: f32,
    /// Width / height.
    pub aspect: f32,
    /// Depth of field, if on.
    pub depth_of_field: Option<crate::scene::DepthOfField>,
    /// Vignetting strength (0 = none).
    pub vignette: f32,
    /// Automatic exposure settings, if that mode is on.
    pub auto_exposure: Option<crate::scene::AutoExposure>,
    /// Settings that were out of range and clamped, one line each.
    pub notes: Vec<String>,
}

/// Consecutive instances of one mesh, drawn with one instanced draw call. Those whose
/// bounding sphere touches the camera's view frustum come first: the G-buffer pass draws
/// only them. Blended and transmissive instances come after every opaque batch, one per
/// batch, farthest from the camera first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Batch {
    /// The mesh.
    pub mesh: MeshHandle,
    /// Index into [`ExtractedFrame::material_maps`] of the batch's textures (`None`:
    /// factors only). A blended, transmissive or clearcoated material without textures
    /// gets neutral maps here, which the forward passes bind.
    pub maps: Option<u32>,
    /// The entities have `MaterialMaps` of their own: the G-buffer draws them with its
    /// textured variant (else with the plain one, whatever `maps` holds).
    pub textured: bool,
    /// Back faces drawn too.
    pub double_sided: bool,
    /// Alpha-blended ([`crate::scene::Material::blend`]): one instance, drawn by the
    /// transparent pass instead of the G-buffer.
    pub blend: bool,
    /// Transmissive ([`crate::scene::Material::transmission`]): one instance, drawn by
    /// the transparent pass over a copy of the opaque frame; its maps entry holds the
    /// transmission.
    pub transmissive: bool,
    /// Clearcoated ([`crate::scene::Material::coat`]) and opaque: drawn by the G-buffer
    /// and then again by the layers pass; its maps entry holds the coat (so does a
    /// blended or transmissive batch's, whose coat the transparent pass draws).
    pub coated: bool,
    /// With a sheen ([`crate::scene::Material::layer_sheen`]) and opaque: drawn again by
    /// the layers pass, under the coat; its maps entry holds the sheen.
    pub sheened: bool,
    /// A relit base: anisotropic ([`crate::scene::Material::anisotropic`]), with a
    /// tinted specular colour ([`crate::scene::Material::tint`]), iridescent
    /// ([`crate::scene::Material::iridescent`]) or translucent
    /// ([`crate::scene::Material::translucent`]). Drawn by the G-buffer,
    /// then lit again by the layers pass with what the G-buffer cannot hold; its maps
    /// entry holds the anisotropy, the tint, the film and the diffuse transmission.
    pub relit: bool,
    /// Index into [`DeformedFrame::instances`] of its one instance, drawn from the
    /// deformation pass's vertices (`None`: the mesh's own).
    pub deformed: Option<u32>,
    /// Index of the first instance in [`ExtractedFrame::instances`].
    pub first_instance: u32,
    /// Number of instances.
    pub count: u32,
    /// How many of them, from the first, are inside the camera's view frustum.
    pub visible: u32,
}

impl Batch {
    /// Drawn by the transparent pass (blended or transmissive), not the G-buffer.
    pub fn transparent(&self) -> bool {
        self.blend || self.transmissive
    }
}

/// A textured or forward-drawn material as the frame's passes bind it: its maps and, for
/// a transmissive one, its transmission with the thickness in world metres.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameMaps {
    /// The textures and their factors.
    pub maps: crate::scene::MaterialMaps,
    /// The transmission, its thickness scaled by the instance's transform (m).
    pub transmission: Option<Transmission>,
    /// Alpha-blended: the transparent pass composites with the base alpha as coverage
    /// (a transmissive surface that is not blended covers what is behind it).
    pub blend: bool,
    /// The clearcoat the layers pass draws over the opaque surface (clamped).
    pub clearcoat: Option<crate::scene::Clearcoat>,
    /// The sheen the layers pass draws over the opaque surface (clamped).
    pub sheen: Option<crate::scene::Sheen>,
    /// The anisotropy the layers pass relights the opaque surface with (clamped).
    pub anisotropy: Option<crate::scene::Anisotropy>,
    /// The specular tint the layers pass relights it with (clamped; `None`: white).
    pub specular_tint: Option<Vec3>,
    /// The iridescent film the layers pass relights it with (clamped).
    pub iridescence: Option<crate::scene::Iridescence>,
    /// The diffuse transmission the layers pass relights it with (clamped).
    pub diffuse_transmission: Option<crate::scene::DiffuseTransmission>,
}

/// A shadow-casting instance and its world-space bounding sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Caster {
    /// Index into [`ExtractedFrame::instances`].
    pub instance: u32,
    /// Its mesh.
    pub mesh: MeshHandle,
    /// Bounding sphere centre (m).
    pub center: Vec3,
    /// Bounding sphere radius (m).
    pub radius: f32,
    /// Index into [`DeformedFrame::instances`] when it is deformed.
    pub deformed: Option<u32>,
    /// Index into [`ExtractedFrame::material_maps`] of its maps where they mask by alpha
    /// (glTF `alphaMode: MASK`, the shadow pass drops the texels the G-buffer drops) or
    /// where it is blended. `None`: an opaque caster.
    pub mask: Option<u32>,
    /// Blended: the shadow pass keeps a fraction α of its texels, in an ordered dither
    /// (docs/src/materials.md#blended-shadows).
    pub blend: bool,
}

/// The environment as the passes need it.
#[derive(Clone, Debug)]
pub struct ExtractedEnvironment {
    /// The image, if not uniform.
    pub image: Option<std::sync::Arc<crate::scene::EquirectImage>>,
    /// Uniform radiance (cd/m² before the intensity); zero for images.
    pub uniform: Vec3,
    /// Intensity (cd/m² per unit value).
    pub intensity: f32,
    /// Rotation about +Y (rad).
    pub rotation: f32,
    /// Whether the sky pass draws it as the background.
    pub show_background: bool,
    /// Background blur as a perceptual roughness 0..1.
    pub background_blur: f32,
}

/// Number of shadowed lights of each kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ShadowCounts {
    /// Directional lights with shadows.
    pub directional: u32,
    /// Point lights with shadows.
    pub point: u32,
    /// Spot lights with shadows.
    pub spot: u32,
    /// Lights with `cast_shadows` whose shadows were not drawn (shadows disabled or
    /// nothing casts).
    pub skipped: u32,
}

/// Number of lights of each kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LightCounts {
    /// Directional lights.
    pub directional: u32,
    /// Point lights.
    pub point: u32,
    /// Spot lights.
    pub spot: u32,
}

impl LightCounts {
    /// All lights.
    pub fn total(&self) -> u32 {
        self.directional + self.point + self.spot
    }
}

/// Everything one frame draws, extracted from the World.
#[derive(Resource, Default, Debug)]
pub struct ExtractedFrame {
    /// The active camera; `None` if the scene has none.
    pub camera: Option<ExtractedCamera>,
    /// Per-frame view uniform.
    pub view: GpuView,
    /// Instances, sorted by mesh; the blended ones last, back to front.
    pub instances: Vec<GpuInstance>,
    /// Draw batches over `instances`.
    pub batches: Vec<Batch>,
    /// The distinct material maps of this frame's instances.
    pub material_maps: Vec<FrameMaps>,
    /// Lights: directional, then point, then spot.
    pub lights: Vec<GpuLight>,
    /// How many of each kind.
    pub light_counts: LightCounts,
    /// How many directional, point and spot lights cast shadows this frame.
    pub shadowed_counts: [u32; 3],
    /// Triangles drawn by the G-buffer pass (those of the instances in view).
    pub triangles: u64,
    /// Instances that cast shadows, sorted by mesh.
    pub casters: Vec<Caster>,
    /// Number of instances that receive shadows.
    pub receivers: usize,
    /// Shadow views, in the order the lights refer to them.
    pub shadow_views: Vec<ShadowView>,
    /// Shadowed lights of each kind.
    pub shadow_counts: ShadowCounts,
    /// Whether shadows were turned off for the frame (`Quality::shadows`).
    pub shadows_disabled: bool,
    /// The first environment, if any.
    pub environment: Option<ExtractedEnvironment>,
    /// What motion vectors and temporal anti-aliasing need of the previous frame.
    pub temporal: TemporalFrame,
    /// The skinned and morphed instances, with their joint matrices and weights.
    pub deformed: DeformedFrame,
}

impl ExtractedFrame {
    /// Instances inside the camera's view frustum: the ones the G-buffer pass draws.
    pub fn visible_instances(&self) -> u32 {
        self.batches.iter().map(|b| b.visible).sum()
    }

    /// The batches the G-buffer pass draws: the opaque ones with an instance in view.
    pub fn drawn_batches(&self) -> impl Iterator<Item = &Batch> {
        self.batches
            .iter()
            .filter(|b| b.visible > 0 && !b.transparent())
    }

    /// The blended and transmissive batches in view, farthest first: what the
    /// transparent pass draws, in its order.
    pub fn transparent_batches(&self) -> impl Iterator<Item = &Batch> {
        self.batches
            .iter()
            .filter(|b| b.visible > 0 && b.transparent())
    }

    /// The clearcoated batches in view: the coats the layers pass draws over the lit frame.
    pub fn coated_batches(&self) -> impl Iterator<Item = &Batch> {
        self.drawn_batches().filter(|b| b.coated)
    }

    /// The batches in view with a sheen: the sheens the layers pass draws over the lit
    /// frame, before the coats.
    pub fn sheened_batches(&self) -> impl Iterator<Item = &Batch> {
        self.drawn_batches().filter(|b| b.sheened)
    }

    /// The relit batches in view (anisotropic, specular-tinted or iridescent): the
    /// surfaces the layers pass lights again, before any sheen or coat.
    pub fn relit_batches(&self) -> impl Iterator<Item = &Batch> {
        self.drawn_batches().filter(|b| b.relit)
    }

    /// The G-buffer pass's draw calls: one per batch with an instance in view.
    pub fn draws(&self) -> usize {
        self.drawn_batches().count()
    }
}

/// This frame and the previous one, for motion vectors: the matrices on every frame that
/// is not a probe capture (the previous one equals this one unless TAA runs), the
/// instances' previous transforms only when TAA runs.
#[derive(Clone, Debug, Default)]
pub struct TemporalFrame {
    /// Clip from world without the jitter, this frame.
    pub clip_from_world: Mat4,
    /// Clip from world without the jitter, the previous frame (this frame's on the first).
    pub previous_clip_from_world: Mat4,
    /// Per instance (parallel to [`ExtractedFrame::instances`]), its world-from-local
    /// transform in the previous frame (its current one if it is new).
    pub previous_world: Vec<[[f32; 4]; 4]>,
    /// How many instances' transforms changed since the previous frame.
    pub moved: usize,
}

/// What extraction remembers of the previous frame for [`TemporalFrame`].
#[derive(Resource, Default, Debug)]
pub struct TemporalMemory {
    /// Clip from world without jitter.
    pub clip_from_world: Option<Mat4>,
    /// Each drawn entity's world-from-local transform.
    pub world: std::collections::HashMap<Entity, Mat4>,
}

fn normal_matrix(m: &Mat4) -> Option<[[f32; 4]; 3]> {
    let m3 = Mat3::from_mat4(*m);
    let det = m3.determinant();
    if !det.is_finite() || det.abs() < 1e-12 {
        return None;
    }
    let n = m3.inverse().transpose();
    Some([
        n.x_axis.extend(0.0).into(),
        n.y_axis.extend(0.0).into(),
        n.z_axis.extend(0.0).into(),
    ])
}

/// The bounding sphere (centre and radius, m) of a box under `m`.
fn sphere_around(aabb: &crate::scene::Aabb, m: &Mat4) -> (Vec3, f32) {
    let center = m.transform_point3(aabb.center());
    let scale = m
        .x_axis
        .truncate()
        .length()
        .max(m.y_axis.truncate().length())
        .max(m.z_axis.truncate().length());
    (center, (aabb.max - aabb.min).length() * 0.5 * scale)
}

/// Shadow settings with out-of-range values clamped (resolution × `scale` into 64..=8192,
/// biases ≥ 0).
fn sanitized(s: ShadowSettings, scale: f32) -> ShadowSettings {
    let bias = |b: f32| {
        if b.is_finite() {
            b.clamp(0.0, 100.0)
        } else {
            1.0
        }
    };
    ShadowSettings {
        resolution: (s.resolution as f32 * finite_or(scale, 1.0).clamp(0.0, 64.0))
            .round()
            .clamp(64.0, 8192.0) as u32,
        depth_bias: bias(s.depth_bias),
        slope_bias: bias(s.slope_bias),
        normal_bias: bias(s.normal_bias),
    }
}

fn shadow_fields(
    first: usize,
    views: usize,
    size: f32,
    s: &ShadowSettings,
) -> ([f32; 4], [f32; 4]) {
    (
        [
            first as f32,
            views as f32,
            finite_or(size, 0.0).max(0.0),
            0.0,
        ],
        [s.depth_bias, s.slope_bias, s.normal_bias, 0.0],
    )
}

/// `cascade_far` of a light without cascades.
const NO_CASCADES: [f32; 4] = [f32::MAX; 4];

const NO_SHADOW: [f32; 4] = [-1.0, 0.0, 0.0, 0.0];

/// `t` with its factor clamped to 0..1, its index of refraction to 1..10, and its
/// thickness in world metres: the mesh's thickness × the transform's mean scale (the cube
/// root of |det|, as glTF's volume thickness is in the mesh's own units). Non-finite or
/// negative thicknesses become 0 (thin-walled), NaN attenuation values their defaults.
fn world_transmission(t: &Transmission, world_from_local: &Mat4) -> Transmission {
    let scale = world_from_local.determinant().abs().cbrt();
    let thickness = finite_or(t.thickness_m, 0.0).max(0.0) * finite_or(scale, 1.0);
    Transmission {
        factor: finite_or(t.factor, 0.0).clamp(0.0, 1.0),
        ior: crate::transmission::clamp_ior(t.ior),
        thickness_m: finite_or(thickness, 0.0),
        attenuation_color: Vec3::select(
            t.attenuation_color.cmpeq(t.attenuation_color),
            t.attenuation_color,
            Vec3::ONE,
        )
        .clamp(Vec3::ZERO, Vec3::ONE),
        attenuation_distance_m: if t.attenuation_distance_m.is_nan() {
            f32::INFINITY
        } else {
            t.attenuation_distance_m.max(0.0)
        },
        dispersion: finite_or(t.dispersion, 0.0).clamp(0.0, 1e3),
    }
}

fn finite_or(x: f32, fallback: f32) -> f32 {
    if x.is_finite() { x } else { fallback }
}

fn inv_range_squared(range_m: f32) -> f32 {
    if range_m.is_finite() && range_m > 0.0 {
        1.0 / (range_m * range_m)
    } else if range_m.is_finite() {
        // A zero or negative range reaches nothing: the smallest positive range.
        1.0 / (1e-6 * 1e-6)
    } else {
        0.0
    }
}

fn exposed(color: Vec3, intensity: f32, exposure: f32) -> [f32; 3] {
    let intensity = finite_or(intensity, 0.0).max(0.0);
    let v = color * (intensity * exposure);
    // Huge values stay finite in f32; the lighting pass clamps what it writes to f16.
    v.min(Vec3::splat(f32::MAX)).into()
}

/// What extraction reads of a drawn entity.
type Drawable = (
    Entity,
    &'static Mesh3d,
    &'static Material,
    &'static GlobalTransform,
    Has<NotShadowCaster>,
    Has<NotShadowReceiver>,
    Option<&'static crate::scene::MaterialMaps>,
);

/// Extracts the frame from the World (a system of the render schedule).
#[allow(clippy::too_many_arguments)]
pub fn extract_frame(
    cameras: Query<(Entity, &Camera, &GlobalTransform)>,
    drawables: Query<Drawable>,
    directional: Query<(
        &DirectionalLight,
        &GlobalTransform,
        Option<&ShadowSettings>,
        Option<&Cascades>,
    )>,
    points: Query<(&PointLight, &GlobalTransform, Option<&ShadowSettings>)>,
    spots: Query<(&SpotLight, &GlobalTransform, Option<&ShadowSettings>)>,
    environments: Query<(Entity, &Environment)>,
    meshes: Res<Meshes>,
    quality: Res<Quality>,
    metered: Res<crate::render::frame::MeteredExposure>,
    output: Res<FrameOutput>,
    capture: Option<Res<CaptureView>>,
    jitter: Option<Res<Jitter>>,
    mut memory: ResMut<TemporalMemory>,
    mut frame: ResMut<ExtractedFrame>,
    mut errors: ResMut<FrameErrors>,
    mut deform: DeformSources,
) {
    let frame = &mut *frame;
    let (width, height) = output.size;
    let aspect = width as f32 / height.max(1) as f32;

    let active = cameras
        .iter()
        .filter(|(_, c, _)| c.active)
        .min_by_key(|(e, _, _)| *e);
    let Some((_, camera, camera_transform)) = active else {
        frame.camera = None;
        errors.0.push(Error::Scene(
            "no active camera: spawn an entity with a Camera component".into(),
        ));
        return;
    };
    // A probe capture looks from the probe, through a centred 90° frustum.
    let main_transform = camera_transform;
    let capture_transform = capture
        .as_deref()
        .map(|c| GlobalTransform(c.world_from_view));
    let camera_transform = capture_transform.as_ref().unwrap_or(camera_transform);
    let projection = match capture.as_deref() {
        Some(c) => crate::scene::Projection {
            fov_y_rad: c.fov_y_rad,
            shift: glam::Vec2::ZERO,
            ..camera.projection
        },
        None => camera.projection,
    };
    let resolved = camera.resolve_exposure(metered.ev100);
    let exposure = resolved.multiplier;
    let view_from_world = camera_transform.0.inverse();
    if !view_from_world.is_finite() {
        errors.0.push(Error::Scene(
            "the camera's transform is not invertible".into(),
        ));
        return;
    }
    // Captures look through pixel centres; the frame samples where its jitter says.
    let jitter = match (&capture, jitter) {
        (None, Some(j)) => *j,
        _ => Jitter::default(),
    };
    let clip_from_view = projection.matrix(aspect);
    let unjittered = clip_from_view * view_from_world;
    let clip_from_world = jitter.clip_matrix(output.size) * unjittered;
    if capture.is_none() {
        let previous = if quality.aa.temporal() {
            memory.clip_from_world.unwrap_or(unjittered)
        } else {
            unjittered
        };
        frame.temporal.clip_from_world = unjittered;
        frame.temporal.previous_clip_from_world = previous;
        memory.clip_from_world = Some(unjittered);
    }
    let position = camera_transform.translation();
    let fov_y = projection.fov_y_rad;
    let focal_length_m = camera.lens.focal_length_m(fov_y);
    let (lens, mut notes) = camera.lens.clamped(focal_length_m);
    notes.extend(resolved.notes);
    notes.dedup();
    frame.camera = Some(ExtractedCamera {
        position,
        view_from_world,
        clip_from_view,
        exposure,
        ev100: resolved.ev100,
        tonemapper: camera.tonemapper,
        lens,
        focal_length_m,
        fov_y,
        aspect,
        depth_of_field: camera.depth_of_field.map(|d| crate::scene::DepthOfField {
            rings: quality.dof_rings.unwrap_or(d.rings).clamp(1, 5),
            max_coc_px: finite_or(d.max_coc_px, 32.0).clamp(1.0, 128.0),
        }),
        vignette: camera
            .vignette
            .map_or(0.0, |v| finite_or(v.strength, 0.0).clamp(0.0, 1.0)),
        auto_exposure: match camera.exposure {
            crate::scene::Exposure::Auto(a) => Some(a),
            _ => None,
        },
        notes,
    });

    // Instances, sorted by mesh (those in view first, then casters first within a mesh)
    // so each mesh is one instanced draw of the instances in view.
    let view_planes = frustum_planes(&clip_from_world);
    struct Item {
        mesh: MeshHandle,
        maps: Option<u32>,
        textured: bool,
        double_sided: bool,
        blend: bool,
        transmissive: bool,
        coated: bool,
        sheened: bool,
        relit: bool,
        // Squared distance (m²) from the camera to the bounding sphere's centre.
        distance2: f32,
        casts: bool,
        in_view: bool,
        sphere: Option<(Vec3, f32)>,
        instance: GpuInstance,
        entity: Entity,
        deformed: Option<u32>,
    }
    let mut items: Vec<Item> = Vec::new();
    let neutral_maps = crate::scene::MaterialMaps::default();
    frame.material_maps.clear();
    frame.deformed.clear();
    for (entity, mesh, material, transform, not_caster, not_receiver, maps) in &drawables {
        if meshes.get(mesh.0).is_none() {
            log::warn!(
                "an entity refers to mesh {} which does not exist; skipped",
                mesh.0.0
            );
            continue;
        }
        // A skinned mesh's vertices come out of the deformation pass in world space.
        let deformed = deform.extract(entity, mesh.0, &meshes, &mut frame.deformed);
        let m = match &deformed {
            Some(d) if d.skinned => Mat4::IDENTITY,
            _ => transform.0,
        };
        // A degenerate (zero-scale) or non-finite transform draws nothing.
        let (Some(normal), true) = (normal_matrix(&m), m.is_finite()) else {
            continue;
        };
        let base = material.base_color;
        // The transparent pass draws through the maps' bind group: a blended or
        // transmissive material without maps gets the neutral ones (every slot white,
        // every factor as given).
        let blend = material.blend;
        // An unlit surface transmits nothing: it shows its base colour.
        let transmission = material
            .transmission
            .filter(|_| !material.unlit)
            .map(|t| world_transmission(&t, &m))
            .filter(|t| t.factor > 0.0);
        let transmissive = transmission.is_some();
        // The layers pass, too, draws through the maps' bind group, which holds the coat
        // and the sheen; a blended or transmissive surface's layers are the transparent
        // pass's.
        let clearcoat = material.coat();
        let coated = !blend && !transmissive && clearcoat.is_some();
        let sheen = material.layer_sheen();
        let sheened = !blend && !transmissive && sheen.is_some();
        let anisotropy = material.anisotropic();
        let specular_textured = maps.is_some_and(|m| m.extensions.specular_textured());
        let specular_tint = material.relit_tint(specular_textured);
        let iridescence = material.iridescent();
        let diffuse_transmission = material.translucent();
        // A blended surface's anisotropy, tint, film and diffuse transmission are the
        // transparent pass's, as a transmissive one's are.
        let relit = !blend
            && !transmissive
            && (anisotropy.is_some()
                || specular_tint.is_some()
                || iridescence.is_some()
                || diffuse_transmission.is_some());
        let textured = maps.is_some();
        let forward = blend || transmissive || coated || sheened || relit;
        let maps = maps.or(forward.then_some(&neutral_maps)).map(|m| {
            let same = |x: &FrameMaps| {
                x.maps == *m
                    && x.transmission == transmission
                    && x.blend == blend
                    && x.clearcoat == clearcoat
                    && x.sheen == sheen
                    && x.anisotropy == anisotropy
                    && x.specular_tint == specular_tint
                    && x.iridescence == iridescence
                    && x.diffuse_transmission == diffuse_transmission
            };
            let index = match frame.material_maps.iter().position(same) {
                Some(i) => i,
                None => {
                    frame.material_maps.push(FrameMaps {
                        maps: m.clone(),
                        transmission,
                        blend,
                        clearcoat,
                        sheen,
                        anisotropy,
                        specular_tint,
                        iridescence,
                        diffuse_transmission,
                    });
                    frame.material_maps.len() - 1
                }
            };
            index as u32
        });
        let sphere = match &deformed {
            Some(d) => d.bounds.map(|b| sphere_around(&b, &m)),
            None => meshes.bounds(mesh.0).map(|b| sphere_around(&b, &m)),
        };
        items.push(Item {
            entity,
            deformed: deformed.map(|d| d.index),
            mesh: mesh.0,
            maps,
            textured,
            double_sided: material.double_sided,
            blend,
            transmissive,
            coated,
            sheened,
            relit,
            distance2: sphere
                .map_or(m.w_axis.truncate(), |(c, _)| c)
                .distance_squared(position),
            casts: !not_caster,
            in_view: sphere.is_none_or(|(c, r)| sphere_in_frustum(&view_planes, c, r)),
            sphere,
            instance: GpuInstance {
                world_from_local: m.to_cols_array_2d(),
                normal_matrix: normal,
                base_color: [
                    finite_or(base.x, 0.0),
                    finite_or(base.y, 0.0),
                    finite_or(base.z, 0.0),
                    finite_or(base.w, 1.0),
                ],
                emissive_occlusion: {
                    let e = exposed(material.emissive.max(Vec3::ZERO), 1.0, exposure);
                    [e[0], e[1], e[2], finite_or(material.occlusion, 1.0)]
                },
                params: [
                    finite_or(material.metallic, 0.0),
                    finite_or(material.perceptual_roughness, 1.0),
                    if material.unlit {
                        crate::encoding::UNLIT_SPECULAR_LEVEL
                    } else {
                        finite_or(material.specular_level, 0.5).max(0.0)
                    },
                    if not_receiver { 0.0 } else { 1.0 },
                ],
            },
        });
    }
    // Opaque instances by mesh; the blended and transmissive ones after them, back to
    // front.
    items.sort_by(|a, b| {
        let key = |item: &Item| {
            (
                item.mesh,
                item.deformed,
                item.maps,
                item.textured,
                item.double_sided,
                !item.in_view,
                !item.casts,
            )
        };
        let transparent = |item: &Item| item.blend || item.transmissive;
        transparent(a).cmp(&transparent(b)).then_with(|| {
            if transparent(a) {
                b.distance2.total_cmp(&a.distance2)
            } else {
                key(a).cmp(&key(b))
            }
        })
    });
    frame.instances.clear();
    frame.batches.clear();
    frame.casters.clear();
    frame.triangles = 0;
    frame.receivers = 0;
    let mut bounds: Vec<(Vec3, f32)> = Vec::with_capacity(items.len());
    // Motion vectors need each instance's previous transform; only TAA uses them, and
    // captures neither read nor update what the frame remembers.
    let temporal = capture.is_none() && quality.aa.temporal();
    frame.temporal.previous_world.clear();
    frame.temporal.moved = 0;
    let mut remembered = std::collections::HashMap::new();
    for item in items {
        let index = frame.instances.len() as u32;
        if temporal {
            let now = Mat4::from_cols_array_2d(&item.instance.world_from_local);
            let before = memory.world.get(&item.entity).copied().unwrap_or(now);
            if before != now {
                frame.temporal.moved += 1;
            }
            frame
                .temporal
                .previous_world
                .push(before.to_cols_array_2d());
            remembered.insert(item.entity, now);
        }
        match frame.batches.last_mut() {
            Some(b)
                if !item.blend
                    && !item.transmissive
                    && !b.transparent()
                    && item.deformed.is_none()
                    && b.deformed.is_none()
                    && b.mesh == item.mesh
                    && b.maps == item.maps
                    && b.textured == item.textured
                    && b.double_sided == item.double_sided =>
            {
                b.count += 1;
                b.visible += u32::from(item.in_view);
            }
            _ => frame.batches.push(Batch {
                mesh: item.mesh,
                maps: item.maps,
                textured: item.textured,
                double_sided: item.double_sided,
                blend: item.blend,
                transmissive: item.transmissive,
                coated: item.coated,
                sheened: item.sheened,
                relit: item.relit,
                deformed: item.deformed,
                first_instance: index,
                count: 1,
                visible: u32::from(item.in_view),
            }),
        }
        if let Some((center, radius)) = item.sphere {
            bounds.push((center, radius));
            if item.casts {
                let mask = item.maps.filter(|&m| {
                    item.blend
                        || frame
                            .material_maps
                            .get(m as usize)
                            .is_some_and(|entry| entry.maps.alpha_cutoff.is_some())
                });
                frame.casters.push(Caster {
                    instance: index,
                    mesh: item.mesh,
                    deformed: item.deformed,
                    center,
                    radius,
                    mask,
                    blend: item.blend,
                });
            }
        }
        frame.receivers += usize::from(item.instance.params[3] > 0.0);
        frame.instances.push(item.instance);
        if item.in_view {
            frame.triangles += meshes
                .get(item.mesh)
                .map_or(0, |m| m.triangle_count() as u64);
        }
    }
    if temporal {
        memory.world = remembered;
    } else if capture.is_none() {
        memory.world.clear();
    }
    let caster_spheres: Vec<(Vec3, f32)> =
        frame.casters.iter().map(|c| (c.center, c.radius)).collect();
    frame.shadows_disabled = !quality.shadows;
    let shadows_on = quality.shadows && !frame.casters.is_empty() && frame.receivers > 0;
    frame.shadow_views.clear();
    frame.shadow_counts = ShadowCounts::default();
    // Captures fit directional cascades to the camera's frustum, not to theirs: every
    // face of every probe then shares one set of shadow views, drawn once per update.
    let shadow_camera = match capture.as_deref() {
        Some(c) => CameraForShadows {
            world_from_view: main_transform.0,
            fov_y: camera.projection.fov_y_rad,
            aspect: c.camera_aspect,
            near: camera.projection.near_m.max(1e-4),
            far: camera.projection.far_m,
        },
        None => CameraForShadows {
            world_from_view: camera_transform.0,
            fov_y: projection.fov_y_rad,
            aspect,
            near: projection.near_m.max(1e-4),
            far: projection.far_m,
        },
    };

    // Lights: directional, point, spot.
    frame.lights.clear();
    let mut counts = LightCounts::default();
    for (light, transform, settings, cascades) in &directional {
        let towards_light = -transform.forward();
        let (mut shadow, mut shadow_bias, mut cascade_far) = (NO_SHADOW, [0.0; 4], NO_CASCADES);
        if (light.cast_shadows || quality.all_lights_cast_shadows) && shadows_on {
            let s = sanitized(
                settings
                    .copied()
                    .unwrap_or_else(ShadowSettings::directional),
                quality.shadow_resolution_scale,
            );
            let mut c = cascades.copied().unwrap_or_default();
            c.count = c.count.min(quality.max_cascades.max(1));
            let views =
                directional_views(&shadow_camera, transform.forward(), &s, &c, &caster_spheres);
            let tan_radius =
                (finite_or(light.angular_diameter_rad, 0.0).clamp(0.0, 0.5) * 0.5).tan();
            (shadow, shadow_bias) =
                shadow_fields(frame.shadow_views.len(), views.len(), tan_radius, &s);
            shadow[3] = finite_or(c.blend_fraction, 0.0).clamp(0.0, 0.5);
            for (far, v) in cascade_far.iter_mut().zip(&views) {
                *far = v.cascade_far;
            }
            frame.shadow_views.extend(views);
            frame.shadow_counts.directional += 1;
        } else if light.cast_shadows || quality.all_lights_cast_shadows {
            frame.shadow_counts.skipped += 1;
        }
        frame.lights.push(GpuLight {
            position: [0.0; 4],
            direction: towards_light.extend(0.0).into(),
            color_inv_range2: {
                let c = exposed(light.color.to_linear_rgb(), light.illuminance_lux, exposure);
                [c[0], c[1], c[2], 0.0]
            },
            spot: [0.0; 4],
            shadow,
            cascade_far,
            shadow_bias,
        });
        counts.directional += 1;
    }
    for (light, transform, settings) in &points {
        let c = exposed(light.color.to_linear_rgb(), light.candela(), exposure);
        let position = transform.translation();
        let (mut shadow, mut shadow_bias) = (NO_SHADOW, [0.0; 4]);
        if (light.cast_shadows || quality.all_lights_cast_shadows) && shadows_on {
            let s = sanitized(
                settings.copied().unwrap_or_else(ShadowSettings::point),
                quality.shadow_resolution_scale,
            );
            let radius = finite_or(light.radius_m, 0.0).max(0.0);
            let views = point_views(position, light.range_m, radius, &s, &bounds);
            (shadow, shadow_bias) =
                shadow_fields(frame.shadow_views.len(), views.len(), radius, &s);
            frame.shadow_views.extend(views);
            frame.shadow_counts.point += 1;
        } else if light.cast_shadows || quality.all_lights_cast_shadows {
            frame.shadow_counts.skipped += 1;
        }
        frame.lights.push(GpuLight {
            position: position.extend(1.0).into(),
            direction: [0.0; 4],
            color_inv_range2: [c[0], c[1], c[2], inv_range_squared(light.range_m)],
            spot: [0.0; 4],
            shadow,
            cascade_far: NO_CASCADES,
            shadow_bias,
        });
        counts.point += 1;
    }
    for (light, transform, settings) in &spots {
        let c = exposed(light.color.to_linear_rgb(), light.candela(), exposure);
        let (scale, offset) = spot_scale_offset(
            finite_or(light.inner_angle_rad, 0.0),
            finite_or(light.outer_angle_rad, 0.0),
        );
        let position = transform.translation();
        let (mut shadow, mut shadow_bias) = (NO_SHADOW, [0.0; 4]);
        if (light.cast_shadows || quality.all_lights_cast_shadows) && shadows_on {
            let s = sanitized(
                settings.copied().unwrap_or_else(ShadowSettings::spot),
                quality.shadow_resolution_scale,
            );
            let radius = finite_or(light.radius_m, 0.0).max(0.0);
            let view = spot_view(
                position,
                transform.forward(),
                light.outer_angle_rad,
                light.range_m,
                radius,
                &s,
                &bounds,
            );
            (shadow, shadow_bias) = shadow_fields(frame.shadow_views.len(), 1, radius, &s);
            frame.shadow_views.push(view);
            frame.shadow_counts.spot += 1;
        } else if light.cast_shadows || quality.all_lights_cast_shadows {
            frame.shadow_counts.skipped += 1;
        }
        frame.lights.push(GpuLight {
            position: position.extend(1.0).into(),
            direction: transform.forward().extend(0.0).into(),
            color_inv_range2: [c[0], c[1], c[2], inv_range_squared(light.range_m)],
            spot: [scale, offset, 0.0, 0.0],
            shadow,
            cascade_far: NO_CASCADES,
            shadow_bias,
        });
        counts.spot += 1;
    }
    // Within each kind, shadowed lights first: the lighting shader loops over them with
    // shadow lookups and over the rest without.
    let (dir, rest) = frame.lights.split_at_mut(counts.directional as usize);
    let (point, spot) = rest.split_at_mut(counts.point as usize);
    let mut shadowed = [0u32; 3];
    for (k, lights) in [dir, point, spot].into_iter().enumerate() {
        lights.sort_by_key(|l| l.shadow[0] < 0.0);
        shadowed[k] = lights.iter().filter(|l| l.shadow[0] >= 0.0).count() as u32;
    }
    frame.shadowed_counts = shadowed;
    frame.light_counts = counts;

    frame.environment = environments.iter().min_by_key(|(e, _)| *e).map(|(_, env)| {
        let (image, uniform) = match &env.source {
            EnvironmentSource::Image(img) => (Some(img.clone()), Vec3::ZERO),
            EnvironmentSource::Uniform(c) => (
                None,
                Vec3::new(
                    finite_or(c.x, 0.0),
                    finite_or(c.y, 0.0),
                    finite_or(c.z, 0.0),
                )
                .max(Vec3::ZERO),
            ),
        };
        let (show_background, blur) = match env.background {
            Background::Environment { blur } => (true, finite_or(blur, 0.0).clamp(0.0, 1.0)),
            Background::CameraColor => (false, 0.0),
        };
        ExtractedEnvironment {
            image,
            uniform,
            intensity: finite_or(env.intensity, 0.0).max(0.0),
            rotation: finite_or(env.rotation_y_rad, 0.0),
            show_background,
            background_blur: blur,
        }
    });
    let background = exposed(camera.background.max(Vec3::ZERO), 1.0, exposure);
    frame.view = GpuView {
        clip_from_world: clip_from_world.to_cols_array_2d(),
        world_from_clip: clip_from_world.inverse().to_cols_array_2d(),
        position_exposure: position.extend(exposure).into(),
        viewport: [
            width as f32,
            height as f32,
            1.0 / width.max(1) as f32,
            1.0 / height.max(1) as f32,
        ],
        background: [background[0], background[1], background[2], 0.0],
        light_counts: [
            counts.directional,
            counts.point,
            counts.spot,
            counts.total(),
        ],
        shadowed_counts: [shadowed[0], shadowed[1], shadowed[2], 0],
        forward: camera_transform.forward().extend(0.0).into(),
        antialiasing: {
            let s = quality.aa.specular;
            [
                finite_or(s.screen_scale(), 0.0).max(0.0),
                finite_or(s.threshold(), 0.0).clamp(0.0, 1.0),
                jitter.offset_px.x,
                jitter.offset_px.y,
            ]
        },
    };
}
