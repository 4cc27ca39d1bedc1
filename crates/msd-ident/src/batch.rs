//! Many parameter sets on one excitation, [`LANES`] at a time (the exact backend).

use crate::{Excitation, InitialState, Parameters, Result};
use msd_ode::{ExactSimulator, Hold, InputSchedule, Lockstep, SampledInput};
use std::ops::Range;

/// Parameter sets a [`BatchSimulator`] steps together.
pub const LANES: usize = 8;

/// The exact simulation of many parameter sets on one excitation, as a Monte Carlo run
/// needs it: the excitation's stencils are worked out (and checked) once, and
/// [`LANES`] parameter sets are stepped together, each giving bit for bit what
/// [`simulate`](crate::simulate) with [`Backend::Exact`](crate::Backend::Exact) gives.
///
/// ```
/// use msd_ident::{simulate, Backend, BatchSimulator, Excitation, InitialState, Parameters, LANES};
/// use msd_ode::Hold;
/// use msd_signal::paper_validation_input;
/// let input = Excitation::from_signal(paper_validation_input(), 0.0, 0.002, 7501)?;
/// let batch = BatchSimulator::new(&input, Hold::Cubic)?;
/// let mut sets = [None; LANES];
/// sets[0] = Some(Parameters::PAPER);
/// sets[1] = Some(Parameters::new(2.6, 1.7, 125.0)?);
/// let mut out = vec![0.0; 7501 * LANES]; // time-major: out[t·LANES + lane]
/// let ok = batch.simulate_lanes(&sets, InitialState::REST, 0..7501, &mut out);
/// assert_eq!(&ok[..3], &[true, true, false]);
/// let alone = simulate(&sets[1].unwrap(), &input, InitialState::REST, &Backend::EXACT)?;
/// assert!((0..7501).all(|t| out[t * LANES + 1] == alone[t]));
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone)]
pub struct BatchSimulator {
    schedule: InputSchedule,
    dt: f64,
    hold: Hold,
}

impl BatchSimulator {
    /// The batch simulator of `excitation` with the given hold.
    pub fn new(excitation: &Excitation, hold: Hold) -> Result<Self> {
        let input = SampledInput {
            values: excitation.samples(),
            breakpoints: excitation.breakpoints(),
        };
        Ok(Self {
            schedule: InputSchedule::new(&input, hold)?,
            dt: excitation.dt(),
            hold,
        })
    }

    /// Number of samples of the excitation.
    pub fn samples(&self) -> usize {
        self.schedule.samples()
    }

    /// Simulates the parameter sets of `parameters` (at most [`LANES`]; `None` leaves a
    /// lane empty) from `initial`, writing the displacement at the samples `range` to
    /// `out[(t − range.start)·LANES + lane]`. Returns which lanes succeeded: a lane fails
    /// for `None`, invalid parameters, a model too stiff for the step, or a state that
    /// overflows (by `range.end`); failed lanes' values in `out` are meaningless.
    ///
    /// # Panics
    /// If `parameters` has more than [`LANES`] entries, `range` goes beyond the
    /// excitation, or `out` is shorter than `range.len()·LANES` (programming errors).
    pub fn simulate_lanes(
        &self,
        parameters: &[Option<Parameters>],
        initial: InitialState,
        range: Range<usize>,
        out: &mut [f64],
    ) -> [bool; LANES] {
        assert!(
            parameters.len() <= LANES,
            "more than {LANES} parameter sets"
        );
        assert!(range.end <= self.samples() && range.start <= range.end);
        assert!(out.len() >= range.len() * LANES, "output buffer too short");
        let sims: [Option<ExactSimulator<2>>; LANES] = std::array::from_fn(|lane| {
            let p = parameters.get(lane).copied().flatten()?;
            p.validate().ok()?;
            ExactSimulator::new(&p.state_space(), self.dt, self.hold).ok()
        });
        let ok = sims.each_ref().map(Option::is_some);
        // Empty lanes run a copy of a good one; their output is ignored.
        let Some(filler) = sims.iter().flatten().next() else {
            return ok;
        };
        let lanes = sims.each_ref().map(|s| s.as_ref().unwrap_or(filler));
        let x0 = initial.vector();
        let Ok(mut stepper) = Lockstep::<2, LANES>::new(lanes, [x0; LANES]) else {
            return [false; LANES];
        };
        let mut store = |t: usize, x: &[[f64; LANES]; 2]| {
            if range.contains(&t) {
                let at = (t - range.start) * LANES;
                out[at..at + LANES].copy_from_slice(&x[0]);
            }
        };
        store(0, stepper.state());
        stepper.advance(&self.schedule, range.end.saturating_sub(1), store);
        // Once a lane overflows its state stays non-finite (every component sums over all
        // of them), so the last state tells which lanes failed, as simulate's
        // NonFiniteState would.
        let last = stepper.state();
        std::array::from_fn(|lane| ok[lane] && (0..2).all(|r| last[r][lane].is_finite()))
    }
}
