// G-buffer pass: rasterises every mesh instance into the G-buffer.
// Layout (see README "G-buffer"):
//   gbuffer0 Rgba8Unorm     : base colour (rgb, exact sRGB curve applied here), AO (7 bits)
//                             and receives-shadows (top bit) in a
//   gbuffer1 Rgba16Float    : octahedral normal (rg), perceptual roughness (b), metallic (a)
//   gbuffer2 Rgba16Float    : pre-exposed emissive (rgb), specular level (a)
//   depth    Depth32Float   : reversed Z

@group(0) @binding(0) var<uniform> view: View;

struct VertexInput {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
}

// The instance (the `Instance` layout of bindings.wgsl) as per-instance attributes.
struct InstanceInput {
    @location(4) world_0: vec4<f32>,
    @location(5) world_1: vec4<f32>,
    @location(6) world_2: vec4<f32>,
    @location(7) world_3: vec4<f32>,
    @location(8) normal_matrix_0: vec4<f32>,
    @location(9) normal_matrix_1: vec4<f32>,
    @location(10) normal_matrix_2: vec4<f32>,
    @location(11) base_color: vec4<f32>,
    @location(12) emissive_occlusion: vec4<f32>,
    @location(13) params: vec4<f32>,
}

// The material is resolved once per vertex and passed flat, not read from the instance
// buffer per fragment: 34 → 23 ms for `spheres` at 1280×720 on lavapipe.
struct VertexOutput {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_normal: vec3<f32>,
    @location(1) @interpolate(flat) base_color_ao: vec4<f32>,
    @location(2) @interpolate(flat) emissive_specular: vec4<f32>,
    @location(3) @interpolate(flat) roughness_metallic: vec2<f32>,
}

@vertex
fn vs_main(in: VertexInput, inst: InstanceInput) -> VertexOutput {
    let world_from_local = mat4x4<f32>(inst.world_0, inst.world_1, inst.world_2, inst.world_3);
    let world = world_from_local * vec4<f32>(in.position, 1.0);
    let normal_matrix = mat3x3<f32>(
        inst.normal_matrix_0.xyz,
        inst.normal_matrix_1.xyz,
        inst.normal_matrix_2.xyz,
    );
    var out: VertexOutput;
    out.clip = view.clip_from_world * world;
    out.world_normal = normal_matrix * in.normal;
    let base = inst.base_color.rgb;
    out.base_color_ao = vec4<f32>(srgb_encode(base.r), srgb_encode(base.g), srgb_encode(base.b),
                                  pack_occlusion_receiver(inst.emissive_occlusion.w, inst.params.w));
    out.emissive_specular = vec4<f32>(min(inst.emissive_occlusion.rgb, vec3<f32>(F16_MAX)),
                                      clamp(inst.params.z, 0.0, 1.0));
    out.roughness_metallic = vec2<f32>(clamp_perceptual_roughness(inst.params.y), clamp(inst.params.x, 0.0, 1.0));
    return out;
}

struct GBufferOutput {
    @location(0) base_color_ao: vec4<f32>,
    @location(1) normal_roughness_metallic: vec4<f32>,
    @location(2) emissive_specular: vec4<f32>,
}

// Largest finite f16, the limit of the Rgba16Float targets.
const F16_MAX: f32 = 65504.0;

@fragment
fn fs_main(in: VertexOutput) -> GBufferOutput {
    let n = safe_normalize(in.world_normal, vec3<f32>(0.0, 0.0, 1.0));
    var out: GBufferOutput;
    out.base_color_ao = in.base_color_ao;
    out.normal_roughness_metallic = vec4<f32>(oct_encode(n), in.roughness_metallic);
    out.emissive_specular = in.emissive_specular;
    return out;
}
