//! The chain's weighted output-error least-squares problem for the Levenberg–Marquardt
//! solver: θ = (ln of every free m, c, k; ln of each estimated filter cut-off; then each
//! estimated delay in seconds).

use super::model::{self, Family, System, Values};
use super::setup::{ChainParameters, ChainSetup};
use super::simulate::{Simulation, simulate};
use msd_opt::LeastSquaresProblem;
use msd_signal::Recording;
use nalgebra::DMatrix;

/// The fitted columns and what is held.
#[derive(Debug, Clone)]
pub(crate) struct Layout {
    /// The free physical parameters, by family and index.
    pub free: Vec<(Family, usize)>,
    /// The channels whose low-pass cut-off is estimated, and each one's start, Hz.
    pub cutoffs: Vec<(usize, f64)>,
    /// The channels whose delay is estimated.
    pub delayed: Vec<usize>,
}

impl Layout {
    /// The columns of a fit of `setup` from `guess`: the masses not known, every c and k,
    /// the ground connections the guess has (> 0), the cut-offs and delays asked for.
    pub(crate) fn new(setup: &ChainSetup, known_masses: &[usize], guess: &ChainParameters) -> Self {
        let n = setup.masses;
        let masses = (0..n).filter(|i| !known_masses.contains(&(i + 1)));
        let grounded = |values: &[f64], family: Family| {
            (0..values.len())
                .filter(move |&i| values[i] > 0.0)
                .map(move |i| (family, i))
                .collect::<Vec<_>>()
        };
        let free = masses
            .map(|i| (Family::Mass, i))
            .chain((0..n).map(|i| (Family::Damper, i)))
            .chain((0..n).map(|i| (Family::Spring, i)))
            .chain(grounded(&guess.ground_dampers, Family::GroundDamper))
            .chain(grounded(&guess.ground_springs, Family::GroundSpring))
            .collect();
        let delayed = (0..setup.sensors.len())
            .filter(|&ch| setup.sensors[ch].estimate_delay)
            .collect();
        let cutoffs = setup
            .sensors
            .iter()
            .enumerate()
            .filter(|(_, s)| s.estimate_cutoff)
            .filter_map(|(ch, s)| s.low_pass.map(|f| (ch, f.cutoff_hz)))
            .collect();
        Self {
            free,
            cutoffs,
            delayed,
        }
    }

    /// Holds column `j` at the start's value: it is no longer fitted.
    pub(crate) fn hold(&mut self, j: usize) {
        let free = self.free.len();
        if j < free {
            self.free.remove(j);
        } else if j < self.simulated() {
            self.cutoffs.remove(j - free);
        } else if j < self.len() {
            self.delayed.remove(j - self.simulated());
        }
    }

    /// The column of the physical parameter `family`, `i`, when it is fitted.
    pub(crate) fn column(&self, family: Family, i: usize) -> Option<usize> {
        self.free.iter().position(|&c| c == (family, i))
    }

    pub(crate) fn len(&self) -> usize {
        self.free.len() + self.cutoffs.len() + self.delayed.len()
    }

    /// The columns with sensitivities from the simulation: m, c, k, then the cut-offs.
    pub(crate) fn simulated(&self) -> usize {
        self.free.len() + self.cutoffs.len()
    }

    /// `setup` with the cut-offs of θ.
    pub(crate) fn setup_at(&self, theta: &[f64], setup: &ChainSetup) -> ChainSetup {
        let mut out = setup.clone();
        for (&(ch, _), &t) in self.cutoffs.iter().zip(&theta[self.free.len()..]) {
            if let Some(filter) = out.sensors[ch].low_pass.as_mut() {
                filter.cutoff_hz = t.exp();
            }
        }
        out
    }

    /// θ of `parameters` and `delays`.
    pub(crate) fn theta(&self, parameters: &ChainParameters, delays: &[f64]) -> Vec<f64> {
        self.free
            .iter()
            .map(|&(family, i)| family_of(parameters, family)[i].ln())
            .chain(self.cutoffs.iter().map(|&(_, hz)| hz.ln()))
            .chain(self.delayed.iter().map(|&ch| delays[ch]))
            .collect()
    }

    /// The parameters and delays at θ, the held ones from `base` and `delays`.
    pub(crate) fn unpack(
        &self,
        theta: &[f64],
        base: &ChainParameters,
        delays: &[f64],
    ) -> (ChainParameters, Vec<f64>) {
        let mut parameters = base.clone();
        for (&(family, i), &t) in self.free.iter().zip(theta) {
            family_of_mut(&mut parameters, family)[i] = t.exp();
        }
        let mut delays = delays.to_vec();
        for (&ch, &t) in self.delayed.iter().zip(&theta[self.simulated()..]) {
            delays[ch] = t;
        }
        (parameters, delays)
    }

    /// The name of column `j` ("m1", "c2", "cutoff1", "delay2", …; sensors from 1).
    pub(crate) fn name(&self, j: usize) -> String {
        let free = self.free.len();
        match self.free.get(j) {
            Some(&(family, i)) => format!("{}{}", symbol(family), i + 1),
            None if j < self.simulated() => format!("cutoff{}", self.cutoffs[j - free].0 + 1),
            None => format!("delay{}", self.delayed[j - self.simulated()] + 1),
        }
    }
}

pub(crate) fn symbol(family: Family) -> &'static str {
    match family {
        Family::Mass => "m",
        Family::Damper => "c",
        Family::Spring => "k",
        Family::GroundDamper => "cg",
        Family::GroundSpring => "kg",
    }
}

pub(crate) fn family_of(p: &ChainParameters, family: Family) -> &[f64] {
    match family {
        Family::Mass => &p.masses,
        Family::Damper => &p.dampers,
        Family::Spring => &p.springs,
        Family::GroundDamper => &p.ground_dampers,
        Family::GroundSpring => &p.ground_springs,
    }
}

fn family_of_mut(p: &mut ChainParameters, family: Family) -> &mut Vec<f64> {
    match family {
        Family::Mass => &mut p.masses,
        Family::Damper => &mut p.dampers,
        Family::Spring => &mut p.springs,
        Family::GroundDamper => &mut p.ground_dampers,
        Family::GroundSpring => &mut p.ground_springs,
    }
}

pub(crate) fn values(p: &ChainParameters) -> Values {
    Values {
        w: p.masses.iter().map(|m| 1.0 / m).collect(),
        c: p.dampers.clone(),
        k: p.springs.clone(),
        cg: or_zeros(&p.ground_dampers, p.masses.len()),
        kg: or_zeros(&p.ground_springs, p.masses.len()),
    }
}

/// `values`, or `n` zeros when there are none.
fn or_zeros(values: &[f64], n: usize) -> Vec<f64> {
    if values.is_empty() {
        vec![0.0; n]
    } else {
        values.to_vec()
    }
}

/// The system at `parameters` and its derivatives to the free θ (log parameters).
pub(crate) fn systems(
    setup: &ChainSetup,
    layout: &Layout,
    parameters: &ChainParameters,
) -> (System, Vec<System>) {
    let v = values(parameters);
    let plant = model::system(setup, &v);
    let partials = layout
        .free
        .iter()
        .map(|&(family, i)| {
            let mut d = model::derivative(setup, &v, family, i);
            // ∂/∂ln m = −w·∂/∂w; ∂/∂ln p = p·∂/∂p otherwise.
            let factor = match family {
                Family::Mass => -v.w[i],
                Family::Damper => v.c[i],
                Family::Spring => v.k[i],
                Family::GroundDamper => v.cg[i],
                Family::GroundSpring => v.kg[i],
            };
            d.a *= factor;
            d.b *= factor;
            d.c *= factor;
            d.d *= factor;
            d
        })
        .chain(
            layout
                .cutoffs
                .iter()
                .map(|&(ch, _)| cutoff_derivative(setup, &v, ch)),
        )
        .collect();
    (plant, partials)
}

/// ∂System/∂ln fc of channel `ch`'s filter: a central difference, exact up to rounding
/// because the system is a polynomial of degree ≤ 2 in fc (ωc·… and ωc²·… entries).
fn cutoff_derivative(setup: &ChainSetup, v: &Values, ch: usize) -> System {
    let at = |factor: f64| {
        let mut s = setup.clone();
        if let Some(filter) = s.sensors[ch].low_pass.as_mut() {
            filter.cutoff_hz *= factor;
        }
        model::system(&s, v)
    };
    const H: f64 = 1e-3;
    let (up, down) = (at(1.0 + H), at(1.0 - H));
    // fc·(S(fc(1 + h)) − S(fc(1 − h)))/(2h·fc)
    System {
        a: (up.a - down.a) / (2.0 * H),
        b: (up.b - down.b) / (2.0 * H),
        c: (up.c - down.c) / (2.0 * H),
        d: (up.d - down.d) / (2.0 * H),
    }
}

/// The weighted residuals (ŷ − y)/σ of every channel, for the solver.
pub(crate) struct ChainProblem<'a> {
    pub setup: &'a ChainSetup,
    pub record: &'a Recording,
    pub layout: &'a Layout,
    pub base: &'a ChainParameters,
    pub delays: &'a [f64],
    /// σ of each channel.
    pub noise: Vec<f64>,
}

impl ChainProblem<'_> {
    /// The simulation at θ, or None where it cannot be computed (a delay out of range,
    /// an exponential out of range).
    pub(crate) fn simulate(
        &self,
        theta: &[f64],
        jacobian: Option<&mut DMatrix<f64>>,
    ) -> Option<Simulation> {
        let (parameters, mut delays) = self.layout.unpack(theta, self.base, self.delays);
        let half = self.record.dt * self.record.len() as f64 / 2.0;
        if delays.iter().any(|d| !(d.is_finite() && *d < half)) {
            return None;
        }
        // A delay is not negative: a step past zero reads the sensor at zero delay (the
        // residual stays continuous, so the other parameters still move when the true
        // delay is zero; a hard wall there stalled every step at the guess).
        for d in &mut delays {
            *d = d.max(0.0);
        }
        let setup = self.layout.setup_at(theta, self.setup);
        let (plant, partials) = systems(&setup, self.layout, &parameters);
        simulate(
            &plant,
            &partials,
            &delays,
            self.record.input(),
            self.record.dt,
            jacobian,
        )
        .ok()
    }

    fn weighted(&self, outputs: &[f64], out: &mut [f64]) {
        let samples = self.record.len();
        for (ch, measured) in self.record.responses().enumerate() {
            let scale = 1.0 / self.noise[ch];
            let range = ch * samples..(ch + 1) * samples;
            for ((r, y), m) in out[range.clone()]
                .iter_mut()
                .zip(&outputs[range])
                .zip(measured)
            {
                *r = (y - m) * scale;
            }
        }
    }
}

impl LeastSquaresProblem for ChainProblem<'_> {
    fn residual_count(&self) -> usize {
        self.record.len() * self.record.channels.len()
    }

    fn residuals(&mut self, theta: &[f64], out: &mut [f64]) -> bool {
        match self.simulate(theta, None) {
            Some(sim) => {
                self.weighted(&sim.outputs, out);
                true
            }
            None => false,
        }
    }

    fn jacobian(&mut self, theta: &[f64], out: &mut DMatrix<f64>) -> bool {
        let Some(sim) = self.simulate(theta, Some(out)) else {
            return false;
        };
        let samples = self.record.len();
        let free = self.layout.simulated();
        for j in 0..free {
            for (ch, sigma) in self.noise.iter().enumerate() {
                out.view_mut((ch * samples, j), (samples, 1))
                    .scale_mut(1.0 / sigma);
            }
        }
        for (j, &ch) in self.layout.delayed.iter().enumerate() {
            let scale = 1.0 / self.noise[ch];
            for k in ch * samples..(ch + 1) * samples {
                // The channel reads y(t − τ): ∂/∂τ = −ẏ(t − τ).
                out[(k, free + j)] = -sim.rates[k] * scale;
            }
        }
        true
    }
}

/// Refuses a record with no more rows than estimated quantities.
pub(crate) fn enough_rows(rows: usize, estimated: usize) -> crate::error::Result<()> {
    if rows <= estimated {
        return Err(crate::error::IdentError::TooFewSamples {
            got: rows,
            needed: estimated + 1,
            why: "more samples than estimated quantities",
        });
    }
    Ok(())
}
