//! The uncertainty an experiment will give, predicted before it is run.

use super::layout::Layout;
use super::problem::output_jacobian;
use crate::uncertainty::{ResidualNoise, from_normal_matrix};
use crate::{
    data::Excitation,
    error::{IdentError, Result},
    estimate::EstimationOptions,
    params::Parameters,
    uncertainty::Uncertainty,
};
use nalgebra::DMatrix;

/// The Cramér–Rao prediction of an estimate's uncertainty: the intervals that
/// [`estimate`](crate::estimate::estimate()) will report on a record of `excitation` from the plant
/// `plant` with white measurement noise of standard deviation `sigma`, estimating what
/// `options` estimates (its fixed parameters, initial state and offset). The covariance
/// is σ²(JᵀJ)⁻¹ with J the exact sensitivities at the plant: the smallest any unbiased
/// estimator reaches, and what least squares reaches on long records.
///
/// Standard errors scale as σ over the force: doubling the input halves them.
///
/// ```
/// use msd_ident::{predicted_uncertainty, EstimationOptions, Excitation, Parameters};
/// use msd_signal::paper_identification_input;
/// let input = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
/// let plan = predicted_uncertainty(&Parameters::PAPER, &input, 2.5e-3, &EstimationOptions::default())?;
/// // The paper's ζ to about ±0.6 % (95 %).
/// let zeta = plan.damping_ratio;
/// assert!(zeta.ci95[1] - zeta.value < 0.01 * zeta.value);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn predicted_uncertainty(
    plant: &Parameters,
    excitation: &Excitation,
    sigma: f64,
    options: &EstimationOptions,
) -> Result<Uncertainty> {
    plant.validate()?;
    check_sigma(sigma)?;
    PlannedInformation::new(plant, excitation, options)?.uncertainty(sigma)
}

/// A noise level to predict with: finite and positive.
fn check_sigma(sigma: f64) -> Result<()> {
    if sigma.is_finite() && sigma > 0.0 {
        return Ok(());
    }
    Err(IdentError::InvalidParameter {
        name: "noise sigma",
        value: sigma,
        expected: "a finite standard deviation > 0 (with no noise there is nothing to predict)",
    })
}

/// The information a planned record holds about what [`estimate`](crate::estimate::estimate())
/// estimates: the normal matrix JᵀJ of the exact sensitivities of the output at the
/// plant (the Fisher information per unit noise variance), and the record's samples.
/// [`predicted_uncertainty`] is [`PlannedInformation::uncertainty`] of it.
///
/// Information adds up over samples: where a longer record only repeats what the record
/// already holds (a periodic input, or a constant one, in steady state), the information
/// of any length follows from two lengths ([`PlannedInformation::extrapolated`]), and
/// `plan` searches record lengths without simulating them.
///
/// ```
/// use msd_ident::{predicted_uncertainty, EstimationOptions, Excitation, Parameters, PlannedInformation};
/// use msd_signal::paper_identification_input;
/// let input = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
/// let options = EstimationOptions::default();
/// let information = PlannedInformation::new(&Parameters::PAPER, &input, &options)?;
/// let direct = predicted_uncertainty(&Parameters::PAPER, &input, 2.5e-3, &options)?;
/// assert_eq!(information.uncertainty(2.5e-3)?.damping, direct.damping);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone)]
pub struct PlannedInformation {
    /// JᵀJ of the output's sensitivities to the estimated quantities.
    pub normal: DMatrix<f64>,
    /// Samples of the record.
    pub samples: usize,
    layout: Layout,
    plant: Parameters,
    values: Vec<f64>,
}

impl PlannedInformation {
    /// The information of a record of `excitation` from `plant`, estimating what
    /// `options` estimates.
    pub fn new(
        plant: &Parameters,
        excitation: &Excitation,
        options: &EstimationOptions,
    ) -> Result<Self> {
        let (jacobian, information) = Self::new_rows(plant, excitation, options)?;
        Ok(Self {
            normal: jacobian.transpose() * &jacobian,
            ..information
        })
    }

    /// The information of the first `lengths[i]` samples of a record of `excitation`
    /// (each at most its length), from one simulation of the whole record: the first rows
    /// of its sensitivities. A prefix differs from a record that ends there only by the
    /// input's interpolation at that end (the cubic hold reads the samples after it).
    ///
    /// ```
    /// use msd_ident::{EstimationOptions, Excitation, Parameters, PlannedInformation};
    /// use msd_signal::paper_identification_input;
    /// let input = Excitation::from_signal(paper_identification_input(), 0.0, 0.002, 7501)?;
    /// let options = EstimationOptions::default();
    /// let [short, whole] = PlannedInformation::prefixes(&Parameters::PAPER, &input, &options, [5001, 7501])?;
    /// let direct = PlannedInformation::new(&Parameters::PAPER, &input, &options)?;
    /// assert!((&whole.normal - &direct.normal).norm() <= 1e-12 * direct.normal.norm());
    /// assert_eq!(short.samples, 5001);
    /// assert!(whole.normal[(1, 1)] > short.normal[(1, 1)]);
    /// # Ok::<(), msd_ident::IdentError>(())
    /// ```
    pub fn prefixes<const K: usize>(
        plant: &Parameters,
        excitation: &Excitation,
        options: &EstimationOptions,
        lengths: [usize; K],
    ) -> Result<[Self; K]> {
        let (jacobian, information) = Self::new_rows(plant, excitation, options)?;
        Ok(lengths.map(|n| {
            let rows = jacobian.rows(0, n.clamp(1, jacobian.nrows()));
            Self {
                normal: rows.tr_mul(&rows),
                samples: rows.nrows(),
                ..information.clone()
            }
        }))
    }

    /// The output Jacobian of the record, and the rest of its information (`normal`
    /// left empty).
    fn new_rows(
        plant: &Parameters,
        excitation: &Excitation,
        options: &EstimationOptions,
    ) -> Result<(DMatrix<f64>, Self)> {
        plant.validate()?;
        let data =
            crate::data::DataSet::new("plan", excitation.clone(), vec![0.0; excitation.len()])?;
        let layout = Layout::new(options, false);
        let plant = layout.apply_fixed(plant);
        let values = layout.pack(&plant, options.initial_state, options.offset);
        let jacobian = output_jacobian(&data, &layout, &values)?;
        let information = Self {
            normal: DMatrix::zeros(0, 0),
            samples: jacobian.nrows(),
            layout,
            plant,
            values,
        };
        Ok((jacobian, information))
    }

    /// The predicted uncertainty with white measurement noise of standard deviation
    /// `sigma`: σ²(JᵀJ)⁻¹ and the intervals that follow (see [`predicted_uncertainty`]).
    pub fn uncertainty(&self, sigma: f64) -> Result<Uncertainty> {
        check_sigma(sigma)?;
        let mut noise = ResidualNoise::independent(0.0, self.samples, self.normal.ncols())?;
        noise.sse = sigma * sigma * noise.dof;
        from_normal_matrix(
            &self.normal,
            noise,
            self.layout.names(),
            self.values.clone(),
            &self.plant,
            self.layout.parameter_columns(),
        )
    }

    /// The information of the record lengthened to `samples` at the rate between `self`
    /// and a longer record `longer` of the same input: `self` + s·(`longer` − `self`),
    /// s the added samples over those `longer` adds. Exact where the added stretch
    /// repeats itself (whole periods of a periodic input, or a constant input, in steady
    /// state).
    pub fn extrapolated(&self, longer: &Self, samples: usize) -> Self {
        debug_assert!(longer.samples > self.samples);
        let s = (samples as f64 - self.samples as f64) / (longer.samples - self.samples) as f64;
        Self {
            normal: &self.normal + (&longer.normal - &self.normal) * s,
            samples,
            ..self.clone()
        }
    }
}
