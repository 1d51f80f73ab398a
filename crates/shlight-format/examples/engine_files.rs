//! An environment's SH lighting to a three.js LightProbe and Unity's
//! SphericalHarmonicsL2, from Rust, without the command line.
//!
//! ```sh
//! cargo run -p shlight-format --example engine_files -- OUT_DIR
//! ```
//!
//! The light is built from closed forms (a sun and a sky) so the example
//! needs no map; with a map, project it with `shlight-core` and fill a
//! [`CoeffFile`] the same way.

use std::path::PathBuf;

use glam::DVec3;
use shlight_core::sh::{Frame, closed_form};
use shlight_format::{CoeffFile, ExportFormat, Quantity, export};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| ".".into()));
    std::fs::create_dir_all(&dir)?;
    // Radiance coefficients to lmax 2 in shlight's y-up frame: a warm sun
    // high in the -Z half of the sky over a dim blue sky.
    let sun = DVec3::new(0.3, 0.8, -0.5).normalize();
    let light = &closed_form::directional(2, sun, DVec3::new(3.0, 2.8, 2.5))
        + &closed_form::constant(2, DVec3::new(0.15, 0.2, 0.3));
    let mut file = CoeffFile::new(light, Frame::YUp, Quantity::Radiance);
    file.provenance.input = "a sun and a sky (closed form)".into();
    file.write(&dir.join("light.json"))?;
    for (format, name) in [
        (ExportFormat::Threejs, "probe.json"),
        (ExportFormat::Unity, "unity.json"),
    ] {
        let out = export(&file, format)?;
        for note in &out.notes {
            eprintln!("note: {note}");
        }
        let path = dir.join(name);
        shlight_io::write_atomically(&path, |w| w.write_all(out.text.as_bytes()))?;
        println!("{} -> {}", format, path.display());
    }
    Ok(())
}
