"""The paper's workflow from Python: fit m, c, k by the paper's method (Nelder–Mead on
ode45), then the whole run with validation and the ±10 % Monte Carlo band, plotted.

    pip install ./crates/msd-py matplotlib && python examples/python/paper.py
"""
import pathlib, sys
import matplotlib.pyplot as plt
import numpy as np
import msd

root = pathlib.Path(__file__).resolve().parents[2]
data = msd.paper_data(seed=1)["identification"]
fit = msd.estimate(data["t"], data["force"], data["displacement"], preset="paper")
print(fit)                                   # m, c, k with 95 % intervals, fn, ζ, R²
run = msd.run(root / "configs/paper.toml", out=root / "target/experiments/paper-python")
v = np.genfromtxt(pathlib.Path(run.out_dir) / "validation.csv", delimiter=",", names=True)
fig, (a, b) = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
a.plot(data["t"], 1e3 * data["displacement"], ".", ms=1, label="measured")
a.plot(data["t"], 1e3 * fit.model_output, label=f"model, R² = {fit.r_squared:.4f}")
b.fill_between(v["t"], 1e3 * v["band_lower"], 1e3 * v["band_upper"], alpha=0.3, label="Monte Carlo 5–95 %")
b.plot(v["t"], 1e3 * v["measured"], ".", ms=1, label="validation data")
b.plot(v["t"], 1e3 * v["model"], label="model")
for ax, title in ((a, "identification"), (b, "validation")):
    ax.set(ylabel="x [mm]", title=title); ax.legend(loc="upper right")
b.set_xlabel("t [s]")
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "paper.png", dpi=120, bbox_inches="tight")
