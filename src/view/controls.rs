//! What the panel and keys of `shlight view` change.

use glam::DMat3;
use shlight_core::Window;
use shlight_gpu::Shading;

/// What the panel and keys change.
pub struct Controls {
    pub shading: Shading,
    /// Environment rotation: yaw about +Y, then pitch about +X (radians).
    pub env_yaw: f64,
    pub env_pitch: f64,
    pub window_choice: usize,
    pub show_panel: bool,
}

/// The windows offered by the `w` key and the panel.
pub const WINDOWS: [(&str, Window); 3] = [
    ("none", Window::None),
    ("hanning", Window::Hanning { w: 0.0 }),
    ("lanczos", Window::Lanczos { w: 0.0 }),
];

impl Controls {
    /// The chosen window, of width lmax + 1 (it reaches zero past lmax).
    pub fn window(&self) -> Window {
        let width = (self.shading.lmax + 1) as f64;
        match WINDOWS[self.window_choice].1 {
            Window::Hanning { .. } => Window::Hanning { w: width },
            Window::Lanczos { .. } => Window::Lanczos { w: width },
            w => w,
        }
    }

    pub fn rotation(&self) -> DMat3 {
        DMat3::from_rotation_x(self.env_pitch) * DMat3::from_rotation_y(self.env_yaw)
    }
}
