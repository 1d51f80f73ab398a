//! shlight's one shader emitter: the code of every lookup shlight ships to
//! a shader or a C program, written once and spelled for WGSL, GLSL, HLSL
//! and C by one writer.
//!
//! - [`Language`], [`Type`] and [`Code`]: how each language spells types,
//!   locals, casts, constants, arrays, signatures, loops and selections,
//!   and lines at a nesting depth.
//! - [`basis`]: the SH basis as straight-line statements for one lmax
//!   (shlight-core's [`Legendre`](shlight_core::sh::Legendre) recurrence
//!   factors as literals), what shlight-gpu's passes sum against their
//!   lights, transfers and probes.
//! - [`sh_sum`]: the SH sum `sum_lm w_l c_lm Y_lm(n)` as loops to a
//!   constant lmax (any lmax, no table), the evaluator of the coefficient
//!   snippets and of the volume snippet.
//! - [`coefficients`]: a coefficient file's snippet (its coefficients and
//!   `shlight_irradiance`, `shlight_radiance`).
//! - [`encodings`]: the encodings' `shlight_irradiance` (dominant lights,
//!   ZH3, non-linear L1, ambient cube), the core's formulas.
//! - [`visibility`]: DDGI's probe visibility weight, the lookup of
//!   shlight-baked's `visibility.rs`, for the volume snippet's textures and
//!   for shlight-gpu's storage buffers.
//! - [`volume`]: an irradiance volume's lookup over probe textures (the
//!   validity-weighted trilinear one, or with visibility), what `shlight
//!   sample` shades with.
//!
//! The CPU definition of each lookup stays where it is (shlight-core's
//! basis and encodings, shlight-baked's grid and visibility); this crate
//! writes the same operations in the same order, and the tests of the
//! crates that ship the code (shlight-format's snippets, shlight-gpu's
//! passes) compile and run it against those definitions.
//!
//! ```
//! use shlight_shader::Language;
//! use shlight_shader::basis::{BasisNames, basis_statements};
//!
//! // The basis to lmax 1 at the direction `d`, in GLSL and in WGSL.
//! let glsl = basis_statements(Language::Glsl, 1, BasisNames::default(), |_, _, _| {});
//! assert_eq!(glsl[0], "float z = d.z;");
//! assert!(glsl.contains(&"float c1 = d.x;".to_string()));
//! let wgsl = basis_statements(Language::Wgsl, 1, BasisNames::default(), |_, _, _| {});
//! assert!(wgsl.contains(&"let c1 = d.x;".to_string()));
//! ```
//!
//! **Architecture invariant:** text only: no file, no GPU, no format; the
//! callers name the lookups' inputs (constants, uniforms, textures).

#![deny(missing_docs)]

pub mod basis;
pub mod coefficients;
pub mod encodings;
mod language;
mod literal;
pub mod sh_sum;
pub mod visibility;
pub mod volume;

pub use language::{Code, Language, ShaderLanguage, Type};
pub use literal::{f32_literal, float_literal};
