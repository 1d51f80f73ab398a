//! What the integration tests share.

use glam::Vec3;
use rand::{Rng, rngs::StdRng};

/// A random unit vector, uniform over the sphere (rejection sampling in
/// the cube, the centre's neighbourhood left out).
pub fn random_unit(rng: &mut StdRng) -> Vec3 {
    loop {
        let v = Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
            return v.normalize();
        }
    }
}
