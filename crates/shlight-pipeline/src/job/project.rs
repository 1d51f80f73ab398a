//! `project`'s whole job: maps in, each projected by [`crate::project`],
//! its coefficient file (or an engine's format, or a glTF light with its
//! specular images) written beside its preview ([`ProjectRequest`] →
//! [`ProjectPlan`] → [`project_files`]); and [`project_each`], the maps
//! projected in parallel for front ends that keep the files in memory.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use rayon::prelude::*;
use shlight_core::map::{Layout, MapOrientation};
use shlight_format::{CoeffFile, ExportFormat, Exported};

use crate::hooks::{Hooks, Progress};
use crate::input_layout::FACE_PLACEHOLDER;
use crate::output_grid::output_grid;
use crate::output_path::{names_dir, refuse_overwriting};
use crate::preview::PreviewOptions;
use crate::project::{Source, project};
use crate::project_options::ProjectOptions;
use crate::projector::Projector;
use crate::settings::{Preview, Settings};
use crate::specular::gltf_specular_images;
use crate::spelling::Spelling;
use crate::{PipelineError, Result};

/// How a coefficient file is written to standard output without a format.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum StdoutForm {
    /// shlight's JSON (for a pipe).
    #[default]
    Json,
    /// The readable table of [`CoeffFile::to_table`] (for a terminal).
    Table,
}

/// A projection of maps to files as a front end asks for it, before
/// [`ProjectRequest::check`].
#[derive(Clone, Debug)]
pub struct ProjectRequest<'a> {
    /// The projection's options.
    pub options: ProjectOptions<'a>,
    /// The maps (a `{face}` name reads six face files).
    pub inputs: &'a [PathBuf],
    /// The output file, or a directory for one file per input (several
    /// inputs, an existing directory, or a path ending in a separator);
    /// none: standard output.
    pub output: Option<&'a Path>,
    /// The preview image, or a directory for one per input.
    pub preview: Option<&'a Path>,
    /// The preview's panels.
    pub preview_options: PreviewOptions,
    /// With the glTF format: the face size of the light's specular cube.
    pub specular_size: usize,
    /// With the glTF format: GGX samples per texel of the first two mips.
    pub specular_samples: u32,
    /// A file on standard output without a format.
    pub stdout: StdoutForm,
}

/// Where a coefficient file goes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Dest {
    /// Standard output: the text comes back to the front end to print.
    Stdout,
    /// This file, written atomically.
    File(PathBuf),
}

/// One input of a [`ProjectPlan`] and where its results go.
#[derive(Clone, Debug)]
pub struct PlannedMap {
    /// The map.
    pub input: PathBuf,
    /// Its coefficient file.
    pub output: Dest,
    /// Its preview, if asked.
    pub preview: Option<PathBuf>,
}

/// A checked [`ProjectRequest`]: the settings and every input's outputs.
#[derive(Clone, Debug)]
pub struct ProjectPlan {
    /// The settings of every input (the preview set per input).
    pub settings: Settings,
    /// The inputs, in order, with their outputs.
    pub maps: Vec<PlannedMap>,
    format: Option<ExportFormat>,
    preview: PreviewOptions,
    specular: (usize, u32),
    stdout: StdoutForm,
    dirs: Vec<PathBuf>,
}

impl ProjectRequest<'_> {
    /// The plan: [`ProjectOptions::check`], the preview's panel size, and
    /// each input's output and preview paths, checked before anything is
    /// read: several inputs need an output directory, no two inputs write
    /// one file, and nothing is written over an input.
    ///
    /// # Errors
    /// The first check that fails, naming the settings as `spelling` does.
    pub fn check(&self, spelling: Spelling) -> Result<ProjectPlan> {
        let settings = self.options.check(spelling)?;
        if self.preview.is_some() {
            output_grid(
                Layout::Equirect,
                self.preview_options.panel,
                MapOrientation::default(),
            )
            .map_err(|e| e.context(spelling.option("preview_size")))?;
        }
        let (maps, dirs) = self.plan_maps(spelling)?;
        Ok(ProjectPlan {
            settings,
            maps,
            format: self.options.format,
            preview: self.preview_options,
            specular: (self.specular_size, self.specular_samples),
            stdout: self.stdout,
            dirs,
        })
    }

    /// Each input's outputs, checked for clashes and for overwriting an
    /// input; the directories to make.
    fn plan_maps(&self, spelling: Spelling) -> Result<(Vec<PlannedMap>, Vec<PathBuf>)> {
        let n = self.inputs.len();
        let ext = self
            .options
            .format
            .unwrap_or(ExportFormat::Json)
            .extension();
        let out_dir = match self.output {
            None if n > 1 => {
                return Err(PipelineError::new(format!(
                    "{n} inputs need {}: one .{ext} file per input is written there",
                    spelling.pick("-o DIR", "an output directory")
                )));
            }
            Some(p) if n > 1 || names_dir(p) => Some(p),
            _ => None,
        };
        let preview_dir = match self.preview {
            Some(p) if n > 1 || names_dir(p) => Some(p),
            _ => None,
        };
        let mut maps = Vec::with_capacity(n);
        for input in self.inputs {
            let output = match (out_dir, self.output) {
                (Some(dir), _) => Dest::File(dir.join(format!("{}.{ext}", stem(input)?))),
                (None, Some(p)) => Dest::File(p.to_path_buf()),
                (None, None) => Dest::Stdout,
            };
            let preview = match (preview_dir, self.preview) {
                (Some(dir), _) => Some(dir.join(format!("{}.png", stem(input)?))),
                (None, p) => p.map(Path::to_path_buf),
            };
            maps.push(PlannedMap {
                input: input.clone(),
                output,
                preview,
            });
        }
        let mut seen: HashMap<PathBuf, &Path> = HashMap::new();
        for map in &maps {
            let output = match &map.output {
                Dest::File(p) => Some(p),
                Dest::Stdout => None,
            };
            for out in output.into_iter().chain(&map.preview) {
                refuse_overwriting(out, self.inputs)?;
                let key = std::path::absolute(out).unwrap_or_else(|_| out.clone());
                if let Some(other) = seen.insert(key, &map.input) {
                    return Err(PipelineError::new(format!(
                        "{} and {} would both be written to {}",
                        other.display(),
                        map.input.display(),
                        out.display()
                    )));
                }
            }
        }
        let dirs = [out_dir, preview_dir]
            .into_iter()
            .flatten()
            .map(Path::to_path_buf)
            .collect();
        Ok((maps, dirs))
    }
}

/// The file name of an input's outputs: `sky_{face}.exr` gives `sky` (the
/// placeholder and the separator before it leave the name).
fn stem(input: &Path) -> Result<String> {
    input
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .map(|s| match s.split_once(FACE_PLACEHOLDER) {
            Some((head, tail)) => {
                format!("{}{tail}", head.trim_end_matches(['_', '-', '.', ' ']))
            }
            None => s,
        })
        .filter(|s| !s.is_empty())
        .ok_or_else(|| PipelineError::new(format!("{}: does not name a file", input.display())))
}

/// Each input projected by [`project`] with `settings`, in parallel (rayon)
/// when there are several, in input order; an input's error names it (a
/// panic too, as an internal error). One input tells its steps to `hooks`;
/// several count the maps done (stage `"projecting"`). Warnings go to
/// `hooks` as they arise.
pub fn project_each(
    inputs: &[PathBuf],
    settings: &Settings,
    projector: &dyn Projector,
    hooks: &dyn Hooks,
) -> Vec<Result<CoeffFile>> {
    each_input(inputs, PathBuf::as_path, hooks, |input, hooks| {
        project(Source::Path(input), settings, projector, hooks)
    })
}

/// `f` on every item, named by its input's path, as [`project_each`] runs
/// [`project`].
fn each_input<I: Sync, T: Send>(
    items: &[I],
    input: fn(&I) -> &Path,
    hooks: &dyn Hooks,
    f: impl Fn(&I, &dyn Hooks) -> Result<T> + Sync,
) -> Vec<Result<T>> {
    if let [item] = items {
        return vec![f(item, hooks)];
    }
    /// A batch's hooks: warnings and notes on, each map's steps off (their
    /// lines would interleave), maps counted.
    struct Batch<'a>(&'a dyn Hooks);
    impl Hooks for Batch<'_> {
        fn warn(&self, message: &str) {
            self.0.warn(message);
        }
        fn note(&self, message: &str) {
            self.0.note(message);
        }
    }
    let counter = crate::hooks::StageCounter::new(hooks, "projecting", items.len());
    let batch = Batch(hooks);
    items
        .par_iter()
        .map(|item| {
            let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| f(item, &batch)));
            counter.add(1);
            let name = input(item).display().to_string();
            match run {
                Ok(Ok(done)) => Ok(done),
                Ok(Err(e)) if e.message().contains(&name) => Err(e),
                Ok(Err(e)) => Err(e.context(&name)),
                Err(panic) => Err(PipelineError::new(format!(
                    "{name}: internal error (please report it): {}",
                    panic_text(panic.as_ref())
                ))),
            }
        })
        .collect()
}

/// The text of a caught panic's payload.
fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".to_string())
}

/// One input of [`project_files`] done.
#[derive(Clone, Debug)]
pub struct Projected {
    /// Its coefficient file.
    pub file: CoeffFile,
    /// The text for standard output where the input's destination is
    /// [`Dest::Stdout`].
    pub stdout: Option<String>,
}

/// `shlight project`: makes the plan's output directories, then projects
/// every input ([`project_each`]'s way, with its preview) and writes its
/// file: shlight's JSON, or the plan's format (a glTF light with its
/// specular images, prefiltered from the map). One result per input, in
/// order.
///
/// # Errors
/// An output directory cannot be made (then nothing is projected); per
/// input, any step's error, naming the input.
pub fn project_files(
    plan: &ProjectPlan,
    projector: &dyn Projector,
    hooks: &dyn Hooks,
) -> Result<Vec<Result<Projected>>> {
    for dir in &plan.dirs {
        std::fs::create_dir_all(dir).map_err(|e| {
            PipelineError::new(format!(
                "{}: cannot create the directory: {e}",
                dir.display()
            ))
        })?;
    }
    Ok(each_input(
        &plan.maps,
        |m| &m.input,
        hooks,
        |map, hooks| project_one(plan, map, projector, hooks),
    ))
}

/// One input of [`project_files`].
fn project_one(
    plan: &ProjectPlan,
    map: &PlannedMap,
    projector: &dyn Projector,
    hooks: &dyn Hooks,
) -> Result<Projected> {
    let settings = Settings {
        preview: map.preview.clone().map(|path| Preview {
            path,
            options: plan.preview,
        }),
        ..plan.settings.clone()
    };
    let file = project(Source::Path(&map.input), &settings, projector, hooks)?;
    let name = map.input.display();
    let specular = if plan.format == Some(ExportFormat::Gltf) {
        hooks.progress(Progress::Step(&format!("specular images of {name}")));
        let p = &plan.settings.project;
        Some(gltf_specular_images(
            &map.input,
            &plan.settings.read,
            p.orientation,
            p.rotation.as_ref().map(|(_, m)| *m),
            plan.specular.0,
            plan.specular.1,
            &|_| {},
        )?)
    } else {
        None
    };
    if let Dest::File(_) = map.output {
        hooks.progress(Progress::Step(&format!("writing {name}")));
    }
    let stdout = write_coeff_file(
        &file,
        plan.format,
        specular.as_ref(),
        &map.output,
        plan.stdout,
        hooks,
    )?;
    Ok(Projected { file, stdout })
}

/// Writes `file` in `format` (shlight's JSON without one; a glTF light
/// with `specular`'s images) to `dest`, atomically, with the exporter's
/// notes to `hooks`, naming the input; for [`Dest::Stdout`] returns the
/// text instead ([`StdoutForm`] without a format).
///
/// # Errors
/// The format cannot hold the file, or the file cannot be written.
pub fn write_coeff_file(
    file: &CoeffFile,
    format: Option<ExportFormat>,
    specular: Option<&shlight_format::gltf::SpecularImages>,
    dest: &Dest,
    stdout: StdoutForm,
    hooks: &dyn Hooks,
) -> Result<Option<String>> {
    if let (None | Some(ExportFormat::Json), Dest::File(path)) = (format, dest) {
        // Written as it is formatted (CoeffFile::write_json).
        shlight_io::write_atomically(path, |w| file.write_json(w))
            .map_err(|e| writing(path, &e))?;
        return Ok(None);
    }
    let out = match (format, dest) {
        (None, Dest::Stdout) if stdout == StdoutForm::Table => Exported {
            text: file.to_table(),
            notes: Vec::new(),
        },
        (Some(ExportFormat::Gltf), _) => shlight_format::export_gltf(file, specular)?,
        (f, _) => shlight_format::export(file, f.unwrap_or(ExportFormat::Json))?,
    };
    for note in &out.notes {
        hooks.note(&format!("{}: {note}", file.provenance.input));
    }
    match dest {
        Dest::Stdout => Ok(Some(out.text)),
        Dest::File(path) => {
            write_text(path, &out.text)?;
            Ok(None)
        }
    }
}

/// A file that could not be written, as the command line has always said it.
fn writing(path: &Path, e: &shlight_io::IoError) -> PipelineError {
    PipelineError::new(format!(
        "writing {}: {}",
        path.display(),
        crate::error_chain(e)
    ))
}

/// Writes `text` to `path`, atomically.
///
/// # Errors
/// The file cannot be written, naming it.
pub(crate) fn write_text(path: &Path, text: &str) -> Result<()> {
    shlight_io::write_atomically(path, |w| w.write_all(text.as_bytes()))
        .map_err(|e| writing(path, &e))
}
