//! Rays against the scene: the acceleration structure every tracer shares (the GPU's
//! tracing passes and path tracer through `shaders/rays/`, the CPU path tracer here).
//!
//! - [`sah`]: the binned-SAH builder, and the bound on a tree's depth.
//! - [`node`]: the 32-byte node and the near-first walk.
//! - [`watertight`]: the ray–triangle test of Woop, Benthin and Wald 2013.
//! - [`blas`]: one mesh's triangles in object space, built once, refitted when it deforms.
//! - [`tlas`]: instances over the meshes' hierarchies, and the arrays a shader binds.
//!
//! The layout and its cost in bytes per triangle are in `docs/rays.md`.

pub mod blas;
pub mod node;
pub mod sah;
pub mod tlas;
pub mod watertight;
