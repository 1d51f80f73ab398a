//! [`ViewerError`]: why the window could not show a scene.

use std::path::PathBuf;

use shlight_gpu::{GpuError, SceneError};

/// Why the viewer stopped with an error.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ViewerError {
    /// Options that do not go together, named as the front end spells
    /// them.
    #[error("{0}")]
    Refused(String),
    /// No display to open a window on.
    #[error("cannot open a window ({0}); is a display available (DISPLAY)?")]
    NoDisplay(String),
    /// The window could not be created.
    #[error("cannot create a window")]
    Window(#[source] winit::error::OsError),
    /// The window's surface cannot be drawn into.
    #[error("cannot draw into the window: {0}")]
    Surface(String),
    /// The window's surface offers no format the adapter renders to.
    #[error("the window's surface offers no format")]
    NoSurfaceFormat,
    /// The window's surface and the adapter do not work together.
    #[error("the window's surface does not work with {0}")]
    SurfaceAdapter(String),
    /// The event loop failed.
    #[error("window event loop: {0}")]
    EventLoop(String),
    /// The GPU failed while drawing.
    #[error(transparent)]
    Gpu(#[from] GpuError),
    /// The scene's renderers could not be made.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The light could not be encoded.
    #[error(transparent)]
    Light(#[from] shlight_pipeline::PipelineError),
    /// A screenshot could not be read back.
    #[error("screenshot")]
    ScreenshotRead(#[source] GpuError),
    /// A screenshot could not be written.
    #[error("{}: writing the screenshot", path.display())]
    ScreenshotWrite {
        /// The PNG file.
        path: PathBuf,
        /// The writer's reason.
        source: shlight_io::IoError,
    },
}
