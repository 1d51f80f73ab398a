//! The WGSL function `ring_sums` of the projection's first pass
//! (`shaders/project.wgsl`), written out as straight-line code for one lmax.
//!
//! For row `j` of an equirect map and the azimuths `ψ_x` of its texels about
//! the map's pole, the ring sums are
//!
//! ```text
//! C_m(j) = sum_x f(x, j) cos(m ψ_x),   S_m(j) = sum_x f(x, j) sin(m ψ_x),   0 <= m <= lmax,
//! ```
//!
//! stored as `2 lmax + 1` slots per row: slot 0 is `C_0`, slot `2m - 1` is
//! `C_m` and slot `2m` is `S_m` ([`ring_slot`]). Each texel's
//! `cos(m ψ) + i sin(m ψ) = (cos ψ + i sin ψ)^m` comes from the column's
//! `(cos ψ, sin ψ)` by complex multiplication (shlight-shader's
//! [`azimuth_power`], the basis's), so a texel costs `2 lmax + 1` multiply-adds per
//! colour channel and no trigonometry. The second pass weighs the rows by
//! `Ω_j Pbar_l^m(cos θ_j)` (`sqrt2` for `m > 0`) to give the coefficients
//! about the map's pole: the ring transform of shlight-core's
//! `project_equirect`.
//!
//! A workgroup of [`ROW_THREADS`] (32) invocations sums one row, in quads
//! of four texels (three `vec4` loads of packed RGB, two `vec4` of
//! azimuths): invocation `t` takes quads `t, t + 32, ...` into `2 lmax + 1`
//! accumulators (registers: every index is a constant). The workgroup then
//! writes its `32 x 3 (2 lmax + 1)` partial sums to workgroup memory
//! (invocation-major: `3 (2 lmax + 1)` is odd, so both this write and the
//! read below touch distinct shared-memory banks on a GPU), and invocation
//! `t` adds the 32 partial sums of scalars `t, t + 32, ...` below
//! `3 (2 lmax + 1)` and writes them: one barrier.
//!
//! Measured on Mesa's lavapipe (docs/benchmarks.md, "GPU"), where every load from a
//! storage buffer or workgroup memory is a separate bounds-checked access
//! per lane and component: the texel loads alone (lmax 0) take about half
//! the pass at lmax 8; this reduction costs a third of the accesses of a
//! tree and one barrier instead of six; 32 invocations per row rather than
//! 64 halve it again (pass 1 at lmax 8: about 125 ms with 64, 100 ms with
//! 32). On a GPU, 32 per row still gives 32,768 invocations for a 2048-row
//! map's 1024 rows, each with five independent loads per quad in flight.

//! Why generated: written with loops over `m` to a run-time lmax, the
//! accumulators would be a function-local array indexed by a loop variable,
//! which Mesa's llvmpipe keeps in memory lane by lane; written out for a
//! fixed lmax they are registers on any GPU.

use std::fmt::Write;

use shlight_core::sh::legendre_count;

use shlight_baked::LIGHT_MAX_LMAX;
use shlight_shader::Language;
use shlight_shader::basis::azimuth_power;

/// Invocations per row in the first pass (the workgroup size; a GPU's
/// 32-wide warp, and few partial sums for llvmpipe to reduce).
pub(crate) const ROW_THREADS: usize = 32;

/// Ring-sum slots per row for `lmax`: `C_0`, then `C_m`, `S_m` for each `m >= 1`.
#[must_use]
pub(crate) const fn ring_slots(lmax: usize) -> usize {
    2 * lmax + 1
}

/// The slot of `C_m` (`sine = false`) or `S_m` (`sine = true`, `m >= 1`).
#[must_use]
pub(crate) const fn ring_slot(m: usize, sine: bool) -> usize {
    if m == 0 {
        0
    } else if sine {
        2 * m
    } else {
        2 * m - 1
    }
}

/// The WGSL text of the first pass's constants, workgroup memory and
/// `ring_sums` for `lmax` (clamped to [`LIGHT_MAX_LMAX`]).
#[must_use]
pub(crate) fn ring_sums_wgsl(lmax: usize) -> String {
    let lmax = lmax.min(LIGHT_MAX_LMAX);
    let slots = ring_slots(lmax);
    let n = ROW_THREADS;
    let mut out = String::new();
    let mut w = |text: String| {
        out.push_str(&text);
        out.push('\n');
    };
    w(format!(
        "// Generated for lmax {lmax} (crates/shlight-gpu/src/ring_sums.rs)."
    ));
    w(format!("const ROW_THREADS: u32 = {n}u;"));
    w(format!(
        "// Ring-sum slots per row: C_0, then C_m, S_m for m = 1..{lmax}."
    ));
    w(format!("const RING_SLOTS: u32 = {slots}u;"));
    w("// Pbar_l^m per row in `weights`, l (l + 1) / 2 + m.".into());
    w(format!(
        "const LEGENDRE_COUNT: u32 = {}u;",
        legendre_count(lmax)
    ));
    w("// Scalars per row, 3 RING_SLOTS (odd: the scratch's two access patterns".into());
    w("// spread over a GPU's shared-memory banks).".into());
    w(format!("const RING_SCALARS: u32 = {}u;", 3 * slots));
    w("// Partial sums of the row: scalar 3 slot + channel of invocation t at t * RING_SCALARS + scalar.".into());
    w(format!(
        "var<workgroup> ring_scratch: array<f32, {}>;",
        3 * slots * n
    ));
    w(String::new());
    w("// Writes the ring sums of map row `row` (row `local_row` of `texels`) to".into());
    w(
        "// `rings[row * RING_SCALARS + 3 slot + channel]`; invocation `t` of the row's workgroup."
            .into(),
    );
    w("fn ring_sums(local_row: u32, row: u32, t: u32) {".into());
    let mut body = String::new();
    let mut line = |indent: usize, text: String| {
        let _ = writeln!(body, "{}{text}", "    ".repeat(indent));
    };
    for slot in 0..slots {
        line(1, format!("var r{slot} = vec3<f32>(0.0);"));
    }
    line(
        1,
        "for (var q = t; q < params.quads; q = q + ROW_THREADS) {".into(),
    );
    line(2, "let k = 3u * (local_row * params.quads + q);".into());
    line(2, "let v0 = texels[k];".into());
    line(2, "let v1 = texels[k + 1u];".into());
    line(2, "let v2 = texels[k + 2u];".into());
    if lmax > 0 {
        line(2, "let ab = columns[2u * q];".into());
        line(2, "let cd = columns[2u * q + 1u];".into());
    }
    // The quad's four texels (RGB packed in three vec4) and azimuths.
    let quad = [
        ("v0.xyz", "ab.x", "ab.y"),
        ("vec3<f32>(v0.w, v1.xy)", "ab.z", "ab.w"),
        ("vec3<f32>(v1.zw, v2.x)", "cd.x", "cd.y"),
        ("v2.yzw", "cd.z", "cd.w"),
    ];
    for (f, x, y) in quad {
        line(2, "{".into());
        line(3, format!("let f = {f};"));
        line(3, format!("r{} = r{0} + f;", ring_slot(0, false)));
        for m in 1..=lmax {
            for text in azimuth_power(Language::Wgsl, m, "", x, y) {
                line(3, text);
            }
            let (c, s) = (ring_slot(m, false), ring_slot(m, true));
            line(3, format!("r{c} = r{c} + f * c{m};"));
            line(3, format!("r{s} = r{s} + f * s{m};"));
        }
        line(2, "}".into());
    }
    line(1, "}".into());
    // Scalar `3 slot + channel` of invocation t at t * SCALARS + scalar.
    for slot in 0..slots {
        for (ch, name) in ["x", "y", "z"].iter().enumerate() {
            line(
                1,
                format!(
                    "ring_scratch[t * RING_SCALARS + {}u] = r{slot}.{name};",
                    3 * slot + ch
                ),
            );
        }
    }
    line(1, "workgroupBarrier();".into());
    // More scalars than invocations from lmax 5 on: some take two.
    line(
        1,
        "for (var q = t; q < RING_SCALARS; q = q + ROW_THREADS) {".into(),
    );
    line(2, "var sum = 0.0;".into());
    line(2, "for (var i = 0u; i < ROW_THREADS; i = i + 1u) {".into());
    line(3, "sum = sum + ring_scratch[i * RING_SCALARS + q];".into());
    line(2, "}".into());
    line(2, "rings[row * RING_SCALARS + q] = sum;".into());
    line(1, "}".into());
    out.push_str(&body);
    out.push_str("}\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slots_are_a_bijection_onto_0_to_2_lmax() {
        for lmax in 0..=LIGHT_MAX_LMAX {
            let mut seen = vec![false; ring_slots(lmax)];
            for m in 0..=lmax {
                for sine in if m == 0 {
                    vec![false]
                } else {
                    vec![false, true]
                } {
                    let slot = ring_slot(m, sine);
                    assert!(!seen[slot], "lmax {lmax}: slot {slot} twice");
                    seen[slot] = true;
                }
            }
            assert!(seen.iter().all(|&s| s), "lmax {lmax}: {seen:?}");
        }
    }

    #[test]
    fn every_slot_sums_each_texel_of_a_quad_once_and_is_reduced_once() {
        for lmax in 0..=LIGHT_MAX_LMAX {
            let text = ring_sums_wgsl(lmax);
            let slots = ring_slots(lmax);
            for slot in 0..slots {
                assert_eq!(
                    text.matches(&format!("r{slot} = r{slot} + f")).count(),
                    4,
                    "lmax {lmax}: slot {slot}\n{text}"
                );
            }
            for q in 0..3 * slots {
                assert_eq!(
                    text.matches(&format!("ring_scratch[t * RING_SCALARS + {q}u]"))
                        .count(),
                    1,
                    "lmax {lmax}: scalar {q}\n{text}"
                );
            }
            let beyond = 3 * slots;
            assert!(!text.contains(&format!("r{slots} ")), "{text}");
            assert!(
                !text.contains(&format!("RING_SCALARS + {beyond}u]")),
                "{text}"
            );
            assert!(!text.contains(&format!("let c{} ", lmax + 1)), "{text}");
        }
    }
}
