//! End-to-end tests of the `shlight` binary: one test binary, a module per topic.

mod accuracy;
mod architecture;
mod batch;
mod cycles;
mod encoding_snippets;
mod encodings_cli;
mod engine_frames;
mod export;
#[cfg(feature = "gpu")]
mod export_shaders;
#[cfg(feature = "gpu")]
mod glossy_gpu;
mod gltf_asset;
#[cfg(feature = "gpu")]
mod gpu;
mod guide;
mod layouts_cli;
#[cfg(not(feature = "gpu"))]
mod lean;
mod lightmap;
mod montecarlo_cli;
mod project;
mod prt;
#[cfg(feature = "gpu")]
mod prt_static_gpu;
mod readme;
mod render;
mod sample;
#[cfg(feature = "gpu")]
mod shaders;
mod show;
mod specular;
mod stream;
mod synth;
mod util;
mod volume;
#[cfg(feature = "gpu")]
mod volume_gpu;
#[cfg(feature = "gpu")]
mod volume_snippets;
mod web;
