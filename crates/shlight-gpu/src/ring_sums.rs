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
//! `(cos ψ, sin ψ)` by complex multiplication (`sh_expansion`'s
//! [`azimuth_power`]), so a texel costs `2 lmax + 1` multiply-adds per
//! colour channel and no trigonometry. The second pass weighs the rows by
//! `Ω_j Pbar_l^m(cos θ_j)` (`sqrt2` for `m > 0`) to give the coefficients
//! about the map's pole: the ring transform of shlight-core's
//! `project_equirect`.
//!
//! A workgroup of [`ROW_THREADS`] invocations sums one row: invocation `t`
//! takes texels `t, t + 64, ...` into `2 lmax + 1` accumulators (registers:
//! every index is a constant), then the workgroup adds the 64 partial sums
//! of each of the `3 (2 lmax + 1)` scalars by a tree in workgroup memory
//! (6 rounds, one barrier each) and invocation 0 writes the row's slots.
//!
//! Why generated: written with loops over `m` to a run-time lmax, the
//! accumulators would be a function-local array indexed by a loop variable,
//! which Mesa's llvmpipe keeps in memory lane by lane; written out for a
//! fixed lmax they are registers on any GPU.

use std::fmt::Write;

use shlight_core::legendre::legendre_count;

use crate::MAX_LMAX;
use crate::sh_expansion::azimuth_power;

/// Invocations per row in the first pass (the workgroup size).
pub(crate) const ROW_THREADS: usize = 64;

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
/// `ring_sums` for `lmax` (clamped to [`MAX_LMAX`]).
#[must_use]
pub(crate) fn ring_sums_wgsl(lmax: usize) -> String {
    let lmax = lmax.min(MAX_LMAX);
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
    w("// Partial sums of the row: scalar q = 3 slot + channel of invocation t at q * ROW_THREADS + t.".into());
    w(format!(
        "var<workgroup> ring_scratch: array<f32, {}>;",
        3 * slots * n
    ));
    w(String::new());
    w("// Adds the ring sums of map row `row` (row `local_row` of `texels`) into".into());
    w("// `rings[row * RING_SLOTS + slot]`; invocation `t` of the row's workgroup.".into());
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
        "for (var x = t; x < params.width; x = x + ROW_THREADS) {".into(),
    );
    line(2, "let k = 3u * (local_row * params.width + x);".into());
    line(
        2,
        "let f = vec3<f32>(texels[k], texels[k + 1u], texels[k + 2u]);".into(),
    );
    line(2, format!("r{} = r{0} + f;", ring_slot(0, false)));
    if lmax > 0 {
        line(2, "let col = columns[x];".into());
    }
    for m in 1..=lmax {
        for text in azimuth_power(m, "col.x", "col.y") {
            line(2, text);
        }
        let (c, s) = (ring_slot(m, false), ring_slot(m, true));
        line(2, format!("r{c} = r{c} + f * c{m};"));
        line(2, format!("r{s} = r{s} + f * s{m};"));
    }
    line(1, "}".into());
    let scalar = |slot: usize, ch: usize| (3 * slot + ch) * n;
    for slot in 0..slots {
        for (ch, name) in ["x", "y", "z"].iter().enumerate() {
            line(
                1,
                format!("ring_scratch[{}u + t] = r{slot}.{name};", scalar(slot, ch)),
            );
        }
    }
    line(1, "workgroupBarrier();".into());
    line(
        1,
        "for (var s = ROW_THREADS / 2u; s > 0u; s = s >> 1u) {".into(),
    );
    line(2, "if t < s {".into());
    for q in 0..3 * slots {
        let base = q * n;
        line(
            3,
            format!(
                "ring_scratch[{base}u + t] = ring_scratch[{base}u + t] + ring_scratch[{base}u + t + s];"
            ),
        );
    }
    line(2, "}".into());
    line(2, "workgroupBarrier();".into());
    line(1, "}".into());
    line(1, "if t == 0u {".into());
    line(2, "let base = row * RING_SLOTS;".into());
    for slot in 0..slots {
        line(
            2,
            format!(
                "rings[base + {slot}u] = vec4<f32>(ring_scratch[{}u], ring_scratch[{}u], ring_scratch[{}u], 0.0);",
                scalar(slot, 0),
                scalar(slot, 1),
                scalar(slot, 2)
            ),
        );
    }
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
        for lmax in 0..=MAX_LMAX {
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
    fn every_slot_is_accumulated_once_and_written_once() {
        for lmax in 0..=MAX_LMAX {
            let text = ring_sums_wgsl(lmax);
            let slots = ring_slots(lmax);
            for slot in 0..slots {
                assert_eq!(
                    text.matches(&format!("r{slot} = r{slot} + f")).count(),
                    1,
                    "lmax {lmax}: slot {slot}\n{text}"
                );
                assert_eq!(
                    text.matches(&format!("rings[base + {slot}u]")).count(),
                    1,
                    "lmax {lmax}: slot {slot}\n{text}"
                );
            }
            assert!(!text.contains(&format!("r{slots} ")), "{text}");
            assert!(!text.contains(&format!("rings[base + {slots}u]")), "{text}");
            assert!(!text.contains(&format!("let c{} ", lmax + 1)), "{text}");
        }
    }
}
