// Tiled light culling (compute; Harada et al. 2012, "Forward+"; Olsson & Assarsson 2011,
// "Tiled Shading"). One 8×8 workgroup per 16×16-pixel screen tile (each invocation reads
// 2×2 pixels; fewer invocations make the barriers cheaper on CPU rasterizers): the tile's
// depth bounds from the G-buffer depth, then the tile's frustum between them as four side
// planes through the eye, a view-depth interval and a world-space box. Every unshadowed
// point and spot light whose range sphere meets all three is listed for the tile. Lights without a range (1/range² = 0) meet every tile. Background-only tiles list
// nothing. Needs common, bindings, light_tiles.

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<storage, read> lights: array<Light>;
@group(0) @binding(2) var depth_buffer: texture_2d<f32>;
@group(0) @binding(3) var<storage, read_write> tiles: array<u32>;

var<workgroup> depth_min: atomic<u32>;
var<workgroup> depth_max: atomic<u32>;
var<workgroup> point_count: atomic<u32>;
var<workgroup> spot_count: atomic<u32>;
var<workgroup> box_min: vec3<f32>;
var<workgroup> box_max: vec3<f32>;
// Inward side planes (normal, offset) and the view-depth interval of the tile.
var<workgroup> planes: array<vec4<f32>, 4>;
var<workgroup> depth_range: vec2<f32>;
var<workgroup> has_geometry: u32;

// Whether the light's range sphere meets the tile's box, side planes and depth interval.
fn reaches(light: Light, lo: vec3<f32>, hi: vec3<f32>, sides: array<vec4<f32>, 4>, depths: vec2<f32>) -> bool {
    let inv_range2 = light.color_inv_range2.w;
    if !(inv_range2 > 0.0) {
        return true;
    }
    let p = light.position.xyz;
    let r = inverseSqrt(inv_range2);
    let d = max(max(lo - p, p - hi), vec3<f32>(0.0));
    var inside = dot(d, d) <= r * r;
    for (var k = 0u; k < 4u; k++) {
        inside = inside && dot(sides[k].xyz, p) + sides[k].w >= -r;
    }
    let z = dot(p - view.position_exposure.xyz, view.forward.xyz);
    return inside && z >= depths.x - r && z <= depths.y + r;
}

const GROUP: u32 = 64u;

@compute @workgroup_size(8, 8, 1)
fn cs_cull(
    @builtin(workgroup_id) tile: vec3<u32>,
    @builtin(local_invocation_id) local: vec3<u32>,
    @builtin(local_invocation_index) index: u32,
) {
    if index == 0u {
        atomicStore(&depth_min, 0x7f800000u);
        atomicStore(&depth_max, 0u);
        atomicStore(&point_count, 0u);
        atomicStore(&spot_count, 0u);
    }
    workgroupBarrier();
    let size = vec2<u32>(view.viewport.xy);
    // Reversed Z: 0 is the background; positive floats order like their bits.
    var lo_bits = 0x7f800000u;
    var hi_bits = 0u;
    for (var k = 0u; k < 4u; k++) {
        let pixel = tile.xy * TILE_SIZE + local.xy * 2u + vec2<u32>(k & 1u, k >> 1u);
        if all(pixel < size) {
            let d = textureLoad(depth_buffer, vec2<i32>(pixel), 0).r;
            if d > 0.0 {
                lo_bits = min(lo_bits, bitcast<u32>(d));
                hi_bits = max(hi_bits, bitcast<u32>(d));
            }
        }
    }
    atomicMin(&depth_min, lo_bits);
    atomicMax(&depth_max, hi_bits);
    workgroupBarrier();
    if index == 0u {
        let max_bits = atomicLoad(&depth_max);
        has_geometry = select(0u, 1u, max_bits != 0u);
        let depths = vec2<f32>(bitcast<f32>(atomicLoad(&depth_min)), bitcast<f32>(max_bits));
        let uv_lo = vec2<f32>(tile.xy * TILE_SIZE) * view.viewport.zw;
        let uv_hi = min(vec2<f32>((tile.xy + 1u) * TILE_SIZE) * view.viewport.zw, vec2<f32>(1.0));
        var lo = vec3<f32>(3.0e38);
        var hi = vec3<f32>(-3.0e38);
        var z = vec2<f32>(3.0e38, -3.0e38);
        var corners: array<vec3<f32>, 4>;
        let eye = view.position_exposure.xyz;
        for (var k = 0u; k < 8u; k++) {
            let uv = select(uv_lo, uv_hi, vec2<bool>((k & 1u) != 0u, (k & 2u) != 0u));
            let ndc = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, select(depths.x, depths.y, (k & 4u) != 0u), 1.0);
            let w = view.world_from_clip * ndc;
            let p = w.xyz / w.w;
            lo = min(lo, p);
            hi = max(hi, p);
            let depth = dot(p - eye, view.forward.xyz);
            z = vec2<f32>(min(z.x, depth), max(z.y, depth));
            corners[k & 3u] = p - eye;
        }
        box_min = lo;
        box_max = hi;
        depth_range = z;
        // Corners 0 (lo, lo), 1 (hi, lo), 3 (hi, hi), 2 (lo, hi) go round the tile; each
        // side plane holds the eye and two neighbouring corner rays, its normal towards
        // the tile's centre ray.
        let centre = corners[0] + corners[1] + corners[2] + corners[3];
        let ring = array<u32, 5>(0u, 1u, 3u, 2u, 0u);
        for (var k = 0u; k < 4u; k++) {
            var n = normalize(cross(corners[ring[k]], corners[ring[k + 1u]]));
            n = select(n, -n, dot(n, centre) < 0.0);
            planes[k] = vec4<f32>(n, -dot(n, eye));
        }
    }
    let tile_has_geometry = workgroupUniformLoad(&has_geometry);
    let base = (tile.y * ((size.x + TILE_SIZE - 1u) / TILE_SIZE) + tile.x) * TILE_STRIDE;
    if tile_has_geometry != 0u {
        let lo = box_min;
        let hi = box_max;
        let sides = planes;
        let depths = depth_range;
        let counts = view.light_counts;
        let shadowed = view.shadowed_counts;
        for (var i = counts.x + shadowed.y + index; i < counts.x + counts.y; i += GROUP) {
            if reaches(lights[i], lo, hi, sides, depths) {
                let slot = atomicAdd(&point_count, 1u);
                if slot < MAX_TILE_LIGHTS {
                    tiles[base + 2u + slot] = i;
                }
            }
        }
        for (var i = counts.x + counts.y + shadowed.z + index; i < counts.w; i += GROUP) {
            if reaches(lights[i], lo, hi, sides, depths) {
                let slot = atomicAdd(&spot_count, 1u);
                if slot < MAX_TILE_LIGHTS {
                    tiles[base + 2u + MAX_TILE_LIGHTS + slot] = i;
                }
            }
        }
    }
    workgroupBarrier();
    if index == 0u {
        let points = atomicLoad(&point_count);
        let spots = atomicLoad(&spot_count);
        tiles[base] = select(points, TILE_OVERFLOW, points > MAX_TILE_LIGHTS);
        tiles[base + 1u] = select(spots, TILE_OVERFLOW, spots > MAX_TILE_LIGHTS);
    }
}
