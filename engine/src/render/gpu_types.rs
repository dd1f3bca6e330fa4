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
    /// Metallic, perceptual roughness, specular level, unused.
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_match_wgsl_layouts() {
        // std140/std430 sizes of the WGSL structs in shaders/bindings.wgsl.
        assert_eq!(std::mem::size_of::<GpuView>(), 64 + 64 + 16 * 4);
        assert_eq!(std::mem::size_of::<GpuInstance>(), 64 + 48 + 48);
        assert_eq!(std::mem::size_of::<GpuLight>(), 64);
    }
}
