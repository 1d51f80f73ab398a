//! End-to-end tests of the `shlight` binary: one test binary, a module per topic.

mod batch;
mod export;
mod layouts_cli;
mod montecarlo_cli;
mod project;
mod prt;
mod render;
mod synth;
mod util;
