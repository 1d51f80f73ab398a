//! `compare`: every encoding of every map against the map's exact
//! irradiance — the table, and in a directory `compare.json` and one plot
//! of error against floats stored per map ([`CompareRequest`] →
//! [`ComparePlan`] → [`compare`]).

use std::path::{Path, PathBuf};

use shlight_accuracy::compare::{self, CompareRow};
use shlight_core::map::MapOrientation;

use crate::accuracy::{compare_encodings, compare_name};
use crate::hooks::{Hooks, Progress};
use crate::read_settings::ReadSettings;
use crate::spelling::Spelling;
use crate::{PipelineError, Result};

/// A comparison as a front end asks for it, before
/// [`CompareRequest::check`].
#[derive(Clone, Debug)]
pub struct CompareRequest<'a> {
    /// The maps.
    pub inputs: &'a [PathBuf],
    /// A directory (made) for `compare.json` and the plots.
    pub output: Option<&'a Path>,
    /// The equirect grid of normals the errors are measured at.
    pub normals: (usize, usize),
    /// How the maps are read.
    pub read: ReadSettings,
    /// How their texels meet world directions.
    pub orientation: MapOrientation,
}

/// A checked [`CompareRequest`].
#[derive(Clone, Debug)]
pub struct ComparePlan {
    inputs: Vec<PathBuf>,
    output: Option<PathBuf>,
    normals: (usize, usize),
    read: ReadSettings,
    orientation: MapOrientation,
}

impl CompareRequest<'_> {
    /// The plan, after the checks every front end makes: a grid of at
    /// least one normal; an output that is a directory, if it exists.
    ///
    /// # Errors
    /// The first check that fails, naming the settings as `spelling` does.
    pub fn check(&self, spelling: Spelling) -> Result<ComparePlan> {
        let (w, h) = self.normals;
        if w == 0 || h == 0 {
            return Err(PipelineError::new(format!(
                "{}: the grid of normals needs at least one texel",
                spelling.option_number("normals", format!("{w}x{h}"), format!("({w}, {h})"))
            )));
        }
        if let Some(dir) = self.output
            && dir.exists()
            && !dir.is_dir()
        {
            return Err(PipelineError::new(format!(
                "{}: exists and is not a directory",
                dir.display()
            )));
        }
        Ok(ComparePlan {
            inputs: self.inputs.to_vec(),
            output: self.output.map(Path::to_path_buf),
            normals: self.normals,
            read: self.read.clone(),
            orientation: self.orientation,
        })
    }
}

/// `shlight compare`: measures every map in turn ([`compare_encodings`]),
/// then, with an output directory, writes `compare.json` (the rows) and
/// `compare-MAP.svg` per map (each noted). Returns the rows and their
/// table.
///
/// # Errors
/// The loader's, naming the map; a file that cannot be written.
pub fn compare(plan: &ComparePlan, hooks: &dyn Hooks) -> Result<(Vec<CompareRow>, String)> {
    if let Some(dir) = &plan.output {
        std::fs::create_dir_all(dir).map_err(|e| {
            PipelineError::new(format!(
                "{}: cannot create the directory: {e}",
                dir.display()
            ))
        })?;
    }
    let mut rows: Vec<CompareRow> = Vec::new();
    let mut names = Vec::new();
    for input in &plan.inputs {
        let name = compare_name(input);
        hooks.progress(Progress::Step(&format!("comparing {name}")));
        rows.extend(compare_encodings(
            input,
            &plan.read,
            plan.orientation,
            plan.normals,
            &|m| hooks.warn(m),
        )?);
        names.push(name);
    }
    if let Some(dir) = &plan.output {
        let json = dir.join("compare.json");
        let text = serde_json::to_string_pretty(&compare::rows_json(&rows))
            .expect("rows are JSON values")
            + "\n";
        crate::job::project::write_text(&json, &text)?;
        hooks.note(&format!("wrote {}", json.display()));
        for name in &names {
            let svg = compare::floats_plot(name, &rows)
                .map_err(|e| PipelineError::new(format!("{name}: plot: {e}")))?;
            let path = dir.join(format!("compare-{name}.svg"));
            shlight_accuracy::plot::write_svg(&path, &svg)
                .map_err(|e| PipelineError::new(format!("{}: {e}", path.display())))?;
            hooks.note(&format!("wrote {}", path.display()));
        }
    }
    let table = compare::table(&rows);
    Ok((rows, table))
}
