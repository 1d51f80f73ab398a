//! The map wing (placeholder doc).

pub mod montecarlo;

pub(crate) mod analytic_light;
pub(crate) mod cube_faces;
pub(crate) mod directional_texels;
pub(crate) mod equirect;
pub(crate) mod irradiance_map;
pub(crate) mod layout;
pub(crate) mod orientation;
pub(crate) mod projection;
pub(crate) mod radiance_map;
pub(crate) mod render;
pub(crate) mod strided_image;
pub(crate) mod texel_means;
pub(crate) mod texel_source;

pub use analytic_light::AnalyticLight;
pub use cube_faces::CubeFaces;
pub use directional_texels::{DirectionalDrawing, DirectionalTexels, directional_texels};
pub use equirect::{EquirectView, equirect_angles, equirect_direction, equirect_row_solid_angle};
pub use irradiance_map::{TexelSet, irradiance_brute_force};
pub use layout::cube::{CubeFace, FaceCell, cube_texel_solid_angle};
pub use layout::env_map::EnvMap;
pub use layout::kind::{Layout, LayoutSizeError, LayoutSizeErrorKind, ParseLayoutError};
pub use layout::texel_grid::TexelGrid;
pub use orientation::MapOrientation;
pub use projection::equirect_simple::project_equirect_simple;
pub use projection::pole::to_frame;
pub use projection::{project, project_equirect, project_map};
pub use radiance_map::{RadianceMap, luminance};
pub use render::{render_coefficients, render_map};
pub use strided_image::StridedImage;
pub use texel_means::texel_means;
pub use texel_source::TexelSource;
