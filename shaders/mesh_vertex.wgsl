// The mesh vertex and instance inputs of the passes that draw meshes with their materials
// (the G-buffer, gbuffer.wgsl, and the transparent pass, transparent.wgsl), and the
// textured variant's vertex stage. The entry module declares `view` (group 0).

struct VertexInput {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
    @location(14) uv1: vec2<f32>,
    @location(15) color: vec4<f32>,
}

// The instance (the `Instance` layout of bindings.wgsl) as per-instance attributes.
struct InstanceInput {
    @location(4) world_0: vec4<f32>,
    @location(5) world_1: vec4<f32>,
    @location(6) world_2: vec4<f32>,
    @location(7) world_3: vec4<f32>,
    @location(8) normal_matrix_0: vec4<f32>,
    @location(9) normal_matrix_1: vec4<f32>,
    @location(10) normal_matrix_2: vec4<f32>,
    @location(11) base_color: vec4<f32>,
    @location(12) emissive_occlusion: vec4<f32>,
    @location(13) params: vec4<f32>,
}

fn instance_world_from_local(inst: InstanceInput) -> mat4x4<f32> {
    return mat4x4<f32>(inst.world_0, inst.world_1, inst.world_2, inst.world_3);
}

fn instance_normal_matrix(inst: InstanceInput) -> mat3x3<f32> {
    return mat3x3<f32>(inst.normal_matrix_0.xyz, inst.normal_matrix_1.xyz, inst.normal_matrix_2.xyz);
}

struct TexturedOutput {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_normal: vec3<f32>,
    @location(1) world_tangent: vec4<f32>,
    @location(2) uv0: vec2<f32>,
    @location(3) uv1: vec2<f32>,
    // Linear base colour factor × vertex colour (rgba).
    @location(4) base_color: vec4<f32>,
    @location(5) @interpolate(flat) emissive_occlusion: vec4<f32>,
    // Metallic, perceptual roughness, specular level, receives shadows.
    @location(6) @interpolate(flat) params: vec4<f32>,
}

fn textured_vertex(in: VertexInput, inst: InstanceInput) -> TexturedOutput {
    let world_from_local = instance_world_from_local(inst);
    let world = world_from_local * vec4<f32>(in.position, 1.0);
    let normal_matrix = instance_normal_matrix(inst);
    var out: TexturedOutput;
    out.clip = view.clip_from_world * world;
    out.world_normal = normal_matrix * in.normal;
    // Tangents transform with the model matrix (they lie in the surface).
    out.world_tangent = vec4<f32>((world_from_local * vec4<f32>(in.tangent.xyz, 0.0)).xyz, in.tangent.w);
    out.uv0 = in.uv;
    out.uv1 = in.uv1;
    out.base_color = inst.base_color * in.color;
    out.emissive_occlusion = inst.emissive_occlusion;
    out.params = inst.params;
    return out;
}
