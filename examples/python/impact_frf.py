"""A real roving-hammer test (ladisk/pyuff's two measured accelerances) to modes:
natural frequencies, damping ratios with 95 % intervals, shapes, MAC.

    cargo xtask fetch-data impact-frf     # data/impact-frf/meas_point_{1,2}.txt
    pip install ./crates/msd-py matplotlib && python examples/python/impact_frf.py
"""
import pathlib, sys
import matplotlib.pyplot as plt
import numpy as np
import msd

folder = pathlib.Path(__file__).resolve().parents[2] / "data/impact-frf"
h = [np.loadtxt(folder / f"meas_point_{i}.txt", dtype=complex) for i in (1, 2)]
f = np.arange(h[0].size) * 1.0                       # 1 Hz lines from 0 Hz
dofs = [((1, 1), (1, 1)), ((1, 1), (2, 1))]          # response 1:+X; hammer at points 1 and 2
fit = msd.modal_fit(f, h, kind="accelerance", dofs=dofs, band_hz=[10.0, 1000.0])
print(fit)
for i, mode in enumerate(fit.modes, 1):
    print(f"mode {i}: fn = {mode.natural_frequency_hz.value:9.3f} Hz, "
          f"ζ = {mode.damping_ratio.value:.2e} [{mode.damping_ratio.ci95[0]:.2e}, {mode.damping_ratio.ci95[1]:.2e}], "
          f"shape {np.round(mode.shape.real, 3)}")
fig, ax = plt.subplots(figsize=(9, 4))
for hi, label in zip(h, ("hammer at 1", "hammer at 2")):
    ax.semilogy(f, np.abs(hi), lw=0.8, label=label)
for mode in fit.modes:
    ax.axvline(mode.natural_frequency_hz.value, color="k", lw=0.5, ls=":")
ax.set(xlabel="f [Hz]", ylabel="|A| [(m/s²)/N]", xlim=(0, 1000), title="accelerances and the fitted modes")
ax.legend()
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "impact_frf.png", dpi=120, bbox_inches="tight")
