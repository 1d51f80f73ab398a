//! The egui overlay panel of `shlight view`.

use shlight_baked::LIGHT_MAX_LMAX;
use shlight_core::encoding::Encoding;
use shlight_gpu::{Background, Mode};
use shlight_io::ToneMap;

use crate::controls::{Controls, WINDOWS};

/// What the panel shows besides the controls.
pub struct PanelInfo<'a> {
    pub fps: f64,
    pub frame_ms: f64,
    pub adapter: &'a str,
    pub coefficients: &'a shlight_core::sh::ShCoeffs<glam::DVec3>,
    pub has_map: bool,
    /// The `--prt` file's mode (`shadowed`, ...), when there is one.
    pub prt: Option<&'a str>,
    /// Lines about `--volume` (probes, relight time, object, keys).
    pub volume: &'a [String],
    /// What the encoding shown holds (empty for plain SH).
    pub encoding: &'a str,
}

/// The overlay panel; returns whether its screenshot button was pressed.
pub fn draw_panel(ctx: &egui::Context, c: &mut Controls, info: &PanelInfo<'_>) -> bool {
    let mut screenshot = false;
    egui::Window::new("shlight")
        .default_pos([10.0, 10.0])
        .resizable(false)
        .show(ctx, |ui| {
            ui.label(format!("{:.0} fps ({:.2} ms)", info.fps, info.frame_ms));
            ui.label(info.adapter);
            ui.add(egui::Slider::new(&mut c.shading.lmax, 0..=LIGHT_MAX_LMAX).text("lmax"));
            ui.horizontal(|ui| {
                ui.label("mode");
                ui.radio_value(&mut c.shading.mode, Mode::Sh, "SH irradiance");
                if let Some(prt) = info.prt {
                    ui.radio_value(&mut c.shading.mode, Mode::Prt, format!("PRT ({prt})"));
                }
                ui.radio_value(&mut c.shading.mode, Mode::Normals, "normals");
            });
            if c.shading.mode == Mode::Sh && info.volume.is_empty() {
                ui.horizontal_wrapped(|ui| {
                    ui.label("encoding (e)");
                    for e in Encoding::ALL {
                        if e != Encoding::DominantSh || info.has_map {
                            ui.radio_value(&mut c.encoding, e, e.name());
                        }
                    }
                });
                if c.encoding != Encoding::Sh && !info.encoding.is_empty() {
                    ui.label(info.encoding);
                }
            }
            ui.horizontal(|ui| {
                ui.label("background");
                ui.radio_value(&mut c.shading.background, Background::None, "none");
                if info.has_map {
                    ui.radio_value(&mut c.shading.background, Background::Map, "map");
                }
                ui.radio_value(&mut c.shading.background, Background::Sh, "SH");
            });
            ui.horizontal(|ui| {
                ui.label("window");
                for (k, (name, _)) in WINDOWS.iter().enumerate() {
                    ui.radio_value(&mut c.window_choice, k, *name);
                }
            });
            ui.add(egui::Slider::new(&mut c.shading.exposure_ev, -8.0..=8.0).text("exposure (EV)"));
            ui.horizontal(|ui| {
                ui.label("tone map");
                for tm in ToneMap::ALL {
                    ui.radio_value(&mut c.shading.tone_map, Some(tm), tm.name());
                }
            });
            ui.add(egui::Slider::new(&mut c.env_yaw, -3.2..=3.2).text("environment yaw"));
            ui.add(egui::Slider::new(&mut c.env_pitch, -1.6..=1.6).text("environment pitch"));
            for line in info.volume {
                ui.label(line);
            }
            screenshot = ui.button("screenshot (p)").clicked();
            ui.collapsing("coefficients (rotated radiance, R G B)", |ui| {
                egui::ScrollArea::vertical()
                    .max_height(220.0)
                    .show(ui, |ui| {
                        for l in 0..=c.shading.lmax.min(info.coefficients.lmax()) {
                            for m in -(l as isize)..=l as isize {
                                let v = info.coefficients[(l, m)];
                                ui.monospace(format!(
                                    "l={l} m={m:+} {:+.4} {:+.4} {:+.4}",
                                    v.x, v.y, v.z
                                ));
                            }
                        }
                    });
            });
            ui.small(
                "drag: orbit · right/shift drag, arrows: environment · 0-8 m e b w t +/- p h q",
            );
        });
    screenshot
}
