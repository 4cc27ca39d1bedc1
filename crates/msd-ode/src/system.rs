//! The system trait: a right-hand side written in place.

use nalgebra::SVector;

/// A first-order system y' = f(t, y) with a state of `N` components.
///
/// Implement [`rhs`](OdeSystem::rhs), or pass a closure
/// `|t, y: &SVector<f64, N>, dydt: &mut SVector<f64, N>| …`, or wrap a slice-based
/// closure in [`SliceSystem`].
///
/// ```
/// use msd_ode::{OdeSystem, SVector};
/// struct Decay { rate: f64 }
/// impl OdeSystem<1> for Decay {
///     fn rhs(&mut self, _t: f64, y: &SVector<f64, 1>, dydt: &mut SVector<f64, 1>) {
///         dydt[0] = -self.rate * y[0];
///     }
/// }
/// let mut d = Decay { rate: 2.0 };
/// let mut out = SVector::<f64, 1>::zeros();
/// d.rhs(0.0, &SVector::<f64, 1>::new(3.0), &mut out);
/// assert_eq!(out[0], -6.0);
/// ```
pub trait OdeSystem<const N: usize> {
    /// Writes f(t, y) into `dydt`.
    fn rhs(&mut self, t: f64, y: &SVector<f64, N>, dydt: &mut SVector<f64, N>);
}

impl<const N: usize, F> OdeSystem<N> for F
where
    F: FnMut(f64, &SVector<f64, N>, &mut SVector<f64, N>),
{
    #[inline]
    fn rhs(&mut self, t: f64, y: &SVector<f64, N>, dydt: &mut SVector<f64, N>) {
        self(t, y, dydt)
    }
}

/// Adapter for a right-hand side written on plain slices, `f(t, y, dydt)`.
///
/// ```
/// use msd_ode::{ode45, Ode45Options, SliceSystem, SVector};
/// let mut system = SliceSystem(|_t: f64, y: &[f64], dydt: &mut [f64]| dydt[0] = -y[0]);
/// let sol = ode45(&mut system, &[0.0, 1.0], &SVector::<f64, 1>::new(1.0), &Ode45Options::default())?;
/// assert!((sol.y.last().unwrap()[0] - (-1.0f64).exp()).abs() < 1e-3);
/// # Ok::<(), msd_ode::OdeError>(())
/// ```
#[derive(Debug, Clone, Copy)]
pub struct SliceSystem<F>(pub F);

impl<const N: usize, F> OdeSystem<N> for SliceSystem<F>
where
    F: FnMut(f64, &[f64], &mut [f64]),
{
    #[inline]
    fn rhs(&mut self, t: f64, y: &SVector<f64, N>, dydt: &mut SVector<f64, N>) {
        (self.0)(t, y.as_slice(), dydt.as_mut_slice())
    }
}
