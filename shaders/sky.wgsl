// Sky pass: the environment where no geometry was drawn. The pipeline's depth test
// (equal to the cleared 0) keeps it to background pixels. Header constant ENV_MAP: an
// image environment (else uniform). Needs common, ibl, bindings, fullscreen.
#import common
#import ibl
#import bindings
#import fullscreen

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> environment: EnvironmentUniform;
@group(0) @binding(2) var env_cube: texture_cube<f32>;
@group(0) @binding(3) var env_sampler: sampler;

const F16_MAX: f32 = 65504.0;

@fragment
fn fs_sky(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let ndc = vec2<f32>(frag.x * view.viewport.z * 2.0 - 1.0, 1.0 - frag.y * view.viewport.w * 2.0);
    let far = view.world_from_clip * vec4<f32>(ndc, 0.5, 1.0);
    let dir = safe_normalize(far.xyz / far.w - view.position_exposure.xyz, vec3<f32>(0.0, 0.0, -1.0));
    var c = environment.uniform_radiance.rgb;
    if ENV_MAP {
        let d = rotate_y(dir, -environment.params.y);
        c = textureSampleLevel(env_cube, env_sampler, d, environment.params.w).rgb * environment.params.x;
    }
    return vec4<f32>(min(c, vec3<f32>(F16_MAX)), 0.0);
}
