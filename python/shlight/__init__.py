"""shlight: spherical-harmonics (SH) lighting from HDR environment maps.

Conventions (docs/conventions.md in the shlight repository):

- Basis: real orthonormal SH, the integral of Y_i Y_j over the sphere is
  delta_ij, with the Condon-Shortley phase (Y_1^-1 = -sqrt(3/4pi) y,
  Y_1^0 = sqrt(3/4pi) z, Y_1^1 = -sqrt(3/4pi) x).
- Index: coefficient row ``l*(l+1)+m``; an expansion to degree ``lmax`` has
  ``(lmax+1)**2`` rows ("lmax 2" is 9 coefficients; shlight never says
  "order").
- Frames: a map's top row faces +Y (``up="y"``, the y-up frame of glTF,
  three.js, Unity) or +Z (``up="z"``, Blender); the equirect map's centre
  column looks down -Z (y-up) or +X (z-up) (docs/conventions.md, "Frames").
  Coefficients live in that frame; ``SH.frame`` names it.
- Arrays: images are ``(H, W, 3)`` linear RGB, rows from the top, float32
  (float64 accepted and read in place); coefficients and directions are
  float64, ``(N, 3)``.
- Quantities: radiance L, or irradiance E(n) = sum A_l L_l^m Y_l^m(n)
  (Ramamoorthi & Hanrahan 2001); a Lambertian surface of albedo a reflects
  a E / pi.

Every function is the shlight command line's code (the same numbers bit for
bit, the same error messages), run in Rust with the GIL released. Errors
are ``shlight.ShlightError`` (a ``ValueError``) naming the input and the
problem; wrong array shapes are ``ValueError``, wrong dtypes ``TypeError``;
warnings (negative texels, a stretched map) are ``UserWarning``.
"""

from ._shlight import (
    EXPORT_FORMATS,
    SH,
    Lightmap,
    Scene,
    ShlightError,
    Transfer,
    Volume,
    load,
    load_scene,
    read_image,
    render,
    write_image,
)
from ._shlight import accuracy_suite as _accuracy
from ._shlight import bake_transfer as _bake_transfer
from ._shlight import convert as _convert
from ._shlight import synth as _synth
from ._shlight import bake_lightmap as _bake_lightmap
from ._shlight import bake_volume as _bake_volume
from ._shlight import compare as _compare
from ._shlight import dfg as _dfg
from ._shlight import irradiance as _irradiance
from ._shlight import prefilter as _prefilter
from ._shlight import project as _project
from ._shlight import project_many as _project_many
from ._shlight import sample as _sample

__all__ = [
    "EXPORT_FORMATS",
    "Lightmap",
    "SH",
    "Scene",
    "ShlightError",
    "Transfer",
    "Volume",
    "accuracy",
    "bake_lightmap",
    "bake_transfer",
    "bake_volume",
    "compare",
    "convert",
    "dfg",
    "irradiance",
    "load",
    "load_scene",
    "prefilter",
    "project",
    "project_many",
    "read_image",
    "render",
    "sample",
    "synth",
    "write_image",
]

__version__ = "0.1.0"


def project(
    source,
    lmax=2,
    *,
    up="y",
    layout="auto",
    method="quadrature",
    samples=None,
    sampler=None,
    seed=None,
    window=None,
    quantity="radiance",
    mirror=False,
    sanitize=False,
    rotate=None,
    layer=None,
    max_pixels=None,
    encoding="sh",
    output=None,
    format=None,
    preview=None,
    preview_size=(512, 256),
    preview_exposure=None,
    preview_tone_map="aces",
    specular_size=128,
    specular_samples=1024,
):
    """Project an environment map to SH coefficients (``shlight project``).

    Parameters
    ----------
    source : str | os.PathLike | numpy.ndarray | sequence of 6 ndarrays
        A map file (OpenEXR, Radiance .hdr, PNG, JPEG; ``NAME_{face}.exr``
        reads six face files px nx py ny pz nz), an ``(H, W, 3)`` float32 or
        float64 array of linear RGB (rows from the top; read in place when
        C-contiguous), or six ``(N, N, 3)`` face arrays in the order
        +X -X +Y -Y +Z -Z.
    lmax : int
        Highest SH degree kept: ``(lmax+1)**2`` coefficients.
    up : "y" | "z"
        The world axis the map's top row faces.
    layout : str
        ``auto`` (by aspect ratio: 2:1 equirect, 4:3 cross-h, 3:4 cross-v,
        6:1 strip, 1:1 angular), ``equirect``, ``cross-h``, ``cross-v``,
        ``strip``, ``angular``, ``mirror-ball``, or ``faces``.
    method : "quadrature" | "montecarlo"
        Exact texel-solid-angle quadrature, or Monte Carlo integration of
        the bilinearly interpolated map with a standard error per
        coefficient (``SH.std_error``).
    samples, sampler, seed :
        Monte Carlo only: directions drawn (default 65536), ``uniform``,
        ``stratified``, ``sobol`` (default) or ``importance``, and the seed
        (default 6001130381083431937); equal seeds give identical results.
    window : None | str
        Ringing window: None (``none``), ``hanning:W``, ``lanczos:W``,
        ``laplacian:LAMBDA``, or ``auto`` (per colour channel the weakest
        Hanning window that keeps the result non-negative).
    quantity : "radiance" | "irradiance"
        What the coefficients hold.
    mirror : bool
        Read a map made for the mirrored pbrt / google mapping.
    sanitize : bool
        Replace NaN and -inf by 0, +inf by the largest finite value and
        negatives by 0, instead of refusing NaN/inf.
    rotate : None | str
        ``yaw:DEG``, ``quat:X,Y,Z,W`` or ``euler:X,Y,Z`` as ``--rotate``: a
        light from a comes from R a afterwards.
    layer, max_pixels :
        EXR layer to read; refuse inputs with more pixels.
    encoding : str
        How the light is kept (``--encoding``): ``sh`` (plain SH to
        ``lmax``), ``dominant+sh`` (the map's compact bright lights kept
        exactly, the rest as SH to ``lmax``), ``sloan+sh``, ``zh3``,
        ``zh3-hallucinated``, ``l1-nonlinear`` or ``ambient-cube``. The
        encodings other than ``sh`` take radiance by quadrature: not with
        ``quantity="irradiance"``, ``rotate``, ``method="montecarlo"`` or a
        ``window`` other than none. Evaluate an encoded light with
        ``SH.irradiance_at``; its coefficients alone are not the light.
    output, format : None | str | os.PathLike, None | str
        Also write the result as ``shlight project MAP -o OUTPUT --format
        FORMAT`` does (a map file only): shlight's JSON, or any name of
        ``EXPORT_FORMATS``; ``gltf`` writes a glTF 2.0 light (``.gltf``,
        or binary ``.glb``) with its specular images prefiltered from the
        map. ``format`` needs ``output``.
    preview, preview_size, preview_exposure, preview_tone_map :
        Also write ``--preview``'s image (input | SH radiance | SH
        irradiance / pi) of a map file, each panel ``preview_size``.
    specular_size, specular_samples :
        The glTF light's specular cube: face size, GGX samples per texel.

    Returns
    -------
    SH
        Coefficients ``((lmax+1)**2, 3)`` float64 with their frame,
        quantity, encoding and provenance; the same numbers as ``shlight
        project`` with the same options, bit for bit (``save`` writes the
        CLI's JSON file byte for byte).

    Raises
    ------
    ShlightError
        An unreadable file, a size that fits no layout, NaN or infinite
        texels (without ``sanitize``), a bad option; the message names the
        input.
    ValueError, TypeError
        An array of the wrong shape or dtype.
    """
    return _project(
        source,
        lmax,
        up=up,
        layout=layout,
        method=method,
        samples=samples,
        sampler=sampler,
        seed=seed,
        window=window,
        quantity=quantity,
        mirror=mirror,
        sanitize=sanitize,
        rotate=rotate,
        layer=layer,
        max_pixels=max_pixels,
        encoding=encoding,
        output=output,
        format=format,
        preview=preview,
        preview_size=preview_size,
        preview_exposure=preview_exposure,
        preview_tone_map=preview_tone_map,
        specular_size=specular_size,
        specular_samples=specular_samples,
    )


def project_many(paths, lmax=2, *, errors="raise", progress=False, **options):
    """Project many map files in parallel (``shlight project a b c -o DIR``).

    The maps are projected on every core by Rust threads with the GIL
    released; each result equals ``project(path, lmax, **options)`` bit
    for bit.

    Parameters
    ----------
    paths : sequence of str | os.PathLike
        Map files (any ``project`` source that is a path).
    lmax : int
        Highest SH degree kept.
    errors : "raise" | "none"
        ``raise``: one ``ShlightError`` listing every failed path with its
        message, after all maps are done. ``none``: a failed map gives None
        in its place and a ``UserWarning`` with its message.
    progress : bool
        Print the maps done so far on stderr.
    **options :
        The keyword options of ``project`` (up, layout, method, samples,
        sampler, seed, window, quantity, mirror, sanitize, rotate, layer,
        max_pixels, encoding); ``output`` and ``preview`` name directories
        (one file per map, as ``shlight project MAPS -o DIR``), with
        ``format`` and the preview and specular options.

    Returns
    -------
    list[SH | None]
        One SH per path, in order (None for failed paths with
        ``errors="none"``).
    """
    return _project_many(
        [str(p) for p in paths], lmax, errors=errors, progress=progress, **options
    )


def irradiance(
    source,
    size=(64, 32),
    *,
    up="y",
    layout="auto",
    mirror=False,
    sanitize=False,
    max_pixels=None,
    sh=None,
    encoding=None,
    output=None,
    error_map=None,
):
    """The exact irradiance of a map (``shlight irradiance MAP -o E.exr``).

    Every texel of the output, an equirect map of ``size`` in the map's
    frame, gets ``E(n) = sum_k L_k max(n . d_k, 0) Omega_k`` over every texel
    ``k`` of the map, ``n`` the output texel's centre direction: the ground
    truth an SH or any encoding's ``SH.irradiance_at`` is compared with.
    ``O(map texels x output texels)`` work, on every core.

    Parameters
    ----------
    source : str | os.PathLike
        A map file in any layout ``project`` reads (``NAME_{face}.exr``:
        six face files).
    size : (int, int)
        ``(width, height)`` of the output, 2:1.
    up, layout, mirror, sanitize, max_pixels :
        As for ``project``. The output lies in the map's own frame, so
        ``up`` and ``mirror`` turn the map and the normals together and
        leave the values as they are.
    sh : int | None
        Also measure the map's SH irradiance to this lmax against the exact
        one (``--sh``); with ``encoding``, the lmax of its SH part (default 2).
    encoding : str | None
        Measure this encoding of the map instead of plain SH (``dominant+sh``,
        ``zh3``, ...; ``--encoding``).
    output : str | os.PathLike | None
        Also write the files ``shlight irradiance -o OUTPUT`` writes: the
        exact map, and with an estimate ``OUT-sh.EXT`` (or
        ``OUT-ENCODING.EXT``) and ``OUT-diff.EXT``.
    error_map : str | os.PathLike | None
        With an estimate: a PNG of its error relative to the peak, 0 to 10%.

    Returns
    -------
    numpy.ndarray | dict
        Without an estimate: ``(height, width, 3)`` float64 linear RGB,
        rows from the top: the numbers the CLI writes to its EXR (float32
        there). With ``sh`` or ``encoding``: a dict with ``exact`` and
        ``estimate`` (such arrays), ``encoding``, ``lmax``, ``floats``
        (stored), the luminance errors ``mean_relative`` and
        ``max_relative`` (to ``E(n)``), ``mean_peak_relative`` and
        ``max_peak_relative`` (to the peak), and ``summary``, the lines the
        CLI prints.

    Raises
    ------
    ShlightError
        An unreadable map, NaN or infinite texels (without ``sanitize``), a
        size that is not 2:1; the CLI's messages.
    """
    return _irradiance(
        source,
        tuple(size),
        up=up,
        layout=layout,
        mirror=mirror,
        sanitize=sanitize,
        max_pixels=max_pixels,
        sh=sh,
        encoding=encoding,
        output=output,
        error_map=error_map,
    )


def compare(paths, normals=(128, 64), *, up="y", layout="auto", sanitize=False, output=None):
    """Every encoding on every map against its exact irradiance (``shlight compare``).

    For each map: the exact irradiance at the texel centres of an equirect
    grid of ``normals`` (as ``irradiance``), and against it the irradiance
    of plain SH (lmax 1, 2, 4), dominant lights plus SH (lmax 1, 2, 4),
    ``sloan+sh``, ``zh3``, ``zh3-hallucinated``, ``l1-nonlinear`` and the
    ambient cube. Errors are of the luminance relative to its peak over
    the normals, mean and RMS weighted by the normals' solid angles.

    Parameters
    ----------
    paths : sequence of str | os.PathLike
        Map files; a row's ``map`` is the file's stem.
    normals : (int, int)
        ``(width, height)`` of the grid of normals.
    up, layout, sanitize :
        As for ``project``.
    output : str | os.PathLike | None
        A directory (made) for ``compare.json`` and one plot of error
        against floats stored per map (``compare-MAP.svg``), as ``shlight
        compare ... -o DIR`` writes them.

    Returns
    -------
    list[dict]
        One dict per map and encoding, in the order of the CLI's table,
        with the keys and values of the ``compare.json`` that ``shlight
        compare ... -o DIR`` writes: ``map``, ``encoding``, ``lmax`` (None
        for the fixed-size encodings), ``floats`` (stored, RGB), ``mean``,
        ``max``, ``rms`` (fractions of the peak), ``lights`` (kept exactly)
        and ``light_angle_degrees`` (first light to the brightest texel, or
        None).
    """
    return _compare(
        [str(p) for p in paths], tuple(normals), up=up, layout=layout, sanitize=sanitize, output=output
    )


def accuracy(quick=False, *, output=None):
    """The accuracy suite of SH irradiance against analytic lights (``shlight accuracy --json``).

    Truncation, quadrature and Monte Carlo cases against closed-form
    irradiance (docs/accuracy.md), each row with its errors, its bound and
    whether it passes.

    Parameters
    ----------
    quick : bool
        The subset that runs in a few seconds (``--quick``).
    output : str | os.PathLike | None
        A directory (made) for the pictures: error plots (SVG) and error
        maps (PNG).

    Returns
    -------
    list[dict]
        The rows ``shlight accuracy --json`` prints.
    """
    return _accuracy(quick, output=output)


def synth(
    kind,
    size=None,
    *,
    layout="equirect",
    up="y",
    mirror=False,
    color=(1.0, 1.0, 1.0),
    value=1.0,
    slope=0.5,
    direction=None,
    half_angle=None,
    supersample=4,
    output=None,
    exposure=0.0,
    tone_map="clamp",
):
    """An analytic environment map (``shlight synth KIND -o MAP``).

    The test inputs whose SH coefficients are known in closed form: each
    texel holds the light's mean over the texel (``supersample`` points a
    side); a directional light is one texel, or a cap of ``half_angle``
    of the same irradiance.

    Parameters
    ----------
    kind : "constant" | "hemisphere" | "cap" | "gradient" | "directional"
        The light.
    size : (int, int) | None
        ``(width, height)``, fitting ``layout`` (default 1024x512 for
        equirect; faces of 256, or a 512x512 disc).
    layout, up, mirror :
        The map's layout and frame (as ``render``'s and ``project``'s).
    color, value, slope, direction, half_angle :
        Linear Rec.709 colour times ``value`` (radiance, or a directional
        light's irradiance facing it); the gradient's ``b`` in ``a + b (d .
        direction)``; the light's axis (default the frame's up); the
        half-angle in degrees (cap: 30; directional: 0, one texel).
    output, exposure, tone_map :
        Also write the map (``.exr``, ``.hdr``, ``.png``), as the CLI does.

    Returns
    -------
    numpy.ndarray
        ``(height, width, 3)`` float32 linear RGB.
    """
    return _synth(
        kind,
        None if size is None else tuple(size),
        layout=layout,
        up=up,
        mirror=mirror,
        color=list(color),
        value=value,
        slope=slope,
        direction=None if direction is None else list(direction),
        half_angle=half_angle,
        supersample=supersample,
        output=output,
        exposure=exposure,
        tone_map=tone_map,
    )


def convert(input, output=None, *, format=None, into=None, precision="half", irradiance_only=False):
    """A coefficient file or volume in another format (``shlight convert``).

    Parameters
    ----------
    input : str | os.PathLike
        A coefficient file or an engine file that keeps its coefficients
        (``load`` reads the same), or an irradiance volume (``.shvol``).
    output : str | os.PathLike | None
        The file to write, atomically; None: the text is returned.
    format : str | None
        A name of ``EXPORT_FORMATS`` (default: from ``output``'s
        extension); a volume converts to ``threejs`` (three.js's
        LightProbeGrid), ``wgsl`` or ``glsl`` (a snippet of its lookup, its
        textures beside it).
    into : str | os.PathLike | None
        Add the light to this glTF asset (``.gltf`` or ``.glb``) in place,
        with ``irradiance_only``.
    precision : "half" | "f32"
        The numbers of a volume's three.js atlas.
    irradiance_only : bool
        A glTF light from the coefficients alone, without its specular
        images (a coefficient file holds no map to prefilter).

    Returns
    -------
    str | list[str] | None
        The text without ``output``; the files a volume's snippet wrote;
        else None.
    """
    return _convert(
        input, output, format=format, into=into, precision=precision, irradiance_only=irradiance_only
    )


def _scene_or_path(scene):
    """A loaded ``Scene`` as it is, anything else as a path string."""
    return scene if isinstance(scene, Scene) else str(scene)



def bake_lightmap(
    scene,
    env,
    output=None,
    *,
    basis="irradiance",
    engine="threejs",
    non_linear=False,
    size=None,
    texel_density=None,
    padding=2,
    denoise=2,
    samples=256,
    bounces=8,
    surface_samples=512,
    max_edge=None,
    lmax=2,
    albedo=0.8,
    invalid_backfaces=0.5,
    light_units="blender",
    seed=0,
    unshare_instances=False,
    exr=None,
    preview=None,
):
    """Bake a glTF scene's lightmap (``shlight lightmap SCENE --env ENV -o OUT.glb``).

    Every placed node gets a square region of one atlas laid on its
    ``TEXCOORD_1``; each texel its triangles cover gathers the light
    arriving at its point (the environment, the scene's punctual lights
    by shadow rays, emitters, and ``bounces`` of interreflection with the
    textures' albedo); texels inside geometry and the padding are filled
    from their neighbours, and UV seams stitched. docs/lightmaps.md
    describes the file. The same options give the CLI's files.

    Parameters
    ----------
    scene : str | os.PathLike | Scene
        A .gltf or .glb file (or a ``Scene`` from ``load_scene``); every
        mesh needs a second UV set (``TEXCOORD_1``) within the unit
        square, its triangles not overlapping.
    env : str | os.PathLike
        The distant light: an equirect map or a radiance coefficient file.
    output : None | str | os.PathLike
        Also write the scene with its lightmaps (``.glb``).
    basis : str
        What a texel holds: ``"irradiance"``, ``"sh-l1"`` (L0 and L1 per
        channel) or ``"monosh"`` (Bakery's MonoSH).
    engine : str
        The engine that reads it (``--for``): ``"threejs"`` (texels are
        irradiance E), ``"bevy"``, ``"godot"``, ``"unity"`` (E / pi), each
        with its packing.
    non_linear : bool
        SH texels read back with Geomerics' non-linear reconstruction.
    size, texel_density : None | int, None | float
        The atlas's side in texels (the regions as large as fit; 512 when
        neither is given), or texels per metre of surface.
    padding : int
        Empty texels around each region, filled by dilation.
    denoise : int
        Radius in texels of the edge-aware filter over the baked texels,
        guided by their positions and normals (never across a geometric
        edge); 0: none.
    samples, bounces, surface_samples, max_edge, lmax, seed
        Rays per texel, interreflection bounces, directions per surface
        vertex, the longest surface edge, the environment's lmax and the
        seed, as ``bake_volume`` takes them.
    albedo : float | (float, float, float)
        Albedo of primitives without a material.
    invalid_backfaces : float
        A texel is inside geometry (filled from its neighbours) when more
        than this fraction of its rays meet back faces.
    light_units : str
        ``"blender"`` (glTF's candela and lux over 683) or ``"as-written"``.
    unshare_instances : bool
        In the written scene, give every baked node its own copy of its
        mesh with ``TEXCOORD_1`` moved into its region (always so for
        three.js).
    exr, preview : None | str | os.PathLike
        Also write each layer as ``EXR.LAYER.exr``, and a picture of the
        irradiance.

    Returns
    -------
    Lightmap
        ``layers`` (float32, ``(layers, side, side, 4)``, named by
        ``layer_names``), ``irradiance`` (``(side, side, 3)``, NaN where
        no surface is), ``regions``, ``texels_per_metre``.

    Raises
    ------
    ShlightError
        A missing scene or light, a mesh without ``TEXCOORD_1`` or with
        overlapping lightmap UVs (named), a bad option; the CLI's messages.
    """
    return _bake_lightmap(
        _scene_or_path(scene),
        str(env),
        None if output is None else str(output),
        basis,
        engine,
        non_linear,
        size,
        texel_density,
        padding,
        denoise,
        samples,
        bounces,
        surface_samples,
        max_edge,
        lmax,
        albedo,
        invalid_backfaces,
        light_units,
        seed,
        unshare_instances,
        None if exr is None else str(exr),
        None if preview is None else str(preview),
    )

def bake_transfer(
    mesh,
    mode="shadowed",
    lmax=4,
    *,
    samples=1024,
    bounces=None,
    albedo=None,
    seed=0,
    brdf=None,
    compress=None,
    output=None,
    light=None,
    preview=None,
    preview_size=(512, 512),
    preview_exposure=None,
    light_units=None,
):
    """Bake precomputed radiance transfer for a mesh (``shlight prt MESH -o OUT``).

    Per-vertex diffuse transfer vectors T (Sloan, Kautz & Snyder 2002),
    albedo / pi folded in: a vertex's exit radiance under distant radiance
    SH L (``project(...).coefficients``, radiance) is ``T[v, c] @ L[:n, c]``
    per channel (a grey transfer, one channel, for each colour of L); or,
    with ``mode="glossy"``, a transfer matrix per vertex for a
    view-dependent BRDF, shaded by ``Transfer.exit_radiance``. The defaults
    are the CLI's.

    Parameters
    ----------
    mesh : str | os.PathLike | Scene
        .obj, .ply, .off, or a glTF scene (.gltf, .glb, or a ``Scene`` from
        ``load_scene``): albedo from its materials (the texel a bounce
        hits), rays through its cut-outs, its punctual lights and emission
        in ``Transfer.static_radiance`` (docs/shprt.md, "glTF scenes").
    mode : "unshadowed" | "shadowed" | "interreflected" | "glossy"
        Cosine-weighted only; with self-shadowing; with self-shadowing and
        ``bounces`` bounces of diffuse interreflection; glossy matrices
        (shadowed, with ``bounces`` diffuse bounces when given) for ``brdf``.
    lmax : int
        Highest SH degree of the transfer, at most 32.
    samples : int
        Directions per vertex over the whole sphere (a stratified grid of
        about this many, shared by all vertices; about half are cast).
    bounces : None | int
        Bounces of interreflection (``mode="interreflected"``, default 2;
        ``mode="glossy"``, default 0).
    albedo : None | float | (float, float, float)
        Diffuse albedo of every vertex of a mesh, linear, in [0, 1]; None:
        the mesh's vertex colours if it has them, otherwise 0.8. Refused
        for a glTF scene, whose materials give it.
    seed : int
        Seed of the direction set (the same seed gives the same bake).
    brdf : None | str
        The glossy BRDF: ``phong:S`` (normalised Phong of exponent S) or
        ``ggx:ALPHA`` / ``ggx:ALPHA,F0`` (GGX of linear roughness ALPHA,
        Schlick's Fresnel of F0); ``mode="glossy"`` only.
    compress : None | str
        ``cpca:C,K``: the glossy matrices by clustered PCA, C clusters of K
        basis vectors.
    output : None | str | os.PathLike
        Also write the bake, as the CLI writes ``-o``: ``.shprt``, or a glTF
        (``.gltf``, ``.glb``) of the mesh with ``_SH_TRANSFER_k`` attributes
        (diffuse transfer only).
    light, preview, preview_size, preview_exposure :
        A radiance coefficient file, and the picture of the mesh shaded by
        it (diffuse transfer), as ``--light L --preview P``.
    light_units : None | "blender" | "as-written"
        How a glTF scene's punctual lights' intensities are read (default
        "blender": glTF's candela and lux over 683); refused for a mesh.

    Returns
    -------
    Transfer
        ``coefficients`` ``(vertex_count, channels, (lmax+1)**2)`` float32
        (or ``matrices`` for glossy transfer); ``save(path)`` writes the
        CLI's .shprt file byte for byte.
    """
    return _bake_transfer(
        _scene_or_path(mesh),
        mode,
        lmax,
        samples=samples,
        bounces=bounces,
        albedo=albedo,
        seed=seed,
        brdf=brdf,
        compress=compress,
        output=output,
        light=light,
        preview=preview,
        preview_size=tuple(preview_size),
        preview_exposure=preview_exposure,
        light_units=light_units,
    )


def bake_volume(
    scene,
    env,
    resolution=(8, 4, 8),
    bounds=None,
    lmax=2,
    samples=1024,
    bounces=2,
    surface_samples=512,
    albedo=0.8,
    invalid_backfaces=0.5,
    seed=0,
    relocate=True,
    visibility=True,
    static=False,
    output=None,
    format=None,
    precision="half",
    preview=None,
    preview_ball=32,
    light_units="blender",
    max_edge=None,
):
    """Bake an irradiance volume through a scene (``shlight volume SCENE --env ENV -o OUT``).

    SH probes on a grid (Greger et al. 1998): each probe's incident radiance
    through the scene's shadows and interreflections, as a transfer matrix
    per channel plus the emitters' light, so the volume can be relit under
    any environment (``Volume.relight``). Probes inside geometry, or too
    near a surface, are moved within their cell (``relocate``); probes
    still inside geometry are invalid. The per-probe distance maps
    (``visibility``) let the ``shlight`` lookup keep light from leaking
    through thin walls. The defaults are the CLI's; the same options give
    the CLI's file byte for byte (``shlight_volume::bake_file``, which the
    CLI calls too). The bake runs on every core with the GIL released.

    Parameters
    ----------
    scene : str | os.PathLike | Scene
        .obj (+ .mtl: Kd albedo, Ke emission), .ply, .off, .gltf or .glb
        (baseColorFactor x COLOR_0 albedo, emissive materials), or a ``Scene``
        from ``load_scene``.
    env : str | os.PathLike
        The distant light: an equirect map (projected to ``lmax``, its top
        row facing +Y) or a radiance coefficient file (``SH.save``,
        ``shlight project -o FILE.json``) holding at least ``lmax``.
    resolution : (int, int, int) | str
        Probes along x, y and z, or ``"NXxNYxNZ"``.
    bounds : None | ((float, float, float), (float, float, float)) | str
        The grid's box ``((x0, y0, z0), (x1, y1, z1))`` or
        ``"X0,Y0,Z0:X1,Y1,Z1"``; None: the scene's bounding box padded by
        2% of its diagonal.
    lmax : int
        Highest SH degree of the probes, at most 8.
    samples : int
        Rays per probe (a stratified set of about this many, shared by all
        probes).
    bounces : int
        Interreflection bounces of the surfaces' light.
    surface_samples : int
        Directions per surface vertex for the surfaces' own light.
    albedo : float | (float, float, float)
        Diffuse albedo of surfaces without colours, linear, in [0, 1].
    invalid_backfaces : float
        A probe is invalid when more than this fraction of its rays hit
        back faces.
    seed : int
        Seed of the ray directions (the same seed gives the same file at
        any thread count).
    relocate : bool
        Move probes inside geometry, or nearer a surface than a fifth of a
        cell, to free space within their cell (``--no-relocate`` when
        False).
    visibility : bool
        Store the probes' distance maps (``--no-visibility`` when False:
        the file is shaded by trilinear interpolation, which leaks).
    static : bool
        Keep only the probes' SH under ``env`` (``--static``: smaller, but
        the volume cannot be relit).
    output : None | str | os.PathLike
        Also write the file: ``.shvol``, its JSON form for a ``.json``
        name, Bevy's KTX2 texture for ``.ktx2`` (as ``Volume.write``).
    format, precision : None | str, str
        The output's format (``shvol``, ``json``, ``bevy``, ``threejs``;
        default by extension) and three.js's atlas numbers (``half`` or
        ``f32``), as ``--format`` and ``--precision``.
    preview : None | str | os.PathLike
        Also write a picture of the probes (PNG, EXR or HDR): each a white
        diffuse ball lit by its light, z layers side by side, invalid
        probes grey (``--preview``).
    preview_ball : int
        Each ball's diameter in pixels.
    light_units : str
        How the intensities of the scene's punctual lights (glTF's
        ``KHR_lights_punctual``) become the units of ``env``'s radiance:
        ``"blender"`` divides glTF's candela and lux by 683, undoing
        Blender's exporter, so a scene bakes to what Cycles renders;
        ``"as-written"`` takes them as they are (``--light-units``). The
        lights' direct light reaches probes and surfaces through shadow
        rays and is static: a relit volume keeps it.
    max_edge : None | float
        The surfaces' light is held at their vertices: edges longer than
        this (scene units) are split first (``--max-edge``); None: the
        scene's bounding-box diagonal over 32. Give a smaller one where
        shadows or patches of light are smaller than that.

    Returns
    -------
    Volume
        The baked volume, its probes lit by ``env``.

    Raises
    ------
    ShlightError
        A missing or unreadable scene or map, a coefficient file below
        ``lmax``, a bad option; the CLI's messages.
    """
    return _bake_volume(
        _scene_or_path(scene),
        str(env),
        resolution,
        bounds,
        lmax,
        samples,
        bounces,
        surface_samples,
        albedo,
        invalid_backfaces,
        seed,
        relocate,
        visibility,
        static_only=static,
        output=None if output is None else str(output),
        format=format,
        precision=precision,
        preview=None if preview is None else str(preview),
        preview_ball=preview_ball,
        light_units=light_units,
        max_edge=max_edge,
    )


def prefilter(
    source,
    output,
    engine="filament",
    size=256,
    mips=None,
    samples=1024,
    *,
    up="y",
    layout="auto",
    mirror=False,
    sanitize=False,
    max_pixels=None,
):
    """A map GGX-prefiltered into cube mips (``shlight prefilter MAP -o OUT``).

    The specular half of image-based lighting: mip ``k`` holds the map
    convolved with the GGX lobe (``n = v = r``, Karis 2013) at the
    roughness ``engine``'s shader reads mip ``k`` at (docs/exporters.md),
    by GGX importance sampling with source-mip filtering (Colbert &
    Krivanek 2007), as Filament's cmgen does; deterministic, on every core.

    Parameters
    ----------
    source : str | os.PathLike
        A map file in any layout ``project`` reads.
    output : str | os.PathLike
        A directory (made if missing; a name without an extension, or one
        ending in ``/``): one float OpenEXR per mip and face, ``m0_px.exr``
        ... ``m<N>_nz.exr``, named and oriented as cmgen's ``--ibl-ld``
        writes them; ``NAME.ktx``: the KTX 1.1 cube Filament's KtxBundle
        reads (``cmgen --format=ktx``); ``NAME.ktx2``: a KTX2 cube with its
        mips (RGBA16F), Bevy's specular map.
    engine : {"filament", "babylon", "bevy", "unreal"}
        Whose roughness per mip and cube axes.
    size : int
        Face size of mip 0, a power of two.
    mips : int | None
        The mip count (default: Filament's 16-pixel smallest mip, the full
        chain for the others).
    samples : int
        GGX samples per texel of mips 0 and 1, doubled per mip after.
    up, layout, mirror, sanitize, max_pixels :
        As for ``project``.

    Returns
    -------
    list[str]
        The files written: the faces, mip 0 first, faces ``px nx py ny pz
        nz``; or the one KTX file.

    Raises
    ------
    ShlightError
        An unreadable map, bad settings; the CLI's messages.
    """
    return _prefilter(
        source,
        output,
        engine,
        size,
        mips,
        samples,
        up=up,
        layout=layout,
        mirror=mirror,
        sanitize=sanitize,
        max_pixels=max_pixels,
    )


def dfg(output, engine="filament", size=128, samples=1024):
    """The DFG (split-sum BRDF) table (``shlight dfg -o LUT``).

    ``size x size`` texels, ``n.v`` left to right, perceptual roughness
    from 1 (top row) to 0. ``engine="filament"`` writes Filament's
    multiscatter form (red: bias ``B``, green: ``A + B``); the others Karis'
    scale and bias of F0 (red ``A``, green ``B``). ``output`` ends in
    ``.exr`` (float) or ``.png`` (8-bit values, not sRGB-encoded).

    Raises
    ------
    ShlightError
        Another extension, a size outside 1..4096, no samples.
    """
    _dfg(output, engine, size, samples)


def sample(
    file,
    output,
    *,
    points=None,
    env=None,
    light=None,
    up="y",
    lookup="shlight",
    view=None,
    eye=None,
    albedo=None,
    lmax=None,
):
    """What a baked file shades with, file to file (``shlight sample``).

    The same JSON (or CSV) file as ``shlight sample FILE -o OUTPUT`` with
    the same options: a volume's irradiance ``E(p, n)`` at the points of
    ``points`` (``Volume.irradiance``), a lightmapped scene's irradiance at
    points on its surfaces as the engine's shader reads the lightmap
    (``bake_lightmap``'s ``.glb``; docs/lightmaps.md), or a PRT file's exit
    radiance per vertex under ``light`` (``Transfer.exit_radiance``).

    Parameters
    ----------
    file : str | os.PathLike
        An irradiance volume (``.shvol``), a lightmapped scene (``.glb``
        from ``bake_lightmap`` or ``shlight lightmap``) or PRT transfer
        (``.shprt``).
    output : str | os.PathLike
        The answer: JSON (the values, the lookup, the file's provenance),
        or CSV rows ``r,g,b`` (``.csv``); written atomically.
    points : str | os.PathLike | Scene
        A volume's points: JSON ``{"points": [...], "normals": [...]}``,
        CSV rows ``x,y,z,nx,ny,nz``, or a mesh or glTF scene (a path, or a
        ``Scene`` from ``load_scene``): every vertex (a scene's flattened
        into world space) facing its normal.
    env : str | os.PathLike
        Relight a relightable volume under this light first (an equirect
        map or a radiance coefficient file).
    light : str | os.PathLike
        The distant light of a ``.shprt`` file.
    up : "y" | "z"
        The world axis a map light's top row faces.
    lookup : "shlight" | "trilinear" | "bevy" | "threejs"
        How a volume's light is read off its probes (``Volume.irradiance``).
    view, eye : (x, y, z)
        A glossy file's view: one direction from the vertices toward the
        eye, or the eye's position (not both).
    albedo : float | (r, g, b)
        A glossy file's diffuse base under its glossy layer.
    lmax : int
        The highest degree shaded.

    Raises
    ------
    ShlightError
        A missing or malformed file, options that do not fit the file; the
        CLI's messages in Python's spelling.
    """
    _sample(
        file,
        output,
        points=None if points is None else _scene_or_path(points),
        env=env,
        light=light,
        up=up,
        lookup=lookup,
        view=view,
        eye=eye,
        albedo=albedo,
        lmax=lmax,
    )
