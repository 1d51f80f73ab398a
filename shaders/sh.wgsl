// Real orthonormal spherical harmonics on the GPU (shaders/README.md).
//
// shlight's basis (docs/conventions.md): Condon-Shortley phase included,
// flat index i = l(l+1) + m, polar axis world +z. With z = cos(theta) and
// x + i y = sin(theta) e^{i phi}, write Y_l^m through
//
//   Q_l^m = Pbar_l^m(z) / sin(theta)^m,   C_m + i S_m = (x + i y)^m,
//   Y_l^m = sqrt2 Q_l^m C_m (m > 0),  Y_l^0 = Q_l^0,  Y_l^-m = sqrt2 Q_l^m S_m,
//
// where Q obeys the same recurrences as the SH-normalised Pbar with the
// sin(theta) factor dropped (so nothing divides by sin(theta) at the poles):
//
//   Q_0^0 = 1/sqrt(4 pi),  Q_m^m = -sqrt((2m+1)/(2m)) Q_{m-1}^{m-1},
//   Q_{m+1}^m = sqrt(2m+3) z Q_m^m,
//   Q_l^m = a (z Q_{l-1}^m - b Q_{l-2}^m),
//   a = sqrt((4l^2-1)/(l^2-m^2)),  b = sqrt(((l-1)^2-m^2)/(4(l-1)^2-1)).
//
// Any lmax up to SH_MAX_LMAX; nothing is hard-wired to 9 coefficients.

// Highest degree the shaders evaluate.
const SH_MAX_LMAX: u32 = 8u;
// (SH_MAX_LMAX + 1)^2.
const SH_MAX_COUNT: u32 = 81u;
const SH_PI: f32 = 3.14159265358979;
const SH_SQRT2: f32 = 1.41421356237310;

// Coefficient count (lmax + 1)^2.
fn sh_count(lmax: u32) -> u32 {
    return (lmax + 1u) * (lmax + 1u);
}

// Writes Y_i(d), i < sh_count(lmax), into y, for a unit direction d.
fn sh_basis(d: vec3<f32>, lmax_in: u32, y: ptr<function, array<f32, 81>>) {
    let lmax = min(lmax_in, SH_MAX_LMAX);
    let z = d.z;
    var c = 1.0;
    var s = 0.0;
    var qmm = 0.282094791773878;
    for (var m = 0u; m <= lmax; m = m + 1u) {
        let mf = f32(m);
        if m > 0u {
            qmm = -sqrt((2.0 * mf + 1.0) / (2.0 * mf)) * qmm;
            let c2 = c * d.x - s * d.y;
            s = c * d.y + s * d.x;
            c = c2;
        }
        var q_prev2 = 0.0;
        var q_prev = qmm;
        for (var l = m; l <= lmax; l = l + 1u) {
            let lf = f32(l);
            var q = qmm;
            if l == m + 1u {
                q = sqrt(2.0 * mf + 3.0) * z * qmm;
            } else if l > m + 1u {
                let a = sqrt((4.0 * lf * lf - 1.0) / (lf * lf - mf * mf));
                let b = sqrt(((lf - 1.0) * (lf - 1.0) - mf * mf) / (4.0 * (lf - 1.0) * (lf - 1.0) - 1.0));
                q = a * (z * q_prev - b * q_prev2);
            }
            if l > m {
                q_prev2 = q_prev;
                q_prev = q;
            }
            let centre = l * (l + 1u);
            if m == 0u {
                (*y)[centre] = q;
            } else {
                (*y)[centre + m] = SH_SQRT2 * q * c;
                (*y)[centre - m] = SH_SQRT2 * q * s;
            }
        }
    }
}

// Band of coefficient index i: the l with l^2 <= i < (l+1)^2.
fn sh_band(i: u32) -> u32 {
    var l = u32(sqrt(f32(i)));
    if (l + 1u) * (l + 1u) <= i {
        l = l + 1u;
    }
    if l * l > i {
        l = l - 1u;
    }
    return l;
}
