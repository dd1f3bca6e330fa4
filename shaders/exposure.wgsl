// Automatic exposure (compute): a histogram of the scene luminance of every pixel (HDR /
// current exposure), then one workgroup that averages log2 luminance between two
// percentiles of the non-black pixels, meters it (EV100 = log2(L · 100 / 12.5)), clamps it and adapts the state
// exponentially towards it. Needs color.wgsl.
#import color

struct ExposureParams {
    // Exposure the HDR target was rendered with (scene luminance = HDR / exposure).
    exposure: f32,
    // log2 luminance (cd/m²) of the histogram's lower edge and the range it spans.
    min_log2: f32,
    log2_range: f32,
    // Seconds since the last frame and the adaptation rate (1/s).
    delta_s: f32,
    rate_per_s: f32,
    // EV100 clamp of the meter.
    min_ev100: f32,
    max_ev100: f32,
    // Percentiles of pixels ignored at the dark and bright ends.
    low_percentile: f32,
    high_percentile: f32,
    // EV100 before anything was metered.
    initial_ev100: f32,
    pad0: f32,
    pad1: f32,
}

const BINS: u32 = 256u;

@group(0) @binding(0) var<uniform> params: ExposureParams;
@group(0) @binding(1) var hdr: texture_2d<f32>;
@group(0) @binding(2) var<storage, read_write> histogram: array<atomic<u32>, 256>;
// EV100 now, metered target EV100, log2 average luminance, 1 once metered.
@group(0) @binding(3) var<storage, read_write> state: array<f32, 4>;

var<workgroup> local_bins: array<atomic<u32>, 256>;
var<workgroup> counts: array<u32, 256>;

// Bin 0 holds black (luminance below 2^min_log2); bins 1..255 split the log range.
fn luminance_bin(lum: f32) -> u32 {
    if !(lum > exp2(params.min_log2)) {
        return 0u;
    }
    let t = (log2(lum) - params.min_log2) / params.log2_range;
    return 1u + u32(clamp(t * f32(BINS - 1u), 0.0, f32(BINS - 2u)));
}

fn bin_log2(bin: u32) -> f32 {
    if bin == 0u {
        return params.min_log2;
    }
    return params.min_log2 + (f32(bin - 1u) + 0.5) / f32(BINS - 1u) * params.log2_range;
}

@compute @workgroup_size(16, 16, 1)
fn cs_histogram(@builtin(global_invocation_id) id: vec3<u32>, @builtin(local_invocation_index) index: u32) {
    atomicStore(&local_bins[index], 0u);
    workgroupBarrier();
    let size = textureDimensions(hdr);
    if id.x < size.x && id.y < size.y {
        let c = textureLoad(hdr, vec2<i32>(id.xy), 0).rgb;
        atomicAdd(&local_bins[luminance_bin(luminance(max(c, vec3<f32>(0.0))) / params.exposure)], 1u);
    }
    workgroupBarrier();
    atomicAdd(&histogram[index], atomicLoad(&local_bins[index]));
}

@compute @workgroup_size(256, 1, 1)
fn cs_average(@builtin(local_invocation_index) index: u32) {
    counts[index] = atomicLoad(&histogram[index]);
    atomicStore(&histogram[index], 0u);
    workgroupBarrier();
    if index == 0u {
        // Bin 0 (black: an empty background, unlit pixels) is not metered.
        var total = 0.0;
        for (var b = 1u; b < BINS; b++) {
            total += f32(counts[b]);
        }
        let low = total * params.low_percentile;
        let high = total * params.high_percentile;
        var cumulative = 0.0;
        var sum = 0.0;
        var weight = 0.0;
        for (var b = 1u; b < BINS; b++) {
            let c = f32(counts[b]);
            let w = min(cumulative + c, high) - max(cumulative, low);
            if w > 0.0 {
                sum += w * bin_log2(b);
                weight += w;
            }
            cumulative += c;
        }
        let previous = select(params.initial_ev100, state[0], state[3] > 0.5);
        // log2(L · 100 / 12.5) = log2 L + 3; an all-black frame keeps the exposure.
        let average_log2 = select(previous - 3.0, sum / weight, weight > 0.0);
        let target_ev = clamp(average_log2 + 3.0, params.min_ev100, params.max_ev100);
        let ev = previous + (target_ev - previous) * (1.0 - exp(-params.delta_s * params.rate_per_s));
        state[0] = ev;
        state[1] = target_ev;
        state[2] = average_log2;
        state[3] = 1.0;
    }
}
