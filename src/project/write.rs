//! Writing a coefficient file: shlight's JSON, the readable table, or any
//! engine format, to a file (atomically) or stdout.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result};
use shlight_format::gltf::SpecularImages;
use shlight_format::{CoeffFile, ExportFormat, Exported};

use crate::progress::Ui;

/// Where a coefficient file goes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Dest {
    /// Standard output: without `--format`, the readable table to a
    /// terminal and JSON to a pipe; with it, that format.
    Stdout,
    /// This file, written atomically.
    File(PathBuf),
}

/// Writes `file` in `format` (a glTF light with `specular`'s images) to `dest` (atomically for files), with the
/// exporter's notes through `ui` (silenced by `--quiet`), naming the input.
/// Without `--format`, a terminal gets the readable table of `shlight show`
/// and everything else JSON.
pub fn write_output(
    file: &CoeffFile,
    format: Option<ExportFormat>,
    specular: Option<&SpecularImages>,
    dest: &Dest,
    ui: &Ui,
) -> Result<()> {
    let to_terminal = || std::io::IsTerminal::is_terminal(&std::io::stdout());
    if let (None | Some(ExportFormat::Json), Dest::File(path)) = (format, dest) {
        // Written as it is formatted (CoeffFile::write_json).
        return shlight_io::write_atomically(path, |w| file.write_json(w))
            .with_context(|| format!("writing {}", path.display()));
    }
    let out = match (format, dest) {
        (None, Dest::Stdout) if to_terminal() => Exported {
            text: file.to_table(),
            notes: Vec::new(),
        },
        (Some(ExportFormat::Gltf), _) => shlight_format::export_gltf(file, specular)?,
        (f, _) => shlight_format::export(file, f.unwrap_or(ExportFormat::Json))?,
    };
    for note in &out.notes {
        ui.note(format!("{}: {note}", file.provenance.input));
    }
    match dest {
        Dest::Stdout => {
            let mut stdout = std::io::stdout().lock();
            stdout
                .write_all(out.text.as_bytes())
                .and_then(|()| stdout.flush())
                .context("writing to stdout")?;
        }
        Dest::File(path) => {
            shlight_io::write_atomically(path, |w| w.write_all(out.text.as_bytes()))
                .with_context(|| format!("writing {}", path.display()))?;
        }
    }
    Ok(())
}
