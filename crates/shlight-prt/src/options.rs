//! What a diffuse bake is asked for ([`BakeOptions`]: the transport, the
//! albedo, the lmax, the directions, the surfaces the rays meet) and where
//! it is ([`Stage`]).

use std::sync::Arc;

use glam::Vec3;
use shlight_mesh::Surfaces;

/// Which light transport the transfer holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Cosine-weighted, no visibility: the SH irradiance transfer.
    Unshadowed,
    /// Cosine-weighted with binary visibility (self-shadowing).
    Shadowed,
    /// Shadowed plus `bounces` bounces of diffuse interreflection.
    Interreflected {
        /// Number of bounces gathered after the shadowed term.
        bounces: u32,
    },
}

impl Mode {
    /// `unshadowed`, `shadowed` or `interreflected`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Mode::Unshadowed => "unshadowed",
            Mode::Shadowed => "shadowed",
            Mode::Interreflected { .. } => "interreflected",
        }
    }

    /// Bounces gathered (0 unless interreflected).
    #[must_use]
    pub fn bounces(self) -> u32 {
        match self {
            Mode::Interreflected { bounces } => bounces,
            _ => 0,
        }
    }
}

/// The surface's diffuse albedo.
#[derive(Clone, Debug, PartialEq)]
pub enum Albedo {
    /// The same linear RGB albedo everywhere; one channel when the three are
    /// equal.
    Constant([f32; 3]),
    /// One linear RGB albedo per vertex (e.g. the mesh's vertex colours).
    PerVertex(Vec<Vec3>),
}

impl Albedo {
    /// 1 for a grey constant albedo, 3 otherwise.
    #[must_use]
    pub fn channels(&self) -> usize {
        match self {
            Albedo::Constant([r, g, b]) if r == g && g == b => 1,
            _ => 3,
        }
    }

    /// Albedo of vertex `v` in channel `c` (`channels()` of them).
    pub(crate) fn get(&self, v: usize, c: usize) -> f32 {
        match self {
            Albedo::Constant(rgb) => rgb[c],
            Albedo::PerVertex(all) => all[v][c],
        }
    }
}

/// What to bake.
#[derive(Clone, Debug)]
pub struct BakeOptions {
    /// Highest SH degree (`(lmax+1)^2` coefficients per channel).
    pub lmax: usize,
    /// Directions wanted over the whole sphere (rounded to a whole grid,
    /// see [`shlight_core::map::montecarlo::stratified_directions`]); about
    /// half are cast per vertex.
    pub samples: usize,
    /// Transport.
    pub mode: Mode,
    /// Albedo.
    pub albedo: Albedo,
    /// Seed of the direction set.
    pub seed: u64,
    /// Emitted radiance per vertex (linear RGB, one per vertex, e.g.
    /// [`shlight_mesh::Mesh::emission`]); with it the bake also gathers the light the
    /// emitters send around the mesh ([`Transfer::emitted`](crate::Transfer::emitted)).
    pub emission: Option<Vec<Vec3>>,
    /// What the rays see where they meet the surface: a flattened glTF
    /// scene ([`shlight_mesh::Scene::flatten`]) whose mesh is the one the
    /// rays are cast against (the baked mesh, or the one it was subdivided
    /// from). With it, triangles whose material cuts out let rays through
    /// ([`shlight_rays::CutOuts`]), shadow rays too, and a bounce takes the
    /// albedo of the texel it hit ([`Surfaces::sample`]) times the
    /// irradiance interpolated there from the vertices
    /// ([`Transfer::incident`](crate::Transfer::incident)); the transfer
    /// then has three channels. The triangles whose material is
    /// double-sided are surfaces on both faces ([`crate::BackSides`]; the
    /// diffuse bake only, glossy transfer stays one-sided). [`albedo`](Self::albedo) stays the albedo
    /// at the vertices, which their own transfer is multiplied by (the
    /// scene's vertex albedo, `Surfaces::mesh`'s colours). `None`: every
    /// triangle is opaque and a hit reads its corners' exit radiance.
    pub surfaces: Option<Arc<Surfaces>>,
    /// Irradiance per vertex (linear RGB, W m^-2 per channel, one per
    /// vertex) from lights the bake does not trace, such as punctual
    /// lights the caller found with shadow rays; reflected diffusely: the
    /// vertex leaves `albedo / pi E` as a source of exit radiance beside its
    /// [`emission`](Self::emission), gathered and bounced as the emitters'
    /// light is ([`Transfer::emitted`](crate::Transfer::emitted)). With
    /// [`surfaces`](Self::surfaces) it is light arriving, `E / pi`, which
    /// a ray that hits the surface takes times the albedo of the texel it
    /// met, as it takes the environment's. With double-sided
    /// [`surfaces`](Self::surfaces), one per vertex of the two-sided mesh
    /// ([`crate::BackSides::two_sided`]: the mesh's vertices, then the
    /// back copies, lit from the back).
    pub direct_irradiance: Option<Vec<Vec3>>,
}

impl BakeOptions {
    /// The transfer's channels: three with [`surfaces`](Self::surfaces),
    /// the albedo's ([`Albedo::channels`]) otherwise.
    #[must_use]
    pub fn channels(&self) -> usize {
        if self.surfaces.is_some() {
            3
        } else {
            self.albedo.channels()
        }
    }

    /// The exit radiance each vertex is a source of, in vertex order: its
    /// emission plus `albedo / pi` times its direct irradiance (the
    /// emission as it is without direct irradiance); `None` with neither.
    pub(crate) fn exit_source(&self) -> Option<Vec<Vec3>> {
        let Some(direct) = &self.direct_irradiance else {
            return self.emission.clone();
        };
        Some(
            direct
                .iter()
                .enumerate()
                .map(|(v, e)| {
                    let rho = Vec3::new(
                        self.albedo.get(v, 0),
                        self.albedo.get(v, 1),
                        self.albedo.get(v, 2),
                    );
                    let reflected = rho * std::f32::consts::FRAC_1_PI * *e;
                    self.emission
                        .as_ref()
                        .map_or(reflected, |le| le[v] + reflected)
                })
                .collect(),
        )
    }

    /// Whether a vertex is a source of exit radiance of its own
    /// ([`exit_source`](Self::exit_source) is not `None`).
    pub(crate) fn has_exit_source(&self) -> bool {
        self.emission.is_some() || self.direct_irradiance.is_some()
    }
}

impl Default for BakeOptions {
    fn default() -> Self {
        Self {
            lmax: 4,
            samples: 1024,
            mode: Mode::Shadowed,
            albedo: Albedo::Constant([0.8; 3]),
            seed: 0,
            emission: None,
            surfaces: None,
            direct_irradiance: None,
        }
    }
}

/// Where a bake is, for progress bars.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Casting rays from the vertices.
    Rays,
    /// Gathering bounce `k` (1-based).
    Bounce(u32),
    /// Summing glossy transfer matrices, in vertices.
    Matrices,
}
