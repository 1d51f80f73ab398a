//! Environment-map layouts (equirect, cube cross, strip, angular map, mirror
//! ball): their geometry, stated on [`Layout`](crate::map::Layout). The
//! layout itself and its errors (`kind.rs`), cube faces and their solid
//! angles (`cube.rs`), the disc layouts' mappings and solid angles
//! (`disc.rs`), texel directions, solid angles and inverse lookups shared
//! inside the crate (`geometry.rs`), the borrowed [`EnvMap`](crate::map::EnvMap)
//! (`env_map.rs`) and the pixel-free [`TexelGrid`](crate::map::TexelGrid)
//! (`texel_grid.rs`).

pub(crate) mod cube;
pub(crate) mod disc;
pub(crate) mod env_map;
pub(crate) mod geometry;
pub(crate) mod kind;
pub(crate) mod texel_grid;
