// Tiled light culling (compute; Harada et al. 2012, "Forward+"; Olsson & Assarsson 2011,
// "Tiled Shading"). One 16×16 workgroup per screen tile: the tile's depth bounds from the
// G-buffer depth, the world-space box of the tile's frustum between them, then every
// unshadowed point and spot light whose range sphere meets the box is listed for the
// tile. Lights without a range (1/range² = 0) meet every tile. Background-only tiles list
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
var<workgroup> has_geometry: u32;

// Whether the light's range sphere meets the box.
fn reaches(light: Light, lo: vec3<f32>, hi: vec3<f32>) -> bool {
    let inv_range2 = light.color_inv_range2.w;
    if !(inv_range2 > 0.0) {
        return true;
    }
    let p = light.position.xyz;
    let d = max(max(lo - p, p - hi), vec3<f32>(0.0));
    return dot(d, d) * inv_range2 <= 1.0;
}

@compute @workgroup_size(16, 16, 1)
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
    let pixel = tile.xy * TILE_SIZE + local.xy;
    if all(pixel < size) {
        // Reversed Z: 0 is the background; positive floats order like their bits.
        let d = textureLoad(depth_buffer, vec2<i32>(pixel), 0).r;
        if d > 0.0 {
            atomicMin(&depth_min, bitcast<u32>(d));
            atomicMax(&depth_max, bitcast<u32>(d));
        }
    }
    workgroupBarrier();
    if index == 0u {
        let max_bits = atomicLoad(&depth_max);
        has_geometry = select(0u, 1u, max_bits != 0u);
        let depths = vec2<f32>(bitcast<f32>(atomicLoad(&depth_min)), bitcast<f32>(max_bits));
        let uv_lo = vec2<f32>(tile.xy * TILE_SIZE) * view.viewport.zw;
        let uv_hi = min(vec2<f32>((tile.xy + 1u) * TILE_SIZE) * view.viewport.zw, vec2<f32>(1.0));
        var lo = vec3<f32>(3.0e38);
        var hi = vec3<f32>(-3.0e38);
        for (var k = 0u; k < 8u; k++) {
            let uv = select(uv_lo, uv_hi, vec2<bool>((k & 1u) != 0u, (k & 2u) != 0u));
            let ndc = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, select(depths.x, depths.y, (k & 4u) != 0u), 1.0);
            let w = view.world_from_clip * ndc;
            let p = w.xyz / w.w;
            lo = min(lo, p);
            hi = max(hi, p);
        }
        box_min = lo;
        box_max = hi;
    }
    let tile_has_geometry = workgroupUniformLoad(&has_geometry);
    let base = (tile.y * ((size.x + TILE_SIZE - 1u) / TILE_SIZE) + tile.x) * TILE_STRIDE;
    if tile_has_geometry != 0u {
        let lo = box_min;
        let hi = box_max;
        let counts = view.light_counts;
        let shadowed = view.shadowed_counts;
        for (var i = counts.x + shadowed.y + index; i < counts.x + counts.y; i += 256u) {
            if reaches(lights[i], lo, hi) {
                let slot = atomicAdd(&point_count, 1u);
                if slot < MAX_TILE_LIGHTS {
                    tiles[base + 2u + slot] = i;
                }
            }
        }
        for (var i = counts.x + counts.y + shadowed.z + index; i < counts.w; i += 256u) {
            if reaches(lights[i], lo, hi) {
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
