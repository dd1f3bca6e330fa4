//! The post-processing stage: what happens to the lit HDR frame before and as it becomes
//! the display image. Anti-aliasing ([`antialias`]: accumulation, TAA, FXAA, SMAA),
//! automatic [`exposure`], depth of field ([`dof`]), tone mapping ([`tonemap`]) into the
//! output, and the [`debug_view`] that replaces it with a G-buffer channel.
pub mod antialias;
pub mod debug_view;
pub mod dof;
pub mod exposure;
pub mod tonemap;
