//! Mapping between the optimiser's vector and (θ, initial state, offset).

use super::EstimationOptions;
use crate::params::{InitialState, Parameters};

/// Which quantities are free and where they sit in the optimiser's vector.
#[derive(Debug, Clone)]
pub(crate) struct Layout {
    /// Fixed values of m, c, k (None = free).
    fixed: [Option<f64>; 3],
    /// Free physical parameters are stored as logarithms.
    log: bool,
    initial_state: Option<InitialState>,
    estimate_initial_state: bool,
    offset: f64,
    estimate_offset: bool,
}

pub(crate) const STATE_NAMES: [&str; 2] = ["initial_displacement", "initial_velocity"];

impl Layout {
    pub(crate) fn new(options: &EstimationOptions, log: bool) -> Self {
        Self {
            fixed: options.fixed.as_array(),
            log,
            initial_state: Some(options.initial_state),
            estimate_initial_state: options.estimate_initial_state,
            offset: options.offset,
            estimate_offset: options.estimate_offset,
        }
    }

    /// Indices (0 = m, 1 = c, 2 = k) of the free physical parameters.
    pub(crate) fn free(&self) -> impl Iterator<Item = usize> + '_ {
        (0..3).filter(|&i| self.fixed[i].is_none())
    }

    pub(crate) fn free_count(&self) -> usize {
        self.free().count()
    }

    pub(crate) fn len(&self) -> usize {
        self.free_count()
            + 2 * usize::from(self.estimate_initial_state)
            + usize::from(self.estimate_offset)
    }

    pub(crate) fn names(&self) -> Vec<&'static str> {
        let mut names: Vec<&'static str> = self
            .free()
            .map(|i| crate::params::Parameters::NAMES[i])
            .collect();
        if self.estimate_initial_state {
            names.extend(STATE_NAMES);
        }
        if self.estimate_offset {
            names.push("offset");
        }
        names
    }

    /// Columns of m, c, k in the vector (None when fixed).
    pub(crate) fn parameter_columns(&self) -> [Option<usize>; 3] {
        let mut columns = [None; 3];
        for (column, i) in self.free().enumerate() {
            columns[i] = Some(column);
        }
        columns
    }

    pub(crate) fn pack(&self, theta: &Parameters, state: InitialState, offset: f64) -> Vec<f64> {
        let values = theta.to_array();
        let mut v: Vec<f64> = self
            .free()
            .map(|i| if self.log { values[i].ln() } else { values[i] })
            .collect();
        if self.estimate_initial_state {
            v.push(state.displacement);
            v.push(state.velocity);
        }
        if self.estimate_offset {
            v.push(offset);
        }
        v
    }

    /// (θ, initial state, offset) from the vector; θ unchecked.
    pub(crate) fn unpack(&self, v: &[f64]) -> (Parameters, InitialState, f64) {
        let mut theta = [0.0; 3];
        let mut j = 0;
        for (i, value) in theta.iter_mut().enumerate() {
            *value = match self.fixed[i] {
                Some(fixed) => fixed,
                None => {
                    let x = v[j];
                    j += 1;
                    if self.log { x.exp() } else { x }
                }
            };
        }
        let state = if self.estimate_initial_state {
            let s = InitialState {
                displacement: v[j],
                velocity: v[j + 1],
            };
            j += 2;
            s
        } else {
            self.initial_state.unwrap_or_default()
        };
        let offset = if self.estimate_offset {
            v[j]
        } else {
            self.offset
        };
        (Parameters::from_array(theta), state, offset)
    }

    /// Fills the starting value of θ where fixed values apply.
    pub(crate) fn apply_fixed(&self, theta: &Parameters) -> Parameters {
        let mut values = theta.to_array();
        for (value, fixed) in values.iter_mut().zip(self.fixed) {
            if let Some(f) = fixed {
                *value = f;
            }
        }
        Parameters::from_array(values)
    }

    pub(crate) fn has_state(&self) -> bool {
        self.estimate_initial_state
    }

    pub(crate) fn has_offset(&self) -> bool {
        self.estimate_offset
    }
}
