//! The built-in passes, registered in one place. A new pass is its own module (and
//! shader) plus one line here; the [`Registry`] derives the rest (see
//! [`crate::render::graph`]).

use crate::error::Result;
use crate::render::geometry::deform_pass::DeformPass;
use crate::render::geometry::gbuffer::GBufferPass;
use crate::render::graph::registry::Registry;
use crate::render::indirect::depth_pyramid::DepthPyramidPass;
use crate::render::indirect::gtao::AoPass;
use crate::render::indirect::reflections::SsrPass;
use crate::render::indirect::volume_irradiance::VolumeIrradiancePass;
use crate::render::lighting::LightingPass;
use crate::render::lighting::layers::LayersPass;
use crate::render::lighting::light_culling::LightCullingPass;
use crate::render::lighting::sky::SkyPass;
use crate::render::post::antialias::accumulate::AccumulatePass;
use crate::render::post::antialias::fxaa::FxaaPass;
use crate::render::post::antialias::smaa::SmaaPass;
use crate::render::post::antialias::taa::TaaPass;
use crate::render::post::debug_view::DebugViewPass;
use crate::render::post::dof::DofPass;
use crate::render::post::exposure::ExposurePass;
use crate::render::post::tonemap::TonemapPass;
use crate::render::shadow::mask::ShadowMaskPass;
use crate::render::shadow::pass::ShadowPass;
use crate::render::transparent::TransparentPass;
use crate::render::transparent::transmission_source::TransmissionSourcePass;

/// Lumen's frame, in registration order (the order in which passes touching the same
/// slot see it).
pub fn builtin() -> Result<Registry> {
    Registry::new()
        .with::<DeformPass>()
        .with::<ShadowPass>()
        .with::<GBufferPass>()
        .with::<AoPass>()
        .with::<DepthPyramidPass>()
        .with::<LightCullingPass>()
        .with::<ShadowMaskPass>()
        .with::<VolumeIrradiancePass>()
        .with::<LightingPass>()
        .with::<SsrPass>()
        .with::<LayersPass>()
        .with::<SkyPass>()
        .with::<TransmissionSourcePass>()
        .with::<TransparentPass>()
        .with::<AccumulatePass>()
        .with::<TaaPass>()
        .with::<ExposurePass>()
        .with::<DofPass>()
        .with::<FxaaPass>()
        .with::<SmaaPass>()
        .with::<TonemapPass>()
        .with::<DebugViewPass>()
        .ordered()
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_pass_a_knob_names_is_registered() {
        let ids = super::builtin().expect("the built-in frame").ids();
        for k in crate::quality::knobs::builtin().iter() {
            for p in k.passes {
                assert!(ids.contains(p), "knob {} names pass {p:?}", k.name);
            }
        }
    }
}
