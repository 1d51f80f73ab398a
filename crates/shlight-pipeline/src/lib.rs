//! The jobs of shlight's commands as a library, for every front end (the
//! `shlight` command line, the Python package) to run the same way.
//!
//! One job per command, one file each under `src/job/`, all of one shape:
//! a request as a front end was given it ([`RenderRequest`],
//! [`ProjectRequest`], [`PrtRequest`], [`VolumeRequest`], [`SampleRequest`],
//! [`PrefilterRequest`], [`DfgRequest`], [`SynthRequest`],
//! [`ConvertRequest`], [`IrradianceRequest`], [`CompareRequest`],
//! [`AccuracyRequest`]); its `check(spelling)`, which makes the job's plan
//! with every refusal both front ends make, naming each setting as the
//! front end spells it ([`Spelling`]: `--lmax 9` or `lmax=9`); and one
//! function that reads the inputs, runs every step and writes the outputs
//! ([`render`], [`project_files`], [`prt`], [`volume`], [`sample`],
//! [`prefilter`], [`dfg`], [`synth`], [`convert`], [`irradiance`],
//! [`compare`], [`accuracy`]), telling its progress, warnings and notes to
//! [`Hooks`]. Front ends turn their arguments into the request, call, and
//! show what comes back; the in-memory halves ([`render_light`],
//! [`project_each`], [`synth_map`], [`volume_irradiance`],
//! [`transfer_radiance`], [`relight_volume`]) serve a front end that keeps
//! the data rather than files. No command-line, GPU or error-erasing
//! dependency, and no mathematics of its own: the maths is shlight-core's,
//! the bakes shlight-prt's and shlight-volume's, the files shlight-format's;
//! the GPU's projection comes in as a [`Projector`].
//!
//! # The projection's steps
//! [`project`]`(source, settings, projector, hooks)` sequences every step
//! of projecting one map, the only place they are sequenced:
//! 1. [`load_map`]: read a map (or six `{face}` files laid out as a strip),
//!    settle its [`InputLayout`], and check its values ([`check_values`]:
//!    NaN and infinity refused, negatives kept with a warning) or
//!    [`sanitize_image`] them. Texels already in memory
//!    ([`Source::Texels`]) are checked by [`source_stats`] and
//!    [`check_values`].
//! 2. The [`Projector`]: [`CpuProjector`] ([`project_radiance_texels`]:
//!    quadrature or Monte Carlo, [`Method`]) or one the caller brings.
//! 3. [`choose_windows`]: the window asked for, or per colour channel the
//!    weakest Hanning window that keeps the result non-negative.
//! 4. [`write_preview`], when [`Settings::preview`] asks for one.
//! 5. [`coeff_file_of`]: windows, rotation, quantity, provenance (the
//!    coefficient file's own [`shlight_format::CoeffFile::windowed`],
//!    [`rotated`](shlight_format::CoeffFile::rotated) and
//!    [`to_irradiance`](shlight_format::CoeffFile::to_irradiance)); with
//!    [`encode_file`], an encoding other than plain SH
//!    ([`Settings::encoding`]).
//!
//! [`ProjectOptions::check`] makes its [`Settings`];
//! [`project_with_warnings`] runs it on the CPU and hands the warnings
//! back. [`Environment`] is the distant light of the commands that shade a
//! scene (a map projected, or a coefficient file), with its encodings and
//! their WGSL snippets.
//!
//! # Conventions
//! Coefficients are shlight's (real orthonormal SH with the Condon-Shortley
//! phase, index `l(l+1)+m`, `lmax` the highest degree; `shlight_core`'s
//! crate documentation and docs/conventions.md); maps are read in a
//! [`shlight_core::map::MapOrientation`] (y-up or z-up frame, mirrored or not).
//!
//! # Example
//! ```
//! use shlight_core::map::{Layout, MapOrientation, StridedImage};
//! use shlight_format::Quantity;
//! use shlight_pipeline::{CpuProjector, Method, ProjectSettings, Settings, Silent, Source, project};
//!
//! // A grey 64x32 equirect map: only L_0^0 = 2 sqrt(pi) * 0.5 is non-zero.
//! let pixels = vec![[0.5_f32; 3]; 64 * 32];
//! let texels = StridedImage::new(Layout::Equirect, 64, 32, 64, &pixels).unwrap();
//! let p = ProjectSettings::new(2, MapOrientation::default(), Method::Quadrature, Quantity::Radiance);
//! let source = Source::Texels { texels: &texels, name: "grey", layout_name: "equirect" };
//! let file = project(source, &Settings::new(p), &CpuProjector, &Silent).unwrap();
//! assert!((file.coeffs[0].x - std::f64::consts::PI.sqrt()).abs() < 1e-12);
//! ```

#![deny(missing_docs)]

mod accuracy;
mod choose_windows;
mod coeff_file_of;
mod cpu_projector;
mod encoded_file;
mod environment;
mod error;
mod hooks;
mod input_layout;
mod job;
mod load;
mod lobe;
mod map_info;
mod output_grid;
mod output_path;
mod preview;
mod project;
mod project_options;
mod projector;
mod read_settings;
mod render;
mod rotation_spec;
mod settings;
mod source_stats;
mod specular;
mod spelling;
mod stream_project;

pub use accuracy::{
    EncodedIrradiance, IrradianceReport, IrradianceSettings, compare_encodings, compare_name,
    map_irradiance,
};
pub use choose_windows::choose_windows;
pub use coeff_file_of::coeff_file_of;
pub use cpu_projector::{CpuProjector, project_radiance, project_radiance_texels};
pub use encoded_file::encode_file;
pub use environment::Environment;
pub use error::{PipelineError, Result, error_chain};
pub use hooks::{Collected, Hooks, Progress, Silent, StageCounter};
pub use input_layout::{FACE_NAMES, FACE_PLACEHOLDER, InputLayout, face_paths, is_faces};
pub use job::accuracy::{AccuracyOutcome, AccuracyRequest, accuracy};
pub use job::compare::{ComparePlan, CompareRequest, compare};
pub use job::convert::{ConvertPlan, ConvertRequest, Converted, convert};
pub use job::dfg::{DfgPlan, DfgRequest, dfg, dfg_channels};
pub use job::irradiance::{
    ERROR_MAP_TOP, IrradiancePlan, IrradianceRequest, irradiance, summary as irradiance_summary,
};
pub use job::lightmap::{
    DEFAULT_SIDE, LightmapBaked, LightmapPlan, LightmapRequest, engine_by_name, engine_name,
    lightmap, lightmap_description, lightmap_of_scene, lightmap_size, reconstruction, texel_basis,
};
pub use job::lightmap_sample::{LightmapAtlas, node_scale_offset};
pub use job::prefilter::{PrefilterOutput, PrefilterPlan, PrefilterRequest, prefilter};
pub use job::project::{
    Dest, PlannedMap, ProjectPlan, ProjectRequest, Projected, StdoutForm, project_each,
    project_files, write_coeff_file,
};
pub use job::prt::{PrtBaked, PrtMode, PrtOutput, PrtPlan, PrtRequest, prt, prt_of_scene};
pub use job::render::{RenderLayout, RenderPlan, RenderRequest, render, render_light};
pub use job::sample::{
    SamplePlan, SampleRequest, Shading, mesh_points, relight_volume, sample, sample_at,
    scene_points, transfer_radiance, volume_irradiance, volume_lookup,
};
pub use job::synth::{SynthKind, SynthPlan, SynthRequest, synth, synth_map};
pub use job::volume::{
    VolumePlan, VolumeRequest, VolumeScene, visibility_size, volume, volume_of, volume_of_scene,
};
pub use load::{LoadedMap, check_values, layout_for_size, load_map, sanitize_image};
pub use lobe::render_lobe;
pub use map_info::MapInfo;
pub use output_grid::{default_output_size, output_grid};
pub use output_path::{names_dir, refuse_overwriting};
pub use preview::{PreviewOptions, preview_exposure, preview_image, write_preview};
pub use project::{Source, project, project_with_warnings};
pub use project_options::ProjectOptions;
pub use projector::{Projection, Projector};
pub use read_settings::ReadSettings;
pub use render::render_map;
pub use rotation_spec::parse_rotation;
pub use settings::{DEFAULT_SAMPLES, Method, Preview, ProjectSettings, Settings};
pub use source_stats::source_stats;
pub use specular::{
    CMGEN_FACE_NAMES, GLTF_SPECULAR_SIZE, cmgen_face_file, gltf_specular_images, write_dfg,
    write_prefiltered_faces, write_prefiltered_ktx1, write_prefiltered_ktx2,
};
pub use spelling::Spelling;
