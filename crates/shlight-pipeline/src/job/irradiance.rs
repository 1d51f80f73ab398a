//! `irradiance`: a map's exact irradiance on an equirect grid of normals
//! (every texel cosine-weighted), and beside it an encoding's (plain SH
//! to an lmax, or any encoding) with its difference, its errors and an
//! error map ([`IrradianceRequest`] → [`IrradiancePlan`] → [`irradiance`]).

use std::path::{Path, PathBuf};

use glam::DVec3;
use shlight_accuracy::plot::{error_map_values, write_error_map};
use shlight_core::encoding::Encoding;
use shlight_core::map::{Layout, MapOrientation};
use shlight_io::{Image, WriteOptions, write_image};

use crate::accuracy::{IrradianceReport, IrradianceSettings, map_irradiance};
use crate::hooks::{Hooks, StageCounter};
use crate::output_grid::output_grid;
use crate::output_path::refuse_overwriting;
use crate::read_settings::ReadSettings;
use crate::spelling::Spelling;
use crate::{PipelineError, Result};

/// Top of the error map's colour scale: 10% of the peak irradiance, about
/// the worst Ramamoorthi & Hanrahan allow for nine terms (9%).
pub const ERROR_MAP_TOP: f64 = 0.1;

/// An irradiance map as a front end asks for it, before
/// [`IrradianceRequest::check`].
#[derive(Clone, Debug)]
pub struct IrradianceRequest<'a> {
    /// The map.
    pub input: &'a Path,
    /// The exact irradiance map to write (equirect, the input's frame);
    /// none: nothing but the error map is written, the values come back.
    pub output: Option<&'a Path>,
    /// The grid of normals (and the output's size), 2:1.
    pub size: (usize, usize),
    /// Measure SH irradiance to this lmax (or an encoding's SH part).
    pub sh: Option<usize>,
    /// Measure this encoding instead of plain SH (its SH part to `sh`,
    /// default 2).
    pub encoding: Option<Encoding>,
    /// Also draw the estimate's error relative to the peak as a PNG.
    pub error_map: Option<&'a Path>,
    /// How the map is read.
    pub read: ReadSettings,
    /// How its texels meet world directions.
    pub orientation: MapOrientation,
}

/// A checked [`IrradianceRequest`].
#[derive(Clone, Debug)]
pub struct IrradiancePlan {
    input: PathBuf,
    /// The files written: the exact map, then (with an estimate) the
    /// estimate's and the difference's; none without an output.
    pub outputs: Vec<PathBuf>,
    error_map: Option<PathBuf>,
    settings: IrradianceSettings,
    /// An encoding other than plain SH was asked for by name.
    named_encoding: bool,
}

/// `out` with `suffix` added to its stem: `dir/name-sh.exr`.
fn beside(out: &Path, suffix: &str) -> PathBuf {
    let stem = out.file_stem().unwrap_or_default().to_string_lossy();
    let name = match out.extension() {
        Some(ext) => format!("{stem}{suffix}.{}", ext.to_string_lossy()),
        None => format!("{stem}{suffix}"),
    };
    out.with_file_name(name)
}

impl IrradianceRequest<'_> {
    /// The plan, after the checks every front end makes: a 2:1 grid; an
    /// error map only with an estimate, and as a PNG; no output over the
    /// input. The estimate's files go beside the output: `OUT-sh.EXT` (or
    /// `OUT-ENCODING.EXT`) and `OUT-diff.EXT`.
    ///
    /// # Errors
    /// The first check that fails, naming the settings as `spelling` does.
    pub fn check(&self, spelling: Spelling) -> Result<IrradiancePlan> {
        output_grid(Layout::Equirect, self.size, MapOrientation::default())
            .map_err(|e| e.context(spelling.option("size")))?;
        let encoding = match (self.encoding, self.sh) {
            (Some(e), lmax) => Some((e, lmax.unwrap_or(2))),
            (None, Some(lmax)) => Some((Encoding::Sh, lmax)),
            (None, None) => None,
        };
        let mut outputs: Vec<PathBuf> = self.output.map(Path::to_path_buf).into_iter().collect();
        if let (Some(output), Some(_)) = (self.output, encoding) {
            let suffix = self
                .encoding
                .map_or_else(|| "-sh".into(), |e| format!("-{e}"));
            outputs.push(beside(output, &suffix));
            outputs.push(beside(output, "-diff"));
        }
        if let Some(map) = self.error_map {
            if encoding.is_none() {
                return Err(PipelineError::new(format!(
                    "{} needs {} or {}: it maps an estimate's error",
                    spelling.option("error_map"),
                    spelling.option("sh"),
                    spelling.option("encoding")
                )));
            }
            if map.extension().and_then(|e| e.to_str()) != Some("png") {
                return Err(PipelineError::new(format!(
                    "{}: {} writes a PNG (.png)",
                    map.display(),
                    spelling.option("error_map")
                )));
            }
        }
        for out in outputs.iter().map(PathBuf::as_path).chain(self.error_map) {
            refuse_overwriting(out, &[self.input])?;
        }
        Ok(IrradiancePlan {
            input: self.input.to_path_buf(),
            outputs,
            error_map: self.error_map.map(Path::to_path_buf),
            settings: IrradianceSettings {
                read: self.read.clone(),
                orientation: self.orientation,
                size: self.size,
                encoding,
            },
            named_encoding: self.encoding.is_some(),
        })
    }
}

/// `shlight irradiance`: measures the map ([`map_irradiance`]; progress:
/// the normals done, stage `"irradiance"`) and writes the exact map, the
/// estimate, the difference and the error map the plan names. Returns the
/// report and its summary ([`summary`]).
///
/// # Errors
/// The loader's; a map without light when an estimate is measured (its
/// relative errors do not exist); a file that cannot be written.
pub fn irradiance(plan: &IrradiancePlan, hooks: &dyn Hooks) -> Result<(IrradianceReport, String)> {
    let name = plan.input.display().to_string();
    let (w, h) = plan.settings.size;
    let normals = StageCounter::new(hooks, "irradiance", w * h);
    let report = map_irradiance(&plan.input, &plan.settings, &|m| hooks.warn(m), &|n| {
        normals.add(n);
    })?;
    let write = |path: &Path, values: &[DVec3]| {
        let pixels = values.iter().map(|v| v.as_vec3().to_array()).collect();
        let image = Image::new(w, h, pixels).expect("w * h values");
        write_image(path, &image, &WriteOptions::default())
            .map_err(|e| PipelineError::from(e).context(format!("{name}: writing")))
    };
    if let Some(path) = plan.outputs.first() {
        write(path, &report.exact.exact)?;
    }
    let Some(measured) = &report.encoded else {
        return Ok((report, String::new()));
    };
    if let [_, estimate, difference] = plan.outputs.as_slice() {
        write(estimate, &measured.estimate)?;
        write(difference, &measured.difference)?;
    }
    if measured.errors.is_none() {
        return Err(PipelineError::new(format!(
            "{name}: the map has no light (its irradiance is 0 everywhere)"
        )));
    }
    if let Some(path) = &plan.error_map {
        let values = report
            .exact
            .peak_relative_map(&measured.estimate)
            .expect("the map has light: its errors exist");
        let (image, _) = error_map_values(w, h, Some(ERROR_MAP_TOP), &values);
        write_error_map(path, &image)
            .map_err(|e| PipelineError::new(format!("{name}: writing: {e}")))?;
    }
    let text = summary(&name, &report, plan.named_encoding);
    Ok((report, text))
}

/// The lines `shlight irradiance` prints of an estimate measured in
/// `report`: what was measured, its floats and lights (an encoding asked
/// for by name), and its mean and largest errors relative to `E(n)` and to
/// the peak. Empty without an estimate.
#[must_use]
pub fn summary(name: &str, report: &IrradianceReport, named_encoding: bool) -> String {
    use std::fmt::Write;
    let Some(measured) = &report.encoded else {
        return String::new();
    };
    let Some(errors) = measured.errors else {
        return String::new();
    };
    let (encoding, lmax) = (measured.encoding, measured.lmax);
    let what = match (named_encoding, encoding.takes_lmax()) {
        (false, _) => format!("SH irradiance (lmax {lmax})"),
        (true, true) => format!("{encoding} irradiance (SH lmax {lmax})"),
        (true, false) => format!("{encoding} irradiance"),
    };
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{name}: {what} against brute force over {} normals ({}x{} texels of input):",
        report.exact.normals.len(),
        report.map_size.0,
        report.map_size.1
    );
    if named_encoding {
        let _ = writeln!(
            out,
            "  floats stored:      {}",
            measured.light.floats(encoding)
        );
        for (i, l) in measured.light.lights().iter().enumerate() {
            let _ = writeln!(
                out,
                "  light {i}: direction {:.4},{:.4},{:.4}  half-angle {:.3}°  power {:.4},{:.4},{:.4}",
                l.direction.x,
                l.direction.y,
                l.direction.z,
                l.half_angle.to_degrees(),
                l.power.x,
                l.power.y,
                l.power.z
            );
        }
    }
    let (p, q) = (errors.pointwise, errors.peak_relative);
    let _ = writeln!(
        out,
        "  relative to E(n):   mean {:.3}%  max {:.3}%",
        100.0 * p.mean,
        100.0 * p.max
    );
    let _ = writeln!(
        out,
        "  relative to max E:  mean {:.3}%  max {:.3}%",
        100.0 * q.mean,
        100.0 * q.max
    );
    out
}
