// Shadow pass: depth of every caster visible to one shadow view. The view's matrix comes
// from a dynamic uniform offset; the instance comes through the view's visible list.

struct CasterView {
    clip_from_world: mat4x4<f32>,
}

@group(0) @binding(0) var<uniform> caster_view: CasterView;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;
@group(0) @binding(2) var<storage, read> visible: array<u32>;

@vertex
fn vs_main(@location(0) position: vec3<f32>, @builtin(instance_index) index: u32) -> @builtin(position) vec4<f32> {
    let inst = instances[visible[index]];
    return caster_view.clip_from_world * (inst.world_from_local * vec4<f32>(position, 1.0));
}
