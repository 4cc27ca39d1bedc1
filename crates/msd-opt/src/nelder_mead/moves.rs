//! The simplex and its moves, one small function each, exactly as fminsearch
//! computes them (same operation order, so results match MATLAB to the last bit
//! where MATLAB's own arithmetic is sequential).

/// Coefficients of the method: reflection ρ, expansion χ, contraction ψ, shrink σ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Coefficients {
    pub rho: f64,
    pub chi: f64,
    pub psi: f64,
    pub sigma: f64,
}

impl Coefficients {
    /// fminsearch's fixed values: ρ = 1, χ = 2, ψ = 0.5, σ = 0.5.
    pub const FMINSEARCH: Self = Self {
        rho: 1.0,
        chi: 2.0,
        psi: 0.5,
        sigma: 0.5,
    };

    /// Gao & Han (2012): ρ = 1, χ = 1 + 2/n, ψ = 0.75 − 1/(2n), σ = 1 − 1/n.
    /// They degenerate for n = 1 (σ = 0), so n < 2 keeps fminsearch's values.
    pub fn adaptive(n: usize) -> Self {
        if n < 2 {
            return Self::FMINSEARCH;
        }
        let n = n as f64;
        Self {
            rho: 1.0,
            chi: 1.0 + 2.0 / n,
            psi: 0.75 - 1.0 / (2.0 * n),
            sigma: 1.0 - 1.0 / n,
        }
    }
}

/// `(1 + t)·xbar − t·worst`, the line through the centroid and the worst vertex.
fn affine(xbar: &[f64], worst: &[f64], t: f64, out: &mut [f64]) {
    for ((o, &m), &w) in out.iter_mut().zip(xbar).zip(worst) {
        *o = (1.0 + t) * m - t * w;
    }
}

/// Reflection `xr = (1 + ρ)·xbar − ρ·worst`.
pub(crate) fn reflect(xbar: &[f64], worst: &[f64], c: &Coefficients, out: &mut [f64]) {
    affine(xbar, worst, c.rho, out);
}

/// Expansion `xe = (1 + ρχ)·xbar − ρχ·worst`.
pub(crate) fn expand(xbar: &[f64], worst: &[f64], c: &Coefficients, out: &mut [f64]) {
    affine(xbar, worst, c.rho * c.chi, out);
}

/// Outside contraction `xc = (1 + ψρ)·xbar − ψρ·worst`.
pub(crate) fn contract_outside(xbar: &[f64], worst: &[f64], c: &Coefficients, out: &mut [f64]) {
    affine(xbar, worst, c.psi * c.rho, out);
}

/// Inside contraction `xcc = (1 − ψ)·xbar + ψ·worst`.
pub(crate) fn contract_inside(xbar: &[f64], worst: &[f64], c: &Coefficients, out: &mut [f64]) {
    for ((o, &m), &w) in out.iter_mut().zip(xbar).zip(worst) {
        *o = (1.0 - c.psi) * m + c.psi * w;
    }
}

/// Shrink one vertex towards the best: `v = best + σ·(v − best)`.
pub(crate) fn shrink_vertex(best: &[f64], vertex: &mut [f64], c: &Coefficients) {
    for (v, &b) in vertex.iter_mut().zip(best) {
        *v = b + c.sigma * (*v - b);
    }
}

/// fminsearch's initial simplex vertex `j` (0-based coordinate): x0 with
/// coordinate `j` raised by 5 %, or set to 0.00025 where it is zero.
pub(crate) fn initial_vertex(x0: &[f64], j: usize, out: &mut [f64]) {
    const USUAL_DELTA: f64 = 0.05;
    const ZERO_TERM_DELTA: f64 = 0.00025;
    out.copy_from_slice(x0);
    out[j] = if x0[j] != 0.0 {
        (1.0 + USUAL_DELTA) * x0[j]
    } else {
        ZERO_TERM_DELTA
    };
}

/// n + 1 vertices stored row after row, with their (non-finite ⇒ +∞) costs.
#[derive(Debug, Clone)]
pub(crate) struct Simplex {
    pub n: usize,
    pub vertices: Vec<f64>,
    pub values: Vec<f64>,
}

impl Simplex {
    pub fn new(n: usize) -> Self {
        Self {
            n,
            vertices: vec![0.0; (n + 1) * n],
            values: vec![f64::INFINITY; n + 1],
        }
    }

    pub fn vertex(&self, j: usize) -> &[f64] {
        &self.vertices[j * self.n..(j + 1) * self.n]
    }

    pub fn vertex_mut(&mut self, j: usize) -> &mut [f64] {
        &mut self.vertices[j * self.n..(j + 1) * self.n]
    }

    /// Best vertex (read) and vertex `j ≥ 1` (write) at once.
    pub fn best_and_vertex_mut(&mut self, j: usize) -> (&[f64], &mut [f64]) {
        debug_assert!(j >= 1);
        let n = self.n;
        let (head, tail) = self.vertices.split_at_mut(j * n);
        (&head[..n], &mut tail[..n])
    }

    /// Centroid of the n best vertices, `sum(v(:,1:n),2)/n` summed in MATLAB's order.
    pub fn centroid(&self, out: &mut [f64]) {
        let n = self.n;
        for (i, o) in out.iter_mut().enumerate() {
            let mut s = 0.0;
            for j in 0..n {
                s += self.vertices[j * n + i];
            }
            *o = s / n as f64;
        }
    }

    /// Replaces the worst vertex.
    pub fn replace_worst(&mut self, x: &[f64], f: f64) {
        let n = self.n;
        self.vertex_mut(n).copy_from_slice(x);
        self.values[n] = f;
    }

    /// Stable ascending sort by cost (as MATLAB's `sort`): insertion sort, which
    /// costs O(n) in the usual case where only the last vertex moved.
    pub fn sort(&mut self) {
        let n = self.n;
        for i in 1..=n {
            let mut j = i;
            while j > 0 && self.values[j] < self.values[j - 1] {
                self.values.swap(j, j - 1);
                let (a, b) = self.vertices.split_at_mut(j * n);
                a[(j - 1) * n..].swap_with_slice(&mut b[..n]);
                j -= 1;
            }
        }
        debug_assert!(self.values.windows(2).all(|w| w[0] <= w[1]));
    }
}

#[cfg(test)]
mod tests {
    //! Each move against vertices computed by hand (exact binary fractions, so the
    //! comparisons are exact).
    use super::*;

    const C: Coefficients = Coefficients::FMINSEARCH;
    const XBAR: [f64; 2] = [1.0, 2.0];
    const WORST: [f64; 2] = [3.0, -1.0];

    #[test]
    fn reflection() {
        let mut out = [0.0; 2];
        reflect(&XBAR, &WORST, &C, &mut out);
        // 2·(1, 2) − (3, −1) = (−1, 5)
        assert_eq!(out, [-1.0, 5.0]);
    }

    #[test]
    fn expansion() {
        let mut out = [0.0; 2];
        expand(&XBAR, &WORST, &C, &mut out);
        // 3·(1, 2) − 2·(3, −1) = (−3, 8)
        assert_eq!(out, [-3.0, 8.0]);
    }

    #[test]
    fn outside_contraction() {
        let mut out = [0.0; 2];
        contract_outside(&XBAR, &WORST, &C, &mut out);
        // 1.5·(1, 2) − 0.5·(3, −1) = (0, 3.5)
        assert_eq!(out, [0.0, 3.5]);
    }

    #[test]
    fn inside_contraction() {
        let mut out = [0.0; 2];
        contract_inside(&XBAR, &WORST, &C, &mut out);
        // 0.5·(1, 2) + 0.5·(3, −1) = (2, 0.5)
        assert_eq!(out, [2.0, 0.5]);
    }

    #[test]
    fn shrink() {
        let mut v = [3.0, -1.0];
        shrink_vertex(&[1.0, 1.0], &mut v, &C);
        // (1, 1) + 0.5·((3, −1) − (1, 1)) = (2, 0)
        assert_eq!(v, [2.0, 0.0]);
    }

    #[test]
    fn adaptive_coefficients() {
        let c = Coefficients::adaptive(4);
        assert_eq!((c.rho, c.chi, c.psi, c.sigma), (1.0, 1.5, 0.625, 0.75));
        assert_eq!(Coefficients::adaptive(1), C);
        let mut out = [0.0; 2];
        expand(&XBAR, &WORST, &c, &mut out);
        // 2.5·(1, 2) − 1.5·(3, −1) = (−2, 6.5)
        assert_eq!(out, [-2.0, 6.5]);
    }

    #[test]
    fn initial_simplex_rule() {
        let x0 = [2.0, 0.0, -4.0];
        let mut v = [0.0; 3];
        initial_vertex(&x0, 0, &mut v);
        assert_eq!(v, [1.05 * 2.0, 0.0, -4.0]);
        initial_vertex(&x0, 1, &mut v);
        assert_eq!(v, [2.0, 0.00025, -4.0]);
        initial_vertex(&x0, 2, &mut v);
        assert_eq!(v, [2.0, 0.0, 1.05 * -4.0]);
    }

    #[test]
    fn centroid_and_stable_sort() {
        let mut s = Simplex::new(2);
        s.vertices.copy_from_slice(&[0.0, 0.0, 2.0, 4.0, 9.0, 9.0]);
        s.values.copy_from_slice(&[1.0, 1.0, 0.5]);
        s.sort();
        // The new value goes first; the two ties keep their order.
        assert_eq!(s.values, [0.5, 1.0, 1.0]);
        assert_eq!(s.vertices, [9.0, 9.0, 0.0, 0.0, 2.0, 4.0]);
        let mut m = [0.0; 2];
        s.centroid(&mut m);
        assert_eq!(m, [4.5, 4.5]);
    }
}
