"""The paper's workflow in SciPy alone: the reference `cargo xtask experiment
configs/paper.toml` is timed against (issue 34; BENCHMARKS.md).

The same work as the Rust command, without figures and report: the identification and
validation records of ../shared/paper-experiment.md simulated by ode45 (solve_ivp RK45,
RelTol 1e-6, AbsTol 1e-9) with 2.5 mm of noise; Nelder–Mead with fminsearch's settings
from (2, 1, 100); the validation R²; the residuals' autocorrelation and Ljung–Box test;
the H1 frequency check (one Hann segment); the Monte Carlo band (1,000 ode45 simulations
of the validation input, parameters uniform within ±10 %). It needs numpy and scipy:

    python examples/python/paper_scipy.py      # prints the estimates and the timings
"""

import time

import numpy as np
from scipy import integrate, optimize, signal, stats

T, DT, SIGMA = 15.0, 0.002, 0.0025
TRUE = np.array([2.5, 1.8, 120.0])
t = np.linspace(0.0, T, 7501)


def f_id(s):
    f = 6.0 * (s >= 0.5)
    if 3.0 <= s < 9.0:
        f += 3.0 * np.sin(2 * np.pi * 0.5 * s)
    if 9.0 <= s <= 15.0:
        f += 2.5 * np.sin(2 * np.pi * 1.4 * s)
    return f


def f_val(s):
    return 2.5 * np.sin(2 * np.pi * (0.2 * s + (3.0 - 0.2) / (2 * T) * s * s)) + 1.0 * (s >= 1.0)


def simulate(theta, force):
    m, c, k = theta
    rhs = lambda s, x: [x[1], (force(s) - c * x[1] - k * x[0]) / m]  # noqa: E731
    sol = integrate.solve_ivp(rhs, (0.0, T), [0.0, 0.0], t_eval=t, rtol=1e-6, atol=1e-9)
    return sol.y[0] if sol.success else np.full_like(t, np.nan)


def r2(y, yhat):
    return 1.0 - np.sum((y - yhat) ** 2) / np.sum((y - y.mean()) ** 2)


def main():
    timings = {}
    clock = time.perf_counter()
    rng = np.random.default_rng(1)
    y_id = simulate(TRUE, f_id) + rng.normal(0.0, SIGMA, t.size)
    y_val = simulate(TRUE, f_val) + rng.normal(0.0, SIGMA, t.size)
    timings["data"], clock = time.perf_counter() - clock, time.perf_counter()

    theta0 = np.array([2.0, 1.0, 100.0])
    simplex = np.vstack([theta0] + [theta0 * (1 + 0.05 * np.eye(3)[i]) for i in range(3)])
    cost = lambda th: np.sum((y_id - simulate(th, f_id)) ** 2)  # noqa: E731
    fit = optimize.minimize(cost, theta0, method="Nelder-Mead", options=dict(
        initial_simplex=simplex, xatol=1e-4, fatol=1e-4, maxiter=600, maxfev=600))
    theta = fit.x
    timings["estimation"], clock = time.perf_counter() - clock, time.perf_counter()

    x_val = simulate(theta, f_val)
    residuals = y_val - x_val
    timings["validation"], clock = time.perf_counter() - clock, time.perf_counter()

    e = residuals - residuals.mean()
    acf = np.array([np.dot(e[:-k], e[k:]) for k in range(1, 21)]) / np.dot(e, e)
    n = e.size
    q = n * (n + 2) * np.sum(acf**2 / (n - np.arange(1, 21)))
    ljung_box_p = stats.chi2.sf(q, 20)
    timings["residuals"], clock = time.perf_counter() - clock, time.perf_counter()

    u = np.array([f_val(s) for s in t])
    fs = 1.0 / DT
    _, pxx = signal.welch(u, fs, window="hann", nperseg=t.size)
    _, pxy = signal.csd(u, y_val, fs, window="hann", nperseg=t.size)
    h1 = pxy / pxx
    timings["frequency_check"], clock = time.perf_counter() - clock, time.perf_counter()

    draws = np.random.default_rng(2).uniform(0.9, 1.1, (1000, 3)) * theta
    band = np.array([simulate(d, f_val) for d in draws])
    low, high = np.nanpercentile(band, [5, 95], axis=0)
    coverage = np.mean((y_val >= low) & (y_val <= high))
    timings["monte_carlo"] = time.perf_counter() - clock

    print(f"m, c, k = {theta[0]:.6f}, {theta[1]:.6f}, {theta[2]:.6f} ({fit.nfev} evaluations)")
    print(f"R2 identification {r2(y_id, simulate(theta, f_id)):.4f}, validation {r2(y_val, x_val):.4f}")
    print(f"Ljung-Box p = {ljung_box_p:.3f}; H1 at 1.1 Hz |H| = {abs(h1[int(1.1 * T)]):.4g} m/N")
    print(f"Monte Carlo coverage {coverage:.3f}")
    print("timings (s): " + ", ".join(f"{k} {v:.3f}" for k, v in timings.items())
          + f", total {sum(timings.values()):.3f}")


if __name__ == "__main__":
    main()
