// Tiled light culling (compute; Harada et al. 2012, "Forward+"; Olsson & Assarsson 2011,
// "Tiled Shading"). One invocation per 16×16-pixel screen tile: the tile's depth bounds
// from the G-buffer depth, then the tile's frustum between them as four side planes
// through the eye, a view-depth interval and a world-space box. Every unshadowed point
// and spot light whose range sphere meets all three is listed for the tile. Lights
// without a range (1/range² = 0) meet every tile. Background-only tiles list nothing.
// An invocation per tile needs no barrier and no atomic, which costs a quarter of the
// cooperative 8×8-workgroup version on lavapipe (measured). Needs common, bindings,
// light_tiles.
#import bindings
#import light_tiles

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<storage, read> lights: array<Light>;
@group(0) @binding(2) var depth_buffer: texture_2d<f32>;
@group(0) @binding(3) var<storage, read_write> tiles: array<u32>;

// The compact copy the lighting pass reads too (UNIFORM_LIGHTS: every light fits).
struct UniformLights {
    items: array<PunctualLight, UNIFORM_LIGHT_CAPACITY>,
}
@group(0) @binding(4) var<uniform> uniform_lights: UniformLights;

// Position (xyz) and 1/range² (w) of light i.
fn light_sphere(i: u32) -> vec4<f32> {
    if UNIFORM_LIGHTS {
        return uniform_lights.items[min(i, UNIFORM_LIGHT_CAPACITY - 1u)].position_inv_range2;
    }
    return vec4<f32>(lights[i].position.xyz, lights[i].color_inv_range2.w);
}

// The tile's bounds: a world-space box, inward side planes (normal, offset) and the
// view-depth interval.
struct TileBounds {
    lo: vec3<f32>,
    hi: vec3<f32>,
    sides: array<vec4<f32>, 4>,
    depths: vec2<f32>,
}

// Whether the range sphere (position xyz, 1/range² w) meets the tile's bounds.
fn reaches(sphere: vec4<f32>, b: TileBounds) -> bool {
    let inv_range2 = sphere.w;
    if !(inv_range2 > 0.0) {
        return true;
    }
    let p = sphere.xyz;
    let r = inverseSqrt(inv_range2);
    let d = max(max(b.lo - p, p - b.hi), vec3<f32>(0.0));
    var inside = dot(d, d) <= r * r;
    for (var k = 0u; k < 4u; k++) {
        inside = inside && dot(b.sides[k].xyz, p) + b.sides[k].w >= -r;
    }
    let z = dot(p - view.position_exposure.xyz, view.forward.xyz);
    return inside && z >= b.depths.x - r && z <= b.depths.y + r;
}

// The bounds of the tile `tile` between the reversed-Z depths `depths` (nearest is the
// larger value).
fn tile_bounds(tile: vec2<u32>, depths: vec2<f32>) -> TileBounds {
    let uv_lo = vec2<f32>(tile * TILE_SIZE) * view.viewport.zw;
    let uv_hi = min(vec2<f32>((tile + 1u) * TILE_SIZE) * view.viewport.zw, vec2<f32>(1.0));
    var b: TileBounds;
    b.lo = vec3<f32>(3.0e38);
    b.hi = vec3<f32>(-3.0e38);
    b.depths = vec2<f32>(3.0e38, -3.0e38);
    var corners: array<vec3<f32>, 4>;
    let eye = view.position_exposure.xyz;
    for (var k = 0u; k < 8u; k++) {
        let uv = select(uv_lo, uv_hi, vec2<bool>((k & 1u) != 0u, (k & 2u) != 0u));
        let ndc = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, select(depths.x, depths.y, (k & 4u) != 0u), 1.0);
        let w = view.world_from_clip * ndc;
        let p = w.xyz / w.w;
        b.lo = min(b.lo, p);
        b.hi = max(b.hi, p);
        let depth = dot(p - eye, view.forward.xyz);
        b.depths = vec2<f32>(min(b.depths.x, depth), max(b.depths.y, depth));
        corners[k & 3u] = p - eye;
    }
    // Corners 0 (lo, lo), 1 (hi, lo), 3 (hi, hi), 2 (lo, hi) go round the tile; each side
    // plane holds the eye and two neighbouring corner rays, its normal towards the tile's
    // centre ray.
    let centre = corners[0] + corners[1] + corners[2] + corners[3];
    let ring = array<u32, 5>(0u, 1u, 3u, 2u, 0u);
    for (var k = 0u; k < 4u; k++) {
        var n = normalize(cross(corners[ring[k]], corners[ring[k + 1u]]));
        n = select(n, -n, dot(n, centre) < 0.0);
        b.sides[k] = vec4<f32>(n, -dot(n, eye));
    }
    return b;
}

@compute @workgroup_size(8, 8, 1)
fn cs_cull(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(view.viewport.xy);
    let tiles_xy = (size + TILE_SIZE - 1u) / TILE_SIZE;
    if any(id.xy >= tiles_xy) {
        return;
    }
    let tile = id.xy;
    let base = (tile.y * tiles_xy.x + tile.x) * TILE_STRIDE;
    // Reversed Z: 0 is the background.
    let origin = tile * TILE_SIZE;
    let end = min(origin + TILE_SIZE, size);
    var far_depth = 3.0e38;
    var near_depth = 0.0;
    for (var y = origin.y; y < end.y; y++) {
        for (var x = origin.x; x < end.x; x++) {
            let d = textureLoad(depth_buffer, vec2<i32>(i32(x), i32(y)), 0).r;
            if d > 0.0 {
                far_depth = min(far_depth, d);
                near_depth = max(near_depth, d);
            }
        }
    }
    var points = 0u;
    var spots = 0u;
    if near_depth > 0.0 {
        let b = tile_bounds(tile, vec2<f32>(far_depth, near_depth));
        let counts = view.light_counts;
        let shadowed = view.shadowed_counts;
        for (var i = counts.x + shadowed.y; i < counts.x + counts.y; i++) {
            if reaches(light_sphere(i), b) {
                if points < MAX_TILE_LIGHTS {
                    tiles[base + 2u + points] = i;
                }
                points += 1u;
            }
        }
        for (var i = counts.x + counts.y + shadowed.z; i < counts.w; i++) {
            if reaches(light_sphere(i), b) {
                if spots < MAX_TILE_LIGHTS {
                    tiles[base + 2u + MAX_TILE_LIGHTS + spots] = i;
                }
                spots += 1u;
            }
        }
    }
    tiles[base] = select(points, TILE_OVERFLOW, points > MAX_TILE_LIGHTS);
    tiles[base + 1u] = select(spots, TILE_OVERFLOW, spots > MAX_TILE_LIGHTS);
}
