"""A numpy projection of an equirect map to lmax 2 written the obvious way,
from the formulas of docs/conventions.md alone (no shlight code): the
independent route the tests compare shlight with, and the numpy baseline of
benches/python_peers.py."""

import numpy as np


def equirect_directions(width, height, up="y"):
    """Texel-centre directions (H, W, 3) of docs/conventions.md, "Frames"."""
    u = (np.arange(width) + 0.5) / width
    v = (np.arange(height) + 0.5) / height
    theta = np.pi * v[:, None]
    phi = 2 * np.pi * (u[None, :] - 0.5)
    s, c = np.sin(theta), np.cos(theta)
    x = s * np.cos(phi)
    if up == "y":
        y, z = np.broadcast_to(c, x.shape), s * np.sin(phi)
    else:
        y, z = -s * np.sin(phi), np.broadcast_to(c, x.shape)
    return np.stack([x, y, z], axis=-1)


def row_solid_angles(width, height):
    """Exact solid angle of a texel of each row:
    (2 pi / W) (cos(j pi / H) - cos((j + 1) pi / H))."""
    j = np.arange(height)
    return (2 * np.pi / width) * (np.cos(j * np.pi / height) - np.cos((j + 1) * np.pi / height))


def sh_basis_l2(d):
    """The nine real orthonormal SH with the Condon-Shortley phase, index
    l*(l+1)+m, at unit directions d (..., 3) -> (..., 9)."""
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    k0 = 0.5 * np.sqrt(1 / np.pi)
    k1 = np.sqrt(3 / (4 * np.pi))
    k2 = 0.5 * np.sqrt(15 / np.pi)
    k20 = 0.25 * np.sqrt(5 / np.pi)
    k22 = 0.25 * np.sqrt(15 / np.pi)
    return np.stack(
        [
            np.full_like(x, k0),
            -k1 * y,
            k1 * z,
            -k1 * x,
            k2 * x * y,
            -k2 * y * z,
            k20 * (3 * z * z - 1),
            -k2 * x * z,
            k22 * (x * x - y * y),
        ],
        axis=-1,
    )


def project_l2(image, up="y"):
    """Radiance coefficients (9, 3) of an equirect (H, W, 3) map:
    sum over texels of L Y Omega, accumulated in float64."""
    h, w, _ = image.shape
    basis = sh_basis_l2(equirect_directions(w, h, up))
    weights = row_solid_angles(w, h)[:, None, None] * basis
    return np.einsum("hwk,hwc->kc", weights, image.astype(np.float64))
