//! The frame graph's decisions: which passes run this frame and which shader features
//! they compile, each with the reason ("model only what a scene requires").

use crate::brdf::VisibilityModel;
use crate::quality::{Quality, ShadowFilter};
use crate::render::debug_view::DebugView;
use crate::render::extract::ExtractedFrame;
use bevy_ecs::prelude::*;

/// A pass of the frame, in execution order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PassId {
    /// Draws shadow casters into the shadow atlas.
    Shadow,
    /// Rasterises meshes into the G-buffer.
    GBuffer,
    /// Lists the lights that reach each screen tile.
    LightCulling,
    /// Full-screen deferred lighting into the HDR target.
    Lighting,
    /// The environment as the background.
    Sky,
    /// Automatic exposure: luminance histogram and metering.
    Exposure,
    /// Depth of field.
    Dof,
    /// Tone mapping and output encoding.
    Tonemap,
    /// A debug view of one channel, instead of tone mapping.
    DebugView,
}

impl PassId {
    /// Every pass, in execution order.
    pub const ALL: [PassId; 4] = [
        PassId::Shadow,
        PassId::GBuffer,
        PassId::Lighting,
        PassId::Tonemap,
    ];

    /// Short name used in reports and JSON.
    pub fn name(self) -> &'static str {
        match self {
            PassId::Shadow => "shadow",
            PassId::GBuffer => "gbuffer",
            PassId::LightCulling => "light culling",
            PassId::Lighting => "lighting",
            PassId::Sky => "sky",
            PassId::Exposure => "exposure",
            PassId::Dof => "dof",
            PassId::Tonemap => "tonemap",
            PassId::DebugView => "debug view",
        }
    }
}

/// Whether a pass or feature is used this frame, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Decision {
    /// Pass or feature name.
    pub name: &'static str,
    /// Whether it runs / is compiled in.
    pub enabled: bool,
    /// Why, in a few words.
    pub reason: String,
}

/// The shader variant of the lighting pass: which light kinds it loops over.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LightingVariant {
    /// Directional-light loop compiled in.
    pub directional: bool,
    /// Point-light loop compiled in.
    pub point: bool,
    /// Spot-light loop compiled in.
    pub spot: bool,
    /// Visibility term.
    pub visibility: VisibilityModel,
    /// Shadow lookups compiled in for directional, point and spot lights.
    pub shadows: [bool; 3],
    /// Shadow filter.
    pub shadow_filter: ShadowFilter,
    /// Image-based lighting compiled in.
    pub environment: bool,
    /// From an image (else a uniform colour).
    pub env_map: bool,
    /// Multiple-scattering energy compensation compiled in.
    pub energy_compensation: bool,
    /// Unshadowed point and spot lights come from the tile lists of the culling pass.
    pub light_culling: bool,
    /// Every light fits the uniform copy of the light array (read from it, not from the
    /// storage buffer).
    pub uniform_lights: bool,
    /// Every shadow view fits the uniform copy of the view array.
    pub uniform_shadow_views: bool,
}

/// This frame's plan.
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct FramePlan {
    /// One decision per pass, in [`PassId::ALL`] order.
    pub passes: Vec<(PassId, Decision)>,
    /// Shader features of the passes that run.
    pub features: Vec<Decision>,
    /// The lighting shader variant.
    pub lighting: LightingVariant,
}

impl Default for FramePlan {
    fn default() -> Self {
        FramePlan {
            passes: Vec::new(),
            features: Vec::new(),
            lighting: LightingVariant {
                directional: false,
                point: false,
                spot: false,
                visibility: VisibilityModel::default(),
                shadows: [false; 3],
                shadow_filter: ShadowFilter::default(),
                environment: false,
                env_map: false,
                energy_compensation: false,
                light_culling: false,
                uniform_lights: false,
                uniform_shadow_views: false,
            },
        }
    }
}

impl FramePlan {
    /// Whether `pass` runs this frame.
    pub fn runs(&self, pass: PassId) -> bool {
        self.passes.iter().any(|(p, d)| *p == pass && d.enabled)
    }

    /// A human-readable account of the plan (`lumen render --explain`).
    pub fn explain(&self) -> String {
        let mut out = String::from("passes:\n");
        for (_, d) in &self.passes {
            out.push_str(&format!(
                "  {:<10} {:<4} {}\n",
                d.name,
                if d.enabled { "run" } else { "skip" },
                d.reason
            ));
        }
        out.push_str("shader features:\n");
        for d in &self.features {
            out.push_str(&format!(
                "  {:<22} {:<3} {}\n",
                d.name,
                if d.enabled { "on" } else { "off" },
                d.reason
            ));
        }
        out
    }
}

fn decision(name: &'static str, enabled: bool, reason: String) -> Decision {
    Decision {
        name,
        enabled,
        reason,
    }
}

/// Decides this frame's passes and shader features from the extracted scene.
pub fn plan_frame(
    frame: Res<ExtractedFrame>,
    quality: Res<Quality>,
    buffers: Res<crate::render::scene_buffers::SceneBuffers>,
    debug: Res<DebugView>,
    mut plan: ResMut<FramePlan>,
) {
    let instances = frame.instances.len();
    let counts = frame.light_counts;
    let sc = frame.shadow_counts;
    let views = frame.shadow_views.len();
    let shadow = decision(
        PassId::Shadow.name(),
        views > 0,
        if views > 0 {
            format!(
                "{views} view(s): {} directional (cascades), {} spot, {} point light(s) (6 faces each); {} caster(s)",
                sc.directional,
                sc.spot,
                sc.point,
                frame.casters.len()
            )
        } else if frame.shadows_disabled {
            "shadows are off (--no-shadows)".into()
        } else if sc.skipped == 0 {
            "no light casts shadows".into()
        } else if frame.casters.is_empty() {
            "no mesh casts shadows".into()
        } else {
            "no mesh receives shadows".into()
        },
    );
    let gbuffer = decision(
        PassId::GBuffer.name(),
        instances > 0,
        if instances > 0 {
            format!(
                "{instances} instance(s) of {} mesh(es), {} triangles",
                frame.batches.len(),
                frame.triangles
            )
        } else {
            "no mesh in view: the G-buffer stays cleared".into()
        },
    );
    let lighting = decision(
        PassId::Lighting.name(),
        true,
        if instances > 0 {
            format!(
                "shades the G-buffer with {} light(s) and writes the background",
                counts.total()
            )
        } else {
            "writes the background".into()
        },
    );
    let unshadowed = (counts.point - frame.shadowed_counts[1].min(counts.point))
        + (counts.spot - frame.shadowed_counts[2].min(counts.spot));
    let min_lights = crate::render::light_culling::LIGHT_CULLING_MIN_LIGHTS;
    let culling = decision(
        PassId::LightCulling.name(),
        quality.light_culling && instances > 0 && unshadowed >= min_lights,
        if !quality.light_culling {
            "off (--no-light-culling)".into()
        } else if instances == 0 {
            "nothing to light".into()
        } else if unshadowed >= min_lights {
            format!("{unshadowed} unshadowed point/spot light(s) into 16×16-pixel tiles")
        } else {
            format!(
                "{unshadowed} unshadowed point/spot light(s): fewer than {min_lights}, every pixel loops over all"
            )
        },
    );
    let env = frame.environment.as_ref();
    let sky = decision(
        PassId::Sky.name(),
        env.is_some_and(|e| e.show_background),
        match env {
            None => "no environment: the camera's background colour".into(),
            Some(e) if !e.show_background => {
                "the environment is hidden: the camera's background colour".into()
            }
            Some(e) if e.image.is_some() => format!(
                "the environment image, blurred to roughness {:.2}",
                e.background_blur
            ),
            Some(_) => "the uniform environment colour".into(),
        },
    );
    let camera = frame.camera.as_ref();
    let exposure = decision(
        PassId::Exposure.name(),
        camera.is_some_and(|c| c.auto_exposure.is_some()),
        match camera.and_then(|c| c.auto_exposure) {
            Some(a) => format!(
                "automatic exposure, EV100 {:.1}..{:.1}",
                a.min_ev100, a.max_ev100
            ),
            None => "manual, physical or linear exposure: nothing to meter".into(),
        },
    );
    let dof = decision(
        PassId::Dof.name(),
        camera.is_some_and(|c| c.depth_of_field.is_some()),
        match camera.and_then(|c| c.depth_of_field.map(|d| (c, d))) {
            Some((c, d)) => format!(
                "f/{:.1}, focus {:.2} m, {:.0} mm, {} rings, CoC ≤ {:.0} px",
                c.lens.aperture_f_stops,
                c.lens.focus_distance_m,
                c.focal_length_m * 1e3,
                d.rings,
                d.max_coc_px
            ),
            None => "depth of field is off".into(),
        },
    );
    let debug_view = *debug != DebugView::Off;
    let tonemap = decision(
        PassId::Tonemap.name(),
        !debug_view,
        if debug_view {
            format!("the {} debug view replaces it", debug.name())
        } else {
            "turns exposed HDR luminance into the display image".into()
        },
    );
    let debug_pass = decision(
        PassId::DebugView.name(),
        debug_view,
        if debug_view {
            format!("shows the {} channel", debug.name())
        } else {
            "no debug view chosen".into()
        },
    );
    let kind = |name: &'static str, n: u32| {
        decision(
            name,
            n > 0 && instances > 0,
            match (n, instances) {
                (0, _) => "no light of this kind".into(),
                (_, 0) => "nothing to light".into(),
                (n, _) => format!("{n} light(s)"),
            },
        )
    };
    let features = vec![
        kind("directional lights", counts.directional),
        kind("point lights", counts.point),
        kind("spot lights", counts.spot),
        decision(
            "visibility term",
            true,
            quality.visibility.name().to_string(),
        ),
        decision(
            "shadow lookups",
            views > 0 && instances > 0,
            if views > 0 {
                format!("{} filter", quality.shadow_filter.name())
            } else {
                "no shadow pass".into()
            },
        ),
        decision(
            "environment lighting",
            env.is_some() && instances > 0,
            match env {
                None => "no environment".into(),
                Some(e) if e.image.is_some() => {
                    "image: SH irradiance + GGX-prefiltered cube".into()
                }
                Some(_) => "uniform colour".into(),
            },
        ),
        decision(
            "energy compensation",
            quality.energy_compensation && instances > 0,
            if quality.energy_compensation {
                "multiple scattering (Kulla-Conty)".into()
            } else {
                "off: single-scattering GGX".into()
            },
        ),
    ];
    plan.lighting = LightingVariant {
        directional: features[0].enabled,
        point: features[1].enabled,
        spot: features[2].enabled,
        visibility: quality.visibility,
        shadows: [0, 1, 2].map(|k| features[4].enabled && frame.shadowed_counts[k] > 0),
        shadow_filter: quality.shadow_filter,
        environment: features[5].enabled,
        env_map: features[5].enabled && env.is_some_and(|e| e.image.is_some()),
        energy_compensation: features[6].enabled,
        light_culling: culling.enabled,
        uniform_lights: counts.total() <= buffers.uniform_light_capacity
            && frame.shadowed_counts.iter().sum::<u32>() <= buffers.shadowed_light_capacity,
        uniform_shadow_views: views <= crate::render::shadow::pass::UNIFORM_SHADOW_VIEWS as usize,
    };
    plan.passes = vec![
        (PassId::Shadow, shadow),
        (PassId::GBuffer, gbuffer),
        (PassId::LightCulling, culling),
        (PassId::Lighting, lighting),
        (PassId::Sky, sky),
        (PassId::Exposure, exposure),
        (PassId::Dof, dof),
        (PassId::Tonemap, tonemap),
        (PassId::DebugView, debug_pass),
    ];
    plan.features = features;
}

/// Run condition: `pass` runs this frame.
pub fn pass_runs(pass: PassId) -> impl Fn(Res<FramePlan>) -> bool + Clone {
    move |plan: Res<FramePlan>| plan.runs(pass)
}
