//! Output paths of every command: shlight-pipeline's rules (never over an
//! input, directories by name).

pub use shlight_pipeline::refuse_overwriting;
