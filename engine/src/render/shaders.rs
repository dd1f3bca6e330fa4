//! WGSL sources and their composition.
//!
//! WGSL has no `#include`: each pass's shader is its own file in `shaders/` preceded by
//! the shared modules it uses and by a header of constants (the "shader defs") that
//! select the features the scene needs. A feature a scene doesn't use is a `false`
//! constant, so its code is removed when the pipeline is compiled.
//!
//! The sources are compiled into the binary, so `lumen` runs from any directory.

use crate::error::Result;
use crate::render::device::Gpu;

/// Shared constants and helpers (`safe_normalize`, `PI`).
pub const COMMON: &str = include_str!("../../../shaders/common.wgsl");
/// The BRDF, twin of `brdf.rs`.
pub const BRDF: &str = include_str!("../../../shaders/brdf.wgsl");
/// Punctual light falloff, twin of `punctual.rs`.
pub const PUNCTUAL: &str = include_str!("../../../shaders/punctual.wgsl");
/// sRGB curve and tone mappers, twin of `color.rs`.
pub const COLOR: &str = include_str!("../../../shaders/color.wgsl");
/// G-buffer encodings, twin of `encoding.rs`.
pub const ENCODING: &str = include_str!("../../../shaders/encoding.wgsl");
/// Uniform and storage layouts shared by the passes (view, instances, lights).
pub const BINDINGS: &str = include_str!("../../../shaders/bindings.wgsl");
/// Full-screen triangle vertex shader.
pub const FULLSCREEN: &str = include_str!("../../../shaders/fullscreen.wgsl");
/// G-buffer pass.
pub const GBUFFER: &str = include_str!("../../../shaders/gbuffer.wgsl");
/// Deferred lighting pass.
pub const LIGHTING: &str = include_str!("../../../shaders/lighting.wgsl");
/// Shadow pass (casters into the atlas).
pub const SHADOW: &str = include_str!("../../../shaders/shadow.wgsl");
/// Shadow-map sampling and filtering, used by the lighting pass.
pub const SHADOWS: &str = include_str!("../../../shaders/shadows.wgsl");
/// Image-based lighting functions, twin of `ibl.rs`.
pub const IBL: &str = include_str!("../../../shaders/ibl.wgsl");
/// Environment preprocessing (compute).
pub const IBL_PREPROCESS: &str = include_str!("../../../shaders/ibl_preprocess.wgsl");
/// The split-sum BRDF table.
pub const BRDF_LUT: &str = include_str!("../../../shaders/brdf_lut.wgsl");
/// Sky pass: the environment as background.
pub const SKY: &str = include_str!("../../../shaders/sky.wgsl");
/// Camera optics (circle of confusion, vignetting), twin of `scene/camera.rs`.
pub const CAMERA: &str = include_str!("../../../shaders/camera.wgsl");
/// Automatic exposure (compute).
pub const EXPOSURE: &str = include_str!("../../../shaders/exposure.wgsl");
/// Depth of field passes.
pub const DOF: &str = include_str!("../../../shaders/dof.wgsl");
/// Tile light lists shared by light culling and lighting.
pub const LIGHT_TILES: &str = include_str!("../../../shaders/light_tiles.wgsl");
/// Tiled light culling (compute).
pub const LIGHT_CULLING: &str = include_str!("../../../shaders/light_culling.wgsl");
/// Tone mapping and output encoding pass.
pub const TONEMAP: &str = include_str!("../../../shaders/tonemap.wgsl");

/// One compile-time constant of a shader variant.
#[derive(Clone, Debug, PartialEq)]
pub enum ShaderDef {
    /// `const NAME: bool = value;`
    Bool(&'static str, bool),
    /// `const NAME: u32 = value;`
    U32(&'static str, u32),
}

/// The header of constants, then the modules, in order.
pub fn compose(defs: &[ShaderDef], modules: &[&str]) -> String {
    let mut source = String::from("// Composed by lumen::render::shaders.\n");
    for def in defs {
        match def {
            ShaderDef::Bool(name, v) => source.push_str(&format!("const {name}: bool = {v};\n")),
            ShaderDef::U32(name, v) => source.push_str(&format!("const {name}: u32 = {v}u;\n")),
        }
    }
    for module in modules {
        source.push('\n');
        source.push_str(module);
    }
    source
}

/// Compiles WGSL into a shader module; a compile error becomes [`Error::Gpu`] with the
/// compiler's message.
pub fn create_module(gpu: &Gpu, label: &str, source: String) -> Result<wgpu::ShaderModule> {
    gpu.checked(&format!("shader '{label}'"), |device| {
        device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        })
    })
}
