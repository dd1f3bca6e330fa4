//! The CPU twins of the shaders' formulas: each module holds, under the same names, the
//! formulas of the WGSL module of the same name in `shaders/` (`brdf.rs` and
//! `brdf.wgsl`, …), with their units and their papers. The path tracer, the tests and the
//! tools evaluate them here; `tests/shader_parity.rs` runs both sides on the same inputs
//! and binds them.

pub mod ambient_occlusion;
pub mod anisotropy;
pub mod antialiasing;
pub mod brdf;
pub mod clearcoat;
pub mod color;
pub mod diffuse_transmission;
pub mod encoding;
pub mod ibl;
pub mod iridescence;
pub mod irradiance_volume;
pub mod punctual;
pub mod reflection_probe;
pub mod shadow_kernel;
pub mod sheen;
pub mod transmission;
pub mod transparency;
