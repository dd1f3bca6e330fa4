// Shadow pass: depth of every caster visible to one shadow view. The view's matrix comes
// from a dynamic uniform offset; each visible caster's world matrix is an instance
// attribute (the views' visible lists, one after another).

struct CasterView {
    clip_from_world: mat4x4<f32>,
}

@group(0) @binding(0) var<uniform> caster_view: CasterView;

@vertex
fn vs_main(
    @location(0) position: vec3<f32>,
    @location(1) world_0: vec4<f32>,
    @location(2) world_1: vec4<f32>,
    @location(3) world_2: vec4<f32>,
    @location(4) world_3: vec4<f32>,
) -> @builtin(position) vec4<f32> {
    let world_from_local = mat4x4<f32>(world_0, world_1, world_2, world_3);
    return caster_view.clip_from_world * (world_from_local * vec4<f32>(position, 1.0));
}
