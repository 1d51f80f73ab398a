//! [`GlossyView`]: glossy PRT transfer matrices (Sloan, Kautz & Snyder
//! 2002, §5), plain or compressed by clustered PCA (Sloan, Hall, Hart &
//! Snyder 2003), and the transferred radiance they give under a light
//! ([`TransferredRadiance`]): the one definition `shlight sample` and the
//! renderer both shade glossy files from.
//!
//! Vertex `p`'s transferred radiance is `T_p = M_p L` per colour channel
//! (`(lmax+1)^2` coefficients; one matrix channel applying to all three
//! colours of the light, or three, one per colour), over the light's
//! coefficients up to the matrices' lmax (missing ones count as 0).
//! Compressed, `M_p = m_c + sum_k w_pk b_ck` for `p`'s cluster `c`, so
//! `T_p = m_c L + sum_k w_pk (b_ck L)`: [`GlossyView::transferred`]
//! computes `m_c L` and every `b_ck L` once per light (a *part* each), and
//! [`TransferredRadiance::vertex`] sums a vertex's parts with its weights.
//! Uncompressed, every vertex is its own group with one part, `M_p L`.

use std::borrow::Cow;

use glam::DVec3;

use crate::ShapeError;

/// The matrices of a glossy bake: every vertex's, or clustered PCA's.
#[derive(Clone, Debug)]
pub enum GlossyMatrices<'a> {
    /// `vertex_count x channels x n x n` values (`n = (lmax+1)^2`):
    /// vertex-major, then channel, then row `i` (the transferred
    /// radiance's coefficient), then column `j` (the light's).
    Full(Cow<'a, [f32]>),
    /// Clustered PCA: `C` clusters of `K` basis vectors, each `dim =
    /// channels x n x n` values laid out as one vertex's matrices.
    Cpca {
        /// Clusters `C`.
        clusters: usize,
        /// Basis vectors per cluster `K`.
        vectors: usize,
        /// `C x dim` cluster means.
        means: Cow<'a, [f32]>,
        /// `C x K x dim` basis vectors.
        bases: Cow<'a, [f32]>,
        /// Each vertex's cluster, below `C`.
        cluster: Cow<'a, [u32]>,
        /// `vertex_count x K` weights.
        weights: Cow<'a, [f32]>,
    },
}

/// Glossy transfer matrices, borrowed (or owned: [`GlossyView::into_owned`]).
#[derive(Clone, Debug)]
pub struct GlossyView<'a> {
    /// Highest degree of the transferred radiance and of the light used.
    pub lmax: usize,
    /// 1 (the same for R, G, B) or 3 (one matrix per colour).
    pub channels: usize,
    /// Vertices.
    pub vertex_count: usize,
    /// The matrices.
    pub matrices: GlossyMatrices<'a>,
}

/// Each vertex's transferred radiance under one light, in parts: group `g`
/// (a cluster, or a vertex when uncompressed) has `vectors + 1` parts of
/// `(lmax+1)^2` RGB coefficients, part 0 the mean's `m_c L`, part `k + 1`
/// the basis vector's `b_ck L`.
#[derive(Clone, Debug, PartialEq)]
pub struct TransferredRadiance {
    /// Highest degree.
    pub lmax: usize,
    /// Groups: clusters, or vertices when uncompressed.
    pub groups: usize,
    /// Basis vectors per group `K` (0 uncompressed).
    pub vectors: usize,
    /// `groups x (K + 1) x (lmax+1)^2` RGB coefficients.
    pub parts: Vec<DVec3>,
}

impl<'a> GlossyView<'a> {
    /// Checks the shapes of `matrices` against `lmax`, `channels` and
    /// `vertex_count`.
    ///
    /// # Errors
    /// [`ShapeError`] for a channel count other than 1 or 3, arrays whose
    /// lengths do not fit the counts, or a cluster index beyond the
    /// clusters.
    pub fn new(
        lmax: usize,
        channels: usize,
        vertex_count: usize,
        matrices: GlossyMatrices<'a>,
    ) -> Result<Self, ShapeError> {
        if channels != 1 && channels != 3 {
            return Err(ShapeError(format!(
                "glossy transfer has {channels} channels (expected 1 or 3)"
            )));
        }
        let n = (lmax + 1) * (lmax + 1);
        let dim = channels * n * n;
        let fits = |what: &str, len: usize, count: Option<usize>| match count {
            Some(c) if c == len => Ok(()),
            _ => Err(ShapeError(format!(
                "glossy transfer: the {what} hold {len} values, not {} (lmax {lmax}, {channels} \
                 channel(s), {vertex_count} vertices)",
                count.map_or_else(|| "that many".to_string(), |c| c.to_string())
            ))),
        };
        match &matrices {
            GlossyMatrices::Full(m) => fits("matrices", m.len(), vertex_count.checked_mul(dim))?,
            GlossyMatrices::Cpca {
                clusters,
                vectors,
                means,
                bases,
                cluster,
                weights,
            } => {
                fits("cluster means", means.len(), clusters.checked_mul(dim))?;
                fits(
                    "basis vectors",
                    bases.len(),
                    clusters
                        .checked_mul(*vectors)
                        .and_then(|c| c.checked_mul(dim)),
                )?;
                fits("cluster indices", cluster.len(), Some(vertex_count))?;
                fits("weights", weights.len(), vertex_count.checked_mul(*vectors))?;
                if let Some(c) = cluster.iter().find(|&&c| c as usize >= *clusters) {
                    return Err(ShapeError(format!(
                        "glossy transfer: cluster {c} of a vertex is not one of the {clusters}"
                    )));
                }
            }
        }
        Ok(Self {
            lmax,
            channels,
            vertex_count,
            matrices,
        })
    }

    /// The same matrices, owned.
    #[must_use]
    pub fn into_owned(self) -> GlossyView<'static> {
        let own = |c: Cow<'_, [f32]>| Cow::Owned(c.into_owned());
        GlossyView {
            lmax: self.lmax,
            channels: self.channels,
            vertex_count: self.vertex_count,
            matrices: match self.matrices {
                GlossyMatrices::Full(m) => GlossyMatrices::Full(own(m)),
                GlossyMatrices::Cpca {
                    clusters,
                    vectors,
                    means,
                    bases,
                    cluster,
                    weights,
                } => GlossyMatrices::Cpca {
                    clusters,
                    vectors,
                    means: own(means),
                    bases: own(bases),
                    cluster: Cow::Owned(cluster.into_owned()),
                    weights: own(weights),
                },
            },
        }
    }

    /// Basis vectors per group: `K`, 0 uncompressed.
    #[must_use]
    pub fn vectors(&self) -> usize {
        match &self.matrices {
            GlossyMatrices::Full(_) => 0,
            GlossyMatrices::Cpca { vectors, .. } => *vectors,
        }
    }

    /// Vertex `v`'s group (its cluster, or `v` uncompressed) and its `K`
    /// weights.
    #[must_use]
    pub fn vertex_group(&self, v: usize) -> (usize, &[f32]) {
        match &self.matrices {
            GlossyMatrices::Full(_) => (v, &[]),
            GlossyMatrices::Cpca {
                vectors,
                cluster,
                weights,
                ..
            } => (cluster[v] as usize, &weights[v * vectors..][..*vectors]),
        }
    }

    /// The transferred radiance's parts under `light` (radiance
    /// coefficients, index `l(l+1)+m`, any lmax): each part's
    /// `T_i[c] = sum_j M_ij L_j[c]` over `j` below both lmax, `M` the
    /// part's matrix of channel `c` (channel 0 for every colour of a
    /// one-channel file), summed in `f64`. Groups are shared among the
    /// machine's threads when there are many.
    #[must_use]
    pub fn transferred(&self, light: &[DVec3]) -> TransferredRadiance {
        let n = (self.lmax + 1) * (self.lmax + 1);
        let nn = n * n;
        let dim = self.channels * nn;
        let used = n.min(light.len());
        let channels = self.channels;
        // One part's transferred radiance from its `dim` matrix values.
        let apply = |m: &[f32], out: &mut [DVec3]| {
            for (i, t) in out.iter_mut().enumerate() {
                let mut sum = DVec3::ZERO;
                for c in 0..3 {
                    let row = &m[(c % channels) * nn + i * n..][..used];
                    sum[c] = row
                        .iter()
                        .zip(light)
                        .map(|(mij, lj)| f64::from(*mij) * lj[c])
                        .sum();
                }
                *t = sum;
            }
        };
        let (groups, vectors) = match &self.matrices {
            GlossyMatrices::Full(_) => (self.vertex_count, 0),
            GlossyMatrices::Cpca {
                clusters, vectors, ..
            } => (*clusters, *vectors),
        };
        let per_group = (vectors + 1) * n;
        let mut parts = vec![DVec3::ZERO; groups * per_group];
        let fill = |first: usize, out: &mut [DVec3]| {
            for (g, group) in out.chunks_exact_mut(per_group).enumerate() {
                let g = first + g;
                match &self.matrices {
                    GlossyMatrices::Full(m) => apply(&m[g * dim..][..dim], group),
                    GlossyMatrices::Cpca { means, bases, .. } => {
                        let (mean, rest) = group.split_at_mut(n);
                        apply(&means[g * dim..][..dim], mean);
                        for (k, part) in rest.chunks_exact_mut(n).enumerate() {
                            apply(&bases[(g * vectors + k) * dim..][..dim], part);
                        }
                    }
                }
            }
        };
        // Threads only where the work is worth it (about a million
        // multiply-adds each).
        let work = groups * (vectors + 1) * nn * 3;
        let threads = std::thread::available_parallelism()
            .map_or(1, std::num::NonZero::get)
            .min(work / (1 << 20) + 1)
            .min(groups.max(1));
        if threads <= 1 {
            fill(0, &mut parts);
        } else {
            let per_thread = groups.div_ceil(threads);
            std::thread::scope(|s| {
                for (t, chunk) in parts.chunks_mut(per_thread * per_group).enumerate() {
                    let fill = &fill;
                    s.spawn(move || fill(t * per_thread, chunk));
                }
            });
        }
        TransferredRadiance {
            lmax: self.lmax,
            groups,
            vectors,
            parts,
        }
    }
}

impl TransferredRadiance {
    /// Vertex `v`'s transferred radiance `T_v` (`(lmax+1)^2` RGB
    /// coefficients into `out`): its group's part 0 plus its weights times
    /// parts 1 to `K`, summed in that order in `f64`.
    ///
    /// # Panics
    /// If `view` is not the one these parts were computed from, or `out`
    /// is not `(lmax+1)^2` long.
    pub fn vertex(&self, view: &GlossyView<'_>, v: usize, out: &mut [DVec3]) {
        let n = (self.lmax + 1) * (self.lmax + 1);
        assert_eq!(out.len(), n);
        let (g, w) = view.vertex_group(v);
        let parts = &self.parts[g * (self.vectors + 1) * n..][..(self.vectors + 1) * n];
        out.copy_from_slice(&parts[..n]);
        for (k, wk) in w.iter().enumerate() {
            let part = &parts[(k + 1) * n..][..n];
            for (o, p) in out.iter_mut().zip(part) {
                *o += f64::from(*wk) * *p;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// lmax 0 (1x1 matrices) worked by hand: a compressed file's parts and
    /// a vertex's sum, and the same matrices uncompressed.
    #[test]
    fn parts_and_sums_by_hand() {
        // Two clusters, one vector each; one channel.
        let view = GlossyView::new(
            0,
            1,
            3,
            GlossyMatrices::Cpca {
                clusters: 2,
                vectors: 1,
                means: Cow::Owned(vec![2.0, 3.0]),
                bases: Cow::Owned(vec![0.5, -1.0]),
                cluster: Cow::Owned(vec![1, 0, 1]),
                weights: Cow::Owned(vec![2.0, 4.0, -1.0]),
            },
        )
        .unwrap();
        let light = [DVec3::new(1.0, 2.0, 10.0), DVec3::splat(100.0)];
        let t = view.transferred(&light);
        assert_eq!((t.groups, t.vectors), (2, 1));
        assert_eq!(
            t.parts,
            vec![
                DVec3::new(2.0, 4.0, 20.0),
                DVec3::new(0.5, 1.0, 5.0),
                DVec3::new(3.0, 6.0, 30.0),
                DVec3::new(-1.0, -2.0, -10.0)
            ]
        );
        let mut out = [DVec3::ZERO];
        // Vertex 0: cluster 1, weight 2: (3 - 2) L.
        t.vertex(&view, 0, &mut out);
        assert_eq!(out[0], DVec3::new(1.0, 2.0, 10.0));
        // Vertex 1: cluster 0, weight 4: (2 + 2) L.
        t.vertex(&view, 1, &mut out);
        assert_eq!(out[0], DVec3::new(4.0, 8.0, 40.0));
        // Uncompressed, three channels: each colour its own matrix.
        let full = GlossyView::new(
            0,
            3,
            1,
            GlossyMatrices::Full(Cow::Owned(vec![1.0, 2.0, 3.0])),
        )
        .unwrap();
        let t = full.transferred(&light);
        t.vertex(&full, 0, &mut out);
        assert_eq!(out[0], DVec3::new(1.0, 4.0, 30.0));
    }

    /// lmax 1: `T_i = sum_j M_ij L_j`, rows against columns, and a light
    /// of lmax 0 uses column 0 only.
    #[test]
    fn rows_times_the_light() {
        let m: Vec<f32> = (0..16).map(|x| x as f32).collect();
        let view = GlossyView::new(1, 1, 1, GlossyMatrices::Full(Cow::Borrowed(&m))).unwrap();
        let light = [
            DVec3::ONE,
            DVec3::splat(2.0),
            DVec3::ZERO,
            DVec3::splat(-1.0),
        ];
        let t = view.transferred(&light);
        // Row i: 4i + 2 (4i + 1) - (4i + 3) = 8i - 1.
        let want: Vec<DVec3> = (0..4).map(|i| DVec3::splat(8.0 * i as f64 - 1.0)).collect();
        assert_eq!(t.parts, want);
        let t = view.transferred(&light[..1]);
        let want: Vec<DVec3> = (0..4).map(|i| DVec3::splat(4.0 * i as f64)).collect();
        assert_eq!(t.parts, want);
    }

    #[test]
    fn shapes_are_checked() {
        let m = vec![0.0f32; 16];
        assert!(GlossyView::new(1, 1, 1, GlossyMatrices::Full(Cow::Borrowed(&m))).is_ok());
        let e = GlossyView::new(1, 1, 2, GlossyMatrices::Full(Cow::Borrowed(&m))).unwrap_err();
        assert!(e.0.contains("matrices hold 16 values, not 32"), "{e}");
        let e = GlossyView::new(1, 2, 1, GlossyMatrices::Full(Cow::Borrowed(&m))).unwrap_err();
        assert!(e.0.contains("2 channels"), "{e}");
        let e = GlossyView::new(
            0,
            1,
            1,
            GlossyMatrices::Cpca {
                clusters: 1,
                vectors: 0,
                means: Cow::Owned(vec![1.0]),
                bases: Cow::Owned(vec![]),
                cluster: Cow::Owned(vec![1]),
                weights: Cow::Owned(vec![]),
            },
        )
        .unwrap_err();
        assert!(
            e.0.contains("cluster 1 of a vertex is not one of the 1"),
            "{e}"
        );
    }
}
