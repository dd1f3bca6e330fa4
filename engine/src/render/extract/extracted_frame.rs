//! What extraction produces: [`ExtractedFrame`], the plain data every pass reads, and
//! what its systems hand each other ([`Viewpoint`], [`InstanceSpheres`],
//! [`LightShadows`]).

use crate::render::extract::deformed::DeformedFrame;
use crate::render::extract::shadow_views::{CameraForShadows, ShadowView};
use crate::render::gpu_types::{GpuInstance, GpuLight, GpuView};
use crate::scene::{MeshHandle, Transmission};
use crate::shading::color::Tonemapper;
use bevy_ecs::prelude::*;
use glam::{Mat4, Vec3};
use std::collections::HashMap;

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
    pub world: HashMap<Entity, Mat4>,
}

/// Where this frame looks from, as the camera's extraction hands it to the others.
/// `None` when the frame has no usable camera: the later systems then leave the frame as
/// it was (the error says why).
#[derive(Resource, Default, Debug)]
pub struct Viewpoint(pub Option<View>);

/// The frame's view, as the instance, shadow and light extraction need it.
#[derive(Clone, Debug)]
pub struct View {
    /// Clip from world, with the frame's jitter.
    pub clip_from_world: Mat4,
    /// The eye's world-space position (m).
    pub position: Vec3,
    /// Linear exposure multiplier applied to luminance.
    pub exposure: f32,
    /// The frustum directional shadow cascades are fitted to: the camera's, also while a
    /// probe capture renders.
    pub shadow_camera: CameraForShadows,
    /// A probe capture renders: the frame remembers nothing for the next one.
    pub capture: bool,
}

impl Viewpoint {
    /// The view, once the camera's extraction found one.
    pub fn view(&self) -> Option<&View> {
        self.0.as_ref()
    }
}

/// The world-space bounding sphere (centre, radius in m) of every instance that has one:
/// what point and spot shadow views are fitted to.
#[derive(Resource, Default, Debug)]
pub struct InstanceSpheres(pub Vec<(Vec3, f32)>);

/// Per light entity that casts shadows this frame, the shadow fields of its
/// [`GpuLight`]: the shadow extraction fills it, the light extraction reads it.
#[derive(Resource, Default, Debug)]
pub struct LightShadows(pub HashMap<Entity, LightShadow>);

/// A light's shadow fields ([`GpuLight::shadow`], [`GpuLight::shadow_bias`],
/// [`GpuLight::cascade_far`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightShadow {
    /// First view, view count, source size (tan of the angular radius, or radius in m),
    /// cascade blend fraction.
    pub shadow: [f32; 4],
    /// Depth, slope and normal bias (texels).
    pub bias: [f32; 4],
    /// Each cascade's far distance (m); `f32::MAX` past the last.
    pub cascade_far: [f32; 4],
}

impl LightShadow {
    /// The fields of a light without shadows.
    pub const NONE: LightShadow = LightShadow {
        shadow: [-1.0, 0.0, 0.0, 0.0],
        bias: [0.0; 4],
        cascade_far: [f32::MAX; 4],
    };
}
