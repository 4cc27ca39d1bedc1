"""Output-only modal analysis of a real steel frame (setup 1 of pyOMA's example data):
msd.oma at default settings against pyOMA2's SSI-cov on the same array in the same run,
and both against the origin's merged result.

    cargo xtask fetch-data steel-frame            # data/steel-frame/
    pip install ./crates/msd-py pyoma-2 && python examples/python/oma_steel_frame.py

pyOMA2 runs SSI-cov with msd's block rows (106, lags spanning one period of the lowest
mode: at pyOMA's usual 45 neither tool finds the three lowest modes), orders to 80,
references 3 and 4; its order-80 poles are then picked at msd's frequencies (pyOMA2 has
no automatic selection for a single setup). It is timed without intervals (pyOMA2's
default) and with them (`calc_unc=True`, its 50-block uncertainty): msd always gives
intervals. Times are medians of repeated runs in this process.
"""
import pathlib
import statistics
import time

import numpy as np

import msd

REFERENCE = [1.2283, 1.4358, 2.1000, 4.0175, 4.7704, 6.6824, 7.6157, 9.6653, 12.1663, 12.5979, 13.8545]

folder = pathlib.Path(__file__).resolve().parents[2] / "data/steel-frame/measurement_1"
y = np.load(folder / "measurement_1.npy")[:, :5]
dofs = [(5, 0), (5, 0), (5, 0), (24, -1), (24, -2)]
quantities = ["velocity"] * 3 + ["acceleration"] * 2


def median_time(run, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        result = run()
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


t_msd, fit = median_time(lambda: msd.oma(y, 256.0, references=[3, 4], dofs=dofs, quantities=quantities), 5)
print(fit)
for f in REFERENCE:
    near = min(fit.modes, key=lambda m: abs(m.natural_frequency_hz.value - f))
    print(f"reference {f:8.4f} Hz: msd {near.natural_frequency_hz.value:8.4f} Hz "
          f"({100 * (near.natural_frequency_hz.value / f - 1):+.2f} %), ζ = {100 * near.damping_ratio.value:.3f} %")
print(f"msd.oma (SSI-cov/ref, automatic selection, jackknife intervals): {1e3 * t_msd:.0f} ms")

try:
    from pyoma2.algorithms import SSI
    from pyoma2.setup import SingleSetup
except ImportError:
    print("pyOMA2 is not installed (pip install pyoma-2): no comparison")
else:
    def pyoma(calc_unc):
        setup = SingleSetup(y, fs=256.0)
        ssi = SSI(name="SSIcov", method="cov", br=fit.data["block_rows"], ordmax=80, ref_ind=[3, 4], calc_unc=calc_unc)
        setup.add_algorithms(ssi)
        setup.run_by_name("SSIcov")
        if not calc_unc:  # its uncertainty's hard criterion (CoV_max) empties order 80
            setup.mpe("SSIcov", sel_freq=[m.natural_frequency_hz.value for m in fit.modes], order_in=80)
        return ssi.result

    t_plain, result = median_time(lambda: pyoma(False), 3)
    print("pyOMA2 at msd's frequencies:", np.round(np.ravel(result.Fn), 4))
    print(f"pyOMA2 SSI-cov without intervals: {1e3 * t_plain:.0f} ms (msd {t_plain / t_msd:.1f}× faster)")
    t_unc, _ = median_time(lambda: pyoma(True), 1)
    print(f"pyOMA2 SSI-cov with its intervals (calc_unc=True, the run alone): {1e3 * t_unc:.0f} ms (msd {t_unc / t_msd:.0f}× faster)")
