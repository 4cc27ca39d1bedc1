//! Box bounds `lower ≤ x ≤ upper`, shared by every solver in the crate.
//!
//! Each solver treats bounds its own documented way:
//! - Nelder–Mead maps an unbounded working variable `z` onto the box with a smooth
//!   transformation (as John D'Errico's `fminsearchbnd`): `x = l + (u − l)(sin z + 1)/2`
//!   for two finite bounds, `x = l + z²` for a lower bound only, `x = u − z²` for an
//!   upper bound only, `x = z` when unbounded.
//! - Levenberg–Marquardt projects each trial point onto the box and holds variables
//!   on a bound fixed while the gradient pushes them outward.
//! - Multistart spreads its starting points over the (finite) box.
//!
//! ```
//! use msd_opt::Bounds;
//!
//! let b = Bounds::new(vec![0.0, f64::NEG_INFINITY], vec![1.0, 2.0]).unwrap();
//! assert!(b.contains(&[0.5, -1e9]));
//! let mut x = [3.0, 5.0];
//! b.project(&mut x);
//! assert_eq!(x, [1.0, 2.0]);
//! ```

use serde::{Deserialize, Serialize};

use crate::error::OptError;

/// Lower and upper bounds per coordinate; infinite values mean "no bound".
///
/// Fields are public so configurations can carry bounds; every solver calls
/// [`Bounds::validate`] before use.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Bounds {
    /// Lower bounds (`-inf` for none).
    pub lower: Vec<f64>,
    /// Upper bounds (`+inf` for none).
    pub upper: Vec<f64>,
}

impl Bounds {
    /// Builds and validates bounds.
    ///
    /// # Errors
    /// See [`Bounds::validate`].
    pub fn new(lower: Vec<f64>, upper: Vec<f64>) -> Result<Self, OptError> {
        let b = Self { lower, upper };
        b.validate()?;
        Ok(b)
    }

    /// Number of coordinates.
    pub fn len(&self) -> usize {
        self.lower.len()
    }

    /// True when there are no coordinates.
    pub fn is_empty(&self) -> bool {
        self.lower.is_empty()
    }

    /// Checks equal lengths, no NaN, and `lower ≤ upper` everywhere.
    ///
    /// # Errors
    /// [`OptError::LengthMismatch`], [`OptError::NaNBound`] or
    /// [`OptError::InvertedBounds`] naming the first offending coordinate.
    pub fn validate(&self) -> Result<(), OptError> {
        if self.upper.len() != self.lower.len() {
            return Err(OptError::LengthMismatch {
                what: "upper bounds vs lower bounds",
                expected: self.lower.len(),
                found: self.upper.len(),
            });
        }
        for (index, (&lower, &upper)) in self.lower.iter().zip(&self.upper).enumerate() {
            if lower.is_nan() {
                return Err(OptError::NaNBound {
                    which: "lower",
                    index,
                });
            }
            if upper.is_nan() {
                return Err(OptError::NaNBound {
                    which: "upper",
                    index,
                });
            }
            if lower > upper || lower == f64::INFINITY || upper == f64::NEG_INFINITY {
                return Err(OptError::InvertedBounds {
                    index,
                    lower,
                    upper,
                });
            }
        }
        Ok(())
    }

    /// Validates and checks that the bounds have `n` coordinates.
    pub(crate) fn validate_for(&self, n: usize) -> Result<(), OptError> {
        self.validate()?;
        if self.len() != n {
            return Err(OptError::LengthMismatch {
                what: "bounds vs x0",
                expected: n,
                found: self.len(),
            });
        }
        Ok(())
    }

    /// Checks that every bound is finite (needed to spread multistart points).
    pub(crate) fn require_finite(&self) -> Result<(), OptError> {
        for (index, (&lower, &upper)) in self.lower.iter().zip(&self.upper).enumerate() {
            if !lower.is_finite() || !upper.is_finite() {
                return Err(OptError::InfiniteBounds {
                    index,
                    lower,
                    upper,
                });
            }
        }
        Ok(())
    }

    /// True when every coordinate of `x` lies in its closed interval.
    pub fn contains(&self, x: &[f64]) -> bool {
        x.len() == self.len()
            && x.iter()
                .zip(self.lower.iter().zip(&self.upper))
                .all(|(&v, (&l, &u))| l <= v && v <= u)
    }

    /// Moves every coordinate of `x` to the nearest point of the box.
    pub fn project(&self, x: &mut [f64]) {
        for (v, (&l, &u)) in x.iter_mut().zip(self.lower.iter().zip(&self.upper)) {
            *v = v.clamp(l, u);
        }
    }

    /// Maps a point of the box to the unbounded working variable of the
    /// Nelder–Mead transformation (points outside are first projected).
    pub(crate) fn unbounded_from_box(&self, x: &[f64], z: &mut [f64]) {
        for (i, (zi, &xi)) in z.iter_mut().zip(x).enumerate() {
            let (l, u) = (self.lower[i], self.upper[i]);
            *zi = match (l.is_finite(), u.is_finite()) {
                (true, true) if u > l => {
                    let s = sine_of(xi, l, u);
                    // 2π + asin keeps z away from zero, so fminsearch's 5 % initial
                    // step is not replaced by its tiny zero-coordinate step.
                    2.0 * std::f64::consts::PI + s.asin()
                }
                (true, true) => 0.0,
                (true, false) => (xi - l).max(0.0).sqrt(),
                (false, true) => (u - xi).max(0.0).sqrt(),
                (false, false) => xi,
            };
        }
    }

    /// Maps the unbounded working variable back into the box (always inside).
    pub(crate) fn box_from_unbounded(&self, z: &[f64], x: &mut [f64]) {
        for (i, (xi, &zi)) in x.iter_mut().zip(z).enumerate() {
            let (l, u) = (self.lower[i], self.upper[i]);
            *xi = match (l.is_finite(), u.is_finite()) {
                (true, true) if (u - l).is_finite() => {
                    (l + (u - l) * (zi.sin() + 1.0) * 0.5).clamp(l, u)
                }
                // A box wider than the largest double: the same map about the midpoint.
                (true, true) => (0.5 * l + 0.5 * u + (0.5 * u - 0.5 * l) * zi.sin()).clamp(l, u),
                (true, false) => l + zi * zi,
                (false, true) => u - zi * zi,
                (false, false) => zi,
            };
        }
    }
}

/// sin z of the point `x` of [l, u] under x = l + (u − l)(sin z + 1)/2, in [−1, 1]; for a
/// box wider than the largest double, computed about the midpoint.
fn sine_of(x: f64, l: f64, u: f64) -> f64 {
    let s = if (u - l).is_finite() {
        2.0 * (x - l) / (u - l) - 1.0
    } else {
        (x - (0.5 * l + 0.5 * u)) / (0.5 * u - 0.5 * l)
    };
    s.clamp(-1.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transformation_round_trips_inside_the_box() {
        let b = Bounds::new(
            vec![0.0, 1.0, f64::NEG_INFINITY, f64::NEG_INFINITY],
            vec![2.0, f64::INFINITY, 3.0, f64::INFINITY],
        )
        .unwrap();
        let x = [0.3, 4.0, -2.0, 7.5];
        let mut z = [0.0; 4];
        let mut back = [0.0; 4];
        b.unbounded_from_box(&x, &mut z);
        b.box_from_unbounded(&z, &mut back);
        for (a, e) in back.iter().zip(&x) {
            assert!((a - e).abs() <= 4.0 * f64::EPSILON * e.abs().max(1.0));
        }
    }

    #[test]
    fn transformation_never_leaves_the_box() {
        let b = Bounds::new(vec![-1.0, 0.5], vec![1e-3, f64::INFINITY]).unwrap();
        let mut x = [0.0; 2];
        for k in -200..200 {
            let z = [k as f64 * 0.37, k as f64 * 1e3];
            b.box_from_unbounded(&z, &mut x);
            assert!(b.contains(&x), "{x:?}");
        }
    }

    /// [−f64::MAX, 1e300]: u − l overflows, yet the map stays finite and inside.
    #[test]
    fn a_box_wider_than_the_largest_double_maps_finitely() {
        let b = Bounds::new(vec![-f64::MAX, 0.0], vec![1e300, f64::MAX]).unwrap();
        let x = [0.0, 1.0];
        let (mut z, mut back) = ([0.0; 2], [0.0; 2]);
        b.unbounded_from_box(&x, &mut z);
        assert!(z.iter().all(|v| v.is_finite()), "{z:?}");
        b.box_from_unbounded(&z, &mut back);
        assert!(b.contains(&back), "{back:?}");
        for k in -50..50 {
            b.box_from_unbounded(&[k as f64 * 0.7, k as f64 * 0.3], &mut back);
            assert!(
                back.iter().all(|v| v.is_finite()) && b.contains(&back),
                "{back:?}"
            );
        }
    }

    #[test]
    fn invalid_bounds_are_named() {
        assert!(matches!(
            Bounds::new(vec![1.0], vec![0.0]),
            Err(OptError::InvertedBounds { index: 0, .. })
        ));
        assert!(matches!(
            Bounds::new(vec![0.0, f64::NAN], vec![1.0, 1.0]),
            Err(OptError::NaNBound {
                which: "lower",
                index: 1
            })
        ));
        assert!(matches!(
            Bounds::new(vec![0.0], vec![1.0, 2.0]),
            Err(OptError::LengthMismatch { .. })
        ));
        assert!(matches!(
            Bounds::new(vec![f64::INFINITY], vec![f64::INFINITY]),
            Err(OptError::InvertedBounds { .. })
        ));
    }
}
