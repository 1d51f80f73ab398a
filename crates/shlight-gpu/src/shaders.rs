//! The WGSL sources in `shaders/`, composed into the modules the pipelines
//! compile.
//!
//! WGSL has no `#include`, so a module is its prelude files followed by its
//! own file: `sh.wgsl` (the SH basis) for all, `scene.wgsl` (frame uniform,
//! light coefficients, tone maps) for the render passes (mesh, background,
//! volume), `material.wgsl` (a glTF material's albedo, cut-outs and
//! instances) for the passes that draw a glTF scene's surfaces. The render
//! passes' modules also get `sh_reconstruct`, written out for one lmax
//! (`sh_expansion.rs`), and the projection's module its `ring_sums`
//! (`ring_sums.rs`), so each is compiled once per lmax. [`MODULES`]
//! lists every module; [`FILES`] every file, so a test can check that each
//! file in the directory belongs to a module and that each module validates
//! at every lmax.

use crate::glossy_expansion::{ggx_band_sums_wgsl, glossy_radiance_wgsl};
use crate::ring_sums::ring_sums_wgsl;
use crate::sh_expansion::sh_reconstruct_wgsl;
use crate::volume_expansion::{volume_wgsl_filtered, volume_wgsl_loads, volume_wgsl_visibility};
use shlight_baked::LIGHT_MAX_LMAX;

/// A shader file: its name in `shaders/` and its text.
pub type ShaderFile = (&'static str, &'static str);

/// Every WGSL file in `shaders/`, by name.
pub const FILES: [ShaderFile; 13] = [
    ("sh.wgsl", SH),
    ("scene.wgsl", SCENE),
    ("mesh.wgsl", MESH),
    ("background.wgsl", BACKGROUND),
    ("project.wgsl", PROJECT),
    ("volume.wgsl", VOLUME),
    ("volume_visibility.wgsl", VOLUME_VISIBILITY),
    ("encoded.wgsl", ENCODED),
    ("material.wgsl", MATERIAL),
    ("lightmap.wgsl", LIGHTMAP),
    ("surface.wgsl", SURFACE),
    ("surface_encoded.wgsl", SURFACE_ENCODED),
    ("volume_surface.wgsl", VOLUME_SURFACE),
];

const SH: &str = include_str!("../shaders/sh.wgsl");
const SCENE: &str = include_str!("../shaders/scene.wgsl");
const MESH: &str = include_str!("../shaders/mesh.wgsl");
const BACKGROUND: &str = include_str!("../shaders/background.wgsl");
const PROJECT: &str = include_str!("../shaders/project.wgsl");
const VOLUME: &str = include_str!("../shaders/volume.wgsl");
const VOLUME_VISIBILITY: &str = include_str!("../shaders/volume_visibility.wgsl");
const ENCODED: &str = include_str!("../shaders/encoded.wgsl");
const MATERIAL: &str = include_str!("../shaders/material.wgsl");
const LIGHTMAP: &str = include_str!("../shaders/lightmap.wgsl");
const SURFACE: &str = include_str!("../shaders/surface.wgsl");
const SURFACE_ENCODED: &str = include_str!("../shaders/surface_encoded.wgsl");
const VOLUME_SURFACE: &str = include_str!("../shaders/volume_surface.wgsl");

/// A compiled unit: a name and its files in order.
#[derive(Clone, Copy, Debug)]
pub struct ShaderModuleSource {
    /// The module's name (its own file's stem, and the variant when one file
    /// makes two).
    pub name: &'static str,
    /// Files concatenated in this order.
    pub files: &'static [&'static str],
    /// The WGSL written out for one lmax that follows the files, if any
    /// (`sh_reconstruct`, or the projection's `ring_sums`).
    pub generated: Option<fn(usize) -> String>,
}

impl ShaderModuleSource {
    /// The concatenated WGSL text at lmax [`LIGHT_MAX_LMAX`].
    #[must_use]
    pub fn source(&self) -> String {
        self.source_at(LIGHT_MAX_LMAX)
    }

    /// The concatenated WGSL text, then the module's generated code written
    /// out for `lmax` (at most [`LIGHT_MAX_LMAX`]) when it has some.
    #[must_use]
    pub fn source_at(&self, lmax: usize) -> String {
        let mut text = self.files_text();
        if let Some(generate) = self.generated {
            text.push('\n');
            text.push_str(&generate(lmax.min(LIGHT_MAX_LMAX)));
        }
        text
    }

    /// The module's files concatenated, without generated code.
    fn files_text(&self) -> String {
        self.files
            .iter()
            .map(|name| {
                FILES
                    .iter()
                    .find(|(n, _)| n == name)
                    .map(|(_, text)| *text)
                    .expect("module files are in FILES")
            })
            .collect::<Vec<_>>()
            .join("\n")
    }
}

/// Mesh shading: vertex and fragment stages of SH, PRT (diffuse and
/// glossy) and normals modes; its generated code is `sh_reconstruct` and
/// `glossy_radiance` at one lmax.
pub const MESH_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "mesh",
    files: &["sh.wgsl", "scene.wgsl", "mesh.wgsl"],
    generated: Some(mesh_generated),
};

/// [`MESH_MODULE`]'s generated code: `sh_reconstruct`, `glossy_radiance`
/// and `ggx_band_sums` for `lmax`, and `GGX_LMAX`, that lmax.
fn mesh_generated(lmax: usize) -> String {
    let mut text = sh_reconstruct_wgsl(lmax);
    text.push('\n');
    text.push_str(&glossy_radiance_wgsl(lmax));
    text.push('\n');
    text.push_str(&ggx_band_sums_wgsl(lmax));
    text.push_str(&format!(
        "const GGX_LMAX: u32 = {}u;\n",
        lmax.min(LIGHT_MAX_LMAX)
    ));
    text
}
/// The environment background (map or SH reconstruction).
pub const BACKGROUND_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "background",
    files: &["sh.wgsl", "scene.wgsl", "background.wgsl"],
    generated: Some(sh_reconstruct_wgsl),
};
/// The compute projection of equirect maps (its `ring_sums` per lmax).
pub const PROJECT_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "project",
    files: &["sh.wgsl", "project.wgsl"],
    generated: Some(ring_sums_wgsl),
};
/// Irradiance-volume shading (meshes lit by interpolated probes, probe
/// spheres, and the interpolation as a compute pass), the probes' texels
/// interpolated by the sampler (`VolumeFetch::Filtered`); its generated
/// `sh_basis`, `volume_sum` and `probe_sum` stop at lmax
/// [`shlight_baked::SHADED_MAX_LMAX`].
pub const VOLUME_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "volume",
    files: &["sh.wgsl", "scene.wgsl", "volume.wgsl"],
    generated: Some(volume_wgsl_filtered),
};
/// [`VOLUME_MODULE`] with the texels read by eight loads each and weighted
/// in the shader (`VolumeFetch::Loads`: hardware GPUs, and adapters that
/// cannot filter `Rgba32Float`).
pub const VOLUME_LOADS_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "volume loads",
    files: &["sh.wgsl", "scene.wgsl", "volume.wgsl"],
    generated: Some(volume_wgsl_loads),
};
/// [`VOLUME_LOADS_MODULE`] with each probe's trilinear weight multiplied
/// by its visibility of the shaded point (`volume_visibility.wgsl`: the
/// probes' positions and distance maps in storage buffers), for a volume
/// that holds distance maps; the same lookup as shlight-volume's
/// `PreparedLookup` with `Lookup::Shlight`.
pub const VOLUME_VISIBILITY_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "volume visibility",
    files: &[
        "sh.wgsl",
        "scene.wgsl",
        "volume.wgsl",
        "volume_visibility.wgsl",
    ],
    generated: Some(volume_wgsl_visibility),
};
/// Shading with an encoding other than plain SH: `mesh.wgsl`'s vertex
/// stage, `encoded.wgsl`'s fragment stage, and the encoding's WGSL snippet
/// (`shlight_irradiance`) appended by the caller ([`encoded_source`]).
/// Its `generated` code, used when the module is validated on its own, is
/// the mesh stages' own at lmax 0 and [`SAMPLE_ENCODING`].
pub const ENCODED_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "encoded",
    files: &["sh.wgsl", "scene.wgsl", "mesh.wgsl", "encoded.wgsl"],
    generated: Some(sample_encoded),
};

/// A stand-in for an encoding's snippet when [`ENCODED_MODULE`] is
/// validated without one: a `shlight_irradiance` of the signature the
/// snippets have (a clamped cosine about +Y).
pub const SAMPLE_ENCODING: &str =
    "fn shlight_irradiance(n: vec3<f32>) -> vec3<f32> {\n    return vec3<f32>(max(n.y, 0.0));\n}\n";

fn sample_encoded(_lmax: usize) -> String {
    encoded_generated(SAMPLE_ENCODING)
}

/// What follows [`ENCODED_MODULE`]'s files: the mesh stages' generated
/// code at lmax 0, then `snippet`.
fn encoded_generated(snippet: &str) -> String {
    let mut text = mesh_generated(0);
    text.push('\n');
    text.push_str(snippet);
    text
}

/// [`ENCODED_MODULE`]'s source with an encoding's WGSL `snippet` (which
/// defines `shlight_irradiance(n: vec3<f32>) -> vec3<f32>`) appended.
#[must_use]
pub fn encoded_source(snippet: &str) -> String {
    with_encoding(&ENCODED_MODULE, snippet)
}

/// `module`'s files followed by [`encoded_generated`]`(snippet)`: the
/// source of a module whose fragment stage calls an encoding's
/// `shlight_irradiance`.
fn with_encoding(module: &ShaderModuleSource, snippet: &str) -> String {
    let mut text = module.files_text();
    text.push('\n');
    text.push_str(&encoded_generated(snippet));
    text
}

/// A glTF scene's surfaces (`material.wgsl`: the albedo from each
/// fragment's material, cut-outs, instances) shaded as [`MESH_MODULE`]
/// shades a mesh (`surface.wgsl`: SH, PRT per unit albedo, normals), a
/// lightmapped scene's baked instances by their lightmap
/// (`lightmap.wgsl`).
pub const MESH_SURFACE_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "mesh surfaces",
    files: &[
        "sh.wgsl",
        "scene.wgsl",
        "mesh.wgsl",
        "material.wgsl",
        "lightmap.wgsl",
        "surface.wgsl",
    ],
    generated: Some(mesh_generated),
};

/// A glTF scene's surfaces shaded with an encoding
/// (`surface_encoded.wgsl`), as [`ENCODED_MODULE`] shades a mesh; the
/// encoding's snippet appended by the caller
/// ([`surface_encoded_source`]), [`SAMPLE_ENCODING`] when validated alone.
pub const SURFACE_ENCODED_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "encoded surfaces",
    files: &[
        "sh.wgsl",
        "scene.wgsl",
        "mesh.wgsl",
        "material.wgsl",
        "lightmap.wgsl",
        "surface.wgsl",
        "surface_encoded.wgsl",
    ],
    generated: Some(sample_encoded),
};

/// [`SURFACE_ENCODED_MODULE`]'s source with an encoding's WGSL `snippet`
/// appended.
#[must_use]
pub fn surface_encoded_source(snippet: &str) -> String {
    with_encoding(&SURFACE_ENCODED_MODULE, snippet)
}

/// A glTF scene's surfaces lit by an irradiance volume
/// (`volume_surface.wgsl`), the texels filtered as [`VOLUME_MODULE`]
/// filters them.
pub const VOLUME_SURFACE_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "volume surfaces",
    files: &[
        "sh.wgsl",
        "scene.wgsl",
        "volume.wgsl",
        "material.wgsl",
        "volume_surface.wgsl",
    ],
    generated: Some(volume_wgsl_filtered),
};

/// [`VOLUME_SURFACE_MODULE`] reading the texels by loads, as
/// [`VOLUME_LOADS_MODULE`].
pub const VOLUME_LOADS_SURFACE_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "volume loads surfaces",
    generated: Some(volume_wgsl_loads),
    ..VOLUME_SURFACE_MODULE
};

/// [`VOLUME_SURFACE_MODULE`] weighing each probe by its visibility, as
/// [`VOLUME_VISIBILITY_MODULE`].
pub const VOLUME_VISIBILITY_SURFACE_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "volume visibility surfaces",
    files: &[
        "sh.wgsl",
        "scene.wgsl",
        "volume.wgsl",
        "volume_visibility.wgsl",
        "material.wgsl",
        "volume_surface.wgsl",
    ],
    generated: Some(volume_wgsl_visibility),
};

/// The SH basis alone (a module of functions, validated on its own).
pub const SH_MODULE: ShaderModuleSource = ShaderModuleSource {
    name: "sh",
    files: &["sh.wgsl"],
    generated: None,
};

/// Every module the crate compiles (and [`SH_MODULE`], checked on its own).
pub const MODULES: [ShaderModuleSource; 13] = [
    SH_MODULE,
    MESH_MODULE,
    BACKGROUND_MODULE,
    PROJECT_MODULE,
    VOLUME_MODULE,
    VOLUME_LOADS_MODULE,
    VOLUME_VISIBILITY_MODULE,
    ENCODED_MODULE,
    MESH_SURFACE_MODULE,
    SURFACE_ENCODED_MODULE,
    VOLUME_SURFACE_MODULE,
    VOLUME_LOADS_SURFACE_MODULE,
    VOLUME_VISIBILITY_SURFACE_MODULE,
];

/// Compiles a module on `device`, at `lmax` if it has generated code.
pub(crate) fn create(
    device: &wgpu::Device,
    module: ShaderModuleSource,
    lmax: usize,
) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(module.name),
        source: wgpu::ShaderSource::Wgsl(module.source_at(lmax).into()),
    })
}
