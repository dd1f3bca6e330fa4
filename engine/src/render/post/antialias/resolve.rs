//! TAA's last step (`taa_resolve.wgsl`): the new history copied into the frame's HDR
//! target, sharpened when [`crate::quality::AaSettings::taa_sharpen`] is above 0
//! (contrast-adaptive sharpening, [`crate::shading::antialiasing::cas_weight`]). Compiled per HDR
//! format. The history is not sharpened, so sharpening never feeds back into later frames.

use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::fullscreen_step::FullscreenStep;
use crate::render::pipeline_cache::Fullscreen;

/// The resolve's inputs.
pub const BINDINGS: BindGroupSpec = BindGroupSpec::fragment("taa resolve", declared::TAA_RESOLVE_0);

/// `ResolveParams` of `taa_resolve.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct ResolveParams {
    settings: [f32; 4],
}

/// The resolve step (one pipeline per HDR format) and its settings buffer.
pub struct TaaResolve {
    /// The step.
    pub step: FullscreenStep,
    params: wgpu::Buffer,
}

impl TaaResolve {
    /// The layouts and the settings buffer; pipelines compile on first use.
    pub fn new(gpu: &Gpu) -> TaaResolve {
        TaaResolve {
            step: FullscreenStep::new(
                gpu,
                Fullscreen::new("taa resolve", "taa_resolve.wgsl"),
                &BINDINGS,
            ),
            params: gpu.uniform_buffer(
                "taa resolve params",
                std::mem::size_of::<ResolveParams>() as u64,
            ),
        }
    }

    /// The bind group that resolves `history`, made (or kept) in `cache`.
    pub fn group<'c>(
        &self,
        cache: &'c mut CachedGroup,
        gpu: &Gpu,
        history: &wgpu::TextureView,
    ) -> Result<&'c wgpu::BindGroup> {
        self.step.bind_in(
            cache,
            gpu,
            vec![
                wgpu::BindingResource::TextureView(history),
                self.params.as_entire_binding(),
            ],
        )
    }

    /// Sets the sharpening strength (0 copies exactly, up to 1; a non-finite strength is 0).
    pub fn set_sharpen(&self, gpu: &Gpu, strength: f32) {
        let strength = if strength.is_finite() {
            strength.clamp(0.0, 1.0)
        } else {
            0.0
        };
        let params = ResolveParams {
            settings: [strength, 0.0, 0.0, 0.0],
        };
        gpu.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_params_lay_out_as_the_shader_does() {
        crate::assert_wgsl_twin!(
            ResolveParams,
            "taa_resolve.wgsl",
            &[],
            "ResolveParams",
            [settings]
        );
    }
}
