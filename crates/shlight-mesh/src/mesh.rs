//! The validated indexed triangle mesh.

use std::path::PathBuf;

use glam::Vec3;

use crate::MeshError;

/// What validation found and fixed while building a [`Mesh`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MeshReport {
    /// Triangles dropped because two corners share an index or their area is
    /// zero to rounding (`|e1 x e2| <= 1e-12 * diag^2`, `diag` the bounding-box
    /// diagonal).
    pub degenerate_triangles: usize,
    /// Vertices whose normal was computed (the file had none for them, or
    /// gave a zero or non-finite one).
    pub computed_normals: usize,
    /// Vertices no kept triangle uses (they stay, so vertex order is kept).
    pub unreferenced_vertices: usize,
}

/// An indexed triangle mesh: positions, unit normals and optional linear
/// RGB colours per vertex, and counter-clockwise triangles (seen from the
/// side the normals face).
///
/// Built only through [`Mesh::new`] (or [`crate::load`] and the
/// [`crate::generate`] functions, which call it), so every position is
/// finite, every index is in range, no triangle is degenerate and every
/// normal has unit length.
#[derive(Clone, Debug)]
pub struct Mesh {
    /// Vertex positions, in the file's order.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<Vec3>,
    /// Linear Rec.709 vertex colours (diffuse albedo), one per position, when
    /// the source has them.
    pub colors: Option<Vec<Vec3>>,
    /// Linear Rec.709 emitted radiance per vertex (W sr^-1 m^-2 per channel,
    /// the same units as the environment's radiance), when the source has
    /// emitters: OBJ `Ke`, glTF `emissiveFactor` times
    /// `KHR_materials_emissive_strength`. Emission leaves the front side
    /// only (both sides of a double-sided material's triangles where a bake
    /// reads [`crate::Surfaces`]' materials).
    pub emission: Option<Vec<Vec3>>,
    /// Triangles as indices into `positions`.
    pub triangles: Vec<[u32; 3]>,
    /// What validation found.
    pub report: MeshReport,
}

impl Mesh {
    /// Validates and completes a mesh from raw data.
    ///
    /// `source` names the file (or generator) in error messages. Missing
    /// normals (`None`, or zero / non-finite entries) are replaced by
    /// area-weighted vertex normals: the normalised sum of `e1 x e2` (twice
    /// the area times the unit face normal) over the triangles at the vertex.
    /// A vertex used by no triangle, or whose faces cancel, gets +Z.
    ///
    /// # Errors
    /// No vertices or no non-degenerate triangles, a non-finite position, an
    /// index out of range, or a normal / colour array of the wrong length.
    pub fn new(
        source: impl Into<PathBuf>,
        positions: Vec<Vec3>,
        triangles: Vec<[u32; 3]>,
        normals: Option<Vec<Vec3>>,
        colors: Option<Vec<Vec3>>,
    ) -> Result<Self, MeshError> {
        Self::new_keeping(source, positions, triangles, normals, colors).map(|(mesh, _)| mesh)
    }

    /// [`Mesh::new`], also giving the index in `triangles` of each kept
    /// triangle (in order), so that per-triangle data can follow.
    pub(crate) fn new_keeping(
        source: impl Into<PathBuf>,
        positions: Vec<Vec3>,
        triangles: Vec<[u32; 3]>,
        normals: Option<Vec<Vec3>>,
        colors: Option<Vec<Vec3>>,
    ) -> Result<(Self, Vec<u32>), MeshError> {
        let path = source.into();
        let invalid = |message: String| MeshError::Invalid {
            path: path.clone(),
            message,
        };
        if positions.is_empty() {
            return Err(invalid("the mesh has no vertices".into()));
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(invalid(format!(
                "vertex {i} has a non-finite coordinate ({:?})",
                positions[i]
            )));
        }
        let n = positions.len();
        if let Some((t, tri)) = triangles
            .iter()
            .enumerate()
            .find(|(_, tri)| tri.iter().any(|&i| i as usize >= n))
        {
            return Err(invalid(format!(
                "triangle {t} has index {:?} out of range ({n} vertices)",
                tri.iter().find(|&&i| i as usize >= n).unwrap()
            )));
        }
        for (name, len) in [
            ("normals", normals.as_ref().map(Vec::len)),
            ("colours", colors.as_ref().map(Vec::len)),
        ] {
            if let Some(len) = len.filter(|&len| len != n) {
                return Err(invalid(format!("{len} {name} for {n} vertices")));
            }
        }
        if let Some(c) = colors
            .as_ref()
            .and_then(|c| c.iter().position(|c| !c.is_finite()))
        {
            return Err(invalid(format!("vertex {c} has a non-finite colour")));
        }

        let (lo, hi) = bounds(&positions);
        let diag2 = (hi - lo).length_squared();
        let mut report = MeshReport::default();
        let mut kept = Vec::with_capacity(triangles.len());
        let mut kept_index = Vec::with_capacity(triangles.len());
        for (t, tri) in triangles.into_iter().enumerate() {
            if is_degenerate(tri, &positions, diag2) {
                report.degenerate_triangles += 1;
            } else {
                kept.push(tri);
                kept_index.push(t as u32);
            }
        }
        if kept.is_empty() {
            return Err(invalid(format!(
                "the mesh has no usable triangles ({} degenerate)",
                report.degenerate_triangles
            )));
        }

        let area_normals = area_weighted_normals(&positions, &kept);
        let mut used = vec![false; n];
        for tri in &kept {
            for &i in tri {
                used[i as usize] = true;
            }
        }
        report.unreferenced_vertices = used.iter().filter(|&&u| !u).count();
        let normals = match normals {
            Some(given) => given
                .into_iter()
                .zip(&area_normals)
                .map(|(g, &computed)| match g.try_normalize() {
                    Some(unit) => unit,
                    None => {
                        report.computed_normals += 1;
                        computed
                    }
                })
                .collect(),
            None => {
                report.computed_normals = n;
                area_normals
            }
        };
        Ok((
            Self {
                positions,
                normals,
                colors,
                emission: None,
                triangles: kept,
                report,
            },
            kept_index,
        ))
    }

    /// The mesh with per-vertex emitted radiance (see [`Mesh::emission`]).
    /// All-zero emission is stored as `None`.
    ///
    /// # Errors
    /// Another count than the mesh's vertices, or a negative or non-finite
    /// component; `source` names the mesh in the message.
    pub fn with_emission(
        mut self,
        source: impl Into<PathBuf>,
        emission: Vec<Vec3>,
    ) -> Result<Self, MeshError> {
        let invalid = |message: String| MeshError::Invalid {
            path: source.into(),
            message,
        };
        if emission.len() != self.positions.len() {
            return Err(invalid(format!(
                "{} emission values for {} vertices",
                emission.len(),
                self.positions.len()
            )));
        }
        if let Some(v) = emission
            .iter()
            .position(|e| !e.is_finite() || e.min_element() < 0.0)
        {
            return Err(invalid(format!(
                "vertex {v} has a negative or non-finite emission ({:?})",
                emission[v]
            )));
        }
        self.emission = emission
            .iter()
            .any(|e| *e != Vec3::ZERO)
            .then_some(emission);
        Ok(self)
    }

    /// Number of vertices.
    #[must_use]
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Axis-aligned bounds `(min, max)` of the positions.
    #[must_use]
    pub fn bounds(&self) -> (Vec3, Vec3) {
        bounds(&self.positions)
    }

    /// A 64-bit FNV-1a hash of what a bake depends on: the vertex count,
    /// then every position and normal as little-endian `f32` bits (x, y, z),
    /// then the triangle count and every index as little-endian `u32`.
    /// Files derived from a mesh (`.shprt`) record it, so a renderer can
    /// check that it pairs them with the same mesh.
    #[must_use]
    pub fn content_hash(&self) -> u64 {
        let mut h = Fnv1a::default();
        h.write(&(self.positions.len() as u64).to_le_bytes());
        for v in self.positions.iter().chain(&self.normals) {
            for c in v.to_array() {
                h.write(&c.to_bits().to_le_bytes());
            }
        }
        h.write(&(self.triangles.len() as u64).to_le_bytes());
        for t in &self.triangles {
            for i in t {
                h.write(&i.to_le_bytes());
            }
        }
        h.0
    }

    /// Total surface area, `sum |e1 x e2| / 2`.
    #[must_use]
    pub fn surface_area(&self) -> f64 {
        self.triangles
            .iter()
            .map(|tri| {
                let [a, b, c] = tri.map(|i| self.positions[i as usize].as_dvec3());
                0.5 * (b - a).cross(c - a).length()
            })
            .sum()
    }
}

/// FNV-1a, 64 bits (offset basis 0xcbf29ce484222325, prime 0x100000001b3).
struct Fnv1a(u64);

impl Default for Fnv1a {
    fn default() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv1a {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
}

/// Whether [`Mesh::new`] drops triangle `tri` of `positions` as
/// degenerate: two corners the same vertex, or twice its area at most
/// `1e-12` of `diag2`, the squared diagonal of the mesh's bounding box.
pub(crate) fn is_degenerate(tri: [u32; 3], positions: &[Vec3], diag2: f32) -> bool {
    let [a, b, c] = tri.map(|i| positions[i as usize]);
    let area2 = (b - a).cross(c - a).length();
    tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] || area2 <= 1e-12 * diag2
}

pub(crate) fn bounds(positions: &[Vec3]) -> (Vec3, Vec3) {
    positions.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    )
}

/// Area-weighted vertex normals: `normalize(sum over faces of e1 x e2)`.
fn area_weighted_normals(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Vec3> {
    let mut sums = vec![glam::DVec3::ZERO; positions.len()];
    for tri in triangles {
        let [a, b, c] = tri.map(|i| positions[i as usize].as_dvec3());
        let n = (b - a).cross(c - a);
        for &i in tri {
            sums[i as usize] += n;
        }
    }
    sums.into_iter()
        .map(|s| s.try_normalize().map_or(Vec3::Z, |u| u.as_vec3()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        (
            vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }

    #[test]
    fn content_hash_is_fnv1a_and_sees_every_change() {
        let mut h = Fnv1a::default();
        h.write(b"a");
        assert_eq!(h.0, 0xaf63_dc4c_8601_ec8c); // the published FNV-1a 64 of "a"
        let (p, t) = quad();
        let m = Mesh::new("quad", p.clone(), t.clone(), None, None).unwrap();
        let mut p2 = p.clone();
        p2[2].x = 1.0 + f32::EPSILON;
        let moved = Mesh::new("quad", p2, t.clone(), None, None).unwrap();
        let flipped = Mesh::new("quad", p, vec![[0, 2, 1], [0, 3, 2]], None, None).unwrap();
        assert_ne!(m.content_hash(), moved.content_hash());
        assert_ne!(m.content_hash(), flipped.content_hash());
        assert_eq!(m.content_hash(), m.clone().content_hash());
    }

    #[test]
    fn flat_quad_gets_plus_z_normals_and_area_one() {
        let (p, t) = quad();
        let m = Mesh::new("quad", p, t, None, None).unwrap();
        assert!(m.normals.iter().all(|n| (*n - Vec3::Z).length() < 1e-6));
        assert!((m.surface_area() - 1.0).abs() < 1e-12);
        assert_eq!(m.report.computed_normals, 4);
    }

    #[test]
    fn normals_are_area_weighted() {
        // A big triangle in z = 0 and a small one in x = 0 share vertex 0.
        let p = vec![
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        let m = Mesh::new("corner", p, vec![[0, 1, 2], [0, 2, 3]], None, None).unwrap();
        // e1 x e2 per face: (2,0,0) x (0,2,0) = (0,0,4) and (0,2,0) x (0,0,1) = (2,0,0).
        let expected = Vec3::new(2.0, 0.0, 4.0).normalize();
        assert!(
            (m.normals[0] - expected).length() < 1e-6,
            "{:?}",
            m.normals[0]
        );
    }

    #[test]
    fn degenerate_triangles_are_counted_and_dropped() {
        let (p, mut t) = quad();
        t.push([0, 0, 1]);
        t.push([0, 1, 1]);
        let p2 = {
            let mut p2 = p.clone();
            p2.push(Vec3::new(2.0, 0.0, 0.0));
            p2
        };
        t.push([0, 1, 4]); // collinear
        let m = Mesh::new("quad", p2, t, None, None).unwrap();
        assert_eq!(m.report.degenerate_triangles, 3);
        assert_eq!(m.triangle_count(), 2);
        assert_eq!(m.report.unreferenced_vertices, 1);
    }

    #[test]
    fn bad_meshes_are_errors_naming_the_source() {
        let (p, t) = quad();
        let err = |r: Result<Mesh, MeshError>| r.unwrap_err().to_string();
        assert!(
            err(Mesh::new("m.obj", vec![], vec![], None, None))
                .contains("m.obj: the mesh has no vertices")
        );
        let mut nan = p.clone();
        nan[2].y = f32::NAN;
        assert!(
            err(Mesh::new("m.obj", nan, t.clone(), None, None))
                .contains("vertex 2 has a non-finite")
        );
        assert!(
            err(Mesh::new("m.obj", p.clone(), vec![[0, 1, 9]], None, None))
                .contains("index 9 out of range")
        );
        assert!(
            err(Mesh::new("m.obj", p.clone(), vec![[0, 1, 1]], None, None))
                .contains("no usable triangles (1 degenerate)")
        );
        assert!(
            err(Mesh::new("m.obj", p, t, Some(vec![Vec3::Z]), None))
                .contains("1 normals for 4 vertices")
        );
    }

    #[test]
    fn given_normals_are_kept_unit_and_bad_ones_replaced() {
        let (p, t) = quad();
        let given = vec![
            Vec3::new(0.0, 0.0, 2.0),
            Vec3::ZERO,
            Vec3::X,
            Vec3::splat(f32::NAN),
        ];
        let m = Mesh::new("quad", p, t, Some(given), None).unwrap();
        assert_eq!(m.normals[0], Vec3::Z);
        assert_eq!(m.normals[1], Vec3::Z);
        assert_eq!(m.normals[2], Vec3::X);
        assert_eq!(m.normals[3], Vec3::Z);
        assert_eq!(m.report.computed_normals, 2);
    }
}
