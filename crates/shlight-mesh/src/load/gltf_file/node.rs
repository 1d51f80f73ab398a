//! The node hierarchy of a glTF scene to instances and lights.
//!
//! Nodes are walked depth-first in document order (a node, then its
//! children), each with its world transform (its parent's times its own
//! matrix or `T R S`). A node's mesh places each of its primitives once,
//! or once per `EXT_mesh_gpu_instancing` instance (the node's transform
//! times the instance's `T R S`; the instances replace the node's own
//! placement, as the extension says); a mesh is read the first time a
//! node uses it and its primitives are shared by every later use. A
//! node's `KHR_lights_punctual` light is placed by its world transform.
//!
//! Refused: a node met twice (a cycle, or a node with two parents: glTF
//! nodes form trees), a non-finite transform, and a singular one on a node
//! that places a mesh or a light, each naming the node; and more placed
//! vertices or triangles than the limits (every instance counts), judged
//! from the accessors' counts before they are read.

use std::path::Path;

use glam::{Mat3, Mat4, Quat, Vec3, Vec4};
use gltf::json;
use json::accessor::Type;

use super::accessor::{self, Data};
use super::{light, primitive};
use crate::scene::{Instance, InstanceSource, Scene};
use crate::{LoadOptions, MeshError};

/// The walk's state: what it has gathered so far.
pub(super) struct Walk<'a> {
    path: &'a Path,
    data: Data<'a>,
    options: LoadOptions,
    /// Primitives, instances, lights and notes gathered.
    pub scene: Scene,
    /// Per glTF mesh, once read: each primitive's index in
    /// `scene.primitives` (`None` where it was skipped).
    meshes: Vec<Option<Vec<Option<usize>>>>,
    /// The nodes met so far.
    visited: Vec<bool>,
    /// Vertices and triangles placed so far (every instance counts).
    placed: (usize, usize),
}

impl<'a> Walk<'a> {
    pub fn new(path: &'a Path, data: Data<'a>, options: LoadOptions) -> Self {
        Self {
            path,
            data,
            options,
            scene: Scene {
                source: path.to_path_buf(),
                ..Scene::default()
            },
            meshes: vec![None; data.root.meshes.len()],
            visited: vec![false; data.root.nodes.len()],
            placed: (0, 0),
        }
    }

    fn fail(&self, message: String) -> MeshError {
        MeshError::Parse {
            path: self.path.to_path_buf(),
            message,
        }
    }

    fn node_name(&self, index: usize) -> String {
        match self
            .data
            .root
            .nodes
            .get(index)
            .and_then(|n| n.name.as_ref())
        {
            Some(name) => format!("node {index} ({name})"),
            None => format!("node {index}"),
        }
    }

    /// Walks the hierarchy under the root nodes `roots`.
    pub fn scene(&mut self, roots: &[usize]) -> Result<(), MeshError> {
        let mut stack: Vec<(usize, Mat4)> =
            roots.iter().rev().map(|&n| (n, Mat4::IDENTITY)).collect();
        while let Some((index, parent)) = stack.pop() {
            // glTF nodes form trees; a node met twice would recurse for
            // ever or multiply the meshes without bound.
            match self.visited.get_mut(index) {
                Some(seen @ false) => *seen = true,
                _ => {
                    return Err(self.fail(format!(
                        "node {index} appears twice in the scene's hierarchy (glTF nodes form trees)"
                    )));
                }
            }
            let root = self.data.root;
            let node = &root.nodes[index];
            let world = parent * self.local(index, node)?;
            if !world.is_finite() {
                return Err(self.fail(format!(
                    "{} has a non-finite world transform",
                    self.node_name(index)
                )));
            }
            if let Some(mesh) = node.mesh {
                self.place_mesh(index, node, mesh.value(), world)?;
            }
            if let Some(light) = node
                .extensions
                .as_ref()
                .and_then(|e| e.khr_lights_punctual.as_ref())
            {
                self.check_invertible(index, world)?;
                let placed = light::place(root, light.light.value(), world)
                    .map_err(|e| self.fail(format!("{}: {e}", self.node_name(index))))?;
                self.scene.lights.push(placed);
            }
            for child in node.children.iter().flatten().rev() {
                stack.push((child.value(), world));
            }
        }
        Ok(())
    }

    /// Every mesh once, untransformed (a file without scenes).
    pub fn every_mesh(&mut self) -> Result<(), MeshError> {
        for mesh in 0..self.data.root.meshes.len() {
            self.read_mesh(mesh)?;
            for p in self.meshes[mesh].clone().into_iter().flatten().flatten() {
                self.place(p, Mat4::IDENTITY)?;
            }
        }
        Ok(())
    }

    /// The node's own transform: its matrix, or `T R S`.
    fn local(&self, index: usize, node: &json::Node) -> Result<Mat4, MeshError> {
        let m = match node.matrix {
            Some(m) => Mat4::from_cols_array(&m),
            None => {
                let t = Vec3::from_array(node.translation.unwrap_or([0.0; 3]));
                let s = Vec3::from_array(node.scale.unwrap_or([1.0; 3]));
                let r = node.rotation.map_or([0.0, 0.0, 0.0, 1.0], |r| r.0);
                let q = unit_quat(r);
                match q {
                    Some(q) if t.is_finite() && s.is_finite() => {
                        Mat4::from_scale_rotation_translation(s, q, t)
                    }
                    _ => Mat4::NAN,
                }
            }
        };
        if m.is_finite() {
            Ok(m)
        } else {
            Err(self.fail(format!(
                "{} has a non-finite transform (or a zero rotation quaternion)",
                self.node_name(index)
            )))
        }
    }

    /// Refuses a singular world transform of a node that places something.
    fn check_invertible(&self, index: usize, world: Mat4) -> Result<(), MeshError> {
        let det = Mat3::from_mat4(world).determinant();
        if det != 0.0 && det.is_finite() && Mat3::from_mat4(world).inverse().is_finite() {
            Ok(())
        } else {
            Err(self.fail(format!(
                "{} has a singular world transform (determinant {det}): a zero scale on it or a parent",
                self.node_name(index)
            )))
        }
    }

    /// Places the node's mesh: once, or once per GPU instance.
    fn place_mesh(
        &mut self,
        index: usize,
        node: &json::Node,
        mesh: usize,
        world: Mat4,
    ) -> Result<(), MeshError> {
        if node.skin.is_some() {
            self.scene.notes.push(format!(
                "{} is skinned; its mesh is placed by the node, in its bind pose",
                self.node_name(index)
            ));
        }
        self.read_mesh(mesh)?;
        let primitives: Vec<usize> = self.meshes[mesh]
            .iter()
            .flatten()
            .flatten()
            .copied()
            .collect();
        let instancing = node
            .extensions
            .as_ref()
            .and_then(|e| e.others.get("EXT_mesh_gpu_instancing"));
        let transforms = match instancing {
            Some(ext) => self.gpu_instances(index, ext, &primitives, world)?,
            None => vec![world],
        };
        for (k, &transform) in transforms.iter().enumerate() {
            self.check_invertible(index, transform)
                .map_err(|e| match (e, instancing) {
                    (MeshError::Parse { path, message }, Some(_)) => MeshError::Parse {
                        path,
                        message: format!("{message} (GPU instance {k})"),
                    },
                    (e, _) => e,
                })?;
            for &p in &primitives {
                self.place(p, transform)?;
                self.scene.instance_sources.push(InstanceSource {
                    node: index,
                    mesh,
                    gpu_instance: instancing.is_some().then_some(k as u32),
                });
            }
        }
        Ok(())
    }

    /// One world transform per `EXT_mesh_gpu_instancing` instance.
    fn gpu_instances(
        &self,
        index: usize,
        ext: &serde_json::Value,
        primitives: &[usize],
        world: Mat4,
    ) -> Result<Vec<Mat4>, MeshError> {
        let name = self.node_name(index);
        let fail =
            |message: String| self.fail(format!("{name}: EXT_mesh_gpu_instancing: {message}"));
        let attributes = ext
            .get("attributes")
            .and_then(serde_json::Value::as_object)
            .ok_or_else(|| fail("no attributes".into()))?;
        let accessor_of = |key: &str| -> Result<Option<usize>, MeshError> {
            match attributes.get(key) {
                None => Ok(None),
                Some(v) => v
                    .as_u64()
                    .and_then(|i| usize::try_from(i).ok())
                    .map(Some)
                    .ok_or_else(|| fail(format!("{key} is not an accessor index"))),
            }
        };
        let (t, r, s) = (
            accessor_of("TRANSLATION")?,
            accessor_of("ROTATION")?,
            accessor_of("SCALE")?,
        );
        let mut count = None;
        for a in [t, r, s].into_iter().flatten() {
            let n = accessor::count(self.data, a).map_err(&fail)?;
            if count.is_some_and(|c| c != n) {
                return Err(fail("its attributes have different counts".into()));
            }
            count = Some(n);
        }
        let Some(count) = count else {
            return Ok(vec![world]);
        };
        if primitives.is_empty() {
            return Ok(Vec::new());
        }
        // Every instance places the whole mesh: the limits are checked on
        // the total before the instances are read (so `count` is at most
        // the vertex limit).
        let (v, tr) = primitives.iter().fold((0usize, 0usize), |(v, t), &p| {
            let m = &self.scene.primitives[p].mesh;
            (v + m.vertex_count(), t + m.triangle_count())
        });
        self.options.check_vertices(
            self.path,
            self.placed.0.saturating_add(v.saturating_mul(count)),
        )?;
        self.options.check_triangles(
            self.path,
            self.placed.1.saturating_add(tr.saturating_mul(count)),
        )?;
        let read = |a: Option<usize>, ty: Type, key: &str| -> Result<Option<Vec<f32>>, MeshError> {
            a.map(|a| {
                accessor::read_floats(self.data, a, &[ty], count)
                    .map(|f| f.values)
                    .map_err(|e| fail(format!("{key}: {e}")))
            })
            .transpose()
        };
        let ts = read(t, Type::Vec3, "TRANSLATION")?;
        let rs = read(r, Type::Vec4, "ROTATION")?;
        let ss = read(s, Type::Vec3, "SCALE")?;
        (0..count)
            .map(|k| {
                let t = ts
                    .as_ref()
                    .map_or(Vec3::ZERO, |v| Vec3::from_slice(&v[3 * k..]));
                let s = ss
                    .as_ref()
                    .map_or(Vec3::ONE, |v| Vec3::from_slice(&v[3 * k..]));
                let q = rs.as_ref().map_or(Some(Quat::IDENTITY), |v| {
                    unit_quat([v[4 * k], v[4 * k + 1], v[4 * k + 2], v[4 * k + 3]])
                });
                match q {
                    Some(q) if t.is_finite() && s.is_finite() => {
                        Ok(world * Mat4::from_scale_rotation_translation(s, q, t))
                    }
                    _ => Err(fail(format!(
                        "instance {k} has a non-finite transform (or a zero rotation quaternion)"
                    ))),
                }
            })
            .collect()
    }

    /// Reads mesh `mesh`'s primitives, if not read yet.
    fn read_mesh(&mut self, mesh: usize) -> Result<(), MeshError> {
        if self.meshes.get(mesh).is_none_or(Option::is_some) {
            return Ok(());
        }
        let root = self.data.root;
        let m = &root.meshes[mesh];
        let mut indices = Vec::with_capacity(m.primitives.len());
        for (k, p) in m.primitives.iter().enumerate() {
            let label = primitive::label(mesh, m, k);
            let (vertices, triangles) =
                primitive::claimed(self.data, p).map_err(|e| self.fail(format!("{label}: {e}")))?;
            // It will be placed at least once: judged with what is placed.
            self.options
                .check_vertices(self.path, self.placed.0.saturating_add(vertices))?;
            self.options
                .check_triangles(self.path, self.placed.1.saturating_add(triangles))?;
            let read = primitive::read(
                self.path,
                self.data,
                label,
                p,
                self.options.max_vertices - self.placed.0,
                self.options.max_triangles - self.placed.1,
            )?;
            match read {
                Ok(primitive) => {
                    indices.push(Some(self.scene.primitives.len()));
                    self.scene.primitives.push(primitive);
                }
                Err(note) => {
                    indices.push(None);
                    self.scene.notes.push(note);
                }
            }
        }
        self.meshes[mesh] = Some(indices);
        Ok(())
    }

    /// One instance of primitive `p`, counted against the limits.
    fn place(&mut self, p: usize, transform: Mat4) -> Result<(), MeshError> {
        let m = &self.scene.primitives[p].mesh;
        let placed = (
            self.placed.0.saturating_add(m.vertex_count()),
            self.placed.1.saturating_add(m.triangle_count()),
        );
        self.options.check_vertices(self.path, placed.0)?;
        self.options.check_triangles(self.path, placed.1)?;
        self.placed = placed;
        self.scene.instances.push(Instance {
            primitive: p,
            transform,
        });
        Ok(())
    }
}

/// The rotation of quaternion `xyzw`, normalised; `None` for a zero or
/// non-finite one.
fn unit_quat(xyzw: [f32; 4]) -> Option<Quat> {
    Vec4::from_array(xyzw).try_normalize().map(Quat::from_vec4)
}
