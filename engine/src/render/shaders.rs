//! WGSL sources and their composition.
//!
//! WGSL has no `#include`: each pass's shader is its own file in `shaders/` preceded by
//! the shared modules it uses and by a header of constants (the "shader defs") that
//! select the features the scene needs. A feature a scene doesn't use is a `false`
//! constant, so its code is removed when the pipeline is compiled.
//!
//! The sources are compiled into the binary, so `lumen` runs from any directory. A
//! [`ShaderLibrary`] can override them with files read from disk at run time
//! ([`crate::App::reload_shaders`], the viewer's hot reload).

use crate::error::{Error, Result};
use crate::render::device::Gpu;
use std::collections::HashMap;
use std::path::Path;
use std::sync::{Arc, RwLock};

/// One WGSL module: its file name in `shaders/` and the source compiled into the binary.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shader {
    /// File name in `shaders/`, e.g. `tonemap.wgsl`.
    pub file: &'static str,
    /// The source as compiled into the binary.
    pub builtin: &'static str,
}

macro_rules! shader {
    ($file:literal) => {
        Shader {
            file: $file,
            builtin: include_str!(concat!("../../../shaders/", $file)),
        }
    };
}

/// Shared constants and helpers (`safe_normalize`, `PI`).
pub const COMMON: Shader = shader!("common.wgsl");
/// The BRDF, twin of `brdf.rs`.
pub const BRDF: Shader = shader!("brdf.wgsl");
/// Punctual light falloff, twin of `punctual.rs`.
pub const PUNCTUAL: Shader = shader!("punctual.wgsl");
/// sRGB curve and tone mappers, twin of `color.rs`.
pub const COLOR: Shader = shader!("color.wgsl");
/// G-buffer encodings, twin of `encoding.rs`.
pub const ENCODING: Shader = shader!("encoding.wgsl");
/// Uniform and storage layouts shared by the passes (view, instances, lights).
pub const BINDINGS: Shader = shader!("bindings.wgsl");
/// Full-screen triangle vertex shader.
pub const FULLSCREEN: Shader = shader!("fullscreen.wgsl");
/// G-buffer pass.
pub const GBUFFER: Shader = shader!("gbuffer.wgsl");
/// Deferred lighting pass.
pub const LIGHTING: Shader = shader!("lighting.wgsl");
/// Shadow pass (casters into the atlas).
pub const SHADOW: Shader = shader!("shadow.wgsl");
/// Shadow-map sampling and filtering, used by the lighting pass.
pub const SHADOWS: Shader = shader!("shadows.wgsl");
/// Image-based lighting functions, twin of `ibl.rs`.
pub const IBL: Shader = shader!("ibl.wgsl");
/// Environment preprocessing (compute).
pub const IBL_PREPROCESS: Shader = shader!("ibl_preprocess.wgsl");
/// The split-sum BRDF table.
pub const BRDF_LUT: Shader = shader!("brdf_lut.wgsl");
/// Sky pass: the environment as background.
pub const SKY: Shader = shader!("sky.wgsl");
/// Camera optics (circle of confusion, vignetting), twin of `scene/camera.rs`.
pub const CAMERA: Shader = shader!("camera.wgsl");
/// Automatic exposure (compute).
pub const EXPOSURE: Shader = shader!("exposure.wgsl");
/// Depth of field passes.
pub const DOF: Shader = shader!("dof.wgsl");
/// Tile light lists shared by light culling and lighting.
pub const LIGHT_TILES: Shader = shader!("light_tiles.wgsl");
/// Tiled light culling (compute).
pub const LIGHT_CULLING: Shader = shader!("light_culling.wgsl");
/// The validator's per-texel rules, twin of `validate.rs`.
pub const VALIDATE: Shader = shader!("validate.wgsl");
/// Debug views of the frame's channels.
pub const DEBUG_VIEW: Shader = shader!("debug_view.wgsl");
/// Tone mapping and output encoding pass.
pub const TONEMAP: Shader = shader!("tonemap.wgsl");

/// Every module, for reloading from disk.
pub const ALL: [Shader; 23] = [
    COMMON,
    BRDF,
    PUNCTUAL,
    COLOR,
    ENCODING,
    BINDINGS,
    FULLSCREEN,
    GBUFFER,
    LIGHTING,
    SHADOW,
    SHADOWS,
    IBL,
    IBL_PREPROCESS,
    BRDF_LUT,
    SKY,
    CAMERA,
    EXPOSURE,
    DOF,
    LIGHT_TILES,
    LIGHT_CULLING,
    TONEMAP,
    VALIDATE,
    DEBUG_VIEW,
];

/// The WGSL sources passes compile from: the built-in ones, with overrides read from disk.
/// Cloning shares the overrides (every clone of a [`Gpu`] sees a reload).
#[derive(Clone, Debug, Default)]
pub struct ShaderLibrary {
    overrides: Arc<RwLock<HashMap<&'static str, Arc<str>>>>,
}

/// Overridden sources by file name.
pub type ShaderOverrides = HashMap<&'static str, Arc<str>>;

impl ShaderLibrary {
    /// The current source of `shader`.
    pub fn source(&self, shader: Shader) -> Arc<str> {
        self.overrides()
            .get(shader.file)
            .cloned()
            .unwrap_or_else(|| Arc::from(shader.builtin))
    }

    /// [`compose`] with the current sources of `modules`.
    pub fn compose(&self, defs: &[ShaderDef], modules: &[Shader]) -> String {
        let sources: Vec<Arc<str>> = modules.iter().map(|m| self.source(*m)).collect();
        let refs: Vec<&str> = sources.iter().map(|s| &**s).collect();
        compose(defs, &refs)
    }

    /// The overrides in force.
    pub fn overrides(&self) -> ShaderOverrides {
        match self.overrides.read() {
            Ok(map) => map.clone(),
            Err(poisoned) => poisoned.into_inner().clone(),
        }
    }

    /// Replaces the overrides.
    pub fn set_overrides(&self, overrides: ShaderOverrides) {
        match self.overrides.write() {
            Ok(mut map) => *map = overrides,
            Err(poisoned) => *poisoned.into_inner() = overrides,
        }
    }
}

/// Reads every module of [`ALL`] that exists in `dir` and differs from the built-in
/// source. A file that is missing keeps the built-in source; one that cannot be read
/// is an error.
pub fn read_overrides(dir: &Path) -> Result<ShaderOverrides> {
    if !dir.is_dir() {
        return Err(Error::InvalidArgument(format!(
            "shader folder {} does not exist",
            dir.display()
        )));
    }
    let mut out = HashMap::new();
    for shader in ALL {
        let path = dir.join(shader.file);
        if !path.exists() {
            continue;
        }
        let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
        if text != shader.builtin {
            out.insert(shader.file, Arc::from(text));
        }
    }
    Ok(out)
}

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
