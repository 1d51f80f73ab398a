//! `shlight.Scene`: a glTF scene loaded once (`shlight.load_scene`), what a
//! user inspects of it (primitives, instances, triangles, materials,
//! punctual lights), and passed wherever a scene path is taken
//! (`bake_volume`, `bake_transfer`, `sample`'s `points`).

use std::path::PathBuf;
use std::sync::Arc;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use shlight_mesh::{AlphaMode, LightKind, LoadOptions, MeshFormat};

use crate::errors::{chained, shlight_error};
use crate::guard::guard;

/// A glTF scene (`.gltf`, `.glb`) read once: its unique primitives, the
/// instances that place them, its materials and its punctual lights
/// (`KHR_lights_punctual`), as `shlight volume` and `shlight prt` read it.
#[pyclass(name = "Scene", module = "shlight", frozen)]
pub struct Scene {
    pub scene: Arc<shlight_mesh::Scene>,
}

/// A scene argument: a path, or a `Scene` loaded already.
#[derive(FromPyObject)]
pub enum SceneArg {
    Loaded(Py<Scene>),
    Path(PathBuf),
}

impl SceneArg {
    /// The path (a loaded scene's source), and the loaded scene if any.
    pub fn split(&self, py: Python<'_>) -> (PathBuf, Option<Arc<shlight_mesh::Scene>>) {
        match self {
            SceneArg::Path(p) => (p.clone(), None),
            SceneArg::Loaded(s) => {
                let scene = s.bind(py).get().scene.clone();
                (scene.source.clone(), Some(scene))
            }
        }
    }
}

/// load_scene(path) -> Scene
/// --
///
/// See the package documentation (`help(shlight.load_scene)`).
#[pyfunction]
pub fn load_scene(py: Python<'_>, path: PathBuf) -> PyResult<Scene> {
    if MeshFormat::from_path(&path) != Some(MeshFormat::Gltf) {
        return Err(shlight_error(format!(
            "{}: a scene is a glTF file (.gltf, .glb); a mesh is read by path",
            path.display()
        )));
    }
    let scene = py.detach(|| {
        guard(|| shlight_mesh::load_scene(&path, &LoadOptions::default()).map_err(|e| chained(&e)))
    })?;
    Ok(Scene {
        scene: Arc::new(scene),
    })
}

#[pymethods]
impl Scene {
    /// The file it was read from.
    #[getter]
    fn path(&self) -> PathBuf {
        self.scene.source.clone()
    }

    /// Unique primitives (each a mesh with one material).
    #[getter]
    fn primitive_count(&self) -> usize {
        self.scene.primitives.len()
    }

    /// Instances: placements of a primitive by a node's world transform.
    #[getter]
    fn instance_count(&self) -> usize {
        self.scene.instances.len()
    }

    /// Triangles of the flattened scene (each instance's own).
    #[getter]
    fn triangle_count(&self) -> usize {
        let s = &self.scene;
        s.instances
            .iter()
            .map(|i| s.primitives[i.primitive].mesh.triangle_count())
            .sum()
    }

    /// Vertices of the flattened scene: what a `.shprt` file baked from it
    /// and `sample(points=scene)` count.
    #[getter]
    fn vertex_count(&self) -> usize {
        let s = &self.scene;
        s.instances
            .iter()
            .map(|i| s.primitives[i.primitive].mesh.vertex_count())
            .sum()
    }

    /// The materials: dicts of "name", "base_color" (linear RGBA factor),
    /// "base_color_texture" (bool), "emissive" (linear RGB factor),
    /// "alpha_mode" ("opaque", "mask", "blend"), "alpha_cutoff" (a mask's,
    /// else None), "double_sided".
    #[getter]
    fn materials<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let mut out = Vec::new();
        for m in &self.scene.materials {
            let d = PyDict::new(py);
            d.set_item("name", m.name.clone())?;
            d.set_item("base_color", m.base_color.to_array())?;
            d.set_item("base_color_texture", m.base_color_texture.is_some())?;
            d.set_item("emissive", m.emissive.to_array())?;
            let (mode, cutoff) = match m.alpha_mode {
                AlphaMode::Opaque => ("opaque", None),
                AlphaMode::Mask { cutoff } => ("mask", Some(cutoff)),
                AlphaMode::Blend => ("blend", None),
            };
            d.set_item("alpha_mode", mode)?;
            d.set_item("alpha_cutoff", cutoff)?;
            d.set_item("double_sided", m.double_sided)?;
            out.push(d);
        }
        Ok(out)
    }

    /// The punctual lights in world space: dicts of "name", "kind"
    /// ("point", "spot", "directional"), "color" (linear RGB), "intensity"
    /// as written in "units" ("cd" for point and spot lights, "lux" for
    /// directional ones; the bakes' `light_units` say how they are read),
    /// "range" (None: infinite), "position", "direction", and a spot's
    /// "inner_cone" and "outer_cone" (radians).
    #[getter]
    fn lights<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let mut out = Vec::new();
        for l in &self.scene.lights {
            let d = PyDict::new(py);
            d.set_item("name", l.name.clone())?;
            let (kind, units) = match l.kind {
                LightKind::Point => ("point", "cd"),
                LightKind::Spot {
                    inner_cone,
                    outer_cone,
                } => {
                    d.set_item("inner_cone", inner_cone)?;
                    d.set_item("outer_cone", outer_cone)?;
                    ("spot", "cd")
                }
                LightKind::Directional => ("directional", "lux"),
            };
            d.set_item("kind", kind)?;
            d.set_item("color", l.color.to_array())?;
            d.set_item("intensity", l.intensity)?;
            d.set_item("units", units)?;
            d.set_item("range", l.range)?;
            d.set_item("position", l.position.to_array())?;
            d.set_item("direction", l.direction.to_array())?;
            out.push(d);
        }
        Ok(out)
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene(path={:?}, primitives={}, instances={}, triangles={}, materials={}, lights={})",
            self.scene.source.display().to_string(),
            self.primitive_count(),
            self.instance_count(),
            self.triangle_count(),
            self.scene.materials.len(),
            self.scene.lights.len()
        )
    }
}

/// Runs a bake whose scene Python gave as a path or as a loaded `Scene`,
/// off the GIL and guarded against panics: `of_scene` on the loaded scene,
/// `of_path` (reading the plan's path) otherwise; the bake's warnings then
/// become Python warnings.
pub fn bake_scene_arg<T: Send>(
    py: Python<'_>,
    loaded: Option<&shlight_mesh::Scene>,
    of_path: impl FnOnce(&crate::hooks::PyHooks) -> shlight_pipeline::Result<T> + Send,
    of_scene: impl FnOnce(&shlight_mesh::Scene, &crate::hooks::PyHooks) -> shlight_pipeline::Result<T>
    + Send,
) -> PyResult<T> {
    let hooks = crate::hooks::PyHooks::new(false);
    let baked = py.detach(|| {
        guard(|| {
            match loaded {
                Some(scene) => of_scene(scene, &hooks),
                None => of_path(&hooks),
            }
            .map_err(crate::errors::pipeline_error)
        })
    });
    crate::errors::warn_all(py, &hooks.warnings(), 2)?;
    baked
}
