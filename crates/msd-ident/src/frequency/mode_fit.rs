//! The single-mode fit of the record's DFT and the transient term of a given model.

use msd_signal::Complex64;

/// The single-mode fit Y ≈ (G·U + a + jbω)/D(ω), D = ωn² − ω² + 2jζωnω, over the band's
/// bins: for fixed (ωn, ζ) the numerator (G, a, b) is linear least squares. With the
/// regressors x = (U, 1, jω) the normal equations are Σ w·Re(conj(x_r)x_s) and
/// Σ w·Re(conj(x_r)·y·D) with w = 1/|D|², so the products of the data are formed once
/// and each trial (ωn, ζ) costs a few flops per bin.
pub(super) struct SingleModeFit {
    omega: Vec<f64>,
    u: Vec<Complex64>,
    y: Vec<Complex64>,
    /// Re(conj(x_r)·x_s) for (r, s) = (0,0), (0,1), (0,2), (1,1), (1,2), (2,2).
    products: Vec<[f64; 6]>,
    /// conj(x_r)·y.
    projections: Vec<[Complex64; 3]>,
}

impl SingleModeFit {
    pub(super) fn new(omega: Vec<f64>, u: Vec<Complex64>, y: Vec<Complex64>) -> Self {
        let mut products = Vec::with_capacity(omega.len());
        let mut projections = Vec::with_capacity(omega.len());
        for ((&w, &ui), &yi) in omega.iter().zip(&u).zip(&y) {
            let x = [ui, Complex64::new(1.0, 0.0), Complex64::new(0.0, w)];
            let re = |r: usize, s: usize| (x[r].conj() * x[s]).re;
            products.push([re(0, 0), re(0, 1), re(0, 2), re(1, 1), re(1, 2), re(2, 2)]);
            projections.push([x[0].conj() * yi, x[1].conj() * yi, x[2].conj() * yi]);
        }
        Self {
            omega,
            u,
            y,
            products,
            projections,
        }
    }

    /// The residual sum of squares of the best numerator for (ωn, ζ); `None` if the normal
    /// equations are singular or the result is not finite.
    pub(super) fn sse(&self, wn: f64, zeta: f64) -> Option<f64> {
        let mut p = [0.0f64; 6];
        let mut q = [0.0f64; 3];
        for ((&w, products), projections) in
            self.omega.iter().zip(&self.products).zip(&self.projections)
        {
            let d = Complex64::new(wn * wn - w * w, 2.0 * zeta * wn * w);
            let weight = 1.0 / d.norm_sqr();
            for (acc, v) in p.iter_mut().zip(products) {
                *acc += weight * v;
            }
            for (acc, v) in q.iter_mut().zip(projections) {
                *acc += weight * (v * d).re;
            }
        }
        let ata = nalgebra::Matrix3::new(p[0], p[1], p[2], p[1], p[3], p[4], p[2], p[4], p[5]);
        let coef = ata.lu().solve(&nalgebra::Vector3::from(q))?;
        let mut sse = 0.0;
        for ((&w, &ui), &yi) in self.omega.iter().zip(&self.u).zip(&self.y) {
            let d = Complex64::new(wn * wn - w * w, 2.0 * zeta * wn * w);
            let numerator = ui * coef[0] + Complex64::new(coef[1], coef[2] * w);
            sse += (yi - numerator / d).norm_sqr();
        }
        sse.is_finite().then_some(sse)
    }
}

/// Least-squares transient (a, b) in Y − H U ≈ (a + jbω)/D for a given model.
pub(super) fn transient_for(
    omega: &[f64],
    u: &[Complex64],
    y: &[Complex64],
    h: &[Complex64],
    d: &[Complex64],
) -> (f64, f64) {
    let mut ata = nalgebra::Matrix2::<f64>::zeros();
    let mut aty = nalgebra::Vector2::<f64>::zeros();
    for i in 0..omega.len() {
        let target = y[i] - h[i] * u[i];
        let c = [
            Complex64::new(1.0, 0.0) / d[i],
            Complex64::new(0.0, omega[i]) / d[i],
        ];
        for r in 0..2 {
            for s in 0..2 {
                ata[(r, s)] += (c[r].conj() * c[s]).re;
            }
            aty[r] += (c[r].conj() * target).re;
        }
    }
    ata.lu().solve(&aty).map_or((0.0, 0.0), |v| (v[0], v[1]))
}
