"""msd in Python against scipy and pyuff on the same arrays (numbers for BENCHMARKS.md,
not a timed test). Run with a release build of the package:

    pip install ./crates/msd-py scipy pyuff && python examples/python/bench.py

1. The paper's fit: msd.estimate(preset="paper") (Nelder–Mead with fminsearch's
   defaults on ode45, RelTol 1e-6, AbsTol 1e-9, from θ0 = (2, 1, 100)) against the same
   fit in scipy: solve_ivp(RK45, same tolerances, the force linear between samples) inside
   scipy.optimize.minimize(method="Nelder-Mead", xatol = fatol = 1e-4, fminsearch's).
2. The call overhead: the Python call's wall time against the Rust estimate's own wall
   time (`wall_time_s`, measured inside msd_ident::estimate).
3. Reading a ~100 MB ASCII dataset-58 file: msd.uff.read against pyuff.
"""

import os
import statistics
import sys
import tempfile
import time

import numpy as np

import msd


def median_time(f, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return statistics.median(times), min(times), max(times)


def scipy_paper_fit(t, force, x):
    from scipy.integrate import solve_ivp
    from scipy.optimize import minimize

    def simulate(theta):
        m, c, k = theta
        def rhs(s, y):
            return [y[1], (np.interp(s, t, force) - c * y[1] - k * y[0]) / m]
        return solve_ivp(rhs, (t[0], t[-1]), [0.0, 0.0], method="RK45", t_eval=t, rtol=1e-6, atol=1e-9).y[0]

    def cost(theta):
        if np.any(np.asarray(theta) <= 0):
            return np.inf
        r = x - simulate(theta)
        return float(r @ r)

    return minimize(cost, [2.0, 1.0, 100.0], method="Nelder-Mead",
                    options={"xatol": 1e-4, "fatol": 1e-4, "maxiter": 600, "maxfev": 600})


def main():
    rows = []
    d = msd.paper_data(1)["identification"]
    t, force, x = d["t"], d["force"], d["displacement"]
    fit = msd.estimate(t, force, x, preset="paper")
    ours = median_time(lambda: msd.estimate(t, force, x, preset="paper"), 21)
    scipy_repeats = int(os.environ.get("BENCH_SCIPY_REPEATS", "3"))
    result = {}
    theirs = median_time(lambda: result.setdefault("r", scipy_paper_fit(t, force, x)), scipy_repeats)
    r = result["r"]
    print(f"msd:   m, c, k = {fit.mass.value:.5f}, {fit.damping.value:.5f}, {fit.stiffness.value:.4f}, "
          f"{fit.iterations} iterations, {fit.evaluations} evaluations")
    print(f"scipy: m, c, k = {r.x[0]:.5f}, {r.x[1]:.5f}, {r.x[2]:.4f}, {r.nit} iterations, {r.nfev} evaluations")
    rows.append(("paper fit: msd.estimate(preset=\"paper\")", ours, 21))
    rows.append(("paper fit: scipy solve_ivp RK45 + Nelder–Mead", theirs, scipy_repeats))
    speedup = theirs[0] / ours[0]

    # The call overhead: Python wall time over the Rust estimate's own wall time.
    ratios = []
    for _ in range(21):
        start = time.perf_counter()
        e = msd.estimate(t, force, x, preset="paper")
        wall = time.perf_counter() - start
        ratios.append(wall / e.data["wall_time_s"])
    overhead = statistics.median(ratios) - 1

    # A ~100 MB ASCII 58 file: 250 complex FRFs of 10,000 lines, double precision.
    import pyuff

    rng = np.random.default_rng(1)
    n, count = 10_000, int(os.environ.get("BENCH_UFF_FUNCTIONS", "250"))
    freq = np.arange(n) * 0.1
    sets = [
        {"type": 58, "func_type": 4, "rsp_node": i + 1, "rsp_dir": 3, "ref_node": 1, "ref_dir": 3,
         "x": freq, "data": rng.normal(size=n) + 1j * rng.normal(size=n), "abscissa_spec_data_type": 18}
        for i in range(count)
    ]
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "large.uff")
        msd.uff.write(path, sets)
        size_mb = os.path.getsize(path) / 1e6
        read_ours = median_time(lambda: msd.uff.read(path), 5)
        read_theirs = median_time(lambda: pyuff.UFF(path).read_sets(), 3)
        a, b = msd.uff.read(path), pyuff.UFF(path).read_sets()
        assert all(np.array_equal(p["data"], q["data"]) for p, q in zip(a, b))
    rows.append((f"read a {size_mb:.0f} MB ASCII 58 file: msd.uff.read", read_ours, 5))
    rows.append((f"read a {size_mb:.0f} MB ASCII 58 file: pyuff.UFF().read_sets()", read_theirs, 3))

    print()
    print("| row | median | min – max | runs |")
    print("|---|---:|---:|---:|")
    for name, (med, lo, hi), runs in rows:
        print(f"| {name} | {med * 1e3:.1f} ms | {lo * 1e3:.1f} – {hi * 1e3:.1f} ms | {runs} |")
    print()
    print(f"paper fit: msd {speedup:.0f}× faster than scipy (target ≥ 50×)")
    print(f"call overhead of msd.estimate over the Rust estimate's wall time: {100 * overhead:.2f} % (target ≤ 5 %)")
    print(f"UFF read: msd {read_theirs[0] / read_ours[0]:.0f}× faster than pyuff (target ≥ 10×); values identical")
    print(f"python {sys.version.split()[0]}, numpy {np.__version__}, load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
