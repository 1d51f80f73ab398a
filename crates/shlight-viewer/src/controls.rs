//! What the panel and keys of `shlight view` change.

use glam::DMat3;
use shlight_core::encoding::Encoding;
use shlight_core::sh::Window;
use shlight_gpu::Shading;

/// What the panel and keys change.
pub struct Controls {
    pub shading: Shading,
    /// Environment rotation: yaw about +Y, then pitch about +X (radians).
    pub env_yaw: f64,
    pub env_pitch: f64,
    pub window_choice: usize,
    /// The light's encoding in SH mode (`e`); plain SH draws by `Mode::Sh`.
    pub encoding: Encoding,
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

    /// The next encoding `e` offers after `current` (`dominant+sh` only
    /// with a map: its lights are found among the texels).
    pub fn next_encoding(current: Encoding, has_map: bool) -> Encoding {
        let all = Encoding::ALL;
        let at = all.iter().position(|&e| e == current).unwrap_or(0);
        (1..=all.len())
            .map(|k| all[(at + k) % all.len()])
            .find(|&e| has_map || e != Encoding::DominantSh)
            .unwrap_or(Encoding::Sh)
    }

    pub fn rotation(&self) -> DMat3 {
        DMat3::from_rotation_x(self.env_pitch) * DMat3::from_rotation_y(self.env_yaw)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn e_cycles_every_encoding_and_skips_dominant_lights_without_a_map() {
        for has_map in [true, false] {
            let mut seen = Vec::new();
            let mut e = Encoding::Sh;
            for _ in 0..Encoding::ALL.len() {
                e = Controls::next_encoding(e, has_map);
                seen.push(e);
            }
            let want: Vec<Encoding> = Encoding::ALL
                .into_iter()
                .filter(|&x| has_map || x != Encoding::DominantSh)
                .collect();
            let mut sorted = seen.clone();
            sorted.sort_by_key(|x| Encoding::ALL.iter().position(|y| y == x));
            sorted.dedup();
            assert_eq!(sorted, want, "has_map {has_map}: {seen:?}");
            assert_eq!(
                seen[0],
                if has_map {
                    Encoding::DominantSh
                } else {
                    Encoding::SloanSh
                }
            );
        }
    }
}
