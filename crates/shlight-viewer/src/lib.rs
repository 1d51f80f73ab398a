//! The window of `shlight view`: winit events, the wgpu surface,
//! shlight-gpu's renderers and an egui overlay, on a scene shlight-gpu
//! read and checked ([`shlight_gpu::Scene`]).
//!
//! - [`run`]: opens the window on a [`Scene`] with the [`ViewerOptions`]
//!   and runs its event loop until it closes (or, with `screenshot`, until
//!   the frame is saved). Left drag orbits the camera (shlight-gpu's
//!   `OrbitCamera`), right drag (or shift + left drag, or the arrow keys)
//!   turns the environment: its radiance coefficients rotated on the CPU
//!   every frame (`ShRotation`, lmax 8) and the map background with them.
//!   Keys: `0`-`8` lmax, `m` mode, `e` the light's encoding (each compiled
//!   into the fragment shader as its WGSL snippet, the normal turned back
//!   by the environment's rotation), `b` background, `w` window, `t` tone
//!   map, `+`/`-` exposure, `p` screenshot, `h` panel, `Esc`/`q` quit;
//!   with a volume (relit every frame under the turned environment, or
//!   kept as stored), `j`/`l`, `u`/`o`, `i`/`k` move the object and `g`
//!   shows the probes.
//! - [`ViewerOptions::check`] refuses options that do not go together,
//!   naming them as the front end spells them.
//!
//! Files: `app.rs` (the window, the surface and the event loop),
//! `controls.rs` (what the panel and keys change), `panel.rs` (the egui
//! overlay), `screenshot.rs` (the swapchain image read back to PNG),
//! `view_volume.rs` (the volume in the window), `viewer_error.rs`.
//!
//! **Architecture invariant:** only the window: no command line (options
//! come in as values, nothing is printed but a saved screenshot's name),
//! no file read, no scene rule (shlight-gpu's `Scene` holds them).

mod app;
mod controls;
mod panel;
mod screenshot;
mod view_volume;
mod viewer_error;

use std::path::PathBuf;

use shlight_gpu::Scene;
use shlight_io::ToneMap;
use shlight_pipeline::Spelling;

pub use viewer_error::ViewerError;

/// How the window starts (each can be changed in it but the size); the
/// lmax, encoding and albedo shown first are the [`Scene`]'s.
#[derive(Clone, Debug)]
pub struct ViewerOptions {
    /// Exposure in stops at start.
    pub exposure: f32,
    /// Tone map at start.
    pub tone_map: ToneMap,
    /// Window size in pixels, `(width, height)`.
    pub size: (usize, usize),
    /// Render `frames` frames, save the last to this PNG and close.
    pub screenshot: Option<PathBuf>,
    /// Frames rendered before `screenshot` saves.
    pub frames: u32,
    /// Start with the overlay panel hidden.
    pub hide_panel: bool,
}

impl ViewerOptions {
    /// Refuses no frames, and a screenshot that is not a PNG file.
    ///
    /// # Errors
    /// As above, naming the option as `spelling` does.
    pub fn check(&self, spelling: Spelling) -> Result<(), ViewerError> {
        if self.frames == 0 {
            return Err(ViewerError::Refused(format!(
                "{} must be at least 1",
                spelling.option("frames")
            )));
        }
        if let Some(path) = &self.screenshot
            && !path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("png"))
        {
            return Err(ViewerError::Refused(format!(
                "{}: {} writes PNG files",
                path.display(),
                spelling.option("screenshot")
            )));
        }
        Ok(())
    }
}

/// Opens the window and runs its event loop until it closes.
///
/// # Errors
/// No display to open a window on, no GPU adapter, a failure while
/// rendering or saving a screenshot.
pub fn run(options: &ViewerOptions, scene: Scene) -> Result<(), ViewerError> {
    use winit::event_loop::{ControlFlow, EventLoop};

    let event_loop = EventLoop::new().map_err(|e| ViewerError::NoDisplay(e.to_string()))?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = app::App::new(options, scene);
    event_loop
        .run_app(&mut app)
        .map_err(|e| ViewerError::EventLoop(e.to_string()))?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_are_refused_in_the_front_ends_spelling() {
        let options = ViewerOptions {
            exposure: 0.0,
            tone_map: ToneMap::Aces,
            size: (64, 48),
            screenshot: Some("shot.jpg".into()),
            frames: 3,
            hide_panel: false,
        };
        let message = |o: &ViewerOptions, s| o.check(s).unwrap_err().to_string();
        assert_eq!(
            message(&options, Spelling::CommandLine),
            "shot.jpg: --screenshot writes PNG files"
        );
        assert_eq!(
            message(&options, Spelling::Python),
            "shot.jpg: screenshot writes PNG files"
        );
        let none = ViewerOptions {
            frames: 0,
            ..options.clone()
        };
        assert_eq!(
            message(&none, Spelling::CommandLine),
            "--frames must be at least 1"
        );
        let fine = ViewerOptions {
            screenshot: Some("shot.PNG".into()),
            ..options
        };
        assert!(fine.check(Spelling::CommandLine).is_ok());
    }
}
