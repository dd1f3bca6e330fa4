// Copies one captured face of a reflection probe (the capture's lit HDR) into the face
// strip the environment prefilter reads (ibl_preprocess.wgsl): face f at x = f × size.
// A right-handed camera sees each cube face mirrored left to right relative to the cube
// map's convention (engine/src/render/capture.rs, FACES), so the copy flips x.

struct FaceCopy {
    // Face 0–5, face side in pixels, unused ×2.
    face_size: vec4<u32>,
}

@group(0) @binding(0) var hdr: texture_2d<f32>;
@group(0) @binding(1) var<uniform> params: FaceCopy;
@group(0) @binding(2) var strip: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn cs_copy_face(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = params.face_size.y;
    if id.x >= size || id.y >= size {
        return;
    }
    let c = textureLoad(hdr, vec2<u32>(size - 1u - id.x, id.y), 0).rgb;
    let safe = clamp(select(c, vec3<f32>(0.0), c != c), vec3<f32>(0.0), vec3<f32>(65504.0));
    textureStore(strip, vec2<u32>(params.face_size.x * size + id.x, id.y), vec4<f32>(safe, 1.0));
}
