//! The band's simulations: many parameter sets on one excitation, [`LANES`] at a time,
//! streamed along the record.
//!
//! What every draw shares is prepared (and checked) once — the input's stencils for the
//! exact backend, the time grid for ode45 — and [`LANES`] parameter sets at a time are
//! advanced along the record in stretches ([`BatchRun`]), so that the engine keeps a
//! short window of every response instead of whole responses. The exact backend steps
//! the lanes with msd-ode's `Lockstep`, ode45 with its `Ode45Lanes`. Every lane gives bit
//! for bit what `msd_ident::simulate` gives for its parameters with the same backend
//! (tested): the band is the percentiles of each draw simulated alone.

use crate::error::Result;
use msd_ident::{Backend, Excitation, IdentError, InitialState, Parameters};
use msd_ode::{
    ExactSimulator, Hold, InputSchedule, LaneSystem, Lockstep, Ode45Lanes, Ode45Options, SVector,
    SampledInput, TimeGrid,
};

#[cfg(test)]
mod tests;

/// Parameter sets a [`BatchRun`] steps together.
pub(crate) const LANES: usize = 8;

/// The simulation of many parameter sets on one excitation with one backend.
#[derive(Debug, Clone)]
pub(crate) struct BatchSimulator<'a> {
    excitation: &'a Excitation,
    kind: Kind<'a>,
}

#[derive(Debug, Clone)]
enum Kind<'a> {
    Exact {
        schedule: InputSchedule,
        hold: Hold,
    },
    Ode45 {
        grid: TimeGrid<'a>,
        options: Ode45Options,
    },
}

impl<'a> BatchSimulator<'a> {
    /// The batch simulator of `excitation` with `backend` (checked).
    pub(crate) fn new(excitation: &'a Excitation, backend: &Backend) -> Result<Self> {
        backend.validate()?;
        let kind = match *backend {
            Backend::Exact { hold } => {
                let input = SampledInput {
                    values: excitation.samples(),
                    breakpoints: excitation.breakpoints(),
                };
                Kind::Exact {
                    schedule: InputSchedule::new(&input, hold).map_err(IdentError::from)?,
                    hold,
                }
            }
            Backend::Ode45 { .. } => Kind::Ode45 {
                grid: TimeGrid::new(excitation.times()).map_err(IdentError::from)?,
                // `simulate`'s options, so that every lane gives its bits.
                options: backend
                    .ode45_options()
                    .expect("the ode45 backend has ode45 options"),
            },
        };
        Ok(Self { excitation, kind })
    }

    /// Number of samples of the excitation.
    pub(crate) fn samples(&self) -> usize {
        self.excitation.len()
    }

    /// Starts the parameter sets of `parameters` (at most [`LANES`]; `None` leaves a
    /// lane empty, and it counts as failed) from `initial`, at sample 0.
    ///
    /// # Panics
    /// If `parameters` has more than [`LANES`] entries (a programming error).
    pub(crate) fn start(
        &self,
        parameters: &[Option<Parameters>],
        initial: InitialState,
    ) -> BatchRun<'a> {
        assert!(
            parameters.len() <= LANES,
            "more than {LANES} parameter sets"
        );
        let set = |lane: usize| {
            let p = parameters.get(lane).copied().flatten()?;
            p.validate().ok().map(|()| p)
        };
        let x0 = SVector::<f64, 2>::new(initial.displacement, initial.velocity);
        let lanes = match &self.kind {
            Kind::Exact { hold, .. } => {
                let sims: [Option<ExactSimulator<2>>; LANES] = std::array::from_fn(|lane| {
                    ExactSimulator::new(&set(lane)?.state_space(), self.excitation.dt(), *hold).ok()
                });
                let ok = sims.each_ref().map(Option::is_some);
                // Empty lanes run a copy of a good one; their output is not used.
                let stepper = sims.iter().flatten().next().and_then(|filler| {
                    let lanes = sims.each_ref().map(|s| s.as_ref().unwrap_or(filler));
                    Lockstep::<2, LANES>::new(lanes, [x0; LANES]).ok()
                });
                Lanes::Exact {
                    ok: if stepper.is_some() {
                        ok
                    } else {
                        [false; LANES]
                    },
                    stepper: stepper.map(Box::new),
                }
            }
            Kind::Ode45 { grid, options } => {
                let sets: [Option<Parameters>; LANES] = std::array::from_fn(set);
                let mut plants = Plants {
                    // Empty lanes get a harmless plant; their values are not used.
                    parameters: sets.map(|p| p.map_or([1.0, 0.0, 1.0], |p| p.to_array())),
                    excitation: self.excitation,
                };
                let y0 = std::array::from_fn(|r| [x0[r]; LANES]);
                let used = sets.map(|p| p.is_some());
                let lanes = Ode45Lanes::new(&mut plants, *grid, &y0, used, options);
                Lanes::Ode45(Box::new((lanes, plants)))
            }
        };
        BatchRun { lanes, next: 0 }
    }
}

/// Up to [`LANES`] parameter sets part-way along the record of a [`BatchSimulator`].
#[derive(Debug, Clone)]
pub(crate) struct BatchRun<'a> {
    lanes: Lanes<'a>,
    next: usize,
}

#[derive(Debug, Clone)]
enum Lanes<'a> {
    Exact {
        /// `None` when no lane is good.
        stepper: Option<Box<Lockstep<2, LANES>>>,
        ok: [bool; LANES],
    },
    Ode45(Box<(Ode45Lanes<'a, 2, LANES>, Plants<'a>)>),
}

// A run's simulators stay small: the memory plan counts N / LANES of them.
const _: () = assert!(BatchRun::MAX_BYTES < 8 << 10);

/// The right-hand sides of [`LANES`] plants driven by one excitation, as
/// `simulate`'s ode45 right-hand side computes each: x'' = (F(t) − c·x' − k·x)/m.
#[derive(Debug, Clone)]
struct Plants<'a> {
    /// (m, c, k) of each lane.
    parameters: [[f64; 3]; LANES],
    excitation: &'a Excitation,
}

impl LaneSystem<2, LANES> for Plants<'_> {
    fn rhs(
        &mut self,
        active: &[bool; LANES],
        t: &[f64; LANES],
        y: &[[f64; LANES]; 2],
        dydt: &mut [[f64; LANES]; 2],
    ) {
        let mut force = [0.0; LANES];
        self.excitation.values(t, active, &mut force);
        for (lane, &[m, c, k]) in self.parameters.iter().enumerate() {
            dydt[0][lane] = y[1][lane];
            dydt[1][lane] = (force[lane] - c * y[1][lane] - k * y[0][lane]) / m;
        }
    }
}

impl BatchRun<'_> {
    /// Bytes a run holds, at most, on the heap and inline, with either backend.
    pub(crate) const MAX_BYTES: usize = {
        let exact = size_of::<Lockstep<2, LANES>>();
        let ode45 = size_of::<(Ode45Lanes<'static, 2, LANES>, Plants<'static>)>();
        size_of::<Self>() + if exact > ode45 { exact } else { ode45 }
    };

    /// Produces the samples from the next one (0 after [`BatchSimulator::start`]) up to
    /// `until` (clamped to the record), writing sample t of lane l to
    /// `out[(t − next)·stride + l]` — the lanes' values at one time are [`LANES`]
    /// contiguous values, `stride` (≥ [`LANES`]) apart from one time to the next, so
    /// that they go straight into a wider time-major table — and returns which lanes
    /// are still good. A lane fails, for good, on a `None` or invalid parameter set, a
    /// model too stiff for the step (exact), a state that overflows, or a solver error
    /// (ode45); a failed lane's values are +∞. Allocates nothing.
    ///
    /// # Panics
    /// If `stride` < [`LANES`], `batch` is not the simulator that started the run (a
    /// different backend) or `out` is too short (programming errors).
    pub(crate) fn advance_strided(
        &mut self,
        batch: &BatchSimulator<'_>,
        until: usize,
        out: &mut [f64],
        stride: usize,
    ) -> [bool; LANES] {
        assert!(stride >= LANES, "stride below {LANES}");
        let (start, until) = (self.next, until.min(batch.samples()).max(self.next));
        let needed = (until - start)
            .checked_sub(1)
            .map_or(0, |last| last * stride + LANES);
        assert!(out.len() >= needed, "output buffer too short");
        let ok = match (&mut self.lanes, &batch.kind) {
            (Lanes::Exact { stepper: None, .. }, Kind::Exact { .. }) => [false; LANES],
            (
                Lanes::Exact {
                    stepper: Some(stepper),
                    ok,
                },
                Kind::Exact { schedule, .. },
            ) => {
                let mut store = |t: usize, x: &[[f64; LANES]; 2]| {
                    let at = (t - start) * stride;
                    out[at..at + LANES].copy_from_slice(&x[0]);
                };
                if start == 0 && until > 0 {
                    store(0, stepper.state());
                }
                stepper.advance(schedule, until.saturating_sub(1), store);
                // Once a lane overflows its state stays non-finite (every component sums
                // over all of them), so the state at the end tells which lanes failed.
                let last = stepper.state();
                for (lane, good) in ok.iter_mut().enumerate() {
                    *good &= (0..2).all(|r| last[r][lane].is_finite());
                }
                *ok
            }
            (Lanes::Ode45(run), Kind::Ode45 { .. }) => {
                let (lanes, plants) = &mut **run;
                lanes.advance(plants, until, 0, |lane, t, x| {
                    out[(t - start) * stride + lane] = x
                })
            }
            _ => panic!("a batch run advanced by a simulator of another backend"),
        };
        for (lane, _) in ok.iter().enumerate().filter(|(_, good)| !**good) {
            for t in 0..until - start {
                out[t * stride + lane] = f64::INFINITY;
            }
        }
        self.next = until;
        ok
    }
}
