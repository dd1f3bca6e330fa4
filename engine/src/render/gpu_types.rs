//! GPU-ready structs, byte for byte the layouts of `shaders/bindings.wgsl`.

use bytemuck::{Pod, Zeroable};

/// Per-frame view data (`View` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuView {
    /// Clip from world (reversed Z), column-major.
    pub clip_from_world: [[f32; 4]; 4],
    /// World from clip.
    pub world_from_clip: [[f32; 4]; 4],
    /// Camera position in metres (xyz), exposure multiplier (w).
    pub position_exposure: [f32; 4],
    /// Width, height, 1/width, 1/height in pixels.
    pub viewport: [f32; 4],
    /// Pre-exposed background luminance (rgb).
    pub background: [f32; 4],
    /// Directional, point, spot and total light counts.
    pub light_counts: [u32; 4],
    /// How many of the directional, point and spot lights cast shadows (each kind's
    /// shadowed lights come first in the light buffer); unused.
    pub shadowed_counts: [u32; 4],
    /// Camera forward direction (xyz, unit) for the view depth that selects cascades.
    pub forward: [f32; 4],
    /// Geometric specular anti-aliasing's screen scale c σ²
    /// ([`crate::quality::SpecularAaSettings::screen_scale`]) and threshold κ
    /// (dimensionless), and this frame's camera jitter in pixels.
    pub antialiasing: [f32; 4],
}

/// One drawn object (`Instance` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuInstance {
    /// World from local, column-major.
    pub world_from_local: [[f32; 4]; 4],
    /// Normal matrix columns (inverse-transpose of the upper 3×3).
    pub normal_matrix: [[f32; 4]; 3],
    /// Linear base colour and alpha.
    pub base_color: [f32; 4],
    /// Pre-exposed emissive luminance (rgb) and ambient occlusion (w).
    pub emissive_occlusion: [f32; 4],
    /// Metallic, perceptual roughness, specular level, receives shadows (1 or 0).
    pub params: [f32; 4],
}

/// One light (`Light` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuLight {
    /// Position in metres (point and spot).
    pub position: [f32; 4],
    /// Unit vector towards the light (directional) or the spot axis (spot).
    pub direction: [f32; 4],
    /// Colour × intensity × exposure (rgb: lux or candela) and 1/range² (w).
    pub color_inv_range2: [f32; 4],
    /// Spot cone scale and offset.
    pub spot: [f32; 4],
    /// Shadow: index of the first shadow view (−1: no shadow), number of views, light
    /// size (directional: tan of the angular radius; point and spot: radius in m),
    /// cascade blend fraction.
    pub shadow: [f32; 4],
    /// Directional lights: camera distance (m) where each of up to 4 cascades ends
    /// (unused entries: f32::MAX).
    pub cascade_far: [f32; 4],
    /// Shadow biases in texels: depth, slope, normal; unused.
    pub shadow_bias: [f32; 4],
}

/// The part of a light that its unshadowed loop reads (`PunctualLight` in WGSL): 48
/// bytes, so 1365 fit a 64 KiB uniform buffer.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuPunctualLight {
    /// Position in metres (xyz) and 1/range² in 1/m² (w, 0 = unlimited).
    pub position_inv_range2: [f32; 4],
    /// Colour × intensity × exposure (rgb: lux or candela) and the spot cone scale (w).
    pub color_spot_scale: [f32; 4],
    /// Unit vector towards the light (directional) or the spot axis (xyz), and the spot
    /// cone offset (w).
    pub direction_spot_offset: [f32; 4],
}

impl From<&GpuLight> for GpuPunctualLight {
    fn from(light: &GpuLight) -> Self {
        let [px, py, pz, _] = light.position;
        let [r, g, b, inv_range2] = light.color_inv_range2;
        let [dx, dy, dz, _] = light.direction;
        GpuPunctualLight {
            position_inv_range2: [px, py, pz, inv_range2],
            color_spot_scale: [r, g, b, light.spot[0]],
            direction_spot_offset: [dx, dy, dz, light.spot[1]],
        }
    }
}

/// One shadow view in the atlas (`ShadowView` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuShadowView {
    /// Clip from world, depth 0 nearest the light.
    pub clip_from_world: [[f32; 4]; 4],
    /// Atlas rectangle in UV: offset (xy), scale (zw).
    pub rect: [f32; 4],
    /// Texel world size (ortho: m; perspective: m per m), perspective flag (1/0), near
    /// (perspective, m) or depth range (ortho, m), far (perspective, m).
    pub texel: [f32; 4],
}

/// The environment as the lighting and sky passes read it (`EnvironmentUniform` in WGSL),
/// pre-exposed (× intensity × exposure).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuEnvironment {
    /// Radiance spherical harmonics, bands 0–2 (rgb), × intensity × exposure.
    pub sh: [[f32; 4]; 9],
    /// Scale of cube samples (intensity × exposure), rotation about +Y (rad), highest
    /// prefiltered mip, background mip (blur).
    pub params: [f32; 4],
    /// Uniform environments: radiance × intensity × exposure (rgb).
    pub uniform_radiance: [f32; 4],
}

/// The matrix one shadow view draws casters with (`CasterView` in WGSL), padded to the
/// 256-byte dynamic-offset alignment.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuCasterView {
    /// Clip from world.
    pub clip_from_world: [[f32; 4]; 4],
    /// Padding to 256 bytes.
    pub pad: [[f32; 4]; 12],
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_wgsl_twin;

    #[test]
    fn the_twins_lay_out_as_the_shaders_do() {
        let shared = "bindings.wgsl";
        #[rustfmt::skip]
        assert_wgsl_twin!(GpuView, shared, &[], "View", [
            clip_from_world, world_from_clip, position_exposure, viewport, background,
            light_counts, shadowed_counts, forward, antialiasing,
        ]);
        #[rustfmt::skip]
        assert_wgsl_twin!(GpuInstance, shared, &[], "Instance", [
            world_from_local, normal_matrix => "normal_matrix_0", base_color,
            emissive_occlusion, params,
        ]);
        #[rustfmt::skip]
        assert_wgsl_twin!(GpuLight, shared, &[], "Light", [
            position, direction, color_inv_range2, spot, shadow, cascade_far, shadow_bias,
        ]);
        #[rustfmt::skip]
        assert_wgsl_twin!(GpuPunctualLight, shared, &[], "PunctualLight", [
            position_inv_range2, color_spot_scale, direction_spot_offset,
        ]);
        assert_wgsl_twin!(
            GpuShadowView,
            shared,
            &[],
            "ShadowView",
            [clip_from_world, rect, texel]
        );
        #[rustfmt::skip]
        assert_wgsl_twin!(GpuEnvironment, shared, &[], "EnvironmentUniform", [
            sh, params, uniform_radiance,
        ]);
    }
}
