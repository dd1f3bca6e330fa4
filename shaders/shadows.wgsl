// Shadow-map lookups for the lighting pass: view selection (cascades, cube faces),
// receiver biasing and filtering. Header constant SHADOW_FILTER: 0 hardware 2×2 PCF,
// 1 Poisson/Vogel-disc PCF, 2 PCSS, 3 tent (see lumen::quality::ShadowFilter).
#import common
#import bindings
#import shadow_kernel

// The lighting pass's group 1 (LIGHTS_AND_SHADOWS in engine/src/render/shadow/lookups.rs).
@group(1) @binding(4) var<storage, read> shadow_views: array<ShadowView>;
@group(1) @binding(5) var shadow_atlas: texture_depth_2d;
@group(1) @binding(6) var shadow_sampler: sampler_comparison;
// The same atlas as plain floats, for the PCSS blocker search (a depth texture cannot be
// read with textureLoad on GL).
@group(1) @binding(7) var shadow_atlas_depth: texture_2d<f32>;

// The first UNIFORM_SHADOW_VIEW_CAPACITY views again, in a uniform buffer, read when every
// view fits (UNIFORM_SHADOW_VIEWS): cheaper than storage loads on lavapipe.
struct UniformShadowViews {
    items: array<ShadowView, UNIFORM_SHADOW_VIEW_CAPACITY>,
}
@group(1) @binding(8) var<uniform> uniform_shadow_views: UniformShadowViews;

fn shadow_view(i: u32) -> ShadowView {
    if UNIFORM_SHADOW_VIEWS {
        return uniform_shadow_views.items[min(i, UNIFORM_SHADOW_VIEW_CAPACITY - 1u)];
    }
    return shadow_views[i];
}

const SHADOW_FILTER_HARDWARE: u32 = 0u;
const SHADOW_FILTER_PCF: u32 = 1u;
const SHADOW_FILTER_PCSS: u32 = 2u;
const SHADOW_FILTER_TENT: u32 = 3u;
const SHADOW_TAPS: u32 = 16u;
// Radius of the PCF kernel, texels.
const PCF_RADIUS: f32 = 1.5;
// Largest PCSS blocker-search and filter radius, texels.
const PCSS_MAX_RADIUS: f32 = 24.0;

// Interleaved gradient noise (Jimenez 2014): a per-pixel rotation of the tap pattern.
fn interleaved_gradient_noise(p: vec2<f32>) -> f32 {
    return fract(52.9829189 * fract(dot(p, vec2<f32>(0.06711056, 0.00583715))));
}

// Vogel (golden-angle spiral) disc of radius 1: tap i at radius √((i + ½)/n) and angle
// i · 2.39996323 plus a per-pixel rotation. The angle advances by multiplying the unit
// direction with the golden-angle rotation, so a kernel costs one sin/cos per pixel, not
// one per tap.
const GOLDEN_ANGLE_ROTATION: vec2<f32> = vec2<f32>(-0.73736888, 0.67549029);

// The next tap direction after `dir`.
fn vogel_step(dir: vec2<f32>) -> vec2<f32> {
    let r = GOLDEN_ANGLE_ROTATION;
    return vec2<f32>(dir.x * r.x - dir.y * r.y, dir.x * r.y + dir.y * r.x);
}

// Radius of tap i of n.
fn vogel_radius(i: u32, n: u32) -> f32 {
    return sqrt((f32(i) + 0.5) / f32(n));
}

// Distance from the light (m) of a stored depth, for a view's `texel` parameters.
fn shadow_linear_depth(texel: vec4<f32>, depth: f32) -> f32 {
    if texel.y > 0.5 {
        let near = texel.z;
        let far = texel.w;
        return near * far / (far - depth * (far - near));
    }
    return depth * texel.z;
}

// One hardware 2×2 PCF tap at `local` UV inside the tile `rect` (clamped half a texel
// in, so bilinear filtering never reads a neighbouring tile).
fn shadow_tap(rect: vec4<f32>, local: vec2<f32>, depth: f32, texel_uv: f32) -> f32 {
    let l = clamp(local, vec2<f32>(texel_uv * 0.5), vec2<f32>(1.0 - texel_uv * 0.5));
    return textureSampleCompareLevel(shadow_atlas, shadow_sampler, rect.xy + l * rect.zw, depth);
}

// Shadow-map coordinates of a clip position: texel position in the view's tile (xy) and
// depth (z).
fn tile_coords(clip: vec4<f32>, size: f32) -> vec3<f32> {
    let ndc = clip.xyz / clip.w;
    return vec3<f32>((ndc.x * 0.5 + 0.5) * size, (0.5 - ndc.y * 0.5) * size, ndc.z);
}

// Fraction of light (0 shadowed .. 1 lit) for a receiver at tile coordinates `p` (texels,
// depth) of the view with tile `rect` and parameters `texel`. `gradient`: the receiver
// plane's depth change per texel (receiver-plane depth bias): each tap compares against
// the receiver's own depth at that tap, lowered by `margin`, so wide kernels do not shadow
// a sloped receiver with its own texels. `light_size`: tan of the angular radius
// (orthographic) or the light's radius in m.
fn filter_shadow(rect: vec4<f32>, texel: vec4<f32>, p: vec3<f32>, size: f32, gradient: vec2<f32>, margin: f32, frag: vec2<f32>, light_size: f32) -> f32 {
    let local = p.xy / size;
    if rect.z <= 0.0 || any(local < vec2<f32>(0.0)) || any(local > vec2<f32>(1.0)) || p.z > 1.0 || p.z < 0.0 {
        return 1.0;
    }
    let atlas_side = f32(textureDimensions(shadow_atlas).x);
    let texel_uv = 1.0 / size;
    let depth = p.z - margin;
    if SHADOW_FILTER == SHADOW_FILTER_HARDWARE {
        return shadow_tap(rect, local, depth, texel_uv);
    }
    if SHADOW_FILTER == SHADOW_FILTER_TENT {
        // 3 × 3 bilinear taps of a 5 × 5-texel kernel (shadow_kernel.wgsl): no noise.
        let corner = floor(p.xy + 0.5);
        let s = p.xy + 0.5 - corner;
        let wx = shadow_tent_weights(s.x);
        let wy = shadow_tent_weights(s.y);
        let tx = shadow_tent_offsets(s.x) + corner.x - 0.5;
        let ty = shadow_tent_offsets(s.y) + corner.y - 0.5;
        var lit = 0.0;
        for (var j = 0; j < 3; j++) {
            for (var i = 0; i < 3; i++) {
                let tap = vec2<f32>(tx[i], ty[j]);
                lit += wx[i] * wy[j] * shadow_tap(rect, tap * texel_uv, depth + dot(gradient, tap - p.xy), texel_uv);
            }
        }
        return lit;
    }
    let phi = interleaved_gradient_noise(frag) * 6.28318531;
    let rotation = vec2<f32>(cos(phi), sin(phi));
    var radius = PCF_RADIUS;
    if SHADOW_FILTER == SHADOW_FILTER_PCSS {
        // Fernando 2005: average depth of the blockers inside the light's footprint, then
        // a penumbra that widens with the blocker-receiver distance.
        let receiver = shadow_linear_depth(texel, p.z);
        var search: f32;
        if texel.y > 0.5 {
            let near = texel.z;
            search = light_size * (receiver - near) / (max(receiver, 1e-4) * texel.x * near);
        } else {
            search = receiver * light_size / texel.x;
        }
        search = clamp(search, 1.0, PCSS_MAX_RADIUS);
        var blocker_sum = 0.0;
        var blockers = 0.0;
        var dir = rotation;
        for (var i = 0u; i < SHADOW_TAPS; i++) {
            let offset = dir * (vogel_radius(i, SHADOW_TAPS) * search);
            dir = vogel_step(dir);
            let l = clamp(local + offset * texel_uv, vec2<f32>(0.0), vec2<f32>(1.0 - texel_uv));
            let z = textureLoad(shadow_atlas_depth, vec2<i32>((rect.xy + l * rect.zw) * atlas_side), 0).r;
            if z < depth + dot(gradient, offset) {
                blocker_sum += shadow_linear_depth(texel, z);
                blockers += 1.0;
            }
        }
        if blockers == 0.0 {
            return 1.0;
        }
        let blocker = blocker_sum / blockers;
        var penumbra: f32;
        if texel.y > 0.5 {
            penumbra = light_size * (receiver - blocker) / (max(blocker, 1e-4) * texel.x * max(receiver, 1e-4));
        } else {
            penumbra = (receiver - blocker) * light_size / texel.x;
        }
        radius = clamp(penumbra, 1.0, PCSS_MAX_RADIUS);
    }
    var lit = 0.0;
    var dir = rotation;
    for (var i = 0u; i < SHADOW_TAPS; i++) {
        let offset = dir * (vogel_radius(i, SHADOW_TAPS) * radius);
        dir = vogel_step(dir);
        lit += shadow_tap(rect, local + offset * texel_uv, depth + dot(gradient, offset), texel_uv);
    }
    return lit / f32(SHADOW_TAPS);
}

// Biases the receiver and filters shadow view `index`:
// - `depth_bias` texels towards the light and `normal_bias · sin θ` texels along the
//   normal (world offsets, texel = world size of a shadow-map texel at the receiver);
// - the receiver plane (normal `n`) gives each tap its own reference depth, and
//   `slope_bias` texels' worth of the plane's depth gradient is kept as margin.
fn biased_shadow(index: u32, light: Light, world: vec3<f32>, n: vec3<f32>, l: vec3<f32>, frag: vec2<f32>) -> f32 {
    let view = shadow_view(index);
    let m = view.clip_from_world;
    let texel = view.texel;
    let rect = view.rect;
    let size = rect.z * f32(textureDimensions(shadow_atlas).x);
    let clip = m * vec4<f32>(world, 1.0);
    // Orthographic: clip.w = 1; perspective: clip.w is the distance along the view axis.
    let texel_world = texel.x * select(1.0, max(clip.w, texel.z), texel.y > 0.5);
    let n_dot_l = clamp(dot(n, l), 0.0, 1.0);
    let sin_theta = sqrt(1.0 - n_dot_l * n_dot_l);
    let bias = light.shadow_bias;
    let offset = l * (bias.x * texel_world) + n * (bias.z * sin_theta * texel_world);
    let biased = clip + m * vec4<f32>(offset, 0.0);
    // Receiver plane: two steps of one texel along the surface, projected.
    let t1 = safe_normalize(cross(n, select(vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(1.0, 0.0, 0.0), abs(n.y) > 0.9)), vec3<f32>(1.0, 0.0, 0.0));
    let t2 = cross(n, t1);
    let p0 = tile_coords(biased, size);
    let p1 = tile_coords(biased + m * vec4<f32>(t1 * texel_world, 0.0), size) - p0;
    let p2 = tile_coords(biased + m * vec4<f32>(t2 * texel_world, 0.0), size) - p0;
    // Solve [p1.xy p2.xy]ᵀ g = (p1.z, p2.z) for the depth gradient per texel.
    let det = p1.x * p2.y - p1.y * p2.x;
    var gradient = vec2<f32>(0.0);
    if abs(det) > 1e-6 {
        gradient = vec2<f32>(p2.y * p1.z - p1.y * p2.z, p1.x * p2.z - p2.x * p1.z) / det;
    }
    // A receiver seen edge-on by the light would get an unbounded gradient: cap it at the
    // depth change of 10 texels per texel.
    let cap = 10.0 * length(vec2<f32>(p1.z, p2.z)) / max(length(vec2<f32>(length(p1.xy), length(p2.xy))), 1e-6) + 1e-7;
    gradient = gradient * min(1.0, cap / max(length(gradient), 1e-12));
    let margin = bias.y * length(gradient);
    return filter_shadow(rect, texel, p0, size, gradient, margin, frag, light.shadow.z);
}

// Directional light: the cascade that holds `view_depth` (camera distance along its
// axis, m): the number of cascade ends in `cascade_far` at or before it. Across the last
// `blend fraction` of a cascade the next cascade (or, past the last one, no shadow) takes
// over with a probability that rises from 0 to 1, decided per pixel by noise: one lookup
// per pixel instead of two.
fn directional_shadow(light: Light, world: vec3<f32>, n: vec3<f32>, frag: vec2<f32>, view_depth: f32) -> f32 {
    let count = u32(light.shadow.y);
    let ends = light.cascade_far;
    var cascade = u32(dot(select(vec4<f32>(0.0), vec4<f32>(1.0), ends <= vec4<f32>(view_depth)), vec4<f32>(1.0)));
    if cascade >= count {
        return 1.0;
    }
    let far = ends[cascade];
    let near = select(0.0, ends[max(cascade, 1u) - 1u], cascade > 0u);
    let start = far - light.shadow.w * (far - near);
    if (view_depth - start) / max(far - start, 1e-4) > interleaved_gradient_noise(frag + vec2<f32>(17.0, 59.0)) {
        cascade += 1u;
        if cascade >= count {
            return 1.0;
        }
    }
    return biased_shadow(u32(light.shadow.x) + cascade, light, world, n, light.direction.xyz, frag);
}

// Spot light: its one view.
fn spot_shadow(light: Light, world: vec3<f32>, n: vec3<f32>, l: vec3<f32>, frag: vec2<f32>) -> f32 {
    return biased_shadow(u32(light.shadow.x), light, world, n, l, frag);
}

// Point light: the cube face of the major axis of the direction from the light.
fn point_shadow(light: Light, world: vec3<f32>, n: vec3<f32>, l: vec3<f32>, frag: vec2<f32>) -> f32 {
    let d = world - light.position.xyz;
    let a = abs(d);
    var face = 0u;
    if a.x >= a.y && a.x >= a.z {
        face = select(1u, 0u, d.x > 0.0);
    } else if a.y >= a.z {
        face = select(3u, 2u, d.y > 0.0);
    } else {
        face = select(5u, 4u, d.z > 0.0);
    }
    return biased_shadow(u32(light.shadow.x) + face, light, world, n, l, frag);
}
