//! Materials for `lumen validate` and `lumen convert`: read from a glTF file or from
//! texture files given by role.

use crate::cli::TextureRoles;
use anyhow::{Result, anyhow};
use lumen::scene::{ColorSpace, TextureData};
use lumen::validate::{ColorInput, MaterialInput, ScalarInput};
use std::path::{Path, PathBuf};

/// The largest texture side the tools keep: larger images are downscaled, with a warning.
pub const MAX_TEXTURE_SIZE: u32 = 8192;

/// A material and where it came from.
pub struct NamedMaterial {
    /// The file (glTF, or the first texture file).
    pub source: PathBuf,
    /// Material name (`textures` for texture files).
    pub name: String,
    /// The maps.
    pub input: MaterialInput,
}

/// Reads an image file as RGBA8 in `color_space`, with the glTF loader's decoder: a side
/// over [`MAX_TEXTURE_SIZE`] is downscaled, with a warning on stderr.
pub fn read_texture(path: &Path, color_space: ColorSpace) -> Result<TextureData> {
    let bytes = lumen::files::read(path, lumen::limits::FileKind::Texture)?;
    let mut warnings = Vec::new();
    let what = path.display().to_string();
    let texture = lumen::assets::texture_io::decode(
        &bytes,
        color_space,
        MAX_TEXTURE_SIZE,
        &mut warnings,
        &what,
    )
    .map_err(|e| anyhow!("{what}: {e}"))?;
    for w in warnings {
        eprintln!("lumen: {w}");
    }
    Ok(texture)
}

fn color(path: &Path) -> Result<ColorInput> {
    Ok(ColorInput {
        texture: Some(read_texture(path, ColorSpace::Srgb)?),
        factor: glam::Vec3::ONE,
    })
}

fn scalar(path: Option<&PathBuf>, channel: usize, default: f32) -> Result<ScalarInput> {
    Ok(match path {
        Some(p) => ScalarInput {
            texture: Some(read_texture(p, ColorSpace::Linear)?),
            channel,
            factor: 1.0,
        },
        None => ScalarInput {
            texture: None,
            channel: 0,
            factor: default,
        },
    })
}

impl TextureRoles {
    /// Whether any role is given.
    pub fn any(&self) -> bool {
        [
            &self.base_color,
            &self.metallic,
            &self.roughness,
            &self.orm,
            &self.diffuse,
            &self.specular,
            &self.glossiness,
        ]
        .iter()
        .any(|p| p.is_some())
    }

    /// The material the roles describe. Metal/roughness needs `--base-color`; a missing
    /// metallic reads as 0 and a missing roughness as 1. Spec/gloss needs `--diffuse` and
    /// `--specular`; a missing glossiness reads as 0.
    pub fn material(&self) -> Result<NamedMaterial> {
        let first = [
            &self.base_color,
            &self.diffuse,
            &self.specular,
            &self.metallic,
            &self.orm,
            &self.roughness,
            &self.glossiness,
        ]
        .into_iter()
        .flatten()
        .next()
        .cloned()
        .ok_or_else(|| anyhow!("no material: give a glTF file or texture files by role"))?;
        let input = if self.diffuse.is_some() || self.specular.is_some() {
            let (Some(d), Some(s)) = (&self.diffuse, &self.specular) else {
                return Err(anyhow!("spec/gloss needs both --diffuse and --specular"));
            };
            MaterialInput::SpecGloss {
                diffuse: color(d)?,
                specular: color(s)?,
                glossiness: scalar(self.glossiness.as_ref(), 0, 0.0)?,
            }
        } else {
            let b = self.base_color.as_ref().ok_or_else(|| {
                anyhow!(
                    "metal/rough needs --base-color (with --metallic and --roughness, or --orm)"
                )
            })?;
            let (metallic, roughness) = match &self.orm {
                Some(orm) => (scalar(Some(orm), 2, 0.0)?, scalar(Some(orm), 1, 1.0)?),
                None => (
                    scalar(self.metallic.as_ref(), 0, 0.0)?,
                    scalar(self.roughness.as_ref(), 0, 1.0)?,
                ),
            };
            MaterialInput::MetalRough {
                base_color: color(b)?,
                metallic,
                roughness,
            }
        };
        Ok(NamedMaterial {
            source: first,
            name: "textures".into(),
            input,
        })
    }
}

/// Every material of a glTF file, with the loader's warnings printed on stderr.
pub fn gltf_materials(path: &Path) -> Result<Vec<NamedMaterial>> {
    let (materials, warnings) = lumen::assets::gltf::material_inputs(path, MAX_TEXTURE_SIZE)?;
    for w in warnings {
        eprintln!("lumen: {}: {w}", path.display());
    }
    if materials.is_empty() {
        return Err(anyhow!("{}: the file has no material", path.display()));
    }
    Ok(materials
        .into_iter()
        .map(|(name, input)| NamedMaterial {
            source: path.to_path_buf(),
            name,
            input,
        })
        .collect())
}

/// A file-name-safe form of a material name.
pub fn file_stem(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() { "material".into() } else { s }
}
