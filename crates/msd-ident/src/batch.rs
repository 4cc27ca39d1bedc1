//! Many parameter sets on one excitation, [`LANES`] at a time, streamed along the record.

use crate::{Backend, Excitation, InitialState, Parameters, Result};
use msd_ode::{
    ExactSimulator, Hold, InputSchedule, LaneSystem, Lockstep, Ode45Lanes, Ode45Options,
    SampledInput, TimeGrid,
};

/// Parameter sets a [`BatchRun`] steps together.
pub const LANES: usize = 8;

/// The simulation of many parameter sets on one excitation, as a Monte Carlo run needs
/// it: what every run shares is prepared (and checked) once — the input's stencils for
/// the exact backend, the time grid for ode45 — and [`LANES`] parameter sets at a time
/// are advanced along the record in stretches ([`BatchRun`]), so a caller can keep a
/// short window of every response instead of whole responses. Every lane gives bit for
/// bit what [`simulate`](crate::simulate) gives for its parameters with the same backend.
///
/// ```
/// use msd_ident::{simulate, Backend, BatchSimulator, Excitation, InitialState, Parameters, LANES};
/// use msd_signal::paper_validation_input;
/// let input = Excitation::from_signal(paper_validation_input(), 0.0, 0.002, 7501)?;
/// let batch = BatchSimulator::new(&input, &Backend::EXACT)?;
/// let mut sets = [None; LANES];
/// sets[0] = Some(Parameters::PAPER);
/// sets[1] = Some(Parameters::new(2.6, 1.7, 125.0)?);
/// let mut out = vec![0.0; 7501 * LANES]; // time-major: out[t·LANES + lane]
/// let ok = batch.simulate_lanes(&sets, InitialState::REST, &mut out);
/// assert_eq!(&ok[..3], &[true, true, false]);
/// let alone = simulate(&sets[1].unwrap(), &input, InitialState::REST, &Backend::EXACT)?;
/// assert!((0..7501).all(|t| out[t * LANES + 1] == alone[t]));
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
#[derive(Debug, Clone)]
pub struct BatchSimulator<'a> {
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
    pub fn new(excitation: &'a Excitation, backend: &Backend) -> Result<Self> {
        backend.validate()?;
        let kind = match *backend {
            Backend::Exact { hold } => {
                let input = SampledInput {
                    values: excitation.samples(),
                    breakpoints: excitation.breakpoints(),
                };
                Kind::Exact {
                    schedule: InputSchedule::new(&input, hold)?,
                    hold,
                }
            }
            Backend::Ode45 { rel_tol, abs_tol } => Kind::Ode45 {
                grid: TimeGrid::new(excitation.times())?,
                options: backend.ode45_options(rel_tol, abs_tol),
            },
        };
        Ok(Self { excitation, kind })
    }

    /// Number of samples of the excitation.
    pub fn samples(&self) -> usize {
        self.excitation.len()
    }

    /// Starts the parameter sets of `parameters` (at most [`LANES`]; `None` leaves a
    /// lane empty, and it counts as failed) from `initial`, at sample 0.
    ///
    /// # Panics
    /// If `parameters` has more than [`LANES`] entries (a programming error).
    pub fn start(&self, parameters: &[Option<Parameters>], initial: InitialState) -> BatchRun<'a> {
        assert!(
            parameters.len() <= LANES,
            "more than {LANES} parameter sets"
        );
        let set = |lane: usize| {
            let p = parameters.get(lane).copied().flatten()?;
            p.validate().ok().map(|()| p)
        };
        let x0 = initial.vector();
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

    /// The whole record of up to [`LANES`] parameter sets at once: [`start`](Self::start)
    /// then [`BatchRun::advance`] to the end, into `out[t·LANES + lane]`.
    ///
    /// # Panics
    /// If `parameters` has more than [`LANES`] entries or `out` is shorter than
    /// `samples()·LANES` (programming errors).
    pub fn simulate_lanes(
        &self,
        parameters: &[Option<Parameters>],
        initial: InitialState,
        out: &mut [f64],
    ) -> [bool; LANES] {
        self.start(parameters, initial)
            .advance(self, self.samples(), out)
    }
}

/// Up to [`LANES`] parameter sets part-way along the record of a [`BatchSimulator`].
#[derive(Debug, Clone)]
pub struct BatchRun<'a> {
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
    ///
    /// ```
    /// assert!(msd_ident::BatchRun::MAX_BYTES < 8 << 10);
    /// ```
    pub const MAX_BYTES: usize = {
        let exact = size_of::<Lockstep<2, LANES>>();
        let ode45 = size_of::<(Ode45Lanes<'static, 2, LANES>, Plants<'static>)>();
        size_of::<Self>() + if exact > ode45 { exact } else { ode45 }
    };

    /// The next sample to be produced (0 after [`BatchSimulator::start`]).
    pub fn next_sample(&self) -> usize {
        self.next
    }

    /// Produces the samples from [`next_sample`](Self::next_sample) up to `until`
    /// (clamped to the record), writing sample t of lane l to
    /// `out[(t − next_sample)·LANES + l]`, and returns which lanes are still good. A lane
    /// fails, for good, on a `None` or invalid parameter set, a model too stiff for the
    /// step (exact), a state that overflows, or a solver error (ode45); a failed lane's
    /// values are +∞. Allocates nothing.
    ///
    /// # Panics
    /// If `batch` is not the simulator that started the run (a different backend) or
    /// `out` is too short (programming errors).
    pub fn advance(
        &mut self,
        batch: &BatchSimulator<'_>,
        until: usize,
        out: &mut [f64],
    ) -> [bool; LANES] {
        self.advance_strided(batch, until, out, LANES)
    }

    /// As [`advance`](Self::advance), writing sample t of lane l to
    /// `out[(t − next_sample)·stride + l]`: the lanes' values at one time are
    /// [`LANES`] contiguous values, `stride` (≥ [`LANES`]) apart from one time to the
    /// next, so a caller can write straight into a wider time-major table.
    ///
    /// ```
    /// use msd_ident::{Backend, BatchSimulator, Excitation, InitialState, Parameters, LANES};
    /// let input = Excitation::from_samples(0.0, 0.01, vec![1.0; 100])?;
    /// let batch = BatchSimulator::new(&input, &Backend::EXACT)?;
    /// let sets = [Some(Parameters::PAPER); LANES];
    /// let mut table = vec![0.0; 100 * 2 * LANES]; // two runs side by side
    /// batch.start(&sets, InitialState::REST).advance_strided(&batch, 100, &mut table[LANES..], 2 * LANES);
    /// let mut alone = vec![0.0; 100 * LANES];
    /// batch.start(&sets, InitialState::REST).advance(&batch, 100, &mut alone);
    /// assert!((0..100).all(|t| table[t * 2 * LANES + LANES] == alone[t * LANES]));
    /// # Ok::<(), msd_ident::IdentError>(())
    /// ```
    ///
    /// # Panics
    /// If `stride` < [`LANES`], or as [`advance`](Self::advance).
    pub fn advance_strided(
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
