//! shlight's coefficient file: self-describing JSON (docs/coefficient-file.md).

use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc;

use glam::DVec3;
use serde_json::{Value, json};
use shlight_core::sh::{Frame, ShCoeffs, lm_from_index, sphere_minimum};

use crate::file_encoding::FileEncoding;
use crate::{FormatError, Quantity, Result};

/// Highest lmax whose file gets `statistics.minimum` (the search costs
/// `O(lmax^4)`: about 80 ms per channel at lmax 32, more than the rest of
/// a 2048x1024 projection; about 5 ms at 16).
pub const MINIMUM_MAX_LMAX: usize = 16;

/// Highest lmax written as pretty-printed JSON (one number per line, for
/// people); files above it are compact JSON on one line, the same document
/// (docs/coefficient-file.md), written straight from the coefficients: a
/// pretty file at lmax 512 is 26 MB of mostly indentation.
pub const PRETTY_MAX_LMAX: usize = 32;

/// From this lmax on, `coefficients` is written as little-endian `f64`
/// bytes in base64 (docs/coefficient-file.md, "Binary coefficients"): at
/// lmax 512 8.4 MB of text instead of 17.4 MB of decimal rows, encoded in
/// a few milliseconds instead of formatted in tens.
pub const BINARY_MIN_LMAX: usize = 129;

/// The `dtype` of binary coefficients: numpy's name for little-endian
/// IEEE-754 binary64.
pub const BINARY_DTYPE: &str = "<f8";

/// Version of the JSON layout written by this build for plain SH.
pub const FORMAT_VERSION: u64 = 1;

/// Version written for a file with an `encoding` other than plain SH: its
/// `coefficients` alone are not the light, so readers of version 1 must
/// refuse it rather than read them as the whole light.
pub const ENCODED_FORMAT_VERSION: u64 = 2;

/// The `format` field of a coefficient file.
pub const FORMAT: &str = "shlight-sh";

/// Where the coefficients came from.
///
/// Fields added after the first release of format 1 (`windows`, `samples`,
/// `seed`, `sampler`, `rotate`) are optional in files: a reader fills them
/// from the older fields or leaves them `None`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Provenance {
    /// Input file as given.
    pub input: String,
    /// Input width in texels.
    pub width: usize,
    /// Input height in texels.
    pub height: usize,
    /// Input layout (`equirect`, ...).
    pub layout: String,
    /// Projection method (`quadrature`, `montecarlo`).
    pub method: String,
    /// Window asked for, in `--window` spelling (`auto` when chosen per channel).
    pub window: String,
    /// Window applied to each channel (red, green, blue), in `--window`
    /// spelling; all three equal `window` unless it was `auto`.
    pub windows: [String; 3],
    /// Monte Carlo samples (directions) used; `None` for quadrature.
    pub samples: Option<u64>,
    /// Seed of the Monte Carlo sampler; `None` for quadrature.
    pub seed: Option<u64>,
    /// Monte Carlo sampler (e.g. `uniform`, `stratified`); `None` for quadrature.
    pub sampler: Option<String>,
    /// Rotation applied to the coefficients (`--rotate`), if any.
    pub rotate: Option<RotationRecord>,
}

/// A rotation applied to the coefficients: as asked for, and as the matrix
/// `R` (row-major, acting on column vectors) that carries a light from `a`
/// to `R a` in the file's frame.
#[derive(Clone, Debug, PartialEq)]
pub struct RotationRecord {
    /// The `--rotate` argument as given (`yaw:30`, `quat:x,y,z,w`, `euler:x,y,z`).
    pub spec: String,
    /// `R`, rows first.
    pub matrix: [[f64; 3]; 3],
}

/// What `--sanitize` replaced in the input, counted in channel values.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SanitizeCounts {
    /// NaN values, set to 0.
    pub nan: usize,
    /// `+inf` values, set to `infinity_replacement`.
    pub positive_infinite: usize,
    /// `-inf` values, set to 0.
    pub negative_infinite: usize,
    /// Finite negative values, set to 0.
    pub negative: usize,
    /// The value that replaced `+inf`: the largest finite value of the input.
    pub infinity_replacement: f64,
}

impl SanitizeCounts {
    /// How many channel values were replaced in all.
    pub fn total(&self) -> usize {
        self.nan + self.positive_infinite + self.negative_infinite + self.negative
    }
}

impl From<shlight_io::SanitizeReport> for SanitizeCounts {
    fn from(r: shlight_io::SanitizeReport) -> Self {
        Self {
            nan: r.nan,
            positive_infinite: r.positive_infinite,
            negative_infinite: r.negative_infinite,
            negative: r.negative,
            infinity_replacement: f64::from(r.infinity_replacement),
        }
    }
}

/// A coefficient file's content.
#[derive(Clone, Debug)]
pub struct CoeffFile {
    /// Linear Rec.709 RGB coefficients, shlight's basis (CS phase included).
    pub coeffs: ShCoeffs<DVec3>,
    /// Frame the map was read in.
    pub frame: Frame,
    /// Whether the mirrored mapping was used.
    pub mirror: bool,
    /// What the coefficients hold.
    pub quantity: Quantity,
    /// Where they came from.
    pub provenance: Provenance,
    /// Negative channel values in the input as read (before `--sanitize`).
    pub input_negative_texels: usize,
    /// Smallest finite channel value of the input as read.
    pub input_min_value: f64,
    /// What `--sanitize` replaced; `None` when it was not asked for.
    pub sanitized: Option<SanitizeCounts>,
    /// Standard error of each coefficient, per channel, in the same units,
    /// index and quantity as `coeffs` (Monte Carlo projection); `None` for
    /// quadrature.
    pub std_error: Option<ShCoeffs<DVec3>>,
    /// Which encoding `coeffs` belong to and what else it keeps
    /// ([`FileEncoding::Sh`] for plain SH).
    pub encoding: FileEncoding,
}

impl Provenance {
    /// The window of each channel: `windows`, where a channel's entry is
    /// empty (a provenance built by hand) `window`.
    pub fn channel_windows(&self) -> [String; 3] {
        self.windows
            .clone()
            .map(|w| if w.is_empty() { self.window.clone() } else { w })
    }
}

impl CoeffFile {
    /// Coefficients with empty provenance and statistics, for files made
    /// from something other than a map (conversions, tests).
    pub fn new(coeffs: ShCoeffs<DVec3>, frame: Frame, quantity: Quantity) -> Self {
        Self {
            coeffs,
            frame,
            mirror: false,
            quantity,
            provenance: Provenance::default(),
            input_negative_texels: 0,
            input_min_value: 0.0,
            sanitized: None,
            std_error: None,
            encoding: FileEncoding::Sh,
        }
    }

    /// The file's light as the core's [`shlight_core::encoding::Encoded`], ready to
    /// evaluate; `None` for irradiance files or coefficients too short for
    /// the encoding.
    #[must_use]
    pub fn encoded(&self) -> Option<shlight_core::encoding::Encoded> {
        if self.quantity != Quantity::Radiance {
            return None;
        }
        self.encoding.to_encoded(&self.coeffs)
    }

    /// The JSON document (docs/coefficient-file.md).
    pub fn to_json(&self) -> Value {
        self.document(true)
    }

    /// The JSON document, with `coefficients` `null` unless `with_rows`.
    fn document(&self, with_rows: bool) -> Value {
        let rgb = |v: DVec3| json!([v.x, v.y, v.z]);
        // The dense search costs O(lmax^4): beyond MINIMUM_MAX_LMAX it would
        // dominate the run (minutes at lmax 128), so the field is null there.
        let minimum: Vec<Value> = (0..3)
            .map(|c| {
                if self.coeffs.lmax() > MINIMUM_MAX_LMAX {
                    return Value::Null;
                }
                let (v, d) = sphere_minimum(&self.coeffs.channel(c));
                json!({ "value": v, "direction": d.to_array() })
            })
            .collect();
        let p = &self.provenance;
        let windows = p.channel_windows();
        let rotate = p.rotate.as_ref().map_or(
            Value::Null,
            |r| json!({ "spec": r.spec, "matrix": r.matrix }),
        );
        let sanitized = self.sanitized.map_or(Value::Null, |c| {
            json!({
                "nan": c.nan,
                "positive_infinite": c.positive_infinite,
                "negative_infinite": c.negative_infinite,
                "negative": c.negative,
                "infinity_replacement": c.infinity_replacement,
            })
        });
        let mut doc = json!({
            "format": "shlight-sh",
            "format_version": FORMAT_VERSION,
            "lmax": self.coeffs.lmax(),
            "basis": {
                "kind": "real-orthonormal",
                "condon_shortley_phase": true,
                "index": "l*(l+1)+m",
            },
            "frame": self.frame.to_string(),
            "mirror": self.mirror,
            "quantity": self.quantity.name(),
            "color_space": "linear-rec709",
            "coefficients": if with_rows {
                if self.coeffs.lmax() >= BINARY_MIN_LMAX {
                    let mut text = Vec::new();
                    encode_run(&mut text, self.coeffs.as_slice(), true);
                    binary_coefficients(
                        self.coeffs.len(),
                        Value::String(String::from_utf8(text).expect("base64 is ASCII")),
                    )
                } else {
                    self.coeffs.as_slice().iter().map(|v| rgb(*v)).collect()
                }
            } else {
                Value::Null
            },
            "provenance": {
                "tool": concat!("shlight ", env!("CARGO_PKG_VERSION")),
                "input": p.input,
                "width": p.width,
                "height": p.height,
                "layout": p.layout,
                "method": p.method,
                "window": p.window,
                "windows": { "red": windows[0], "green": windows[1], "blue": windows[2] },
                "samples": p.samples,
                "seed": p.seed,
                "sampler": p.sampler,
                "rotate": rotate,
            },
            "statistics": {
                "band_power": self.coeffs.band_power().into_iter().map(rgb).collect::<Vec<_>>(),
                "minimum": { "red": minimum[0], "green": minimum[1], "blue": minimum[2] },
                "input_negative_texels": self.input_negative_texels,
                "input_min_value": self.input_min_value,
                "sanitized": sanitized,
            },
        });
        if let Some(se) = &self.std_error {
            doc["statistics"]["std_error"] = se.as_slice().iter().map(|v| rgb(*v)).collect();
        }
        if let Some(e) = self.encoding.to_json(&self.coeffs) {
            doc["encoding"] = e;
            doc["format_version"] = json!(ENCODED_FORMAT_VERSION);
        }
        doc
    }

    /// The file's JSON text: pretty-printed up to [`PRETTY_MAX_LMAX`],
    /// compact (one line) above it. Both are the document of
    /// [`CoeffFile::to_json`], with the same numbers.
    #[must_use]
    pub fn to_json_string(&self) -> String {
        let mut out = Vec::with_capacity(self.coeffs.len() * 3 * 24 + 4096);
        self.write_json_text(&mut out)
            .expect("writing to memory cannot fail");
        String::from_utf8(out).expect("serde_json writes UTF-8")
    }

    /// Writes [`CoeffFile::to_json_string`] and a newline to `w`. Above
    /// [`PRETTY_MAX_LMAX`] the rows are formatted on every core while the
    /// text before them is written, so a large file is written as it is
    /// formatted, without the whole text in memory.
    ///
    /// # Errors
    /// The first error of `w`.
    pub fn write_json(&self, w: &mut dyn Write) -> std::io::Result<()> {
        self.write_json_text(w)?;
        w.write_all(b"\n")
    }

    /// [`CoeffFile::to_json_string`]'s text to `w`.
    fn write_json_text(&self, w: &mut dyn Write) -> std::io::Result<()> {
        if self.coeffs.lmax() <= PRETTY_MAX_LMAX {
            return serde_json::to_writer_pretty(&mut *w, &self.to_json()).map_err(Into::into);
        }
        // The document without its rows, written member by member, with the
        // rows written straight from the coefficients in its place: no
        // value tree of (lmax+1)^2 arrays.
        let doc = self.document(false);
        w.write_all(b"{")?;
        for (i, (key, value)) in doc.as_object().expect("an object").iter().enumerate() {
            if i > 0 {
                w.write_all(b",")?;
            }
            serde_json::to_writer(&mut *w, key)?;
            w.write_all(b":")?;
            if key == "coefficients" && self.coeffs.lmax() >= BINARY_MIN_LMAX {
                // `{"base64":"...","dtype":"<f8","shape":[N,3]}`, the keys
                // in serde_json's order.
                w.write_all(b"{\"base64\":\"")?;
                write_runs(w, self.coeffs.as_slice(), encode_run)?;
                write!(
                    w,
                    "\",\"dtype\":\"{BINARY_DTYPE}\",\"shape\":[{},3]}}",
                    self.coeffs.len()
                )?;
            } else if key == "coefficients" {
                w.write_all(b"[")?;
                write_runs(w, self.coeffs.as_slice(), write_run)?;
                w.write_all(b"]")?;
            } else {
                serde_json::to_writer(&mut *w, value)?;
            }
        }
        w.write_all(b"}")
    }

    /// Writes the JSON file to `path` atomically (a temporary file renamed
    /// into place), so a failure leaves an existing file as it was.
    ///
    /// # Errors
    /// [`FormatError::Write`] naming the file.
    pub fn write(&self, path: &Path) -> Result<()> {
        shlight_io::write_atomically(path, |w| self.write_json(w))?;
        Ok(())
    }

    /// Reads the coefficient file at `path`.
    ///
    /// # Errors
    /// [`FormatError::Read`] when it cannot be read, [`FormatError::Invalid`]
    /// naming the file when it is not a valid coefficient file.
    pub fn read(path: &Path) -> Result<Self> {
        let text = read_text(path)?;
        Self::from_json_str(&text, &path.display().to_string())
    }

    /// Reads the coefficient file at `path`, which must hold radiance:
    /// `user` (e.g. `--env`) and `fix` complete the message that refuses
    /// irradiance, from which radiance cannot be recovered.
    ///
    /// # Errors
    /// As [`CoeffFile::read`], and [`FormatError::Invalid`] for irradiance.
    pub fn read_radiance(path: &Path, user: &str, fix: &str) -> Result<Self> {
        let name = path.display().to_string();
        let file = Self::read(path)?;
        if file.encoding != FileEncoding::Sh {
            return Err(FormatError::invalid(
                &name,
                format!(
                    "holds the {} encoding, whose coefficients are not the whole light; {user} needs plain SH ({fix}, without an encoding)",
                    file.encoding.encoding()
                ),
            ));
        }
        if file.quantity != Quantity::Radiance {
            return Err(FormatError::invalid(
                &name,
                format!("holds irradiance; {user} needs radiance coefficients ({fix})"),
            ));
        }
        Ok(file)
    }

    /// Parses a coefficient file's text; `name` is used in error messages.
    ///
    /// # Errors
    /// [`FormatError::Invalid`] naming `name` and the first problem found.
    pub fn from_json_str(text: &str, name: &str) -> Result<Self> {
        let bad = |message: String| FormatError::invalid(name, message);
        let v: Value =
            serde_json::from_str(text).map_err(|e| bad(format!("not valid JSON ({e})")))?;
        let field = |k: &str| {
            v.get(k)
                .ok_or_else(|| bad(format!("missing field \"{k}\"")))
        };
        if field("format")?.as_str() != Some(FORMAT) {
            return Err(bad(format!(
                "not a shlight coefficient file (\"format\" is not \"{FORMAT}\")"
            )));
        }
        let version = field("format_version")?.as_u64().unwrap_or(0);
        if version == 0 || version > ENCODED_FORMAT_VERSION {
            return Err(bad(format!(
                "format_version {version} is not supported (this build reads 1..={ENCODED_FORMAT_VERSION})"
            )));
        }
        let lmax = field("lmax")?
            .as_u64()
            .ok_or_else(|| bad("\"lmax\" is not an integer".into()))? as usize;
        let want = lmax
            .checked_add(1)
            .and_then(|n| n.checked_mul(n))
            .filter(|&n| n <= MAX_COEFFICIENTS);
        let Some(want) = want else {
            return Err(bad(format!("lmax {lmax} is too large")));
        };
        let coefficients = field("coefficients")?;
        let coeffs = match coefficients {
            Value::Object(binary) => read_binary(binary, want).map_err(bad)?,
            Value::Array(rows) => {
                if rows.len() != want {
                    return Err(bad(format!(
                        "lmax {lmax} needs {want} coefficients, the file has {}",
                        rows.len()
                    )));
                }
                let mut coeffs = Vec::with_capacity(rows.len());
                for (i, row) in rows.iter().enumerate() {
                    match read_rgb(row) {
                        Some(c) => coeffs.push(c),
                        None => {
                            let (l, m) = lm_from_index(i);
                            return Err(bad(format!(
                                "coefficient {i} (l={l}, m={m}) is not three numbers"
                            )));
                        }
                    }
                }
                coeffs
            }
            _ => {
                return Err(bad(
                    "\"coefficients\" is neither an array of rows nor binary coefficients".into(),
                ));
            }
        };
        let frame = field("frame")?
            .as_str()
            .unwrap_or("")
            .parse::<Frame>()
            .map_err(|e| bad(e.to_string()))?;
        let quantity = match field("quantity")?.as_str() {
            Some("radiance") => Quantity::Radiance,
            Some("irradiance") => Quantity::Irradiance,
            other => return Err(bad(format!("unknown quantity {other:?}"))),
        };
        let p = field("provenance")?;
        let s = |k: &str| p.get(k).and_then(Value::as_str).unwrap_or("").to_string();
        let n = |k: &str| p.get(k).and_then(Value::as_u64).unwrap_or(0) as usize;
        let opt_u64 = |k: &str| -> Result<Option<u64>> {
            match p.get(k) {
                None | Some(Value::Null) => Ok(None),
                Some(v) => v.as_u64().map(Some).ok_or_else(|| {
                    bad(format!("provenance \"{k}\" is not a non-negative integer"))
                }),
            }
        };
        let window = s("window");
        let windows = match p.get("windows") {
            None | Some(Value::Null) => [window.clone(), window.clone(), window.clone()],
            Some(w) => {
                let channel = |c: &str| {
                    w.get(c)
                        .and_then(Value::as_str)
                        .map(str::to_string)
                        .ok_or_else(|| bad(format!("provenance \"windows\" has no string \"{c}\"")))
                };
                [channel("red")?, channel("green")?, channel("blue")?]
            }
        };
        let rotate = match p.get("rotate") {
            None | Some(Value::Null) => None,
            Some(r) => Some(read_rotation(r).ok_or_else(|| {
                bad("provenance \"rotate\" is not {\"spec\": text, \"matrix\": 3x3 numbers}".into())
            })?),
        };
        let stats = v.get("statistics");
        let stat = |k: &str| stats.and_then(|s| s.get(k)).filter(|v| !v.is_null());
        let sanitized = match stat("sanitized") {
            None => None,
            Some(c) => {
                let count = |k: &str| {
                    c.get(k)
                        .and_then(Value::as_u64)
                        .map(|n| n as usize)
                        .ok_or_else(|| {
                            bad(format!("statistics \"sanitized\" has no count \"{k}\""))
                        })
                };
                Some(SanitizeCounts {
                    nan: count("nan")?,
                    positive_infinite: count("positive_infinite")?,
                    negative_infinite: count("negative_infinite")?,
                    negative: count("negative")?,
                    infinity_replacement: c
                        .get("infinity_replacement")
                        .and_then(Value::as_f64)
                        .unwrap_or(0.0),
                })
            }
        };
        let std_error = match stat("std_error") {
            None => None,
            Some(rows) => {
                let rows = rows
                    .as_array()
                    .filter(|r| r.len() == coeffs.len())
                    .ok_or_else(|| {
                        bad(format!(
                            "statistics \"std_error\" is not {} rows of three numbers",
                            coeffs.len()
                        ))
                    })?;
                let mut se = Vec::with_capacity(rows.len());
                for (i, row) in rows.iter().enumerate() {
                    se.push(read_rgb(row).ok_or_else(|| {
                        let (l, m) = lm_from_index(i);
                        bad(format!("std_error {i} (l={l}, m={m}) is not three numbers"))
                    })?);
                }
                Some(ShCoeffs::from_vec(se).expect("length checked"))
            }
        };
        let encoding = match v.get("encoding") {
            None | Some(Value::Null) => FileEncoding::Sh,
            Some(e) => FileEncoding::from_json(e, lmax).map_err(bad)?,
        };
        if encoding != FileEncoding::Sh && version < ENCODED_FORMAT_VERSION {
            return Err(bad(format!(
                "an \"encoding\" needs format_version {ENCODED_FORMAT_VERSION}, the file says {version}"
            )));
        }
        Ok(Self {
            encoding,
            coeffs: ShCoeffs::from_vec(coeffs).expect("length checked"),
            frame,
            mirror: v.get("mirror").and_then(Value::as_bool).unwrap_or(false),
            quantity,
            provenance: Provenance {
                input: s("input"),
                width: n("width"),
                height: n("height"),
                layout: s("layout"),
                method: s("method"),
                window,
                windows,
                samples: opt_u64("samples")?,
                seed: opt_u64("seed")?,
                sampler: p.get("sampler").and_then(Value::as_str).map(str::to_string),
                rotate,
            },
            input_negative_texels: stat("input_negative_texels")
                .and_then(Value::as_u64)
                .unwrap_or(0) as usize,
            input_min_value: stat("input_min_value")
                .and_then(Value::as_f64)
                .unwrap_or(0.0),
            sanitized,
            std_error,
        })
    }

    /// A readable table: a header naming what the numbers are, then one
    /// coefficient per line.
    pub fn to_table(&self) -> String {
        let p = &self.provenance;
        let w = p.channel_windows();
        let window = if w.iter().all(|x| *x == w[0]) {
            format!("window {}", w[0])
        } else {
            format!("windows r {}, g {}, b {}", w[0], w[1], w[2])
        };
        let method = match p.samples {
            Some(n) => format!("{}, {n} samples", p.method),
            None => p.method.clone(),
        };
        let rotate = match &p.rotate {
            Some(r) => format!(", rotated {}", r.spec),
            None => String::new(),
        };
        let mut s = format!(
            "# shlight SH {}: lmax {} ({} coefficients), real orthonormal basis with Condon-Shortley phase,\n\
             # index l*(l+1)+m, frame {}{}, linear Rec.709 RGB; from {} ({}x{} {}, {method}, {window}{rotate})\n",
            self.quantity.name(),
            self.coeffs.lmax(),
            self.coeffs.len(),
            self.frame,
            if self.mirror { " (mirrored)" } else { "" },
            p.input,
            p.width,
            p.height,
            p.layout,
        );
        s.push_str(&coefficient_rows(&self.coeffs, self.std_error.as_ref()));
        s
    }
}

/// The rows of [`CoeffFile::to_table`]: a line naming the columns, then
/// `l`, `m` and the red, green and blue coefficient (and its standard
/// error, when given) per line.
pub(crate) fn coefficient_rows(
    coeffs: &ShCoeffs<DVec3>,
    std_error: Option<&ShCoeffs<DVec3>>,
) -> String {
    let mut s = String::from("#  l   m           red         green          blue");
    if std_error.is_some() {
        s.push_str("     std error (red, green, blue)");
    }
    s.push('\n');
    for (i, v) in coeffs.as_slice().iter().enumerate() {
        let (l, m) = lm_from_index(i);
        s.push_str(&format!(
            "{l:4} {m:3} {:13.6e} {:13.6e} {:13.6e}",
            v.x, v.y, v.z
        ));
        if let Some(se) = std_error {
            let e = se[i];
            s.push_str(&format!(" {:11.3e} {:11.3e} {:11.3e}", e.x, e.y, e.z));
        }
        s.push('\n');
    }
    s
}

/// `[r, g, b]`: exactly three numbers.
fn read_rgb(row: &Value) -> Option<DVec3> {
    match row.as_array()?.as_slice() {
        [r, g, b] => Some(DVec3::new(r.as_f64()?, g.as_f64()?, b.as_f64()?)),
        _ => None,
    }
}

/// `{"spec": "...", "matrix": [[..3], [..3], [..3]]}`.
fn read_rotation(r: &Value) -> Option<RotationRecord> {
    let spec = r.get("spec")?.as_str()?.to_string();
    let rows = r.get("matrix")?.as_array()?;
    if rows.len() != 3 {
        return None;
    }
    let mut matrix = [[0.0; 3]; 3];
    for (out, row) in matrix.iter_mut().zip(rows) {
        *out = read_rgb(row)?.to_array();
    }
    Some(RotationRecord { spec, matrix })
}

/// The text of the file at `path` (UTF-8).
pub(crate) fn read_text(path: &Path) -> Result<String> {
    let bytes = std::fs::read(path).map_err(|source| FormatError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    String::from_utf8(bytes).map_err(|_| {
        FormatError::invalid(&path.display().to_string(), "not a text file (not UTF-8)")
    })
}

/// `rows` as a compact JSON array of `[r, g, b]` arrays, numbers as
/// serde_json writes them (shortest round-trip form; non-finite as `null`,
/// as in a value tree).
///
/// Formatting the numbers is most of the cost of a large file (263 169
/// rows at lmax 512), so runs of [`ROWS_PER_RUN`] rows are formatted on
/// scoped threads, one per core, each taking the next run not yet taken,
/// and written in order by the calling thread as they are done: the text
/// is the same for any thread count, and writing overlaps formatting.
fn write_runs(
    w: &mut dyn Write,
    rows: &[DVec3],
    write_run: fn(&mut Vec<u8>, &[DVec3], bool),
) -> std::io::Result<()> {
    let runs: Vec<&[DVec3]> = rows.chunks(ROWS_PER_RUN).collect();
    let threads = std::thread::available_parallelism()
        .map_or(1, usize::from)
        .min(runs.len());
    if threads <= 1 {
        let mut text = Vec::new();
        for (i, run) in runs.iter().enumerate() {
            text.clear();
            write_run(&mut text, run, i == 0);
            w.write_all(&text)?;
        }
        return Ok(());
    }
    let next = AtomicUsize::new(0);
    // Set when writing fails: the threads stop taking runs.
    let stop = AtomicBool::new(false);
    std::thread::scope(|scope| {
        let (send, receive) = mpsc::channel::<(usize, Vec<u8>)>();
        for _ in 0..threads {
            let (send, next, stop, runs) = (send.clone(), &next, &stop, &runs);
            scope.spawn(move || {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    if i >= runs.len() || stop.load(Ordering::Relaxed) {
                        break;
                    }
                    let mut text = Vec::with_capacity(runs[i].len() * 3 * 24);
                    write_run(&mut text, runs[i], i == 0);
                    if send.send((i, text)).is_err() {
                        break;
                    }
                }
            });
        }
        drop(send);
        // Runs arrive in any order; each is written once those before it are.
        let mut pending = std::collections::BTreeMap::new();
        let mut written = 0;
        for (i, text) in receive {
            pending.insert(i, text);
            while let Some(text) = pending.remove(&written) {
                if let Err(e) = w.write_all(&text) {
                    stop.store(true, Ordering::Relaxed);
                    return Err(e);
                }
                written += 1;
            }
        }
        Ok(())
    })
}

/// Rows per run of [`write_runs`]: about 200 kB of text, so the first run
/// is written early and the runs' buffers stay small.
const ROWS_PER_RUN: usize = 4096;

/// The base64 text of `rows` as little-endian `f64` bytes, `r, g, b` of
/// each row in turn. Runs of [`ROWS_PER_RUN`] rows are 98 304 bytes, a
/// multiple of 3, so their texts join without padding between them.
fn encode_run(out: &mut Vec<u8>, rows: &[DVec3], _first: bool) {
    use base64::Engine;
    const _: () = assert!((ROWS_PER_RUN * 24).is_multiple_of(3));
    let mut bytes = Vec::with_capacity(rows.len() * 24);
    for v in rows {
        for x in v.to_array() {
            bytes.extend_from_slice(&x.to_le_bytes());
        }
    }
    let start = out.len();
    out.resize(
        start + base64::encoded_len(bytes.len(), true).expect("fits"),
        0,
    );
    let n = base64::engine::general_purpose::STANDARD
        .encode_slice(&bytes, &mut out[start..])
        .expect("sized above");
    out.truncate(start + n);
}

/// `coefficients` as binary: `{"base64": TEXT, "dtype": "<f8", "shape": [count, 3]}`.
fn binary_coefficients(count: usize, text: Value) -> Value {
    json!({ "base64": text, "dtype": BINARY_DTYPE, "shape": [count, 3] })
}

/// Most coefficients a file may hold: lmax 4095 (16.8 M rows).
const MAX_COEFFICIENTS: usize = 4096 * 4096;

/// The rows of binary `coefficients`, which must hold `want` of them.
fn read_binary(
    binary: &serde_json::Map<String, Value>,
    want: usize,
) -> std::result::Result<Vec<DVec3>, String> {
    use base64::Engine;
    let dtype = binary.get("dtype").and_then(Value::as_str);
    if dtype != Some(BINARY_DTYPE) {
        return Err(format!(
            "binary \"coefficients\" need \"dtype\": \"{BINARY_DTYPE}\" (little-endian f64), not {}",
            binary
                .get("dtype")
                .map_or("nothing".into(), Value::to_string)
        ));
    }
    let shape: Option<Vec<u64>> = binary
        .get("shape")
        .and_then(Value::as_array)
        .and_then(|a| a.iter().map(Value::as_u64).collect());
    if shape.as_deref() != Some(&[want as u64, 3]) {
        return Err(format!(
            "binary \"coefficients\" have \"shape\" {}, lmax needs [{want}, 3]",
            binary
                .get("shape")
                .map_or("(none)".into(), Value::to_string)
        ));
    }
    let text = binary
        .get("base64")
        .and_then(Value::as_str)
        .ok_or("binary \"coefficients\" have no \"base64\" text")?;
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(text)
        .map_err(|e| format!("binary \"coefficients\": bad base64 ({e})"))?;
    if bytes.len() != want * 24 {
        return Err(format!(
            "binary \"coefficients\" hold {} bytes, {want} rows of three f64 need {}",
            bytes.len(),
            want * 24
        ));
    }
    let f = |b: &[u8]| f64::from_le_bytes(b.try_into().expect("8 bytes"));
    bytes
        .chunks_exact(24)
        .enumerate()
        .map(|(i, b)| {
            let v = DVec3::new(f(&b[0..8]), f(&b[8..16]), f(&b[16..24]));
            if v.is_finite() {
                Ok(v)
            } else {
                let (l, m) = lm_from_index(i);
                Err(format!("coefficient {i} (l={l}, m={m}) is not finite"))
            }
        })
        .collect()
}

/// `[r,g,b]` of each row, separated by commas, with a comma before the
/// first row unless `first`.
fn write_run(out: &mut Vec<u8>, rows: &[DVec3], first: bool) {
    for (i, v) in rows.iter().enumerate() {
        if i > 0 || !first {
            out.push(b',');
        }
        out.push(b'[');
        for (c, x) in v.to_array().iter().enumerate() {
            if c > 0 {
                out.push(b',');
            }
            serde_json::to_writer(&mut *out, x).expect("writes to memory");
        }
        out.push(b']');
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_file() -> CoeffFile {
        let coeffs = ShCoeffs::from_fn(3, |l, m| {
            DVec3::new(l as f64, m as f64 * 0.5, 0.125 + l as f64)
        });
        CoeffFile {
            encoding: FileEncoding::Sh,
            std_error: Some(coeffs.map(|c| c * 0.01)),
            coeffs,
            frame: Frame::ZUp,
            mirror: true,
            quantity: Quantity::Irradiance,
            provenance: Provenance {
                input: "x.exr".into(),
                width: 64,
                height: 32,
                layout: "equirect".into(),
                method: "montecarlo".into(),
                window: "auto".into(),
                windows: ["hanning:4".into(), "hanning:5.5".into(), "none".into()],
                samples: Some(1 << 20),
                seed: Some(7),
                sampler: Some("stratified".into()),
                rotate: Some(RotationRecord {
                    spec: "yaw:90".into(),
                    matrix: [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]],
                }),
            },
            input_negative_texels: 3,
            input_min_value: -0.004,
            sanitized: Some(SanitizeCounts {
                nan: 2,
                positive_infinite: 1,
                negative_infinite: 0,
                negative: 3,
                infinity_replacement: 1500.0,
            }),
        }
    }

    #[test]
    fn json_round_trips() {
        let file = sample_file();
        let back = CoeffFile::from_json_str(&file.to_json_string(), "t.json").unwrap();
        assert_eq!(back.coeffs, file.coeffs);
        assert_eq!(back.frame, Frame::ZUp);
        assert!(back.mirror);
        assert_eq!(back.quantity, Quantity::Irradiance);
        assert_eq!(back.provenance, file.provenance);
        assert_eq!(back.input_negative_texels, 3);
        assert_eq!(back.input_min_value, -0.004);
        assert_eq!(back.sanitized, file.sanitized);
        assert_eq!(back.std_error, file.std_error);
        // Without the optional parts, they stay absent.
        let plain = CoeffFile::new(file.coeffs.clone(), Frame::YUp, Quantity::Radiance);
        let json = plain.to_json();
        assert!(json["statistics"].get("std_error").is_none());
        assert!(json["statistics"]["sanitized"].is_null());
        let back = CoeffFile::from_json_str(&plain.to_json_string(), "p.json").unwrap();
        assert_eq!(back.provenance, plain.provenance);
        assert_eq!(back.sanitized, None);
        assert_eq!(back.std_error, None);
    }

    #[test]
    fn large_compact_files_are_serde_jsons_own_text_of_the_value_tree() {
        // Enough rows for several formatting threads (ROWS_PER_RUN):
        // the joined runs must be exactly serde_json's compact text, for
        // decimal rows and for binary coefficients alike.
        for lmax in [100, 200] {
            assert!((lmax + 1) * (lmax + 1) > 2 * ROWS_PER_RUN);
            let mut file = sample_file();
            file.coeffs = ShCoeffs::from_fn(lmax, |l, m| {
                let x = (l * l) as f64 + 0.37 * m as f64;
                DVec3::new(x.sin(), 1.0 / (1.0 + x), -x.sqrt().exp())
            });
            file.std_error = None;
            assert_eq!(
                file.to_json_string(),
                serde_json::to_string(&file.to_json()).unwrap()
            );
        }
    }

    /// From BINARY_MIN_LMAX on, `coefficients` are base64 of little-endian
    /// f64, decoded here by hand from the bytes (an independent route), and
    /// read back bit for bit; below it they are decimal rows.
    #[test]
    fn high_lmax_coefficients_are_little_endian_f64_in_base64() {
        use base64::Engine;
        let at = |lmax: usize| {
            let mut file = sample_file();
            file.coeffs = ShCoeffs::from_fn(lmax, |l, m| {
                let x = (l * l) as f64 + 0.37 * m as f64;
                DVec3::new(x.sin(), 1.0 / (1.0 + x), -x.sqrt().exp() * 1e-300)
            });
            file.std_error = None;
            file
        };
        let below: Value = serde_json::from_str(&at(BINARY_MIN_LMAX - 1).to_json_string()).unwrap();
        assert!(below["coefficients"].is_array());
        let file = at(BINARY_MIN_LMAX);
        let text = file.to_json_string();
        let doc: Value = serde_json::from_str(&text).unwrap();
        let c = &doc["coefficients"];
        assert_eq!(c["dtype"], "<f8");
        assert_eq!(c["shape"], json!([file.coeffs.len(), 3]));
        let bytes = base64::engine::general_purpose::STANDARD
            .decode(c["base64"].as_str().unwrap())
            .unwrap();
        assert_eq!(bytes.len(), file.coeffs.len() * 24);
        for (i, v) in file.coeffs.as_slice().iter().enumerate() {
            for (k, x) in v.to_array().iter().enumerate() {
                let o = i * 24 + k * 8;
                let mut b = [0u8; 8];
                b.copy_from_slice(&bytes[o..o + 8]);
                assert_eq!(f64::from_bits(u64::from_le_bytes(b)).to_bits(), x.to_bits());
            }
        }
        let back = CoeffFile::from_json_str(&text, "b.json").unwrap();
        assert_eq!(back.coeffs, file.coeffs);
        assert_eq!(back.provenance, file.provenance);
    }

    #[test]
    fn bad_binary_coefficients_are_refused_naming_the_problem() {
        let doc = |c: Value| {
            json!({"format": "shlight-sh", "format_version": 1, "lmax": 1,
                   "frame": "y-up", "mirror": false, "quantity": "radiance", "coefficients": c,
                   "provenance": {"input": "a.exr", "width": 8, "height": 4, "layout": "equirect",
                                  "method": "quadrature", "window": "none"},
                   "statistics": {"input_negative_texels": 0, "input_min_value": 0.0}})
            .to_string()
        };
        let good = {
            let mut t = Vec::new();
            encode_run(&mut t, &[DVec3::ONE; 4], true);
            String::from_utf8(t).unwrap()
        };
        let ok = CoeffFile::from_json_str(
            &doc(json!({"base64": good, "dtype": "<f8", "shape": [4, 3]})),
            "ok.json",
        )
        .unwrap();
        assert_eq!(ok.coeffs.as_slice(), &[DVec3::ONE; 4]);
        let nan = {
            let mut t = Vec::new();
            encode_run(
                &mut t,
                &[
                    DVec3::ONE,
                    DVec3::ONE,
                    DVec3::new(1.0, f64::NAN, 1.0),
                    DVec3::ONE,
                ],
                true,
            );
            String::from_utf8(t).unwrap()
        };
        for (c, want) in [
            (
                json!({"base64": good, "dtype": ">f8", "shape": [4, 3]}),
                "dtype",
            ),
            (
                json!({"base64": good, "dtype": "<f8", "shape": [9, 3]}),
                "shape",
            ),
            (json!({"base64": good, "dtype": "<f8"}), "shape"),
            (json!({"dtype": "<f8", "shape": [4, 3]}), "no \"base64\""),
            (
                json!({"base64": "!!!!", "dtype": "<f8", "shape": [4, 3]}),
                "bad base64",
            ),
            (
                json!({"base64": "AAAA", "dtype": "<f8", "shape": [4, 3]}),
                "hold 3 bytes",
            ),
            (
                json!({"base64": nan, "dtype": "<f8", "shape": [4, 3]}),
                "coefficient 2 (l=1, m=0) is not finite",
            ),
            (json!("rows"), "neither an array"),
        ] {
            let err = CoeffFile::from_json_str(&doc(c), "bad.json")
                .unwrap_err()
                .to_string();
            assert!(
                err.contains("bad.json") && err.contains(want),
                "{want}: {err}"
            );
        }
    }

    #[test]
    fn every_encoding_round_trips_and_old_versions_refuse_it() {
        use shlight_core::encoding::CapLight;
        use shlight_core::sh::ShCoeffs;
        let l1 = ShCoeffs::from_fn(1, |l, m| DVec3::new(1.0 + l as f64, 0.5 * m as f64, 0.25));
        let light = CapLight {
            direction: DVec3::new(0.0, 0.6, 0.8),
            half_angle: 0.01,
            power: DVec3::new(10.0, 9.0, 7.5),
        };
        let cube = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0].map(|c| DVec3::new(c, c * 0.5, 0.1));
        for encoding in [
            FileEncoding::DominantSh {
                lights: vec![light.clone(), light],
            },
            FileEncoding::Zh3 {
                zonal: DVec3::new(0.1, -0.2, 0.3),
            },
            FileEncoding::Zh3Hallucinated,
            FileEncoding::SloanSh,
            FileEncoding::L1NonLinear,
            FileEncoding::AmbientCube { colours: cube },
        ] {
            let mut file = CoeffFile::new(l1.clone(), Frame::YUp, Quantity::Radiance);
            file.encoding = encoding.clone();
            let text = file.to_json_string();
            let back = CoeffFile::from_json_str(&text, "e.json").unwrap();
            assert_eq!(back.encoding, encoding);
            assert_eq!(back.coeffs, l1);
            assert!(back.encoded().is_some());
            let json: Value = serde_json::from_str(&text).unwrap();
            assert_eq!(json["format_version"], ENCODED_FORMAT_VERSION);
            let old = text.replacen("\"format_version\": 2", "\"format_version\": 1", 1);
            let err = CoeffFile::from_json_str(&old, "old.json")
                .unwrap_err()
                .to_string();
            assert!(
                err.contains("old.json") && err.contains("format_version"),
                "{err}"
            );
        }
        // Engine formats refuse an encoding rather than export part of it.
        let mut file = CoeffFile::new(l1.clone(), Frame::YUp, Quantity::Radiance);
        file.provenance.input = "enc.exr".into();
        file.encoding = FileEncoding::L1NonLinear;
        let err = crate::export(&file, crate::ExportFormat::Threejs)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("enc.exr") && err.contains("l1-nonlinear"),
            "{err}"
        );
        assert!(crate::export(&file, crate::ExportFormat::Json).is_ok());
        // The snippets take it, with the encoding's own evaluator.
        let glsl = crate::export(&file, crate::ExportFormat::Glsl)
            .unwrap()
            .text;
        assert!(glsl.contains("shlight_l1_channel"), "{glsl}");
        // A broken light names itself.
        let mut file = CoeffFile::new(l1.clone(), Frame::YUp, Quantity::Radiance);
        file.encoding = FileEncoding::DominantSh { lights: Vec::new() };
        let text = file.to_json_string().replace(
            "\"lights\": []",
            "\"lights\": [{\"direction\": [0, 0, 0], \"half_angle\": 0, \"power\": [1, 1, 1]}]",
        );
        let err = CoeffFile::from_json_str(&text, "z.json")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("z.json") && err.contains("light 0 direction"),
            "{err}"
        );
    }

    #[test]
    fn files_above_the_pretty_lmax_are_compact_with_the_same_document() {
        let at = |lmax: usize| {
            let mut file = sample_file();
            file.coeffs = ShCoeffs::from_fn(lmax, |l, m| {
                let x = (l * l) as f64 + 0.37 * m as f64;
                DVec3::new(x.sin(), 1.0 / (1.0 + x), -x.sqrt().exp())
            });
            file.std_error = None;
            file
        };
        let pretty = at(PRETTY_MAX_LMAX).to_json_string();
        assert!(
            pretty.contains("\n    ["),
            "pretty rows, one number per line"
        );
        let mut file = at(PRETTY_MAX_LMAX + 8);
        let compact = file.to_json_string();
        assert!(!compact.contains('\n') && !compact.contains(": "));
        // serde_json's own serialisation of the value tree, parsed back:
        // the same document, the same numbers.
        let parsed: Value = serde_json::from_str(&compact).unwrap();
        assert_eq!(parsed, file.to_json());
        let back = CoeffFile::from_json_str(&compact, "c.json").unwrap();
        assert_eq!(back.coeffs, file.coeffs);
        assert_eq!(back.provenance, file.provenance);
        // A non-finite coefficient is null in both, as the value tree has it.
        file.coeffs[5] = DVec3::new(f64::NAN, f64::INFINITY, 1.0);
        let parsed: Value = serde_json::from_str(&file.to_json_string()).unwrap();
        assert_eq!(parsed["coefficients"][5], json!([null, null, 1.0]));
        assert_eq!(parsed, file.to_json());
    }

    #[test]
    fn files_without_the_newer_fields_are_read() {
        // A format 1 file as the first release wrote it.
        let text = r#"{"format":"shlight-sh","format_version":1,"lmax":0,
            "frame":"y-up","mirror":false,"quantity":"radiance",
            "coefficients":[[1,2,3]],
            "provenance":{"input":"a.exr","width":8,"height":4,"layout":"equirect",
                          "method":"quadrature","window":"hanning:3"},
            "statistics":{"input_negative_texels":1,"input_min_value":-0.5}}"#;
        let f = CoeffFile::from_json_str(text, "old.json").unwrap();
        assert_eq!(f.coeffs[0], DVec3::new(1.0, 2.0, 3.0));
        assert_eq!(
            f.provenance.windows,
            ["hanning:3", "hanning:3", "hanning:3"].map(String::from)
        );
        assert_eq!(
            (
                f.provenance.samples,
                f.provenance.seed,
                &f.provenance.sampler
            ),
            (None, None, &None)
        );
        assert_eq!(f.provenance.rotate, None);
        assert_eq!((f.sanitized, f.std_error), (None, None));
        assert_eq!(f.input_negative_texels, 1);
    }

    #[test]
    fn the_table_shows_per_channel_windows_rotation_and_std_errors() {
        let table = sample_file().to_table();
        assert!(
            table.contains("windows r hanning:4, g hanning:5.5, b none")
                && table.contains("rotated yaw:90")
                && table.contains("montecarlo, 1048576 samples")
                && table.contains("std error"),
            "{table}"
        );
        assert_eq!(table.lines().count(), 3 + 16);
    }

    #[test]
    fn bad_files_are_refused_with_the_reason() {
        let err = CoeffFile::from_json_str("{", "a.json")
            .unwrap_err()
            .to_string();
        assert!(err.contains("a.json") && err.contains("JSON"), "{err}");
        let err = CoeffFile::from_json_str(
            r#"{"format":"shlight-sh","format_version":1,"lmax":1,"coefficients":[[1,2,3]]}"#,
            "b.json",
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("needs 4 coefficients"), "{err}");
    }
}
