//! shlight's coefficient file: self-describing JSON (docs/coefficient-file.md).

use anyhow::{Context, Result, bail};
use clap::ValueEnum;
use glam::DVec3;
use serde_json::{Value, json};
use shlight_core::rotation::Frame;
use shlight_core::window::sphere_minimum;
use shlight_core::{ShCoeffs, lm_from_index};

/// Version of the JSON layout written by this build.
pub const FORMAT_VERSION: u64 = 1;

/// What a coefficient file's numbers are.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Quantity {
    /// Distant radiance `L(w)`.
    Radiance,
    /// Irradiance `E(n) = A_l L_lm` (Ramamoorthi & Hanrahan 2001).
    Irradiance,
}

impl Quantity {
    fn name(self) -> &'static str {
        match self {
            Quantity::Radiance => "radiance",
            Quantity::Irradiance => "irradiance",
        }
    }
}

/// Where the coefficients came from.
#[derive(Clone, Debug, PartialEq)]
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
    /// Window applied, in `--window` spelling.
    pub window: String,
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
    /// Negative texels in the input (kept as data).
    pub input_negative_texels: usize,
    /// Smallest texel value of the input.
    pub input_min_value: f64,
}

impl CoeffFile {
    /// The JSON document (docs/coefficient-file.md).
    pub fn to_json(&self) -> Value {
        let rgb = |v: DVec3| json!([v.x, v.y, v.z]);
        let minimum: Vec<Value> = (0..3)
            .map(|c| {
                let (v, d) = sphere_minimum(&self.coeffs.channel(c));
                json!({ "value": v, "direction": d })
            })
            .collect();
        json!({
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
            "coefficients": self.coeffs.as_slice().iter().map(|v| rgb(*v)).collect::<Vec<_>>(),
            "provenance": {
                "tool": concat!("shlight ", env!("CARGO_PKG_VERSION")),
                "input": self.provenance.input,
                "width": self.provenance.width,
                "height": self.provenance.height,
                "layout": self.provenance.layout,
                "method": self.provenance.method,
                "window": self.provenance.window,
            },
            "statistics": {
                "band_power": self.coeffs.band_power().into_iter().map(rgb).collect::<Vec<_>>(),
                "minimum": { "red": minimum[0], "green": minimum[1], "blue": minimum[2] },
                "input_negative_texels": self.input_negative_texels,
                "input_min_value": self.input_min_value,
            },
        })
    }

    /// Pretty-printed JSON.
    pub fn to_json_string(&self) -> String {
        serde_json::to_string_pretty(&self.to_json()).expect("JSON values serialise")
    }

    /// Reads a coefficient file's text; `name` is used in error messages.
    pub fn from_json_str(text: &str, name: &str) -> Result<Self> {
        let v: Value =
            serde_json::from_str(text).with_context(|| format!("{name}: not valid JSON"))?;
        let field = |k: &str| {
            v.get(k)
                .with_context(|| format!("{name}: missing field \"{k}\""))
        };
        if field("format")?.as_str() != Some("shlight-sh") {
            bail!("{name}: not a shlight coefficient file (\"format\" is not \"shlight-sh\")");
        }
        let version = field("format_version")?.as_u64().unwrap_or(0);
        if version == 0 || version > FORMAT_VERSION {
            bail!(
                "{name}: format_version {version} is not supported (this build reads 1..={FORMAT_VERSION})"
            );
        }
        let lmax = field("lmax")?
            .as_u64()
            .with_context(|| format!("{name}: \"lmax\" is not an integer"))?
            as usize;
        let rows = field("coefficients")?
            .as_array()
            .with_context(|| format!("{name}: \"coefficients\" is not an array"))?;
        if rows.len() != (lmax + 1) * (lmax + 1) {
            bail!(
                "{name}: lmax {lmax} needs {} coefficients, the file has {}",
                (lmax + 1) * (lmax + 1),
                rows.len()
            );
        }
        let mut coeffs = Vec::with_capacity(rows.len());
        for (i, row) in rows.iter().enumerate() {
            let c: Option<Vec<f64>> = row
                .as_array()
                .map(|a| a.iter().filter_map(Value::as_f64).collect());
            match c.as_deref() {
                Some([r, g, b]) => coeffs.push(DVec3::new(*r, *g, *b)),
                _ => {
                    let (l, m) = lm_from_index(i);
                    bail!("{name}: coefficient {i} (l={l}, m={m}) is not three numbers");
                }
            }
        }
        let frame = field("frame")?
            .as_str()
            .unwrap_or("")
            .parse::<Frame>()
            .map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        let quantity = match field("quantity")?.as_str() {
            Some("radiance") => Quantity::Radiance,
            Some("irradiance") => Quantity::Irradiance,
            other => bail!("{name}: unknown quantity {other:?}"),
        };
        let p = field("provenance")?;
        let s = |k: &str| p.get(k).and_then(Value::as_str).unwrap_or("").to_string();
        let n = |k: &str| p.get(k).and_then(Value::as_u64).unwrap_or(0) as usize;
        let stats = v.get("statistics");
        Ok(Self {
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
                window: s("window"),
            },
            input_negative_texels: stats
                .and_then(|s| s.get("input_negative_texels"))
                .and_then(Value::as_u64)
                .unwrap_or(0) as usize,
            input_min_value: stats
                .and_then(|s| s.get("input_min_value"))
                .and_then(Value::as_f64)
                .unwrap_or(0.0),
        })
    }

    /// A readable table: a header naming what the numbers are, then one
    /// coefficient per line.
    pub fn to_table(&self) -> String {
        let mut s = format!(
            "# shlight SH {}: lmax {} ({} coefficients), real orthonormal basis with Condon-Shortley phase,\n\
             # index l*(l+1)+m, frame {}{}, linear Rec.709 RGB; from {} ({}x{} {}, {}, window {})\n",
            self.quantity.name(),
            self.coeffs.lmax(),
            self.coeffs.len(),
            self.frame,
            if self.mirror { " (mirrored)" } else { "" },
            self.provenance.input,
            self.provenance.width,
            self.provenance.height,
            self.provenance.layout,
            self.provenance.method,
            self.provenance.window,
        );
        s.push_str("#  l   m           red         green          blue\n");
        for (i, v) in self.coeffs.as_slice().iter().enumerate() {
            let (l, m) = lm_from_index(i);
            s.push_str(&format!(
                "{l:4} {m:3} {:13.6e} {:13.6e} {:13.6e}\n",
                v.x, v.y, v.z
            ));
        }
        s
    }
}

/// `shlight show FILE`: reads a coefficient file and prints its table.
pub fn show(path: &std::path::Path) -> Result<()> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).with_context(|| format!("{name}: cannot read"))?;
    print!("{}", CoeffFile::from_json_str(&text, &name)?.to_table());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_round_trips() {
        let coeffs = ShCoeffs::from_fn(3, |l, m| {
            DVec3::new(l as f64, m as f64 * 0.5, 0.125 + l as f64)
        });
        let file = CoeffFile {
            coeffs,
            frame: Frame::ZUp,
            mirror: true,
            quantity: Quantity::Irradiance,
            provenance: Provenance {
                input: "x.exr".into(),
                width: 64,
                height: 32,
                layout: "equirect".into(),
                method: "quadrature".into(),
                window: "hanning:4".into(),
            },
            input_negative_texels: 3,
            input_min_value: -0.004,
        };
        let back = CoeffFile::from_json_str(&file.to_json_string(), "t.json").unwrap();
        assert_eq!(back.coeffs, file.coeffs);
        assert_eq!(back.frame, Frame::ZUp);
        assert!(back.mirror);
        assert_eq!(back.quantity, Quantity::Irradiance);
        assert_eq!(back.provenance, file.provenance);
        assert_eq!(back.input_negative_texels, 3);
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
