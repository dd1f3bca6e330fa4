// Shadow pass: depth of every caster visible to one shadow view. The view's matrix comes
// from a dynamic uniform offset; each visible caster's world matrix and base colour are
// instance attributes (the views' visible lists, one after another). Casters with an
// alpha-masked material (glTF `alphaMode: MASK`) draw with `vs_masked` / `fs_masked`,
// which drop the texels the G-buffer drops, so the shadow has the mask's shape. Blended
// casters (`Material::blend`) draw with them too, keeping a fraction α of their texels in
// an ordered dither (blended_shadow_threshold), so their shadow lets about 1 − α through.
#import material_maps
#import shadow_kernel

struct CasterView {
    clip_from_world: mat4x4<f32>,
}

@group(0) @binding(0) var<uniform> caster_view: CasterView;

// A caster's vertex position and its instance's world matrix.
struct CasterVertex {
    @location(0) position: vec3<f32>,
    @location(1) world_0: vec4<f32>,
    @location(2) world_1: vec4<f32>,
    @location(3) world_2: vec4<f32>,
    @location(4) world_3: vec4<f32>,
}

fn caster_clip(in: CasterVertex) -> vec4<f32> {
    let world_from_local = mat4x4<f32>(in.world_0, in.world_1, in.world_2, in.world_3);
    return caster_view.clip_from_world * (world_from_local * vec4<f32>(in.position, 1.0));
}

@vertex
fn vs_main(in: CasterVertex) -> @builtin(position) vec4<f32> {
    return caster_clip(in);
}

struct MaskedOutput {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv0: vec2<f32>,
    @location(1) uv1: vec2<f32>,
    // Base colour factor alpha × vertex colour alpha (x), 1 for a blended caster (y).
    @location(2) coverage: vec2<f32>,
}

@vertex
fn vs_masked(
    in: CasterVertex,
    @location(5) coverage: vec4<f32>,
    @location(6) uv0: vec2<f32>,
    @location(7) uv1: vec2<f32>,
    @location(8) color: vec4<f32>,
) -> MaskedOutput {
    var out: MaskedOutput;
    out.clip = caster_clip(in);
    out.uv0 = uv0;
    out.uv1 = uv1;
    out.coverage = vec2<f32>(coverage.x * color.a, coverage.y);
    return out;
}

@fragment
fn fs_masked(in: MaskedOutput) {
    let alpha = in.coverage.x * base_color_texel(in.uv0, in.uv1).a;
    let blended = in.coverage.y > 0.5;
    let dropped = select(masked_out(alpha), alpha <= blended_shadow_threshold(vec2<u32>(in.clip.xy)), blended);
    if dropped {
        discard;
    }
}
