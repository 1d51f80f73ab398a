//! Python bindings of shlight: the `shlight._shlight` extension module
//! behind the `shlight` package (`python/shlight/__init__.py`).
//!
//! One job: translating between Python (numpy arrays, keyword options,
//! exceptions, warnings) and shlight's libraries. Every step of a
//! projection, render, export, measurement or bake is a library call
//! (`shlight_pipeline`, `shlight_core`, `shlight_io`, `shlight_format`,
//! `shlight_accuracy`, `shlight_prt`, `shlight_volume`, `shlight_specular`);
//! nothing here computes lighting. Work runs with the GIL released, and no
//! Rust panic reaches Python ([`guard::guard`] turns one into a
//! `shlight.ShlightError`).

mod accuracy;
mod convert;
mod errors;
mod guard;
mod hooks;
mod images;
mod light;
mod lightmap;
mod options;
mod project;
mod prt;
mod sample;
mod scene;
mod sh;
mod source;
mod specular;
mod volume;

use pyo3::prelude::*;

/// The extension module.
#[pymodule]
fn _shlight(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("ShlightError", py.get_type::<errors::ShlightError>())?;
    m.add_class::<sh::Sh>()?;
    m.add_class::<prt::Transfer>()?;
    m.add_class::<volume::Volume>()?;
    m.add_class::<lightmap::Lightmap>()?;
    m.add_class::<scene::Scene>()?;
    m.add_function(wrap_pyfunction!(scene::load_scene, m)?)?;
    m.add_function(wrap_pyfunction!(project::project, m)?)?;
    m.add_function(wrap_pyfunction!(project::project_many, m)?)?;
    m.add_function(wrap_pyfunction!(sh::load, m)?)?;
    m.add_function(wrap_pyfunction!(images::read_image, m)?)?;
    m.add_function(wrap_pyfunction!(images::write_image, m)?)?;
    m.add_function(wrap_pyfunction!(images::render, m)?)?;
    m.add_function(wrap_pyfunction!(images::synth, m)?)?;
    m.add_function(wrap_pyfunction!(convert::convert, m)?)?;
    m.add_function(wrap_pyfunction!(accuracy::irradiance, m)?)?;
    m.add_function(wrap_pyfunction!(accuracy::compare, m)?)?;
    m.add_function(wrap_pyfunction!(accuracy::accuracy_suite, m)?)?;
    m.add_function(wrap_pyfunction!(prt::bake_transfer, m)?)?;
    m.add_function(wrap_pyfunction!(volume::bake_volume, m)?)?;
    m.add_function(wrap_pyfunction!(lightmap::bake_lightmap, m)?)?;
    m.add_function(wrap_pyfunction!(sample::sample, m)?)?;
    m.add_function(wrap_pyfunction!(specular::prefilter, m)?)?;
    m.add_function(wrap_pyfunction!(specular::dfg, m)?)?;
    m.add("EXPORT_FORMATS", export_formats())?;
    Ok(())
}

/// The names `SH.export` takes, as `shlight project --format` spells them.
fn export_formats() -> Vec<&'static str> {
    shlight_format::ExportFormat::ALL
        .iter()
        .map(|f| f.name())
        .collect()
}
