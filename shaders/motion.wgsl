// Motion vectors (engine/src/render/antialiasing/motion.rs): each pixel's screen motion
// in pixels from the previous frame to this one, both without the camera's jitter.
// fs_camera: every pixel, from its depth, as if nothing moved but the camera.
// vs_object/fs_object: the instances that moved, drawn again over their own depth
// (equal test; @invariant positions match the G-buffer's), from their previous transform.
#import bindings
#import fullscreen

struct MotionView {
    // Clip from world without jitter, this frame and the previous one.
    clip_from_world: mat4x4<f32>,
    previous_clip_from_world: mat4x4<f32>,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> motion: MotionView;
@group(1) @binding(0) var depth: texture_2d<f32>;

fn ndc_to_pixel(ndc: vec2<f32>) -> vec2<f32> {
    return vec2<f32>((ndc.x * 0.5 + 0.5) * view.viewport.x, (0.5 - ndc.y * 0.5) * view.viewport.y);
}

// Screen motion (pixels) between a point's clip positions before and now.
fn screen_motion(now: vec4<f32>, before: vec4<f32>) -> vec2<f32> {
    return ndc_to_pixel(now.xy / now.w) - ndc_to_pixel(before.xy / before.w);
}

@fragment
fn fs_camera(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let d = textureLoad(depth, vec2<i32>(frag.xy), 0).r;
    // The surface seen at this pixel, through this frame's (jittered) projection.
    let ndc = vec2<f32>(frag.x * view.viewport.z * 2.0 - 1.0, 1.0 - frag.y * view.viewport.w * 2.0);
    let h = view.world_from_clip * vec4<f32>(ndc, d, 1.0);
    let world = vec4<f32>(h.xyz / h.w, 1.0);
    return vec4<f32>(screen_motion(motion.clip_from_world * world, motion.previous_clip_from_world * world), 0.0, 0.0);
}

struct ObjectInput {
    @location(0) position: vec3<f32>,
    @location(4) world_0: vec4<f32>,
    @location(5) world_1: vec4<f32>,
    @location(6) world_2: vec4<f32>,
    @location(7) world_3: vec4<f32>,
    @location(8) previous_0: vec4<f32>,
    @location(9) previous_1: vec4<f32>,
    @location(10) previous_2: vec4<f32>,
    @location(11) previous_3: vec4<f32>,
}

struct ObjectOutput {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) now: vec4<f32>,
    @location(1) before: vec4<f32>,
}

@vertex
fn vs_object(in: ObjectInput) -> ObjectOutput {
    let world_from_local = mat4x4<f32>(in.world_0, in.world_1, in.world_2, in.world_3);
    let previous = mat4x4<f32>(in.previous_0, in.previous_1, in.previous_2, in.previous_3);
    let world = world_from_local * vec4<f32>(in.position, 1.0);
    var out: ObjectOutput;
    out.clip = view.clip_from_world * world;
    out.now = motion.clip_from_world * world;
    out.before = motion.previous_clip_from_world * (previous * vec4<f32>(in.position, 1.0));
    return out;
}

@fragment
fn fs_object(in: ObjectOutput) -> @location(0) vec4<f32> {
    return vec4<f32>(screen_motion(in.now, in.before), 0.0, 0.0);
}
