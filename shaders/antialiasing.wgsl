// Anti-aliasing formulas; each has a Rust twin with the same name in
// engine/src/shading/antialiasing.rs (tests/shader_parity.rs holds them together).
// Needs color.wgsl.

// Whether every channel is finite, from the exponent bits: WGSL lets a compiler assume
// floats are never NaN or ∞, so comparisons like c != c may be folded away.
fn is_finite4(c: vec4<f32>) -> bool {
    let exponent = bitcast<vec4<u32>>(c) & vec4<u32>(0x7f800000u);
    return all(exponent != vec4<u32>(0x7f800000u));
}

// One step of a running mean (Welford 1962): m + (x − m) w with w = 1/n; w ≥ 1 starts a
// new mean. A non-finite sample is left out, so NaN and ∞ never enter the accumulation.
fn running_mean(mean: vec4<f32>, sample: vec4<f32>, weight: f32) -> vec4<f32> {
    let finite = is_finite4(sample);
    if weight >= 1.0 {
        return select(vec4<f32>(0.0), sample, finite);
    }
    if !finite {
        return mean;
    }
    return mean + (sample - mean) * weight;
}

// How sharply the depth bends at a pixel, from its reversed-Z depth and its four
// neighbours': the larger of the horizontal and vertical second differences, relative to
// the largest of the five depths (0 where all are 0). Reversed-Z depth is affine in
// 1/z (z the view depth), and 1/z is linear across the screen on any plane (Heckbert &
// Moreton 1991, "Interpolation for Polygon Texture Mapping and Shading"), so the bend is
// 0 inside a flat surface, small on a curved one, and of the order of 1 where one surface
// ends in front of another: a silhouette.
fn depth_bend(centre: f32, north: f32, south: f32, west: f32, east: f32) -> f32 {
    let scale = max(centre, max(max(north, south), max(west, east)));
    let second = max(abs(north + south - 2.0 * centre), abs(west + east - 2.0 * centre));
    return select(0.0, second / scale, scale > 0.0);
}

// The depth_bend (dimensionless) above which FXAA treats a pixel as on a silhouette.
const SILHOUETTE_BEND: f32 = 0.02;

// Whether unit normals a and b meet at a crease, the edge between two faces of one
// object: an angle of more than 60° between them, where no depth step shows it.
fn creased(a: vec3<f32>, b: vec3<f32>) -> bool {
    return dot(a, b) < CREASE_COSINE;
}

// The cosine of the smallest angle between two normals that creased calls a crease.
const CREASE_COSINE: f32 = 0.5;

// Karis's luminance compression (Karis 2014): c / (1 + Y(c)).
fn compress_hdr(c: vec3<f32>) -> vec3<f32> {
    return c / (1.0 + max(luminance(c), 0.0));
}

// The inverse of compress_hdr: c / (1 − Y(c)), the denominator kept ≥ 1e-4.
fn expand_hdr(c: vec3<f32>) -> vec3<f32> {
    return c / max(1.0 - luminance(c), 1e-4);
}

// FXAA's perceptual luma (Lottes 2009): √Y of the compressed colour.
fn perceptual_luma(compressed: vec3<f32>) -> f32 {
    return sqrt(max(luminance(compressed), 0.0));
}

// Contrast-adaptive sharpening's neighbour weight (Lottes 2019): −strength/5 ·
// √(min(lo, 1 − hi)/hi) per channel.
fn cas_weight(lo: vec3<f32>, hi: vec3<f32>, strength: f32) -> vec3<f32> {
    let room = min(lo, vec3<f32>(1.0) - hi) / max(hi, vec3<f32>(1e-6));
    return -sqrt(clamp(room, vec3<f32>(0.0), vec3<f32>(1.0))) * clamp(strength, 0.0, 1.0) / 5.0;
}

// Sharpening applied: (c + w · cross)/(1 + 4w), non-negative, scaled down where its
// luminance passes cap.
fn cas_apply(c: vec3<f32>, cross: vec3<f32>, w: vec3<f32>, cap: f32) -> vec3<f32> {
    let r = max((c + w * cross) / (vec3<f32>(1.0) + 4.0 * w), vec3<f32>(0.0));
    let y = luminance(r);
    if y > cap {
        return r * (cap / y);
    }
    return r;
}

// RGB → YCoCg (Malvar & Sullivan 2003).
fn rgb_to_ycocg(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(0.25 * c.x + 0.5 * c.y + 0.25 * c.z, 0.5 * c.x - 0.5 * c.z, -0.25 * c.x + 0.5 * c.y - 0.25 * c.z);
}

// YCoCg → RGB.
fn ycocg_to_rgb(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z);
}

// Clips history towards mean into the box mean ± extent (Karis 2014; extent = γσ,
// Salvi 2016).
fn clip_towards_mean(history: vec3<f32>, mean: vec3<f32>, extent: vec3<f32>) -> vec3<f32> {
    let d = history - mean;
    let r = abs(d) / max(extent, vec3<f32>(1e-6));
    let t = max(r.x, max(r.y, r.z));
    if t > 1.0 {
        return mean + d / t;
    }
    return history;
}

// SMAA's luma edge test with local contrast adaptation (Jimenez et al. 2012, §3.1): 1 if
// the step reaches the threshold and half the largest step around the pixel.
fn smaa_edge(delta: f32, local_max: f32, threshold: f32) -> f32 {
    return select(0.0, 1.0, delta >= threshold && 2.0 * delta >= local_max);
}

// The revectorized silhouette's height at a segment end (Reshetov 2009): +½ for a step
// (a crossing edge one pixel long, not continuing `beyond`) on the neighbour's side only
// (x), −½ on the centre's side only (y); corners and plain ends stay at 0.
fn smaa_end_height(crossing: vec2<f32>, beyond: vec2<f32>) -> f32 {
    let neighbour = crossing.x > 0.5 && beyond.x < 0.5;
    let centre = crossing.y > 0.5 && beyond.y < 0.5;
    if neighbour && !centre {
        return 0.5;
    }
    if centre && !neighbour {
        return -0.5;
    }
    return 0.0;
}

// Area between the edge and the line start → end over the column [column, column + 1]:
// (centre's side, neighbour's side), in pixels.
fn line_coverage(column: f32, start: vec2<f32>, end: vec2<f32>) -> vec2<f32> {
    let lo = max(column, start.x);
    let hi = min(column + 1.0, end.x);
    if hi <= lo {
        return vec2<f32>(0.0);
    }
    let slope = (end.y - start.y) / (end.x - start.x);
    let y0 = start.y + slope * (lo - start.x);
    let y1 = start.y + slope * (hi - start.x);
    if y0 * y1 < 0.0 {
        let cross = lo + (hi - lo) * y0 / (y0 - y1);
        let a0 = 0.5 * y0 * (cross - lo);
        let a1 = 0.5 * y1 * (hi - cross);
        return vec2<f32>(max(-a0, 0.0) + max(-a1, 0.0), max(a0, 0.0) + max(a1, 0.0));
    }
    let area = 0.5 * (y0 + y1) * (hi - lo);
    return vec2<f32>(max(-area, 0.0), max(area, 0.0));
}

// SMAA's coverage across an edge segment (Jimenez et al. 2012, orthogonal patterns):
// a Z is one line end to end, an L or U lines from each stepped end towards the middle,
// reaching no farther than `reach` (per end). (pixel covered by the neighbour's colour,
// neighbour covered by the pixel's).
fn smaa_coverage(column: f32, length: f32, ends: vec2<f32>, reach: vec2<f32>) -> vec2<f32> {
    if ends.x * ends.y < 0.0 {
        return line_coverage(column, vec2<f32>(0.0, ends.x), vec2<f32>(length, ends.y));
    }
    let half = 0.5 * length;
    let start = vec2<f32>(min(half, reach.x), 0.0);
    let end = vec2<f32>(length - min(half, reach.y), 0.0);
    return line_coverage(column, vec2<f32>(0.0, ends.x), start)
        + line_coverage(column, end, vec2<f32>(length, ends.y));
}
