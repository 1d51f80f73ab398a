//! Clustered principal component analysis (CPCA) of glossy transfer
//! matrices (Sloan, Hall, Hart & Snyder 2003), the compression a glossy
//! bake's matrices are meant to be stored and shaded in ([`Cpca`] states
//! the method).

use rand::{Rng, SeedableRng, rngs::StdRng};
use rayon::prelude::*;

/// Passes of Lloyd's iteration at most.
const KMEANS_PASSES: usize = 16;

/// Subspace iterations per cluster.
const SUBSPACE_PASSES: usize = 24;

/// A CPCA of `n` vectors of `dim` values.
///
/// Each vertex's matrix, flattened to a vector `x_p` of `dim` values, is
/// approximated as its cluster's mean plus `K` weighted basis vectors:
///
/// ```text
/// x_p ~ m_c + sum_k w_pk b_ck,   c = cluster(p),   w_pk = (x_p - m_c) . b_ck
/// ```
///
/// with the `b_ck` orthonormal: a renderer computes `m_c L` and `b_ck L`
/// once per cluster and light, and each vertex sums `K + 1` of them. This is
/// the paper's static CPCA: clusters by k-means (Lloyd's iteration, from
/// the vertices `i n / C` as seeds, until no vertex changes cluster or 16
/// passes), then per cluster the `K` leading principal directions of its
/// members by subspace iteration (`X^T X V`, orthonormalised, from a seeded
/// start; exact once `K` reaches the cluster's rank, since `X^T X V` then
/// spans every direction the members take), all sums in `f64`.
///
/// With `C` the vertex count, or `K` at least each cluster's member count
/// (or `dim`), the matrices are reproduced but for `f32` rounding.
///
/// [`compress_file`] compresses a glossy `.shprt` file's matrices in place
/// (`shlight prt --compress cpca:C,K`); the file then keeps the means, bases,
/// cluster indices and weights (docs/shprt.md).
#[derive(Clone, Debug, PartialEq)]
pub struct Cpca {
    /// Values per vector.
    pub dim: usize,
    /// Clusters `C` (at most the vector count).
    pub clusters: usize,
    /// Basis vectors per cluster `K`.
    pub vectors: usize,
    /// `C x dim` cluster means.
    pub means: Vec<f32>,
    /// `C x K x dim` orthonormal basis vectors (zero where a cluster has
    /// fewer directions than `K`).
    pub bases: Vec<f32>,
    /// Each vector's cluster.
    pub cluster: Vec<u32>,
    /// `n x K` weights.
    pub weights: Vec<f32>,
}

impl Cpca {
    /// The vectors as the compression gives them back,
    /// `m_c + sum_k w_k b_ck`, `n x dim`.
    #[must_use]
    pub fn reconstruct(&self) -> Vec<f32> {
        let (d, k) = (self.dim, self.vectors);
        let mut out = vec![0.0f32; self.cluster.len() * d];
        out.par_chunks_mut(d)
            .zip(self.cluster.par_iter())
            .enumerate()
            .for_each(|(i, (x, &c))| {
                let c = c as usize;
                let w = &self.weights[i * k..][..k];
                let mut acc: Vec<f64> = self.means[c * d..][..d]
                    .iter()
                    .map(|&m| f64::from(m))
                    .collect();
                for (j, &wj) in w.iter().enumerate() {
                    let b = &self.bases[(c * k + j) * d..][..d];
                    for (a, bi) in acc.iter_mut().zip(b) {
                        *a += f64::from(wj) * f64::from(*bi);
                    }
                }
                for (xi, a) in x.iter_mut().zip(&acc) {
                    *xi = *a as f32;
                }
            });
        out
    }

    /// Floats stored: means, bases, and per vector its cluster index and
    /// weights.
    #[must_use]
    pub fn stored_floats(&self) -> usize {
        self.means.len() + self.bases.len() + self.cluster.len() * (1 + self.vectors)
    }
}

/// Parses `cpca:C,K` (`C >= 1` clusters, `K >= 0` vectors each).
///
/// # Errors
/// A message saying what `cpca:C,K` takes.
pub fn parse_cpca(text: &str) -> Result<(usize, usize), String> {
    let parsed = text
        .trim()
        .strip_prefix("cpca:")
        .and_then(|r| r.split_once(','))
        .and_then(|(c, k)| {
            Some((
                c.trim().parse::<usize>().ok()?,
                k.trim().parse::<usize>().ok()?,
            ))
        });
    match parsed {
        Some((c, k)) if c >= 1 => Ok((c, k)),
        _ => Err(format!(
            "compression \"{text}\" is not cpca:C,K (C >= 1 clusters of K basis vectors, e.g. cpca:64,8)"
        )),
    }
}

/// How far a compression is from the matrices it replaced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompressionError {
    /// Root mean square of the entries' errors.
    pub rms: f64,
    /// Root mean square of the entries themselves.
    pub rms_entries: f64,
    /// Bytes of the matrices before.
    pub bytes_before: u64,
    /// Bytes of the compressed form.
    pub bytes_after: u64,
}

/// Compresses a glossy file's matrices in place into `clusters` clusters
/// of `vectors` basis vectors ([`compress`], the vectors being each
/// vertex's matrices, all channels), and says how far the compression is
/// from them.
///
/// # Errors
/// A diffuse or already compressed file, or `vectors` beyond a vertex's
/// matrix entries.
pub fn compress_file(
    file: &mut shlight_format::ShprtFile,
    clusters: usize,
    vectors: usize,
    seed: u64,
) -> Result<CompressionError, String> {
    let dim = file.channels * file.coeffs_per_channel();
    let Some(glossy) = file.glossy.as_mut() else {
        return Err("only glossy transfer matrices are compressed (a glossy bake)".into());
    };
    if glossy.cpca.is_some() {
        return Err("the matrices are compressed already".into());
    }
    let z = compress(&file.transfer, dim, clusters, vectors, seed)?;
    let back = z.reconstruct();
    let n = file.transfer.len().max(1) as f64;
    let rms = (back
        .iter()
        .zip(&file.transfer)
        .map(|(a, b)| (f64::from(*a) - f64::from(*b)).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
    let rms_entries = (file
        .transfer
        .iter()
        .map(|x| f64::from(*x).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
    let error = CompressionError {
        rms,
        rms_entries,
        bytes_before: 4 * file.transfer.len() as u64,
        bytes_after: 4 * z.stored_floats() as u64,
    };
    glossy.cpca = Some(shlight_format::CpcaData {
        clusters: z.clusters,
        vectors: z.vectors,
        means: z.means,
        bases: z.bases,
        cluster: z.cluster,
        weights: z.weights,
    });
    file.transfer = Vec::new();
    Ok(error)
}

/// The matrices a file's compressed form gives back (`dim` values per
/// vertex: its channels' matrices).
#[must_use]
pub fn reconstruct_data(z: &shlight_format::CpcaData, dim: usize) -> Vec<f32> {
    Cpca {
        dim,
        clusters: z.clusters,
        vectors: z.vectors,
        means: z.means.clone(),
        bases: z.bases.clone(),
        cluster: z.cluster.clone(),
        weights: z.weights.clone(),
    }
    .reconstruct()
}

/// Squared distance in `f64`.
fn distance2(a: &[f32], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            let d = f64::from(*x) - y;
            d * d
        })
        .sum()
}

/// Compresses `data` (`n` vectors of `dim` values, one after another) into
/// `clusters` clusters of `vectors` basis vectors each (`clusters` is
/// taken down to `n`). Deterministic for `seed`.
///
/// # Errors
/// An empty or ragged `data`, `dim` 0, `clusters` 0, or `vectors` beyond
/// `dim`.
pub fn compress(
    data: &[f32],
    dim: usize,
    clusters: usize,
    vectors: usize,
    seed: u64,
) -> Result<Cpca, String> {
    if dim == 0 || data.is_empty() || !data.len().is_multiple_of(dim) {
        return Err(format!(
            "CPCA needs whole vectors: {} values are not a positive multiple of {dim}",
            data.len()
        ));
    }
    if clusters == 0 {
        return Err("CPCA needs at least one cluster".into());
    }
    if vectors > dim {
        return Err(format!(
            "CPCA of {dim}-value vectors takes at most {dim} basis vectors per cluster, not {vectors}"
        ));
    }
    let n = data.len() / dim;
    let c_count = clusters.min(n);
    let row = |i: usize| &data[i * dim..][..dim];
    // Lloyd's iteration from evenly spaced seeds.
    let mut centres: Vec<Vec<f64>> = (0..c_count)
        .map(|c| row(c * n / c_count).iter().map(|&x| f64::from(x)).collect())
        .collect();
    let mut cluster = vec![u32::MAX; n];
    for _ in 0..KMEANS_PASSES {
        let next: Vec<u32> = (0..n)
            .into_par_iter()
            .map(|i| {
                let x = row(i);
                let mut best = (f64::INFINITY, 0u32);
                for (c, m) in centres.iter().enumerate() {
                    let d = distance2(x, m);
                    if d < best.0 {
                        best = (d, c as u32);
                    }
                }
                best.1
            })
            .collect();
        let changed = next != cluster;
        cluster = next;
        let mut sums = vec![vec![0.0f64; dim]; c_count];
        let mut counts = vec![0usize; c_count];
        for (i, &c) in cluster.iter().enumerate() {
            counts[c as usize] += 1;
            for (s, x) in sums[c as usize].iter_mut().zip(row(i)) {
                *s += f64::from(*x);
            }
        }
        for ((centre, sum), &count) in centres.iter_mut().zip(sums).zip(&counts) {
            if count > 0 {
                *centre = sum.into_iter().map(|s| s / count as f64).collect();
            }
        }
        if !changed {
            break;
        }
    }
    // Members per cluster.
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); c_count];
    for (i, &c) in cluster.iter().enumerate() {
        members[c as usize].push(i);
    }
    let k = vectors;
    // Per cluster: its basis (K x dim, f64).
    let bases: Vec<Vec<f64>> = members
        .par_iter()
        .zip(&centres)
        .enumerate()
        .map(|(c, (idx, mean))| {
            let centred: Vec<Vec<f64>> = idx
                .iter()
                .map(|&i| {
                    row(i)
                        .iter()
                        .zip(mean)
                        .map(|(x, m)| f64::from(*x) - m)
                        .collect()
                })
                .collect();
            principal_directions(
                &centred,
                dim,
                k,
                seed ^ (c as u64).wrapping_mul(0x9e37_79b9),
            )
        })
        .collect();
    let mut weights = vec![0.0f32; n * k];
    if k > 0 {
        weights.par_chunks_mut(k).enumerate().for_each(|(i, w)| {
            let c = cluster[i] as usize;
            let x = row(i);
            for (j, wj) in w.iter_mut().enumerate() {
                let b = &bases[c][j * dim..][..dim];
                *wj = x
                    .iter()
                    .zip(&centres[c])
                    .zip(b)
                    .map(|((x, m), b)| (f64::from(*x) - m) * b)
                    .sum::<f64>() as f32;
            }
        });
    }
    Ok(Cpca {
        dim,
        clusters: c_count,
        vectors: k,
        means: centres.iter().flatten().map(|&m| m as f32).collect(),
        bases: bases.iter().flatten().map(|&b| b as f32).collect(),
        cluster,
        weights,
    })
}

/// The `k` leading principal directions of the rows `x` (centred), as `k`
/// orthonormal rows of `dim` (zero rows past the rows' rank), by subspace
/// iteration `V <- orth(X^T X V)` from a seeded start.
fn principal_directions(x: &[Vec<f64>], dim: usize, k: usize, seed: u64) -> Vec<f64> {
    let mut v = vec![0.0f64; k * dim];
    if k == 0 || x.is_empty() {
        return v;
    }
    let mut rng = StdRng::seed_from_u64(seed);
    v.iter_mut().for_each(|e| *e = rng.random::<f64>() - 0.5);
    let scale: f64 = x.iter().flatten().map(|e| e * e).sum::<f64>().sqrt();
    if scale == 0.0 {
        v.fill(0.0);
        return v;
    }
    orthonormalise(&mut v, dim, 0.0);
    let mut xv = vec![0.0f64; x.len() * k];
    for _ in 0..SUBSPACE_PASSES {
        // X V: rows of x against each basis vector.
        for (r, row) in x.iter().enumerate() {
            for j in 0..k {
                xv[r * k + j] = row
                    .iter()
                    .zip(&v[j * dim..][..dim])
                    .map(|(a, b)| a * b)
                    .sum();
            }
        }
        // X^T (X V).
        v.fill(0.0);
        for (r, row) in x.iter().enumerate() {
            for j in 0..k {
                let s = xv[r * k + j];
                for (o, a) in v[j * dim..][..dim].iter_mut().zip(row) {
                    *o += s * a;
                }
            }
        }
        // Directions the rows do not take come out near zero: dropped.
        orthonormalise(&mut v, dim, 1e-12 * scale * scale);
    }
    v
}

/// Modified Gram-Schmidt, twice, on the rows of `v`; rows whose norm
/// before normalising is at most `floor` (or 1e-13 of their norm before
/// orthogonalising) become zero.
fn orthonormalise(v: &mut [f64], dim: usize, floor: f64) {
    let k = v.len() / dim;
    for _ in 0..2 {
        for j in 0..k {
            let before: f64 = v[j * dim..][..dim]
                .iter()
                .map(|a| a * a)
                .sum::<f64>()
                .sqrt();
            for i in 0..j {
                let (head, tail) = v.split_at_mut(j * dim);
                let bi = &head[i * dim..][..dim];
                let bj = &mut tail[..dim];
                let p: f64 = bi.iter().zip(bj.iter()).map(|(a, b)| a * b).sum();
                for (b, a) in bj.iter_mut().zip(bi) {
                    *b -= p * a;
                }
            }
            let row = &mut v[j * dim..][..dim];
            let norm: f64 = row.iter().map(|a| a * a).sum::<f64>().sqrt();
            if norm <= floor || norm <= 1e-13 * before || norm == 0.0 {
                row.fill(0.0);
            } else {
                row.iter_mut().for_each(|a| *a /= norm);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rms(a: &[f32], b: &[f32]) -> f64 {
        (a.iter()
            .zip(b)
            .map(|(x, y)| (f64::from(*x) - f64::from(*y)).powi(2))
            .sum::<f64>()
            / a.len() as f64)
            .sqrt()
    }

    /// Three well-separated clusters, each in its own 2-D affine subspace
    /// of R^12, members of a cluster one after another.
    fn planes() -> (Vec<f32>, usize) {
        let dim = 12;
        let mut rng = StdRng::seed_from_u64(4);
        let mut data = Vec::new();
        for c in 0..3 {
            let offset: Vec<f64> = (0..dim)
                .map(|i| if i == c { 100.0 } else { rng.random::<f64>() })
                .collect();
            let axes: Vec<Vec<f64>> = (0..2)
                .map(|_| (0..dim).map(|_| rng.random::<f64>() - 0.5).collect())
                .collect();
            for _ in 0..40 {
                let (s, t) = (
                    rng.random::<f64>() * 4.0 - 2.0,
                    rng.random::<f64>() * 4.0 - 2.0,
                );
                data.extend((0..dim).map(|i| (offset[i] + s * axes[0][i] + t * axes[1][i]) as f32));
            }
        }
        (data, dim)
    }

    #[test]
    fn clusters_in_planes_are_found_and_reproduced_by_two_vectors_each() {
        let (data, dim) = planes();
        let two = compress(&data, dim, 3, 2, 1).unwrap();
        assert!(
            rms(&two.reconstruct(), &data) < 1e-4,
            "{}",
            rms(&two.reconstruct(), &data)
        );
        // Each cluster is one plane: 40 members each, in order.
        for c in 0..3 {
            assert!(
                two.cluster[c * 40..][..40]
                    .iter()
                    .all(|&x| x == two.cluster[c * 40])
            );
        }
        // One vector per cluster leaves the second direction out.
        let one = compress(&data, dim, 3, 1, 1).unwrap();
        assert!(rms(&one.reconstruct(), &data) > 0.05);
        // The bases are orthonormal.
        for c in 0..3 {
            let b = &two.bases[c * 2 * dim..][..2 * dim];
            let dot = |i: usize, j: usize| -> f32 {
                (0..dim).map(|e| b[i * dim + e] * b[j * dim + e]).sum()
            };
            assert!((dot(0, 0) - 1.0).abs() < 1e-5 && (dot(1, 1) - 1.0).abs() < 1e-5);
            assert!(dot(0, 1).abs() < 1e-5);
        }
    }

    #[test]
    fn at_the_most_clusters_or_vectors_the_data_comes_back_and_error_falls_with_k() {
        let mut rng = StdRng::seed_from_u64(8);
        let (n, dim) = (60, 9);
        let data: Vec<f32> = (0..n * dim)
            .map(|_| rng.random::<f32>() * 2.0 - 1.0)
            .collect();
        // A cluster per vector: the means are the vectors.
        let each = compress(&data, dim, n, 0, 0).unwrap();
        assert_eq!(each.reconstruct(), data);
        // Clusters beyond the vectors are taken down to them.
        assert_eq!(compress(&data, dim, 10 * n, 0, 0).unwrap().clusters, n);
        // One cluster, every direction.
        let all = compress(&data, dim, 1, dim, 0).unwrap();
        assert!(rms(&all.reconstruct(), &data) < 1e-6);
        // Fewer vectors: the error grows as directions are left out.
        let errors: Vec<f64> = (0..=dim)
            .map(|k| rms(&compress(&data, dim, 2, k, 0).unwrap().reconstruct(), &data))
            .collect();
        for w in errors.windows(2) {
            assert!(w[1] <= w[0] + 1e-9, "{errors:?}");
        }
        assert!(errors[0] > 0.3 && errors[dim] < 1e-6, "{errors:?}");
        assert_eq!(all.stored_floats(), dim + dim * dim + n * (1 + dim));
        for (bad, says) in [
            (compress(&data, 7, 1, 0, 0), "whole vectors"),
            (compress(&data, dim, 0, 0, 0), "at least one cluster"),
            (compress(&data, dim, 1, dim + 1, 0), "at most 9"),
            (compress(&[], dim, 1, 0, 0), "whole vectors"),
        ] {
            assert!(bad.unwrap_err().contains(says));
        }
    }
}
