// Linear blend skinning (Magnenat-Thalmann, Laperrière and Thalmann 1988), as glTF 2.0
// §3.7.3 defines it. The Rust twins are in engine/src/scene/deform.rs (same names);
// tests/shader_parity.rs compares them.

// The skin matrix S = Σ a_i J_i of a vertex whose four joints have the matrices j0..j3
// (world from bind-pose model space) and the weights a (summing to 1).
fn skin_matrix(j0: mat4x4<f32>, j1: mat4x4<f32>, j2: mat4x4<f32>, j3: mat4x4<f32>, a: vec4<f32>) -> mat4x4<f32> {
    return j0 * a.x + j1 * a.y + j2 * a.z + j3 * a.w;
}

// The matrix that carries normals through the linear map m: sign(det m) · cof(m), the
// inverse transpose up to a positive factor (defined even where m is singular).
fn skin_normal_matrix(m: mat3x3<f32>) -> mat3x3<f32> {
    let cofactor = mat3x3<f32>(cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1]));
    return cofactor * select(1.0, -1.0, determinant(m) < 0.0);
}
