//! The jobs of shlight's commands, one file each, for every front end.
//!
//! Each job has the same shape, `project`'s ([`crate::ProjectOptions`]):
//! a request as a front end was given it (`RenderRequest`, plain values
//! and paths), its `check(spelling)`, which makes the job's plan with
//! every refusal both front ends make, naming the settings as the front
//! end spells them ([`crate::Spelling`]), and one function that reads the
//! inputs, runs every step and writes the outputs, telling its progress,
//! warnings and notes to [`crate::Hooks`]. Front ends only turn their
//! arguments into the request, call, and show what comes back.

pub mod accuracy;
mod by_name;
pub mod compare;
pub mod convert;
pub mod dfg;
pub mod irradiance;
pub mod lightmap;
pub(crate) mod lightmap_sample;
pub mod prefilter;
pub mod project;
pub mod prt;
pub mod render;
pub mod sample;
pub mod synth;
pub mod volume;
