//! Rays on the GPU: the frame's acceleration structure in storage buffers
//! ([`scene_rays`], built from the extracted frame with [`crate::rays`]) and the kernel
//! that traces a batch of rays against it ([`ray_batch`]: `lumen bench --rays` and the
//! traversal's tests). Tracing shaders import `shaders/rays.wgsl`.

pub mod ray_batch;
pub mod scene_rays;
