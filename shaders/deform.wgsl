// The deformation pass (engine/src/render/deform_pass.rs): one invocation per vertex of one
// deformed instance morphs its rest vertex by the weighted target offsets, then, for a
// skinned mesh, carries it into world space by its skin matrix (the formulas of
// engine/src/scene/deform.rs). The result has the mesh's vertex layout and is drawn by the
// G-buffer, shadow and transparent passes in place of the mesh's vertices.
#import skinning

// Floats per vertex (crate::scene::Vertex): position 0..3, normal 3..6, uv 6..8,
// tangent 8..12, uv1 12..14, colour 14..18.
const VERTEX_FLOATS: u32 = 18u;
// Floats per morph target and vertex: position, normal and tangent offsets.
const TARGET_FLOATS: u32 = 9u;
const WORKGROUP_SIZE: u32 = 64u;

struct DeformParams {
    vertex_count: u32,
    joint_offset: u32,
    joint_count: u32,
    weight_offset: u32,
    target_count: u32,
    skinned: u32,
    pad0: u32,
    pad1: u32,
}

struct Influence {
    joints: vec4<u32>,
    weights: vec4<f32>,
}

@group(0) @binding(0) var<uniform> params: DeformParams;
@group(0) @binding(1) var<storage, read> joint_matrices: array<mat4x4<f32>>;
@group(0) @binding(2) var<storage, read> morph_weights: array<f32>;

@group(1) @binding(0) var<storage, read> rest: array<f32>;
@group(1) @binding(1) var<storage, read> influences: array<Influence>;
@group(1) @binding(2) var<storage, read> targets: array<f32>;
@group(1) @binding(3) var<storage, read_write> deformed: array<f32>;

fn rest3(o: u32) -> vec3<f32> {
    return vec3<f32>(rest[o], rest[o + 1u], rest[o + 2u]);
}

fn target3(o: u32) -> vec3<f32> {
    return vec3<f32>(targets[o], targets[o + 1u], targets[o + 2u]);
}

fn joint(j: u32) -> mat4x4<f32> {
    return joint_matrices[params.joint_offset + min(j, params.joint_count - 1u)];
}

fn store3(o: u32, v: vec3<f32>) {
    deformed[o] = v.x;
    deformed[o + 1u] = v.y;
    deformed[o + 2u] = v.z;
}

// Dispatched as (x, y) workgroups so that more than 65 535 × 64 vertices fit.
@compute @workgroup_size(64)
fn cs_deform(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = id.y * groups.x * WORKGROUP_SIZE + id.x;
    if i >= params.vertex_count {
        return;
    }
    let b = i * VERTEX_FLOATS;
    var p = rest3(b);
    var n = rest3(b + 3u);
    var t = rest3(b + 8u);
    for (var k = 0u; k < params.target_count; k++) {
        let w = morph_weights[params.weight_offset + k];
        let o = (k * params.vertex_count + i) * TARGET_FLOATS;
        p += w * target3(o);
        n += w * target3(o + 3u);
        t += w * target3(o + 6u);
    }
    if params.skinned != 0u {
        let inf = influences[i];
        let s = skin_matrix(joint(inf.joints.x), joint(inf.joints.y), joint(inf.joints.z),
                            joint(inf.joints.w), inf.weights);
        let s3 = mat3x3<f32>(s[0].xyz, s[1].xyz, s[2].xyz);
        p = (s * vec4<f32>(p, 1.0)).xyz;
        n = skin_normal_matrix(s3) * n;
        t = s3 * t;
    }
    let n_len = length(n);
    let t_len = length(t);
    store3(b, p);
    store3(b + 3u, select(vec3<f32>(0.0, 0.0, 1.0), n / n_len, n_len > 0.0));
    deformed[b + 6u] = rest[b + 6u];
    deformed[b + 7u] = rest[b + 7u];
    store3(b + 8u, select(vec3<f32>(1.0, 0.0, 0.0), t / t_len, t_len > 0.0));
    for (var k = 11u; k < VERTEX_FLOATS; k++) {
        deformed[b + k] = rest[b + k];
    }
}
