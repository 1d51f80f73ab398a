//! End-to-end tests of the `shlight` binary: one test binary, a module per topic.

mod export;
mod project;
mod util;
