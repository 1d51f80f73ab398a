//! [`Scene`]: what `render-mesh` and `view` shade, read from its files and
//! checked against them ([`Scene::read`]).

use std::path::PathBuf;

use glam::{DMat3, DVec3};
use shlight_baked::LIGHT_MAX_LMAX;
use shlight_core::encoding::Encoding;
use shlight_core::sh::{ShCoeffs, ShRotation};
use shlight_format::ShprtFile;
use shlight_mesh::Mesh;
use shlight_pipeline::{Environment, LightmapAtlas, Spelling, node_scale_offset};

use shlight_pipeline::{Hooks, Progress};

use super::scene_options::refuse;
use super::transfer_file::read_transfer;
use super::{
    BuiltIn, GltfScene, SceneError, SceneGeometry, SceneSettings, SceneVolume, VolumeLight,
};
use crate::{Background, Mode};

/// The albedo of surfaces without colours or a material when none is asked.
const DEFAULT_ALBEDO: [f32; 3] = [0.8; 3];

/// A mesh with its PRT transfer, the light (an environment map or a
/// coefficient file, to lmax [`LIGHT_MAX_LMAX`]), and an irradiance volume
/// with an object moved through it; each setting resolved.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The mesh (a glTF scene's flattening, [`GltfScene::surfaces`]).
    pub mesh: Mesh,
    /// A glTF file's scene, drawn with its materials, textures and
    /// instances; `None` for the other formats.
    pub gltf: Option<GltfScene>,
    /// What the mesh is called in messages: its path, or the built-in
    /// mesh's name.
    pub mesh_name: PathBuf,
    /// Its PRT transfer, checked against the mesh.
    pub transfer: Option<ShprtFile>,
    /// The light as read (not turned).
    pub light: Environment,
    /// The light's turn (identity without one): a light from `a` comes
    /// from `R a`; the map background turns with it.
    pub rotation: DMat3,
    /// What the mesh shows: [`Mode::Sh`], [`Mode::Prt`] or
    /// [`Mode::Normals`].
    pub mode: Mode,
    /// The light's encoding (in SH mode).
    pub encoding: Encoding,
    /// The lmax shaded: as asked; else the volume's (at most
    /// [`shlight_baked::SHADED_MAX_LMAX`]); in PRT mode the transfer's (at
    /// most [`LIGHT_MAX_LMAX`]); else 2.
    pub lmax: usize,
    /// The albedo asked for ([`Scene::albedo`] resolves it per mode).
    pub albedo: Option<[f32; 3]>,
    /// Behind the mesh.
    pub background: Background,
    /// An irradiance volume lighting the mesh and an object moved through
    /// it; the mesh is then drawn by the volume's pass.
    pub volume: Option<SceneVolume>,
    /// How the front end names its settings.
    pub spelling: Spelling,
    /// A lightmapped scene's lightmap, when the scene is drawn by it
    /// ([`SceneOptions::wants_lightmap`](crate::SceneOptions::wants_lightmap)).
    pub lightmap: Option<SceneLightmap>,
}

/// A lightmapped scene's lightmap as the renderer draws it: its atlas and
/// each instance's `scaleOffset` (`[0; 4]` for an instance of a node the
/// lightmap skipped).
#[derive(Clone, Debug)]
pub struct SceneLightmap {
    /// The texel format and the pages.
    pub atlas: LightmapAtlas,
    /// Per instance of the glTF scene, its node's `scaleOffset`.
    pub instances: Vec<[f32; 4]>,
}

impl SceneLightmap {
    /// The lightmap of `gltf`, read from `path`, when the file holds one
    /// (a GLB with a root `SHLIGHT_lightmap`).
    ///
    /// # Errors
    /// A lightmap shlight cannot read (its pages, a node's `scaleOffset`),
    /// or a scene whose instances are not placed by nodes.
    pub fn read(path: &std::path::Path, gltf: &GltfScene) -> Result<Option<Self>, SceneError> {
        let Some(pages) = shlight_mesh::read_lightmap_pages_if_any(path)? else {
            return Ok(None);
        };
        let name = path.display().to_string();
        let atlas = LightmapAtlas::new(&name, &pages)?;
        let scene = &gltf.scene;
        if scene.instance_sources.len() != scene.instances.len() {
            return refuse(format!("{name}: its instances are not placed by nodes"));
        }
        let instances = scene
            .instance_sources
            .iter()
            .map(|source| match pages.nodes.get(&source.node) {
                Some(ext) => node_scale_offset(&name, source.node, ext),
                None => Ok([0.0; 4]),
            })
            .collect::<Result<_, _>>()?;
        Ok(Some(Self { atlas, instances }))
    }
}

impl Scene {
    /// Reads the files `settings` name (the built-in mesh and map where
    /// none is named, the built-in mesh as a volume's object) and checks
    /// what needs them:
    ///
    /// 1. the mesh; the transfer, baked for it; the volume and its object
    ///    (a warning when the volume was baked in another scene);
    /// 2. the light (its reader's warnings passed on); `dominant+sh`
    ///    finds its lights among a map's texels, and a map background needs
    ///    a map;
    /// 3. a static volume cannot be turned.
    ///
    /// # Errors
    /// A file that cannot be read or does not fit, naming it, or a setting
    /// the files refuse, named as `settings.spelling` does.
    pub fn read(
        settings: &SceneSettings,
        built_in: &BuiltIn<'_>,
        hooks: &dyn Hooks,
    ) -> Result<Self, SceneError> {
        let (options, spelling) = (&settings.options, settings.spelling);
        hooks.progress(Progress::Step(if options.volume.is_some() {
            "reading the scene"
        } else {
            "reading the mesh"
        }));
        let default_albedo = options.albedo.unwrap_or(DEFAULT_ALBEDO);
        let (mesh, mesh_name, gltf) = match &options.mesh {
            Some(path) => match GltfScene::read(path, default_albedo)? {
                Some(gltf) => (gltf.mesh().clone(), path.clone(), Some(gltf)),
                None => (shlight_mesh::load(path)?, path.clone(), None),
            },
            None => (built_in.mesh()?, PathBuf::from(built_in.mesh_name), None),
        };
        let transfer = match &options.prt {
            Some(path) => Some(read_transfer(path, &mesh, &mesh_name)?),
            None => None,
        };
        let volume = match &options.volume {
            Some(path) => Some(SceneVolume::read(
                path,
                options,
                (&mesh, &mesh_name),
                built_in,
                hooks,
            )?),
            None => None,
        };
        let lightmap = match (&gltf, &options.mesh) {
            (Some(gltf), Some(path)) if options.wants_lightmap() => {
                SceneLightmap::read(path, gltf)?
            }
            _ => None,
        };
        if options.lightmap && lightmap.is_none() {
            return refuse(format!(
                "{}: {} draws a scene by its lightmap, and it holds none (no SHLIGHT_lightmap: bake one with shlight lightmap)",
                mesh_name.display(),
                spelling.option("lightmap")
            ));
        }
        hooks.progress(Progress::Step("reading the environment"));
        let light = match (&options.env, &lightmap) {
            (Some(path), _) => Environment::load(path, options.up, LIGHT_MAX_LMAX)?,
            // A lightmap and no light: the nodes it skipped are black.
            (None, Some(_)) => Environment {
                path: PathBuf::from("no light"),
                radiance: ShCoeffs::zeros(LIGHT_MAX_LMAX),
                map: None,
                orientation: Default::default(),
                warnings: Vec::new(),
            },
            (None, None) => built_in.environment(options.up, LIGHT_MAX_LMAX)?,
        };
        light.warnings.iter().for_each(|w| hooks.warn(w));
        let has_map = light.map.is_some();
        let name = light.path.display();
        if options.encoding == Encoding::DominantSh && !has_map {
            return refuse(format!(
                "{} finds its lights among a map's texels; {name} holds coefficients (pass the map, or use {})",
                spelling.option_value("encoding", Encoding::DominantSh.name()),
                spelling.option_value("encoding", Encoding::SloanSh.name())
            ));
        }
        let background = match options.background {
            Some(Background::Map) if !has_map => {
                return refuse(format!(
                    "{} needs an environment map; {name} holds coefficients (use {})",
                    spelling.option_value("background", Background::Map.name()),
                    spelling.option_value("background", Background::Sh.name())
                ));
            }
            Some(background) => background,
            None if has_map => Background::Map,
            None if options.env.is_none() && lightmap.is_some() => Background::None,
            None => Background::Sh,
        };
        if let Some(v) = &volume
            && v.light() == VolumeLight::Stored
            && options.rotate.is_some()
        {
            return refuse(format!(
                "{}: baked {} (no transfer matrices), so {} cannot relight it; bake it without {}",
                v.path.display(),
                spelling.option("static"),
                spelling.option("rotate"),
                spelling.option("static")
            ));
        }
        let lmax = options.lmax.unwrap_or(match (&volume, &transfer) {
            (Some(v), _) => v.shaded_lmax(),
            (None, Some(t)) if settings.mode == Mode::Prt => t.lmax.min(LIGHT_MAX_LMAX),
            _ => 2,
        });
        Ok(Self {
            mesh,
            gltf,
            mesh_name,
            transfer,
            light,
            rotation: settings.rotation,
            mode: settings.mode,
            encoding: options.encoding,
            lmax,
            albedo: options.albedo,
            background,
            volume,
            spelling,
            lightmap,
        })
    }

    /// The albedo in `mode`: as asked, else none in PRT mode with a glossy
    /// file (its glossy layer alone), else 0.8 each.
    #[must_use]
    pub fn albedo(&self, mode: Mode) -> [f32; 3] {
        let glossy = self.transfer.as_ref().is_some_and(|t| t.glossy.is_some());
        match self.albedo {
            Some(albedo) => albedo,
            None if mode == Mode::Prt && glossy => [0.0; 3],
            None => DEFAULT_ALBEDO,
        }
    }

    /// What the passes draw as the scene: the glTF scene, else the mesh.
    #[must_use]
    pub fn geometry(&self) -> SceneGeometry<'_> {
        match &self.gltf {
            Some(gltf) => SceneGeometry::Gltf(gltf),
            None => SceneGeometry::Mesh(&self.mesh),
        }
    }

    /// The light's radiance turned by `rotation`.
    #[must_use]
    pub fn turned_radiance(&self, rotation: DMat3) -> ShCoeffs<DVec3> {
        let radiance = &self.light.radiance;
        ShRotation::from_mat3(radiance.lmax(), rotation).apply(radiance)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SceneOptions;
    use shlight_core::sh::{Frame, closed_form};
    use shlight_format::{CoeffFile, Quantity};
    use shlight_pipeline::Spelling::{CommandLine, Python};
    use std::path::Path;

    /// No built-in files: every scene below names its own.
    const NONE: BuiltIn<'static> = BuiltIn {
        mesh_name: "none.obj",
        mesh_obj: b"",
        map_name: "none.exr",
        map: b"",
    };

    /// The Cornell box under a coefficient file (no map) named `name`.
    fn options(name: &str) -> SceneOptions {
        let dir = std::env::temp_dir().join(format!("shlight-gpu-scene-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let light = dir.join(name);
        let file = CoeffFile::new(
            closed_form::constant(1, DVec3::ONE),
            Frame::YUp,
            Quantity::Radiance,
        );
        std::fs::write(&light, file.to_json_string()).unwrap();
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        SceneOptions {
            mesh: Some(root.join("meshes/cornell_box.obj")),
            env: Some(light),
            ..SceneOptions::default()
        }
    }

    fn read(options: &SceneOptions, spelling: Spelling) -> Result<Scene, SceneError> {
        Scene::read(
            &options.check(spelling).unwrap(),
            &NONE,
            &shlight_pipeline::Silent,
        )
    }

    /// What needs a map is refused for a coefficient file, in each front
    /// end's spelling; without those, the background is the light's SH,
    /// lmax 2 and the albedo 0.8.
    #[test]
    fn what_a_coefficient_file_cannot_light_is_refused_in_each_spelling() {
        let map_background = SceneOptions {
            background: Some(Background::Map),
            ..options("light.json")
        };
        let name = map_background.env.clone().unwrap();
        let name = name.display();
        let cases = [
            (
                map_background.clone(),
                format!(
                    "--background map needs an environment map; {name} holds coefficients (use --background sh)"
                ),
                format!(
                    "background=\"map\" needs an environment map; {name} holds coefficients (use background=\"sh\")"
                ),
            ),
            (
                SceneOptions {
                    encoding: Encoding::DominantSh,
                    ..options("light.json")
                },
                format!(
                    "--encoding dominant+sh finds its lights among a map's texels; {name} holds coefficients (pass the map, or use --encoding sloan+sh)"
                ),
                format!(
                    "encoding=\"dominant+sh\" finds its lights among a map's texels; {name} holds coefficients (pass the map, or use encoding=\"sloan+sh\")"
                ),
            ),
        ];
        for (options, cli, python) in cases {
            assert_eq!(read(&options, CommandLine).unwrap_err().to_string(), cli);
            assert_eq!(read(&options, Python).unwrap_err().to_string(), python);
        }
        let scene = read(&options("light.json"), Python).unwrap();
        assert_eq!(scene.background, Background::Sh);
        assert_eq!((scene.mode, scene.lmax), (Mode::Sh, 2));
        assert_eq!(scene.albedo(Mode::Prt), [0.8; 3]);
        assert_eq!(scene.light.radiance.lmax(), 1);
    }
}
