// G-buffer pass: rasterises every mesh instance into the G-buffer.
// Layout (see README "G-buffer"):
//   gbuffer0 Rgba8Unorm     : base colour (rgb, exact sRGB curve applied here), AO (7 bits)
//                             and receives-shadows (top bit) in a
//   gbuffer1 Rgba16Float    : octahedral normal (rg), perceptual roughness (b), metallic (a)
//   gbuffer2 Rgba16Float    : pre-exposed emissive (rgb), specular level (a; negative:
//                             unlit, the lighting pass shows the base colour as it is)
//   depth    Depth32Float   : reversed Z
//   motion   Rg16Float      : screen motion (px) since the previous frame, without jitter
//                             (the `*_motion` entry points, only while TAA runs)
//   level    R16Float       : gbuffer2's alpha again, for the reflection pass (only while
//                             screen-space reflections run; after motion when both do)
// Header constant: SPECULAR_AA (geometric specular anti-aliasing widens the stored
// roughness where the normal varies across the pixel, and where a normal-map texel
// averages diverging normals).
#import common
#import brdf
#import material_maps
#import color
#import encoding
#import bindings
#import mesh_vertex

@group(0) @binding(0) var<uniform> view: View;

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
    return plain_vertex(in, inst);
}

fn plain_vertex(in: VertexInput, inst: InstanceInput) -> VertexOutput {
    let world_from_local = instance_world_from_local(inst);
    let world = world_from_local * vec4<f32>(in.position, 1.0);
    let normal_matrix = instance_normal_matrix(inst);
    var out: VertexOutput;
    out.clip = view.clip_from_world * world;
    out.world_normal = normal_matrix * in.normal;
    let base = inst.base_color.rgb;
    out.base_color_ao = vec4<f32>(srgb_encode(base.r), srgb_encode(base.g), srgb_encode(base.b),
                                  pack_occlusion_receiver(inst.emissive_occlusion.w, inst.params.w));
    out.emissive_specular = vec4<f32>(min(inst.emissive_occlusion.rgb, vec3<f32>(F16_MAX)),
                                      stored_specular_level(inst.params.z));
    out.roughness_metallic = vec2<f32>(clamp_perceptual_roughness(inst.params.y), clamp(inst.params.x, 0.0, 1.0));
    return out;
}

// The last output repeats target 2's alpha, the specular level, for the reflection pass
// (location 3 here, 4 after the motion vectors); in frames without reflections it has no
// target and is discarded.
struct GBufferOutput {
    @location(0) base_color_ao: vec4<f32>,
    @location(1) normal_roughness_metallic: vec4<f32>,
    @location(2) emissive_specular: vec4<f32>,
    @location(3) specular_level: f32,
}

// Largest finite f16, the limit of the Rgba16Float targets.
const F16_MAX: f32 = 65504.0;

// The roughness to store: widened by geometric specular anti-aliasing (when compiled
// in) from the screen-space derivatives of the geometric normal `ng` and the length of
// the filtered normal-map texel (1 without one). Every fragment of the quad calls this,
// so the derivatives are taken in uniform control flow.
fn stored_roughness(perceptual_roughness: f32, ng: vec3<f32>, normal_length: f32) -> f32 {
    if !SPECULAR_AA {
        return perceptual_roughness;
    }
    let dx = dpdx(ng);
    let dy = dpdy(ng);
    return specular_aa_roughness(perceptual_roughness, dot(dx, dx) + dot(dy, dy), normal_length,
                                 view.antialiasing.x, view.antialiasing.y);
}

@fragment
fn fs_main(in: VertexOutput, @builtin(front_facing) front: bool) -> GBufferOutput {
    return plain_gbuffer(in, front);
}

fn plain_gbuffer(in: VertexOutput, front: bool) -> GBufferOutput {
    // Back faces reach here only for double-sided materials: light them from the side
    // the viewer sees.
    let n = safe_normalize(select(-in.world_normal, in.world_normal, front), vec3<f32>(0.0, 0.0, 1.0));
    var out: GBufferOutput;
    out.base_color_ao = in.base_color_ao;
    let roughness = stored_roughness(in.roughness_metallic.x, n, 1.0);
    out.normal_roughness_metallic = vec4<f32>(oct_encode(n), roughness, in.roughness_metallic.y);
    out.emissive_specular = in.emissive_specular;
    out.specular_level = in.emissive_specular.a;
    return out;
}

// ---- Textured variant: entities with MaterialMaps (textures and/or vertex colours) ----

@vertex
fn vs_textured(in: VertexInput, inst: InstanceInput) -> TexturedOutput {
    return textured_vertex(in, inst);
}

@fragment
fn fs_textured(in: TexturedOutput, @builtin(front_facing) front: bool) -> GBufferOutput {
    return textured_gbuffer(in, front);
}

fn textured_gbuffer(in: TexturedOutput, front: bool) -> GBufferOutput {
    // Derivatives first, before the alpha test's discard can leave the quad.
    let sign = select(-1.0, 1.0, front);
    let ng = safe_normalize(in.world_normal * sign, vec3<f32>(0.0, 0.0, 1.0));
    let dng_dx = dpdx(ng);
    let dng_dy = dpdy(ng);
    let base = in.base_color * base_color_texel(in.uv0, in.uv1);
    if masked_out(base.a) {
        discard;
    }
    let mapped = mapped_material(in.uv0, in.uv1, ng, in.world_tangent, in.params, in.emissive_occlusion);
    var roughness = mapped.roughness;
    if SPECULAR_AA {
        roughness = specular_aa_roughness(roughness, dot(dng_dx, dng_dx) + dot(dng_dy, dng_dy),
                                          mapped.normal_length, view.antialiasing.x, view.antialiasing.y);
    }
    let n = mapped.n;
    let metallic = mapped.metallic;
    let occlusion = mapped.occlusion;
    let emissive = min(mapped.emissive, vec3<f32>(F16_MAX));
    let rgb = clamp(base.rgb, vec3<f32>(0.0), vec3<f32>(1.0));

    var out: GBufferOutput;
    out.base_color_ao = vec4<f32>(srgb_encode(rgb.r), srgb_encode(rgb.g), srgb_encode(rgb.b),
                                  pack_occlusion_receiver(occlusion, in.params.w));
    out.normal_roughness_metallic = vec4<f32>(oct_encode(n), roughness, metallic);
    out.emissive_specular = vec4<f32>(emissive, stored_specular_level(in.params.z));
    out.specular_level = out.emissive_specular.a;
    return out;
}

// ---- Motion vectors: the same variants, writing a fourth target (only while TAA runs) ----
// Each vertex's clip position through this frame's and the previous frame's unjittered
// camera, the previous one from the instance's previous transform (indexed by the
// instance, like the instance attributes). Every fragment that wins the depth test writes
// its screen motion; the background keeps the clear value 0 (TAA takes its motion from
// the camera).

struct MotionView {
    // Clip from world without jitter, this frame and the previous one.
    clip_from_world: mat4x4<f32>,
    previous_clip_from_world: mat4x4<f32>,
}

@group(2) @binding(0) var<uniform> motion: MotionView;
@group(2) @binding(1) var<storage, read> previous_world: array<mat4x4<f32>>;
// A deformed instance's vertices as the deformation pass left them in the previous frame
// (the mesh's vertex layout, 18 floats each), read where motion_source.x is 1.
@group(2) @binding(2) var<storage, read> previous_vertices: array<f32>;
@group(2) @binding(3) var<uniform> motion_source: vec4<u32>;

const VERTEX_FLOATS: u32 = 18u;

// The clip positions (unjittered) of a vertex now and in the previous frame.
struct MotionVarying {
    @location(10) now: vec4<f32>,
    @location(11) before: vec4<f32>,
}

fn motion_varying(position: vec3<f32>, inst: InstanceInput, instance: u32, vertex: u32) -> MotionVarying {
    let world = instance_world_from_local(inst) * vec4<f32>(position, 1.0);
    var before = position;
    if motion_source.x != 0u {
        let o = vertex * VERTEX_FLOATS;
        before = vec3<f32>(previous_vertices[o], previous_vertices[o + 1u], previous_vertices[o + 2u]);
    }
    return MotionVarying(motion.clip_from_world * world,
                         motion.previous_clip_from_world * (previous_world[instance] * vec4<f32>(before, 1.0)));
}

// Screen motion (pixels, y down) between a point's clip positions before and now.
fn screen_motion(now: vec4<f32>, before: vec4<f32>) -> vec2<f32> {
    let ndc = now.xy / now.w - before.xy / before.w;
    return vec2<f32>(ndc.x * 0.5, -ndc.y * 0.5) * view.viewport.xy;
}

struct MotionGBufferOutput {
    @location(0) base_color_ao: vec4<f32>,
    @location(1) normal_roughness_metallic: vec4<f32>,
    @location(2) emissive_specular: vec4<f32>,
    @location(3) motion: vec4<f32>,
    @location(4) specular_level: f32,
}

fn with_motion(g: GBufferOutput, m: MotionVarying) -> MotionGBufferOutput {
    return MotionGBufferOutput(g.base_color_ao, g.normal_roughness_metallic, g.emissive_specular,
                               vec4<f32>(screen_motion(m.now, m.before), 0.0, 0.0), g.specular_level);
}

struct MotionVertexOutput {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_normal: vec3<f32>,
    @location(1) @interpolate(flat) base_color_ao: vec4<f32>,
    @location(2) @interpolate(flat) emissive_specular: vec4<f32>,
    @location(3) @interpolate(flat) roughness_metallic: vec2<f32>,
    @location(10) now: vec4<f32>,
    @location(11) before: vec4<f32>,
}

@vertex
fn vs_main_motion(in: VertexInput, inst: InstanceInput, @builtin(instance_index) instance: u32,
                  @builtin(vertex_index) vertex: u32) -> MotionVertexOutput {
    let v = plain_vertex(in, inst);
    let m = motion_varying(in.position, inst, instance, vertex);
    return MotionVertexOutput(v.clip, v.world_normal, v.base_color_ao, v.emissive_specular,
                              v.roughness_metallic, m.now, m.before);
}

@fragment
fn fs_main_motion(in: VertexOutput, m: MotionVarying, @builtin(front_facing) front: bool) -> MotionGBufferOutput {
    return with_motion(plain_gbuffer(in, front), m);
}

struct MotionTexturedOutput {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_normal: vec3<f32>,
    @location(1) world_tangent: vec4<f32>,
    @location(2) uv0: vec2<f32>,
    @location(3) uv1: vec2<f32>,
    @location(4) base_color: vec4<f32>,
    @location(5) @interpolate(flat) emissive_occlusion: vec4<f32>,
    @location(6) @interpolate(flat) params: vec4<f32>,
    @location(10) now: vec4<f32>,
    @location(11) before: vec4<f32>,
}

@vertex
fn vs_textured_motion(in: VertexInput, inst: InstanceInput, @builtin(instance_index) instance: u32,
                      @builtin(vertex_index) vertex: u32) -> MotionTexturedOutput {
    let v = textured_vertex(in, inst);
    let m = motion_varying(in.position, inst, instance, vertex);
    return MotionTexturedOutput(v.clip, v.world_normal, v.world_tangent, v.uv0, v.uv1, v.base_color,
                                v.emissive_occlusion, v.params, m.now, m.before);
}

@fragment
fn fs_textured_motion(in: TexturedOutput, m: MotionVarying, @builtin(front_facing) front: bool) -> MotionGBufferOutput {
    return with_motion(textured_gbuffer(in, front), m);
}
