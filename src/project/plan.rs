//! The batch plan of `shlight project`: one job per input, with its output
//! and preview paths, checked for clashes and for overwriting an input
//! before anything is read.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use shlight_format::ExportFormat;

use crate::input::FACE_PLACEHOLDER;
use crate::output_path::{names_dir, refuse_overwriting};

use super::args::ProjectArgs;
use super::write::Dest;

/// One input and where its results go.
#[derive(Debug)]
pub struct Job {
    pub input: PathBuf,
    pub output: Dest,
    pub preview: Option<PathBuf>,
}

/// The jobs of a run: output paths per input, checked for clashes and for
/// overwriting an input before anything is read; output directories made.
pub fn plan(args: &ProjectArgs) -> Result<Vec<Job>> {
    let n = args.inputs.len();
    let ext = args.format.unwrap_or(ExportFormat::Json).extension();
    let out_dir = match &args.output {
        None if n > 1 => {
            bail!("{n} inputs need -o DIR: one .{ext} file per input is written there")
        }
        Some(p) if n > 1 || names_dir(p) => Some(p.as_path()),
        _ => None,
    };
    let preview_dir = match &args.preview {
        Some(p) if n > 1 || names_dir(p) => Some(p.as_path()),
        _ => None,
    };
    let mut jobs = Vec::with_capacity(n);
    for input in &args.inputs {
        // `sky_{face}.exr` writes `sky.json`: the placeholder and the
        // separator before it leave the name.
        let stem = || {
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
                .ok_or_else(|| anyhow!("{}: does not name a file", input.display()))
        };
        let output = match (out_dir, &args.output) {
            (Some(dir), _) => Dest::File(dir.join(format!("{}.{ext}", stem()?))),
            (None, Some(p)) => Dest::File(p.clone()),
            (None, None) => Dest::Stdout,
        };
        let preview = match (preview_dir, &args.preview) {
            (Some(dir), _) => Some(dir.join(format!("{}.png", stem()?))),
            (None, p) => p.clone(),
        };
        jobs.push(Job {
            input: input.clone(),
            output,
            preview,
        });
    }
    let mut seen: HashMap<PathBuf, &Path> = HashMap::new();
    for job in &jobs {
        let outputs = [
            match &job.output {
                Dest::File(p) => Some(p),
                Dest::Stdout => None,
            },
            job.preview.as_ref(),
        ];
        for out in outputs.into_iter().flatten() {
            refuse_overwriting(out, &args.inputs)?;
            let key = std::path::absolute(out).unwrap_or_else(|_| out.clone());
            if let Some(other) = seen.insert(key, &job.input) {
                bail!(
                    "{} and {} would both be written to {}",
                    other.display(),
                    job.input.display(),
                    out.display()
                );
            }
        }
    }
    for dir in [out_dir, preview_dir].into_iter().flatten() {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create the directory", dir.display()))?;
    }
    Ok(jobs)
}
