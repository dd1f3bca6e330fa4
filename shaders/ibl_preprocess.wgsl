// Environment preprocessing (compute), run once per environment image:
//   cs_equirect_to_cube : equirectangular image → cube map mip 0 (as a face strip)
//   cs_downsample       : cube mip n−1 → mip n (2×2 box average, face strip to face strip)
//   cs_prefilter        : GGX-prefiltered cube mip (roughness = mip / (mips − 1)) from the
//                         source cube, with filtered importance sampling (Křivánek &
//                         Colbert 2008): each sample reads the source mip whose texel solid
//                         angle matches the sample's, so a few samples give no fireflies.
// Needs common.wgsl, brdf.wgsl and ibl.wgsl. Cube faces follow the Vulkan/WebGPU order
// +X, −X, +Y, −Y, +Z, −Z.
#import common
#import brdf
#import ibl

struct Params {
    // Output face size in texels, output mip, number of prefiltered mips, sample count.
    size: u32,
    mip: u32,
    mips: u32,
    samples: u32,
    // Source cube face size at mip 0 (texels).
    source_size: f32,
    pad0: f32,
    pad1: f32,
    pad2: f32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var output: texture_storage_2d_array<rgba16float, write>;
@group(0) @binding(2) var input_sampler: sampler;
@group(0) @binding(3) var equirect: texture_2d<f32>;
@group(0) @binding(4) var source_cube: texture_cube<f32>;
// The source cube's mips are built as face strips: the six faces of one mip side by side
// in a 2D texture (face k at columns k·size..(k+1)·size), each copied into the cube.
@group(0) @binding(5) var previous_strip: texture_2d<f32>;
@group(0) @binding(6) var strip: texture_storage_2d<rgba16float, write>;

// Texel `p` of face `face` in a strip of `size`² faces.
fn strip_texel(face: u32, p: vec2<u32>, size: u32) -> vec2<i32> {
    return vec2<i32>(i32(p.x + face * size), i32(p.y));
}

// World direction through face coordinates `uv` in [−1, 1]² of cube face `face`.
fn cube_direction(face: u32, uv: vec2<f32>) -> vec3<f32> {
    var d: vec3<f32>;
    switch face {
        case 0u: { d = vec3<f32>(1.0, -uv.y, -uv.x); }
        case 1u: { d = vec3<f32>(-1.0, -uv.y, uv.x); }
        case 2u: { d = vec3<f32>(uv.x, 1.0, uv.y); }
        case 3u: { d = vec3<f32>(uv.x, -1.0, -uv.y); }
        case 4u: { d = vec3<f32>(uv.x, -uv.y, 1.0); }
        default: { d = vec3<f32>(-uv.x, -uv.y, -1.0); }
    }
    return normalize(d);
}

@compute @workgroup_size(8, 8, 1)
fn cs_equirect_to_cube(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.size || id.y >= params.size {
        return;
    }
    // 2×2 samples per texel, so the cube face averages the equirect where it is denser.
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < 4u; k++) {
        let offset = vec2<f32>(f32(k & 1u), f32(k >> 1u)) * 0.5 - vec2<f32>(0.25);
        let uv = (vec2<f32>(id.xy) + vec2<f32>(0.5) + offset) / f32(params.size) * 2.0 - vec2<f32>(1.0);
        sum += textureSampleLevel(equirect, input_sampler, equirect_uv(cube_direction(id.z, uv)), 0.0).rgb;
    }
    textureStore(strip, strip_texel(id.z, id.xy, params.size), vec4<f32>(sum * 0.25, 1.0));
}

@compute @workgroup_size(8, 8, 1)
fn cs_downsample(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.size || id.y >= params.size {
        return;
    }
    let previous = params.size * 2u;
    let p = id.xy * 2u;
    let c = textureLoad(previous_strip, strip_texel(id.z, p, previous), 0)
        + textureLoad(previous_strip, strip_texel(id.z, p + vec2<u32>(1u, 0u), previous), 0)
        + textureLoad(previous_strip, strip_texel(id.z, p + vec2<u32>(0u, 1u), previous), 0)
        + textureLoad(previous_strip, strip_texel(id.z, p + vec2<u32>(1u, 1u), previous), 0);
    textureStore(strip, strip_texel(id.z, id.xy, params.size), vec4<f32>(c.rgb * 0.25, 1.0));
}

@compute @workgroup_size(8, 8, 1)
fn cs_prefilter(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.size || id.y >= params.size {
        return;
    }
    let n = cube_direction(id.z, (vec2<f32>(id.xy) + vec2<f32>(0.5)) / f32(params.size) * 2.0 - vec2<f32>(1.0));
    if params.mip == 0u {
        textureStore(output, vec2<i32>(id.xy), i32(id.z), vec4<f32>(textureSampleLevel(source_cube, input_sampler, n, 0.0).rgb, 1.0));
        return;
    }
    let r = f32(params.mip) / f32(max(params.mips - 1u, 1u));
    let alpha = perceptual_roughness_to_alpha(r);
    // Tangent frame around n (n = v = reflection direction, the split-sum assumption).
    let up = select(vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(1.0, 0.0, 0.0), abs(n.z) > 0.999);
    let t = normalize(cross(up, n));
    let b = cross(n, t);
    let texel_solid_angle = 4.0 * PI / (6.0 * params.source_size * params.source_size);
    let max_lod = f32(textureNumLevels(source_cube) - 1u);
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    for (var i = 0u; i < params.samples; i++) {
        let h_t = importance_sample_ggx(hammersley(i, params.samples), alpha);
        let h = t * h_t.x + b * h_t.y + n * h_t.z;
        let l = 2.0 * dot(n, h) * h - n;
        let n_dot_l = dot(n, l);
        if n_dot_l > 0.0 {
            // pdf(l) = D (n·h) / (4 v·h) = D / 4 with v = n.
            let n_dot_h = clamp(h_t.z, 0.0, 1.0);
            let pdf = d_ggx(alpha, n_dot_h, max(1.0 - n_dot_h * n_dot_h, 0.0)) * 0.25;
            let sample_solid_angle = 1.0 / (f32(params.samples) * max(pdf, 1e-6));
            let lod = clamp(0.5 * log2(sample_solid_angle / texel_solid_angle) + 1.0, 0.0, max_lod);
            sum += textureSampleLevel(source_cube, input_sampler, l, lod).rgb * n_dot_l;
            weight += n_dot_l;
        }
    }
    textureStore(output, vec2<i32>(id.xy), i32(id.z), vec4<f32>(sum / max(weight, 1e-6), 1.0));
}
