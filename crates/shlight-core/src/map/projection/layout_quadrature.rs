//! The texel-solid-angle quadrature of any layout, texel by texel: the
//! route for every layout but equirect (whose rows go through the ring
//! transform).

use glam::DVec3;

use super::rows::{RowState, run_rows};
use crate::map::layout::geometry::Geometry;
use crate::map::orientation::MapOrientation;
use crate::map::texel_source::TexelSource;
use crate::sh::basis::ShBasis;
use crate::sh::sh_coeffs::ShCoeffs;

/// `sum f(texel) Y(d(texel)) Ω(texel)` over the texels of `source` that
/// hold a direction, read in orientation `o`, the basis evaluated in batches
/// ([`ShBasis::eval_batch`]) per row, rows in parallel with the `rayon`
/// feature. The size must fit the layout (checked by the caller).
pub(crate) fn project_texels<S: TexelSource + ?Sized>(
    source: &S,
    lmax: usize,
    o: MapOrientation,
) -> ShCoeffs<DVec3> {
    let (w, h) = source.size();
    let geo = Geometry::new(source.layout(), o, w, h);
    let rule = geo.disc_rule();
    let basis = ShBasis::<f64>::new(lmax);
    let row = |y: usize, acc: &mut Batch| {
        for x in 0..w {
            let Some(d) = geo.direction(x, y) else {
                continue;
            };
            let omega = geo.solid_angle(x, y, rule.as_ref());
            let f = DVec3::from(source.texel(x, y).map(f64::from));
            acc.push(d, f * omega, &basis);
        }
        acc.flush(&basis);
    };
    run_rows::<Batch>(h, lmax, row)
}

/// Texels per basis batch: `(lmax+1)^2 * BATCH` values of scratch.
const BATCH: usize = 128;

/// Per-thread partial sums and a batch of weighted texels.
struct Batch {
    sh: ShCoeffs<DVec3>,
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    /// `f(texel) Ω(texel)`.
    fw: Vec<DVec3>,
    /// Basis values, coefficient-major.
    basis: Vec<f64>,
}

impl Batch {
    fn new(lmax: usize) -> Self {
        let count = crate::sh::index::sh_count(lmax);
        Self {
            sh: ShCoeffs::zeros(lmax),
            x: Vec::with_capacity(BATCH),
            y: Vec::with_capacity(BATCH),
            z: Vec::with_capacity(BATCH),
            fw: Vec::with_capacity(BATCH),
            basis: vec![0.0; count * BATCH],
        }
    }

    fn push(&mut self, d: DVec3, fw: DVec3, basis: &ShBasis<f64>) {
        self.x.push(d.x);
        self.y.push(d.y);
        self.z.push(d.z);
        self.fw.push(fw);
        if self.x.len() == BATCH {
            self.flush(basis);
        }
    }

    fn flush(&mut self, basis: &ShBasis<f64>) {
        let n = self.x.len();
        if n == 0 {
            return;
        }
        let count = basis.count();
        let values = &mut self.basis[..count * n];
        basis.eval_batch(&self.x, &self.y, &self.z, values);
        for i in 0..count {
            let mut s = DVec3::ZERO;
            for (fw, yk) in self.fw.iter().zip(&values[i * n..(i + 1) * n]) {
                s += *fw * *yk;
            }
            self.sh[i] += s;
        }
        self.x.clear();
        self.y.clear();
        self.z.clear();
        self.fw.clear();
    }
}

impl RowState for Batch {
    fn new(lmax: usize) -> Self {
        Batch::new(lmax)
    }
    fn into_coeffs(self) -> ShCoeffs<DVec3> {
        self.sh
    }
}
