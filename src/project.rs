//! `shlight project`: environment maps in, SH coefficients out.
//!
//! One input goes to `-o FILE` (or stdout); several go to `-o DIR`, one
//! file per input, processed in parallel. Each input runs the same steps:
//! [`load`] (read, check, `--sanitize`), [`project_map`] (layout and method),
//! the window (per channel), `--preview`, `--rotate`, the quantity, and
//! [`write_output`] (the one place that knows output formats: shlight's
//! JSON, or any exporter of [`crate::export`]).

use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{Args, ValueEnum};
use glam::{DMat3, DQuat, DVec3};
use indicatif::ProgressBar;
use rayon::prelude::*;
use shlight_core::layout::{self, EnvMap, Layout};
use shlight_core::montecarlo::{
    DEFAULT_SEED, ImportanceGrid, McOptions, Sampler, project_montecarlo,
};
use shlight_core::projection::MapOrientation;
use shlight_core::rotation::{Frame, rotate_once};
use shlight_core::window::{WindowFamily, WindowTarget, auto_window};
use shlight_core::zonal::clamped_cosine_eigenvalue;
use shlight_core::{ShCoeffs, ShRotation, Window, irradiance};
use shlight_io::{Image, PixelStats, ReadOptions, ToneMap, read_image};

use crate::preview::{PreviewOptions, write_preview};
use crate::progress::Ui;
use crate::texels::{LayoutArg, TexelGrid, parse_size};
use shlight_format::{
    CoeffFile, ExportFormat, Exported, Provenance, Quantity, RotationRecord, SanitizeCounts,
};

/// Arguments of `shlight project`.
#[derive(Args, Debug)]
pub struct ProjectArgs {
    /// Environment maps (OpenEXR, Radiance .hdr, PNG, JPEG) in any layout
    /// (--layout); `NAME_{face}.exr` reads six cube-face files.
    /// Several need `-o DIR`.
    #[arg(required = true, value_name = "INPUT")]
    pub inputs: Vec<PathBuf>,
    /// Highest SH degree kept (lmax 2 = 9 coefficients).
    #[arg(long, default_value_t = 2)]
    pub lmax: usize,
    /// Which world axis the top row of the map faces.
    #[arg(long, default_value = "y", value_parser = ["y", "z"])]
    pub up: String,
    /// Read a map made for the mirrored pbrt / google mapping.
    #[arg(long)]
    pub mirror: bool,
    /// Layout of the input maps: auto (by aspect ratio: 2:1 equirect, 4:3
    /// cross-h, 3:4 cross-v, 6:1 strip, 1:1 angular), equirect, cross-h,
    /// cross-v, strip, angular, mirror-ball, or faces (six square files: an
    /// INPUT holding `{face}`, which becomes px nx py ny pz nz).
    #[arg(long, default_value = "auto", value_parser = parse_input_layout)]
    pub layout: InputLayout,
    /// How the coefficients are computed: exact texel-solid-angle
    /// quadrature, or Monte Carlo integration of the bilinearly interpolated
    /// map (with a standard error per coefficient in the file).
    #[arg(long, value_enum, default_value_t)]
    pub method: Method,
    /// Monte Carlo: directions to draw [default: 65536]. Stratified and
    /// sobol round to whole grids; the count used is recorded.
    #[arg(long, value_name = "N", value_parser = parse_samples, allow_negative_numbers = true)]
    pub samples: Option<usize>,
    /// Monte Carlo: how directions are drawn [default: sobol]. importance
    /// follows the map's luminance.
    #[arg(long, value_parser = sampler_parser())]
    pub sampler: Option<Sampler>,
    /// Monte Carlo: seed of the random streams (equal seeds give identical
    /// files) [default: 6001130381083431937].
    #[arg(long, allow_negative_numbers = true)]
    pub seed: Option<u64>,
    /// What the coefficients hold.
    #[arg(long, value_parser = crate::values::quantity(), default_value = "radiance")]
    pub quantity: Quantity,
    /// Ringing window: none, hanning:W, lanczos:W, laplacian:LAMBDA, or auto
    /// (per colour channel, the weakest Hanning window that makes that
    /// channel's result non-negative).
    #[arg(long, default_value = "none")]
    pub window: String,
    /// Rotate the coefficients: yaw:DEG (about the frame's up axis,
    /// right-handed), quat:X,Y,Z,W, or euler:X,Y,Z (degrees; about world X,
    /// then Y, then Z). A light from a comes from R a afterwards.
    #[arg(long, allow_hyphen_values = true)]
    pub rotate: Option<String>,
    /// Project on the GPU (equirect maps, quadrature, lmax up to 8): the
    /// same sums in f32 by a compute shader, within 1e-4 of the CPU.
    #[arg(long)]
    pub gpu: bool,
    /// Replace NaN and -inf with 0, +inf with the largest finite value, and
    /// negatives with 0, instead of refusing NaN/inf and keeping negatives.
    #[arg(long)]
    pub sanitize: bool,
    /// EXR layer to read (default: the first with R, G, B).
    #[arg(long)]
    pub layer: Option<String>,
    /// Refuse inputs with more pixels than this (judged from the header).
    #[arg(long, default_value_t = ReadOptions::DEFAULT_MAX_PIXELS)]
    pub max_pixels: usize,
    /// Output file, or with several inputs (or an existing directory) a
    /// directory for one file per input, NAME.json (the extension follows
    /// --format); without it, and without --format, a readable table goes to
    /// a terminal and JSON to a pipe.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Output format [default: json]: shlight's coefficient file, or an
    /// engine or shader format (docs/exporters.md).
    #[arg(long, value_parser = crate::values::export_format())]
    pub format: Option<ExportFormat>,
    /// Write a preview image: input | SH radiance | SH irradiance/π, side
    /// by side. With several inputs, a directory for one NAME.png each.
    #[arg(long, value_name = "FILE.png")]
    pub preview: Option<PathBuf>,
    /// Size of each preview panel, WIDTHxHEIGHT (2:1).
    #[arg(long, default_value = "512x256", value_parser = parse_size)]
    pub preview_size: (usize, usize),
    /// Preview exposure in stops (default: the mean radiance at 0.18).
    #[arg(long, allow_negative_numbers = true)]
    pub preview_exposure: Option<f32>,
    /// Preview tone map: clamp, reinhard or aces.
    #[arg(long, default_value = "aces")]
    pub preview_tone_map: ToneMap,
}

/// `--layout` of `shlight project`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputLayout {
    /// [`Layout::detect`] by aspect ratio (or six faces for `{face}` inputs).
    Auto,
    /// Six face files, `{face}` in the input name.
    Faces,
    /// One image in this layout.
    Image(Layout),
}

/// `--layout NAME`.
pub fn parse_input_layout(s: &str) -> std::result::Result<InputLayout, String> {
    match s.trim() {
        "auto" => Ok(InputLayout::Auto),
        "faces" => Ok(InputLayout::Faces),
        name => name
            .parse::<Layout>()
            .map(InputLayout::Image)
            .map_err(|e| format!("{e} (or auto, faces)")),
    }
}

/// The placeholder of six-face inputs, and the faces' names in strip order
/// (+X -X +Y -Y +Z -Z).
pub const FACE_PLACEHOLDER: &str = "{face}";
/// Face names replacing [`FACE_PLACEHOLDER`], in strip order.
pub const FACE_NAMES: [&str; 6] = ["px", "nx", "py", "ny", "pz", "nz"];

/// How `shlight project` computes coefficients.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum Method {
    /// Exact texel-solid-angle quadrature over every texel.
    #[default]
    Quadrature,
    /// Monte Carlo integration (--samples, --sampler, --seed), with
    /// standard errors.
    #[value(name = "montecarlo")]
    MonteCarlo,
}

impl Method {
    fn name(self) -> &'static str {
        match self {
            Method::Quadrature => "quadrature",
            Method::MonteCarlo => "montecarlo",
        }
    }
}

/// Monte Carlo directions drawn when `--samples` is not given.
pub const DEFAULT_SAMPLES: usize = 1 << 16;

/// `--samples N`: a whole number of at least 1.
fn parse_samples(s: &str) -> std::result::Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(0) => Err("the sample count must be at least 1".into()),
        Ok(n) => Ok(n),
        Err(_) => Err(format!("{s:?} is not a whole number of samples")),
    }
}

/// `--sampler NAME`: one of the Monte Carlo samplers' names.
fn sampler_parser() -> impl TypedValueParser<Value = Sampler> {
    PossibleValuesParser::new(Sampler::ALL.map(Sampler::name)).map(|name| {
        name.parse::<Sampler>()
            .expect("possible values are sampler names")
    })
}

/// Runs `shlight project`.
pub fn run(args: &ProjectArgs, ui: &Ui) -> Result<()> {
    let settings = Settings::new(args)?;
    let jobs = plan(args)?;
    if let [job] = jobs.as_slice() {
        let bar = ui.spinner("starting");
        let result = process(job, &settings, ui, &bar);
        bar.finish_and_clear();
        return result;
    }
    let bar = ui.bar(jobs.len() as u64, "projecting");
    let failed: usize = jobs
        .par_iter()
        .map(|job| {
            let result = process(job, &settings, ui, &ProgressBar::hidden());
            bar.inc(1);
            match result {
                Ok(()) => 0,
                Err(e) => {
                    let msg = format!("{e:#}");
                    let input = job.input.display().to_string();
                    if msg.contains(&input) {
                        ui.error(msg);
                    } else {
                        ui.error(format!("{input}: {msg}"));
                    }
                    1
                }
            }
        })
        .sum();
    bar.finish_and_clear();
    if failed > 0 {
        bail!("{failed} of {} inputs failed", jobs.len());
    }
    Ok(())
}

/// Everything decided from the arguments before any input is read.
struct Settings<'a> {
    args: &'a ProjectArgs,
    orientation: MapOrientation,
    window: Option<Window>,
    /// The record for the file and the matrix.
    rotation: Option<(RotationRecord, DMat3)>,
    read: ReadOptions,
    preview: PreviewOptions,
    /// Monte Carlo options (`--method montecarlo`).
    montecarlo: Option<McOptions>,
    /// The device and pipelines of `--gpu`.
    gpu: Option<(shlight_gpu::GpuContext, shlight_gpu::GpuProjector)>,
}

impl<'a> Settings<'a> {
    fn new(args: &'a ProjectArgs) -> Result<Self> {
        let frame = crate::environment::frame_of(&args.up);
        let window = match args.window.trim() {
            "auto" => None,
            spec => Some(
                spec.parse::<Window>()
                    .map_err(|e| anyhow!("--window {spec}: {e}"))?,
            ),
        };
        let rotation = match &args.rotate {
            None => None,
            Some(spec) => {
                let matrix = parse_rotation(spec, frame)?;
                let record = RotationRecord {
                    spec: spec.trim().to_string(),
                    matrix: matrix.transpose().to_cols_array_2d(),
                };
                Some((record, matrix))
            }
        };
        let montecarlo = match args.method {
            Method::MonteCarlo => Some(McOptions {
                lmax: args.lmax,
                samples: args.samples.unwrap_or(DEFAULT_SAMPLES),
                sampler: args.sampler.unwrap_or_default(),
                seed: args.seed.unwrap_or(DEFAULT_SEED),
            }),
            Method::Quadrature => {
                let given: Vec<&str> = [
                    ("--samples", args.samples.is_some()),
                    ("--sampler", args.sampler.is_some()),
                    ("--seed", args.seed.is_some()),
                ]
                .into_iter()
                .filter_map(|(flag, given)| given.then_some(flag))
                .collect();
                if !given.is_empty() {
                    bail!(
                        "{} only apply to --method montecarlo (the method is quadrature)",
                        given.join(", ")
                    );
                }
                None
            }
        };
        let gpu = if args.gpu {
            if montecarlo.is_some() {
                bail!("--gpu computes the quadrature; it does not apply to --method montecarlo");
            }
            if args.lmax > shlight_gpu::MAX_LMAX {
                bail!(
                    "--gpu projects to lmax {} at most (asked: {})",
                    shlight_gpu::MAX_LMAX,
                    args.lmax
                );
            }
            let ctx = shlight_gpu::GpuContext::headless().context("--gpu")?;
            let projector = shlight_gpu::GpuProjector::new(&ctx);
            Some((ctx, projector))
        } else {
            None
        };
        if args.preview.is_some() {
            LayoutArg::Equirect
                .check_size(args.preview_size.0, args.preview_size.1)
                .map_err(|e| anyhow!("--preview-size: {e}"))?;
        }
        Ok(Self {
            args,
            orientation: MapOrientation {
                frame,
                mirror: args.mirror,
            },
            window,
            rotation,
            read: ReadOptions {
                layer: args.layer.clone(),
                max_pixels: args.max_pixels,
            },
            preview: PreviewOptions {
                panel: args.preview_size,
                exposure: args.preview_exposure,
                tone_map: args.preview_tone_map,
            },
            montecarlo,
            gpu,
        })
    }
}

/// Parses `--rotate` into the rotation matrix `R` (a light from `a` comes
/// from `R a` afterwards) in the frame `frame`.
fn parse_rotation(spec: &str, frame: Frame) -> Result<DMat3> {
    let err = |why: &str| {
        anyhow!("--rotate {spec}: {why} (expected yaw:DEG, quat:X,Y,Z,W or euler:X,Y,Z in degrees)")
    };
    let (kind, rest) = spec.trim().split_once(':').ok_or_else(|| err("no kind"))?;
    let numbers: Vec<f64> = rest
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|e| err(&e.to_string()))?;
    if !numbers.iter().all(|v| v.is_finite()) {
        return Err(err("not finite"));
    }
    let deg = f64::to_radians;
    match (
        kind.trim().to_ascii_lowercase().as_str(),
        numbers.as_slice(),
    ) {
        ("yaw", [a]) => Ok(DMat3::from_axis_angle(
            frame.direction(0.0, 0.0).normalize(),
            deg(*a),
        )),
        ("quat", [x, y, z, w]) => {
            let q = DQuat::from_xyzw(*x, *y, *z, *w);
            if q.length_squared() == 0.0 {
                return Err(err("the zero quaternion is no rotation"));
            }
            Ok(DMat3::from_quat(q.normalize()))
        }
        ("euler", [x, y, z]) => Ok(DMat3::from_rotation_z(deg(*z))
            * DMat3::from_rotation_y(deg(*y))
            * DMat3::from_rotation_x(deg(*x))),
        ("yaw" | "quat" | "euler", _) => Err(err("wrong count of numbers")),
        _ => Err(err("unknown kind")),
    }
}

/// Where a coefficient file goes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Dest {
    /// Standard output: without `--format`, the readable table to a
    /// terminal and JSON to a pipe; with it, that format.
    Stdout,
    /// This file, written atomically.
    File(PathBuf),
}

/// One input and where its results go.
#[derive(Debug)]
struct Job {
    input: PathBuf,
    output: Dest,
    preview: Option<PathBuf>,
}

/// Whether `-o PATH` names a directory: it is one, or ends with a separator.
fn names_dir(p: &Path) -> bool {
    p.is_dir()
        || p.as_os_str()
            .to_string_lossy()
            .ends_with(std::path::is_separator)
}

/// The jobs of a run: output paths per input, checked for clashes and for
/// overwriting an input before anything is read; output directories made.
fn plan(args: &ProjectArgs) -> Result<Vec<Job>> {
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

/// Refuses `output` when it is one of `inputs` (the same file by path, link
/// or inode).
pub fn refuse_overwriting(output: &Path, inputs: &[PathBuf]) -> Result<()> {
    for input in inputs {
        if same_file(output, input) {
            bail!(
                "{}: refusing to write over the input {}",
                output.display(),
                input.display()
            );
        }
    }
    Ok(())
}

fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
        use std::os::unix::fs::MetadataExt;
        return x.dev() == y.dev() && x.ino() == y.ino();
    }
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(x), Ok(y)) => x == y,
        _ => match (std::path::absolute(a), std::path::absolute(b)) {
            (Ok(x), Ok(y)) => x == y,
            _ => false,
        },
    }
}

/// Projects one input and writes its results.
fn process(job: &Job, s: &Settings<'_>, ui: &Ui, bar: &ProgressBar) -> Result<()> {
    let args = s.args;
    let name = job.input.display().to_string();
    bar.set_message(format!("reading {name}"));
    let (image, layout, stats, sanitized) =
        load(&job.input, s.args.layout, &s.read, s.args.sanitize, ui)?;

    bar.set_message(format!(
        "projecting {name} ({}x{}, lmax {})",
        image.width(),
        image.height(),
        args.lmax
    ));
    let projection =
        project_map(&image, layout, s).with_context(|| format!("{name}: projecting"))?;

    let target = match args.quantity {
        Quantity::Radiance => WindowTarget::Function,
        Quantity::Irradiance => WindowTarget::Irradiance,
    };
    if s.window.is_none() {
        bar.set_message(format!("choosing windows for {name}"));
    }
    let windows = choose_windows(s.window, &projection.coeffs, target)
        .with_context(|| format!("{name}: --window auto"))?;
    let mut radiance = apply_windows(&windows, &projection.coeffs);

    if let Some(path) = &job.preview {
        bar.set_message(format!("preview of {name}"));
        let equirect = match layout {
            Layout::Equirect => None,
            other => Some(to_equirect(&image, other, s)?),
        };
        let shown = equirect.as_ref().unwrap_or(&image);
        write_preview(path, shown, &radiance, s.orientation, &s.preview)
            .with_context(|| format!("{name}: preview"))?;
    }

    // Window factors lie in [0, 1], so errors scale by them as they are.
    let mut std_error = projection.std_error.map(|se| apply_windows(&windows, &se));
    if let Some((_, matrix)) = &s.rotation {
        radiance = rotate_once(&radiance, *matrix);
        std_error =
            std_error.map(|se| rotate_std_error(&ShRotation::from_mat3(se.lmax(), *matrix), &se));
    }
    let coeffs = match args.quantity {
        Quantity::Radiance => radiance,
        Quantity::Irradiance => {
            std_error =
                std_error.map(|se| se.scaled_per_band(|l| clamped_cosine_eigenvalue(l).abs()));
            irradiance(&radiance)
        }
    };

    let mut file = CoeffFile::new(coeffs, s.orientation.frame, args.quantity);
    file.mirror = s.orientation.mirror;
    file.provenance = Provenance {
        input: name.clone(),
        width: image.width(),
        height: image.height(),
        layout: if is_faces(&job.input) {
            "faces".into()
        } else {
            layout.name().into()
        },
        method: args.method.name().into(),
        window: match s.window {
            Some(w) => w.to_string(),
            None => "auto".into(),
        },
        windows: windows.map(|w| w.to_string()),
        samples: projection.samples,
        seed: projection.seed,
        sampler: projection.sampler,
        rotate: s.rotation.as_ref().map(|(r, _)| r.clone()),
    };
    file.input_negative_texels = stats.negative;
    file.input_min_value = f64::from(stats.min_value);
    file.sanitized = sanitized;
    file.std_error = std_error;
    if job.output == Dest::Stdout {
        // Nothing may draw on the terminal while the result is printed.
        bar.finish_and_clear();
    } else {
        bar.set_message(format!("writing {name}"));
    }
    write_output(&file, args.format, &job.output, ui)
}

/// Whether an input names six face files (holds [`FACE_PLACEHOLDER`]).
fn is_faces(path: &Path) -> bool {
    path.to_string_lossy().contains(FACE_PLACEHOLDER)
}

/// The six face files of a `{face}` input, in strip order.
fn face_paths(path: &Path) -> Vec<PathBuf> {
    let pattern = path.to_string_lossy();
    FACE_NAMES
        .iter()
        .map(|f| PathBuf::from(pattern.replace(FACE_PLACEHOLDER, f)))
        .collect()
}

/// Reads the six face files of `path` (all must exist, be square and of
/// one size) and lays them side by side as a strip, +X -X +Y -Y +Z -Z.
fn read_faces(path: &Path, read: &ReadOptions) -> Result<Image> {
    let mut faces: Vec<(PathBuf, Image)> = Vec::with_capacity(6);
    for p in face_paths(path) {
        if !p.exists() {
            bail!(
                "{}: face file {} does not exist (a {FACE_PLACEHOLDER} input needs all six: {})",
                path.display(),
                p.display(),
                FACE_NAMES.join(" ")
            );
        }
        let image = read_image(&p, read).with_context(|| format!("reading {}", p.display()))?;
        if image.width() != image.height() {
            bail!(
                "{}: a cube face must be square, not {}x{}",
                p.display(),
                image.width(),
                image.height()
            );
        }
        if let Some((first, f)) = faces.first()
            && f.width() != image.width()
        {
            bail!(
                "{}: {}x{} faces, but {} is {}x{}; all six must be the same size",
                p.display(),
                image.width(),
                image.height(),
                first.display(),
                f.width(),
                f.height()
            );
        }
        faces.push((p, image));
    }
    let n = faces[0].1.width();
    let (w, h) = Layout::Strip.dimensions(n);
    let max = read.max_pixels;
    if w.checked_mul(h).is_none_or(|p| p > max) {
        bail!(
            "{}: six faces of {n}x{n} make more than --max-pixels {max}",
            path.display()
        );
    }
    Ok(Image::from_fn(w, h, |x, y| faces[x / n].1.get(x % n, y)))
}

/// Reads an input (or, for `{face}`, six faces as a strip), settles its
/// layout, and checks its values: NaN/inf are refused (or with
/// `--sanitize` replaced, see [`Image::sanitize`]), negatives are kept with
/// a warning (or replaced). Returns the image, its layout, the statistics
/// of the values as read, and what was replaced.
pub fn load(
    path: &Path,
    input_layout: InputLayout,
    read: &ReadOptions,
    sanitize: bool,
    ui: &Ui,
) -> Result<(Image, Layout, PixelStats, Option<SanitizeCounts>)> {
    let name = path.display();
    let faces = is_faces(path);
    let (mut image, layout) = match (faces, input_layout) {
        (true, InputLayout::Auto | InputLayout::Faces) => (read_faces(path, read)?, Layout::Strip),
        (true, InputLayout::Image(l)) => bail!(
            "{name}: an input with {FACE_PLACEHOLDER} names six face files; it needs --layout faces or auto, not {l}"
        ),
        (false, InputLayout::Faces) => bail!(
            "{name}: --layout faces reads six files named by an INPUT containing {FACE_PLACEHOLDER} (e.g. sky_{FACE_PLACEHOLDER}.exr for sky_px.exr ... sky_nz.exr)"
        ),
        (false, InputLayout::Auto) => {
            let image = read_image(path, read)?;
            let (w, h) = (image.width(), image.height());
            let Some(layout) = Layout::detect(w, h) else {
                bail!(
                    "{name}: a {w}x{h} image fits no layout by its aspect ratio (2:1 equirect, 4:3 cross-h, 3:4 cross-v, 6:1 strip, 1:1 angular); name one with --layout"
                );
            };
            (image, layout)
        }
        (false, InputLayout::Image(layout)) => {
            let image = read_image(path, read)?;
            if let Err(e) = layout.check_size(image.width(), image.height()) {
                bail!("{name}: {e}");
            }
            (image, layout)
        }
    };
    let stats = image.stats();
    if sanitize {
        let counts = SanitizeCounts::from(image.sanitize());
        if counts.total() > 0 {
            ui.warn(format!(
                "{name}: --sanitize replaced {} values: {} NaN and {} -inf by 0, {} +inf by {}, {} negative by 0",
                counts.total(),
                counts.nan,
                counts.negative_infinite,
                counts.positive_infinite,
                counts.infinity_replacement,
                counts.negative
            ));
        }
        return Ok((image, layout, stats, Some(counts)));
    }
    if stats.non_finite > 0 {
        let (x, y) = stats.first_non_finite.unwrap_or((0, 0));
        bail!(
            "{name}: {} texels are NaN or infinite (the first at x={x}, y={y}); --sanitize replaces them",
            stats.non_finite
        );
    }
    if stats.negative > 0 {
        ui.warn(format!(
            "{name}: {} negative texels (minimum {}), kept as data",
            stats.negative, stats.min_value
        ));
    }
    Ok((image, layout, stats, None))
}

/// An equirect panel (the preview's size) of a map in another layout,
/// looked up bilinearly at each texel centre, for `--preview`.
fn to_equirect(image: &Image, layout: Layout, s: &Settings<'_>) -> Result<Image> {
    let map = EnvMap::new(
        layout,
        s.orientation,
        image.width(),
        image.height(),
        image.pixels(),
    )
    .map_err(|e| anyhow!("{e}"))?;
    let grid = TexelGrid::new(LayoutArg::Equirect, s.preview.panel, s.orientation)?;
    Ok(Image::from_fn(grid.width, grid.height, |x, y| {
        let d = grid.direction(x, y).unwrap_or(DVec3::Y);
        map.radiance_bilinear(d).as_vec3().to_array()
    }))
}

/// Radiance coefficients of a map, and what the method reports about them.
struct Projection {
    coeffs: ShCoeffs<DVec3>,
    /// Standard error per coefficient (Monte Carlo).
    std_error: Option<ShCoeffs<DVec3>>,
    samples: Option<u64>,
    seed: Option<u64>,
    sampler: Option<String>,
}

/// The projection step: the place where layouts and methods meet.
///
/// Quadrature sums texel × basis × exact texel solid angle
/// ([`layout::project_map`]). Monte Carlo looks the map up bilinearly
/// ([`EnvMap::radiance_bilinear`]) and, for importance sampling, draws from
/// [`ImportanceGrid::from_equirect`] over an equirect map's texels, or from
/// [`ImportanceGrid::from_map`] on a grid of the map's size otherwise.
fn project_map(image: &Image, layout: Layout, s: &Settings<'_>) -> Result<Projection> {
    let (width, height, pixels) = (image.width(), image.height(), image.pixels());
    let map =
        EnvMap::new(layout, s.orientation, width, height, pixels).map_err(|e| anyhow!("{e}"))?;
    Ok(match (&s.montecarlo, &s.gpu) {
        (None, Some((ctx, projector))) => {
            if layout != Layout::Equirect {
                bail!(
                    "--gpu projects equirect maps; this one is {}",
                    layout.name()
                );
            }
            let view = shlight_core::projection::EquirectView {
                width,
                height,
                pixels,
            };
            Projection {
                coeffs: projector.project(ctx, view, s.args.lmax, s.orientation)?,
                std_error: None,
                samples: None,
                seed: None,
                sampler: None,
            }
        }
        (None, None) => Projection {
            coeffs: layout::project_map(&map, s.args.lmax),
            std_error: None,
            samples: None,
            seed: None,
            sampler: None,
        },
        (Some(options), _) => {
            let grid = (options.sampler == Sampler::Importance).then(|| match layout {
                Layout::Equirect => {
                    ImportanceGrid::from_equirect(width, height, pixels, s.orientation)
                }
                _ => {
                    // About as many cells as texels, 2:1 like the grid's φ x θ.
                    let rows = ((width * height) as f64 / 2.0).sqrt().ceil().max(1.0) as usize;
                    ImportanceGrid::from_map(&map, 2 * rows, rows, s.orientation)
                }
            });
            let estimate =
                project_montecarlo(&map, options, grid.as_ref()).map_err(|e| anyhow!("{e}"))?;
            Projection {
                coeffs: estimate.coeffs,
                std_error: Some(estimate.std_error),
                samples: Some(estimate.samples as u64),
                seed: Some(options.seed),
                sampler: Some(options.sampler.name().to_string()),
            }
        }
    })
}

/// The window of each colour channel: `fixed` for all three, or (`None`,
/// `--window auto`) each channel's weakest Hanning window that makes its
/// `target` non-negative.
fn choose_windows(
    fixed: Option<Window>,
    radiance: &ShCoeffs<DVec3>,
    target: WindowTarget,
) -> Result<[Window; 3]> {
    if let Some(w) = fixed {
        return Ok([w; 3]);
    }
    let mut out = [Window::None; 3];
    for (c, w) in out.iter_mut().enumerate() {
        *w = auto_window(&radiance.channel(c), WindowFamily::Hanning, target)
            .map_err(|e| anyhow!("{e}"))?
            .window;
    }
    Ok(out)
}

/// Each channel of `f` multiplied by its own window.
fn apply_windows(windows: &[Window; 3], f: &ShCoeffs<DVec3>) -> ShCoeffs<DVec3> {
    if windows.iter().all(|w| *w == windows[0]) {
        return windows[0].apply(f);
    }
    let [r, g, b] = std::array::from_fn(|c| windows[c].apply(&f.channel(c)));
    ShCoeffs::from_channels(&r, &g, &b)
}

/// Standard errors carried through a rotation, taking the errors of the
/// coefficients as independent: `σ'_m = sqrt(Σ_n M_mn² σ_n²)` per channel.
fn rotate_std_error(rotation: &ShRotation, se: &ShCoeffs<DVec3>) -> ShCoeffs<DVec3> {
    let mut out = ShCoeffs::<DVec3>::zeros(se.lmax());
    for l in 0..=se.lmax().min(rotation.lmax()) {
        let n = 2 * l + 1;
        let block = rotation.block(l);
        let band = se.band(l);
        for (m, o) in out.band_mut(l).iter_mut().enumerate() {
            let var: DVec3 = (0..n)
                .map(|k| band[k] * band[k] * block[m * n + k] * block[m * n + k])
                .sum();
            *o = DVec3::new(var.x.sqrt(), var.y.sqrt(), var.z.sqrt());
        }
    }
    out
}

/// Writes `file` in `format` to `dest` (atomically for files), with the
/// exporter's notes through `ui` (silenced by `--quiet`), naming the input.
/// Without `--format`, a terminal gets the readable table of `shlight show`
/// and everything else JSON.
pub fn write_output(
    file: &CoeffFile,
    format: Option<ExportFormat>,
    dest: &Dest,
    ui: &Ui,
) -> Result<()> {
    let to_terminal = || std::io::IsTerminal::is_terminal(&std::io::stdout());
    let out = match (format, dest) {
        (None, Dest::Stdout) if to_terminal() => Exported {
            text: file.to_table(),
            notes: Vec::new(),
        },
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotations_parse_to_the_documented_matrices() {
        let close = |a: DMat3, b: DMat3| (a - b).to_cols_array().iter().all(|v| v.abs() < 1e-12);
        // yaw about +Y (y-up) takes +X to -Z; about +Z (z-up) +X to +Y.
        let r = parse_rotation("yaw:90", Frame::YUp).unwrap();
        assert!((r * DVec3::X - DVec3::NEG_Z).length() < 1e-12);
        let r = parse_rotation("yaw:90", Frame::ZUp).unwrap();
        assert!((r * DVec3::X - DVec3::Y).length() < 1e-12);
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let q = parse_rotation("quat:0,0,2,2", Frame::YUp).unwrap();
        assert!(close(q, DMat3::from_quat(DQuat::from_xyzw(0.0, 0.0, s, s))));
        let e = parse_rotation("euler:90,0,90", Frame::YUp).unwrap();
        // X first: +Y -> +Z; then Z: +Z stays.
        assert!((e * DVec3::Y - DVec3::Z).length() < 1e-12);
        assert!((e * DVec3::X - DVec3::Y).length() < 1e-12);
        for bad in ["yaw", "yaw:1,2", "quat:0,0,0,0", "spin:3", "yaw:nan"] {
            assert!(parse_rotation(bad, Frame::YUp).is_err(), "{bad}");
        }
    }

    #[test]
    fn the_help_states_the_library_defaults() {
        use clap::Args as _;
        let cmd = ProjectArgs::augment_args(clap::Command::new("project"));
        let help = |id: &str| {
            cmd.get_arguments()
                .find(|a| a.get_id() == id)
                .and_then(|a| a.get_help())
                .map(|h| h.to_string())
                .unwrap_or_default()
        };
        let d = McOptions::default();
        assert!(help("seed").contains(&format!("[default: {DEFAULT_SEED}]")));
        assert!(help("samples").contains(&format!("[default: {DEFAULT_SAMPLES}]")));
        assert!(help("sampler").contains(&format!("[default: {}]", d.sampler)));
        assert_eq!((d.samples, d.seed), (DEFAULT_SAMPLES, DEFAULT_SEED));
    }

    #[test]
    fn std_errors_follow_a_quarter_turn() {
        // Rz(90°) swaps x and y up to sign: band 1 (-y, z, -x) errors swap.
        let rot = ShRotation::from_mat3(1, DMat3::from_rotation_z(std::f64::consts::FRAC_PI_2));
        let se = ShCoeffs::from_vec(vec![
            DVec3::splat(1.0),
            DVec3::splat(2.0),
            DVec3::splat(3.0),
            DVec3::splat(4.0),
        ])
        .unwrap();
        let out = rotate_std_error(&rot, &se);
        let got: Vec<f64> = out.as_slice().iter().map(|v| v.x).collect();
        for (g, w) in got.iter().zip([1.0, 4.0, 3.0, 2.0]) {
            assert!((g - w).abs() < 1e-12, "{got:?}");
        }
    }
}
