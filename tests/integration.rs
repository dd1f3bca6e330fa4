//! Every integration test but the soak test, as modules of one test binary: one
//! compile and link instead of thirty-odd.
//! Each module is named for what it tests; `cargo test --release --test integration
//! golden::` runs one of them. The soak test (`soak.rs`) stays a binary of its own: it
//! measures its process's resident memory, which other tests would move.

mod common;

mod antialiasing;
mod bench;
mod bindings;
mod camera;
mod cli;
mod docs;
mod examples;
mod frame_graph;
mod fuzz;
mod global_illumination;
mod gltf;
mod gnu_parallel;
mod golden;
mod ibl;
mod indirect;
mod knobs;
mod layering;
mod layers;
mod lights;
mod rays;
mod reference;
mod reflection_probes;
mod render;
mod robustness;
mod scale_out;
mod scripting;
mod shader_parity;
mod shadows;
mod skinning;
mod slurm;
mod temporal;
mod toy;
mod tradeoff;
mod transmission;
mod transparency;
mod unlit;
mod validate;
mod viewer;
