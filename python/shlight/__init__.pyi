"""Type stubs of shlight (conventions: see the package docstring)."""

import os
from typing import Any, Literal, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

PathLike = Union[str, "os.PathLike[str]"]
Image = npt.NDArray[np.floating]
"""(H, W, 3) linear RGB, float32 or float64."""

EXPORT_FORMATS: list[str]
__version__: str

class ShlightError(ValueError):
    """A map, file or option shlight cannot use; the message names it."""

class SH:
    """SH lighting: real orthonormal coefficients (Condon-Shortley phase,
    row l*(l+1)+m) of RGB radiance or irradiance in a y-up or z-up frame."""

    @property
    def coefficients(self) -> npt.NDArray[np.float64]:
        """((lmax+1)**2, 3) float64; row l*(l+1)+m, columns R, G, B."""
    @property
    def lmax(self) -> int:
        """Highest SH degree."""
    @property
    def frame(self) -> Literal["y-up", "z-up"]:
        """The frame of the coefficients (docs/conventions.md)."""
    @property
    def mirror(self) -> bool:
        """Whether the map was read mirrored."""
    @property
    def quantity(self) -> Literal["radiance", "irradiance"]:
        """What the coefficients hold."""
    @property
    def encoding(self) -> str:
        """How the light is kept: "sh" (plain) or an encoding ("zh3", ...)."""
    @property
    def std_error(self) -> Optional[npt.NDArray[np.float64]]:
        """((lmax+1)**2, 3) float64 standard errors (Monte Carlo), else None."""
    def irradiance(self) -> "SH":
        """E_l^m = A_l L_l^m (Ramamoorthi & Hanrahan 2001)."""
    def eval(self, dirs: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """The expansion at directions (N, 3) -> (N, 3) (or (3,) -> (3,)),
        in the SH's frame; directions are normalised. Plain SH only."""
    def irradiance_at(self, dirs: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """The irradiance E(n) the light gives at normals (N, 3) -> (N, 3)
        (or (3,) -> (3,)), for every encoding."""
    def rotate(self, r: npt.ArrayLike) -> "SH":
        """Rotated by a 3x3 matrix or a quaternion (x, y, z, w): a light
        from a comes from R a afterwards."""
    def window(self, window: str) -> "SH":
        """none, hanning:W, lanczos:W, laplacian:LAMBDA or auto."""
    def save(self, path: PathLike) -> None:
        """Writes shlight's JSON coefficient file (as the CLI's -o FILE.json)."""
    def export(self, format: str, irradiance_only: bool = False) -> str:
        """The coefficients in an engine or shader format (EXPORT_FORMATS).
        A glTF light needs the map's specular images: refused, unless
        irradiance_only asks for the coefficients alone."""
    def to_json(self) -> str:
        """The coefficient file as JSON text."""
    @staticmethod
    def from_json(text: str) -> "SH":
        """An SH from a coefficient file's JSON text (pickling uses it)."""

class Scene:
    """A glTF scene read once (load_scene), passed wherever a scene path is
    taken (bake_transfer, bake_volume, sample's points)."""

    @property
    def path(self) -> str:
        """The file it was read from."""
    @property
    def primitive_count(self) -> int:
        """Unique primitives."""
    @property
    def instance_count(self) -> int:
        """Instances placing them."""
    @property
    def triangle_count(self) -> int:
        """Triangles of the flattened scene."""
    @property
    def vertex_count(self) -> int:
        """Vertices of the flattened scene."""
    @property
    def materials(self) -> list[dict[str, Any]]:
        """name, base_color, base_color_texture, emissive, alpha_mode,
        alpha_cutoff, double_sided."""
    @property
    def lights(self) -> list[dict[str, Any]]:
        """name, kind, color, intensity (as written), units ("cd" or
        "lux"), range, position, direction (a spot's inner_cone,
        outer_cone)."""

SceneLike = Union[PathLike, Scene]

def load_scene(path: PathLike) -> Scene:
    """Reads a glTF scene (.gltf, .glb)."""

class Transfer:
    """Per-vertex transfer of a mesh (a .shprt file): diffuse, whose exit
    radiance of vertex v under radiance SH L is coefficients[v, c] @ L[:n, c],
    or glossy matrices shaded toward a view by exit_radiance."""

    @staticmethod
    def load(path: PathLike) -> "Transfer":
        """Reads a .shprt file (diffuse version 1, glossy version 2, a
        scene's diffuse transfer with its static term version 3)."""
    @property
    def static_radiance(self) -> Optional[npt.NDArray[np.float32]]:
        """A scene's static term, (vertex_count, 3); None without one."""
    @property
    def brdf(self) -> Optional[str]:
        """A glossy file's BRDF ("phong:32"); None for diffuse transfer."""
    @property
    def matrices(self) -> Optional[npt.NDArray[np.float32]]:
        """A glossy file's (vertex_count, channels, n, n) float32 matrices,
        n = (lmax+1)**2; None for diffuse transfer."""
    @property
    def positions(self) -> Optional[npt.NDArray[np.float32]]:
        """A glossy file's (vertex_count, 3) vertex positions; None for diffuse."""
    @property
    def normals(self) -> Optional[npt.NDArray[np.float32]]:
        """A glossy file's (vertex_count, 3) unit normals; None for diffuse."""
    def exit_radiance(
        self,
        light: Union[PathLike, SH],
        view: Optional[Tuple[float, float, float]] = None,
        eye: Optional[Tuple[float, float, float]] = None,
        albedo: Optional[Union[float, Tuple[float, float, float]]] = None,
    ) -> npt.NDArray[np.float64]:
        """(vertex_count, 3) exit radiance under light (a map or radiance
        coefficient file, y up, or an SH of radiance), as shlight sample
        gives it: view is one direction from every vertex toward the eye,
        eye a camera position (a glossy file needs one; a diffuse file
        ignores both); albedo adds a glossy file's diffuse base, as
        sample --albedo does (a diffuse file refuses it)."""

    @property
    def lmax(self) -> int:
        """Highest SH degree."""
    @property
    def channels(self) -> Literal[1, 3]:
        """1 (grey albedo) or 3 (RGB)."""
    @property
    def mode(self) -> Literal["unshadowed", "shadowed", "interreflected", "glossy"]:
        """The light transport baked."""
    @property
    def bounces(self) -> int:
        """Interreflection bounces (0 unless interreflected)."""
    @property
    def samples(self) -> int:
        """Directions in the shared stratified set."""
    @property
    def vertex_count(self) -> int:
        """Vertices, in the mesh file's order."""
    @property
    def coefficients(self) -> npt.NDArray[np.float32]:
        """(vertex_count, channels, (lmax+1)**2) float32 (raises for a glossy file)."""
    def save(self, path: PathLike) -> None:
        """Writes the .shprt file (as the CLI's shlight prt -o FILE.shprt)."""

Lookup = Literal["shlight", "trilinear", "bevy", "threejs"]

class Volume:
    """An irradiance volume (a .shvol file): SH probes on a grid through a
    scene, with validity, positions, distance maps and, when relightable,
    transfer matrices."""

    @staticmethod
    def load(path: PathLike) -> "Volume":
        """Reads a .shvol file (versions 1 and 2)."""
    @property
    def lmax(self) -> int:
        """Highest SH degree of every probe."""
    @property
    def resolution(self) -> tuple[int, int, int]:
        """Probes along x, y and z (x fastest in per-probe arrays)."""
    @property
    def bounds(self) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """The grid's box ((x0, y0, z0), (x1, y1, z1))."""
    @property
    def probe_count(self) -> int:
        """nx * ny * nz."""
    @property
    def valid(self) -> npt.NDArray[np.bool_]:
        """(N,) bool: whether a lookup may use each probe."""
    @property
    def positions(self) -> npt.NDArray[np.float32]:
        """(N, 3) float32: each probe's cell centre plus its offset."""
    @property
    def offsets(self) -> Optional[npt.NDArray[np.float32]]:
        """(N, 3) float32 moves out of geometry; None without relocation."""
    @property
    def relightable(self) -> bool:
        """Whether the file keeps transfer matrices (not static)."""
    @property
    def has_visibility(self) -> bool:
        """Whether the file holds the probes' distance maps."""
    @property
    def radiance(self) -> npt.NDArray[np.float32]:
        """(N, (lmax+1)**2, 3) float32 incident radiance SH per probe."""
    @property
    def frame(self) -> str:
        """The probes' frame ("y-up")."""
    @property
    def scene(self) -> str:
        """The scene's file name."""
    @property
    def environment(self) -> str:
        """The environment's file name."""
    @property
    def samples(self) -> int:
        """Rays per probe."""
    @property
    def bounces(self) -> int:
        """Interreflection bounces."""
    @property
    def seed(self) -> int:
        """Seed of the ray directions."""
    @property
    def lights(self) -> Optional[dict[str, Union[str, int]]]:
        """The punctual lights baked in: {"units", "point", "spot",
        "directional"}; None for a scene without lights."""
    def relight(self, env: Union[PathLike, SH], *, up: Literal["y", "z"] = "y") -> "Volume":
        """A new Volume relit under a map, a radiance coefficient file or an
        SH of radiance (shlight sample --env); static volumes refuse."""
    def irradiance(
        self,
        points: npt.ArrayLike,
        normals: npt.ArrayLike,
        lookup: Lookup = "shlight",
        lmax: Optional[int] = None,
    ) -> npt.NDArray[np.float64]:
        """(N, 3) points facing (N, 3) normals -> (N, 3) float64 irradiance
        E(p, n) (shlight sample --lookup)."""
    def write(
        self,
        path: PathLike,
        format: Optional[Literal["shvol", "json", "bevy", "threejs"]] = None,
        precision: Literal["half", "f32"] = "half",
    ) -> list[str]:
        """Writes .shvol, .json, .ktx2 (Bevy) or three.js's grid as shlight
        volume -o does; returns the writer's notes."""

Source = Union[PathLike, Image, Sequence[Image]]
Encoding = Literal[
    "sh", "dominant+sh", "sloan+sh", "zh3", "zh3-hallucinated", "l1-nonlinear", "ambient-cube"
]

def project(
    source: Source,
    lmax: int = 2,
    *,
    up: Literal["y", "z"] = "y",
    layout: str = "auto",
    method: Literal["quadrature", "montecarlo"] = "quadrature",
    samples: Optional[int] = None,
    sampler: Optional[Literal["uniform", "stratified", "sobol", "importance"]] = None,
    seed: Optional[int] = None,
    window: Optional[str] = None,
    quantity: Literal["radiance", "irradiance"] = "radiance",
    mirror: bool = False,
    sanitize: bool = False,
    rotate: Optional[str] = None,
    layer: Optional[str] = None,
    max_pixels: Optional[int] = None,
    encoding: Encoding = "sh",
    output: Optional[PathLike] = None,
    format: Optional[str] = None,
    preview: Optional[PathLike] = None,
    preview_size: tuple[int, int] = (512, 256),
    preview_exposure: Optional[float] = None,
    preview_tone_map: Literal["clamp", "reinhard", "aces"] = "aces",
    specular_size: int = 128,
    specular_samples: int = 1024,
) -> SH: ...
def project_many(
    paths: Sequence[PathLike],
    lmax: int = 2,
    *,
    errors: Literal["raise", "none"] = "raise",
    progress: bool = False,
    up: Literal["y", "z"] = "y",
    layout: str = "auto",
    method: Literal["quadrature", "montecarlo"] = "quadrature",
    samples: Optional[int] = None,
    sampler: Optional[str] = None,
    seed: Optional[int] = None,
    window: Optional[str] = None,
    quantity: Literal["radiance", "irradiance"] = "radiance",
    mirror: bool = False,
    sanitize: bool = False,
    rotate: Optional[str] = None,
    layer: Optional[str] = None,
    max_pixels: Optional[int] = None,
    encoding: Encoding = "sh",
    output: Optional[PathLike] = None,
    format: Optional[str] = None,
    preview: Optional[PathLike] = None,
    preview_size: tuple[int, int] = (512, 256),
    preview_exposure: Optional[float] = None,
    preview_tone_map: Literal["clamp", "reinhard", "aces"] = "aces",
    specular_size: int = 128,
    specular_samples: int = 1024,
) -> list[Optional[SH]]: ...
def load(path: PathLike) -> SH:
    """A coefficient file, or any engine file `shlight convert` reads."""
def read_image(
    path: PathLike, *, layer: Optional[str] = None, max_pixels: Optional[int] = None
) -> npt.NDArray[np.float32]:
    """(H, W, 3) float32 linear RGB."""
def write_image(
    path: PathLike, array: Image, *, exposure: float = 0.0, tone_map: str = "clamp"
) -> None:
    """.exr, .hdr or .png (tone mapped: clamp, reinhard, aces)."""
def render(
    sh: SH,
    size: Union[None, int, tuple[int, int]] = None,
    *,
    layout: str = "equirect",
    irradiance: bool = False,
    view: Optional[tuple[float, float, float]] = None,
) -> npt.NDArray[np.float32]:
    """(H, W, 3) float32: the expansion at every texel centre, or with
    layout="lobe" the luminance's lobe seen from view."""
def irradiance(
    source: PathLike,
    size: tuple[int, int] = (64, 32),
    *,
    up: Literal["y", "z"] = "y",
    layout: str = "auto",
    mirror: bool = False,
    sanitize: bool = False,
    max_pixels: Optional[int] = None,
    sh: Optional[int] = None,
    encoding: Optional[Encoding] = None,
    output: Optional[PathLike] = None,
    error_map: Optional[PathLike] = None,
) -> Union[npt.NDArray[np.float64], dict[str, Any]]:
    """(H, W, 3) float64: the exact irradiance of the map at every texel
    centre of an equirect grid (shlight irradiance); with sh or encoding, a
    dict of the exact and estimated irradiance and the estimate's errors."""
def compare(
    paths: Sequence[PathLike],
    normals: tuple[int, int] = (128, 64),
    *,
    up: Literal["y", "z"] = "y",
    layout: str = "auto",
    sanitize: bool = False,
    output: Optional[PathLike] = None,
) -> list[dict[str, Any]]:
    """Every encoding on every map against its exact irradiance: the rows
    of shlight compare's compare.json."""
def accuracy(quick: bool = False, *, output: Optional[PathLike] = None) -> list[dict[str, Any]]:
    """The accuracy suite's rows, as shlight accuracy --json prints them."""
def synth(
    kind: Literal["constant", "hemisphere", "cap", "gradient", "directional"],
    size: Optional[tuple[int, int]] = None,
    *,
    layout: str = "equirect",
    up: Literal["y", "z"] = "y",
    mirror: bool = False,
    color: tuple[float, float, float] = (1.0, 1.0, 1.0),
    value: float = 1.0,
    slope: float = 0.5,
    direction: Optional[tuple[float, float, float]] = None,
    half_angle: Optional[float] = None,
    supersample: int = 4,
    output: Optional[PathLike] = None,
    exposure: float = 0.0,
    tone_map: Literal["clamp", "reinhard", "aces"] = "clamp",
) -> npt.NDArray[np.float32]:
    """An analytic environment map (shlight synth)."""
def convert(
    input: PathLike,
    output: Optional[PathLike] = None,
    *,
    format: Optional[str] = None,
    into: Optional[PathLike] = None,
    precision: Literal["half", "f32"] = "half",
    irradiance_only: bool = False,
) -> Union[str, list[str], None]:
    """A coefficient file or volume in another format (shlight convert)."""
def bake_transfer(
    mesh: SceneLike,
    mode: Literal["unshadowed", "shadowed", "interreflected", "glossy"] = "shadowed",
    lmax: int = 4,
    *,
    samples: int = 1024,
    bounces: Optional[int] = None,
    albedo: Union[None, float, tuple[float, float, float]] = None,
    seed: int = 0,
    brdf: Optional[str] = None,
    compress: Optional[str] = None,
    output: Optional[PathLike] = None,
    light: Optional[PathLike] = None,
    preview: Optional[PathLike] = None,
    preview_size: tuple[int, int] = (512, 512),
    preview_exposure: Optional[float] = None,
    light_units: Optional[Literal["blender", "as-written"]] = None,
) -> Transfer:
    """PRT of a mesh as shlight prt bakes it."""
def bake_volume(
    scene: SceneLike,
    env: PathLike,
    resolution: Union[tuple[int, int, int], str] = (8, 4, 8),
    bounds: Union[
        None, tuple[tuple[float, float, float], tuple[float, float, float]], str
    ] = None,
    lmax: int = 2,
    samples: int = 1024,
    bounces: int = 2,
    surface_samples: int = 512,
    albedo: Union[float, tuple[float, float, float]] = 0.8,
    invalid_backfaces: float = 0.5,
    seed: int = 0,
    relocate: bool = True,
    visibility: bool = True,
    static: bool = False,
    output: Optional[PathLike] = None,
    format: Optional[Literal["shvol", "json", "bevy", "threejs"]] = None,
    precision: Literal["half", "f32"] = "half",
    preview: Optional[PathLike] = None,
    preview_ball: int = 32,
    light_units: Literal["blender", "as-written"] = "blender",
    max_edge: Optional[float] = None,
) -> Volume:
    """An irradiance volume as shlight volume bakes it."""

Engine = Literal["filament", "babylon", "bevy", "unreal"]

def prefilter(
    source: PathLike,
    output: PathLike,
    engine: Engine = "filament",
    size: int = 256,
    mips: Optional[int] = None,
    samples: int = 1024,
    *,
    up: Literal["y", "z"] = "y",
    layout: str = "auto",
    mirror: bool = False,
    sanitize: bool = False,
    max_pixels: Optional[int] = None,
) -> list[str]:
    """GGX-prefiltered cube mips as cmgen --ibl-ld files, a KTX or a KTX2
    cube (shlight prefilter)."""
def dfg(output: PathLike, engine: Engine = "filament", size: int = 128, samples: int = 1024) -> None:
    """The DFG table as .exr or .png (shlight dfg)."""
def sample(
    file: PathLike,
    output: PathLike,
    *,
    points: Optional[SceneLike] = None,
    env: Optional[PathLike] = None,
    light: Optional[PathLike] = None,
    up: Literal["y", "z"] = "y",
    lookup: Literal["shlight", "trilinear", "bevy", "threejs"] = "shlight",
    view: Optional[tuple[float, float, float]] = None,
    eye: Optional[tuple[float, float, float]] = None,
    albedo: Union[None, float, tuple[float, float, float]] = None,
    lmax: Optional[int] = None,
) -> None:
    """What a baked file shades with, written as shlight sample writes it."""
