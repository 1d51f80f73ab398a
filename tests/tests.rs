//! End-to-end tests of the `shlight` binary: one test binary, a module per topic.

mod accuracy;
mod batch;
mod engine_frames;
mod export;
mod export_shaders;
mod gltf_asset;
mod gpu;
mod layouts_cli;
mod montecarlo_cli;
mod project;
mod prt;
mod render;
mod shaders;
mod synth;
mod util;
