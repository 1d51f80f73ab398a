//! Triangle meshes for shlight's PRT baking and GPU rendering.
//!
//! A [`Mesh`] is an indexed triangle list with one position and one unit
//! normal per vertex (and optional per-vertex linear colours). Meshes come
//! from files ([`load`]: OBJ, PLY, OFF, glTF/GLB, each in its file's vertex
//! order) or from generators ([`generate`]: sphere, plane, box, torus, bowl,
//! plane under a sphere; and [`generate::cornell_box`], the standard test room); either way they
//! pass the same validation ([`Mesh::new`]), so code downstream may assume
//! finite positions, in-range indices, no degenerate triangles and unit
//! normals. Files are read under [`LoadOptions`] limits on the vertex and
//! triangle counts, checked before the memory is allocated, so that no
//! file makes the loader hang or allocate without bound
//! (docs/limits.md). [`Mesh::subdivided`] splits long edges (conforming)
//! for bakes that store light per vertex ([`Mesh::subdivided_with_map`]
//! also finds points of the original triangles in the subdivided ones, so
//! rays can be cast against the fewer original triangles); meshes may carry per-vertex
//! emission ([`Mesh::emission`]) from OBJ `Ke` or glTF `emissiveFactor`.
//!
//! A glTF file is also read as a [`Scene`] ([`load_scene`]): unique [`Primitive`]s placed
//! by [`Instance`]s, [`Material`]s with [`Texture`]s, and
//! [`PunctualLight`]s; [`Scene::flatten`] gives the world-space mesh with
//! each triangle's material ([`Surfaces`]), and [`Scene::flat_layout`]
//! where each instance's triangles land in it without building it
//! ([`FlatLayout`]: for ray casting over the unique primitives).
//!
//! [`write_lightmapped_glb`] rewrites a glTF scene as one GLB that keeps
//! everything it held and adds a baker's lightmaps ([`LightmapRequest`]:
//! the encoded pages, each baked node's atlas rectangle and page;
//! `MOZ_lightmap` on materials, `SHLIGHT_lightmap` on nodes and the root,
//! meshes copied per node where asked); [`read_lightmap_pages`] reads
//! them back.

pub mod cornell_box;
mod error;
mod flat_layout;
pub mod generate;
mod lightmap_pages;
mod lightmapped_glb;
mod load;
mod load_options;
mod material;
mod mesh;
mod punctual_light;
mod scene;
mod subdivide;
mod texture;

pub use error::MeshError;
pub use flat_layout::FlatLayout;
pub use lightmap_pages::{
    LightmapPages, lightmap_pages_from_bytes, read_lightmap_pages, read_lightmap_pages_if_any,
};
pub use lightmapped_glb::{
    BakedNode, LightmapImage, LightmapImageFormat, LightmapRequest, LightmappedGlb,
    lightmapped_glb, write_lightmapped_glb,
};
pub use load::{
    MeshFormat, MtlMaterial, load, load_bytes, load_bytes_with, load_scene, load_scene_bytes,
    load_with, parse_mtl_bytes,
};
pub use load_options::LoadOptions;
pub use material::{AlphaMode, Material, SurfaceSample, TextureRef};
pub use mesh::{Mesh, MeshReport};
pub use punctual_light::{Arrival, LightKind, LightUnits, PunctualLight};
pub use scene::{Instance, InstanceSource, MAX_UV_SETS, Primitive, Scene, Surfaces};
pub use subdivide::Subdivision;
pub use texture::{Filter, Texture, Wrap};
