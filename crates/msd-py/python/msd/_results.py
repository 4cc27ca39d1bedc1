"""Result objects: the Rust results' fields as attributes, `to_dict`, `repr` (the Rust
display text) and an HTML table for notebooks."""

from __future__ import annotations

import html
from dataclasses import dataclass, field
from typing import Any, Dict, Iterator, List, Optional, Tuple

import numpy as np

from ._convert import MissingKeyError, OutOfRangeError, integer, items, jsonable, mapping, number
from ._convert import field as _key


@dataclass(frozen=True)
class Interval:
    """An estimated quantity with its standard error and 95 % confidence interval."""

    value: float
    standard_error: float
    ci95: Tuple[float, float]

    @classmethod
    def from_dict(cls, d: Dict[str, Any]) -> "Interval":
        """The interval of a result dict's entry {value, standard_error, ci95} (None: NaN).

        Raises MissingKeyError (a ValueError) naming a missing key, TypeError or
        ValueError naming a key whose value is not a number (ci95: two)."""
        owner, expected = "Interval.from_dict", "expected value, standard_error, ci95"
        keys = [_key(owner, d, k, expected) for k in ("value", "standard_error", "ci95")]
        value, se, ci95 = keys
        bounds = items(f"{owner}: ci95", ci95, "[low, high]")
        if len(bounds) != 2:
            raise ValueError(f"{owner}: ci95 = {ci95!r:.60}: expected [low, high]")
        nan = float("nan")
        low, high = (nan if v is None else number(f"{owner}: ci95[{i}]", v) for i, v in enumerate(bounds))
        return cls(
            number(f"{owner}: value", value),
            nan if se is None else number(f"{owner}: standard_error", se),
            (low, high),
        )

    def contains(self, x: float) -> bool:
        """Whether x lies within the 95 % interval."""
        return self.ci95[0] <= x <= self.ci95[1]

    def to_dict(self) -> Dict[str, Any]:
        """{value, standard_error, ci95} as plain floats."""
        return jsonable(
            {"value": self.value, "standard_error": self.standard_error, "ci95": list(self.ci95)}
        )

    def __repr__(self) -> str:
        return (
            f"{self.value:.6g} ± {self.standard_error:.2e} "
            f"(95 % CI {self.ci95[0]:.6g} … {self.ci95[1]:.6g})"
        )


@dataclass(frozen=True)
class Plant:
    """A mass–spring–damper: mass m (kg), damping c (N·s/m), stiffness k (N/m)."""

    mass: float
    damping: float
    stiffness: float

    def to_dict(self) -> Dict[str, float]:
        """{mass, damping, stiffness}."""
        return {"mass": self.mass, "damping": self.damping, "stiffness": self.stiffness}


def _table(title: str, rows: List[Tuple[str, Any]]) -> str:
    """An HTML table of (name, Interval or value) rows."""
    out = [f"<table><caption>{html.escape(title)}</caption>"]
    out.append("<tr><th>quantity</th><th>estimate</th><th>standard error</th><th>95 % interval</th></tr>")
    for name, v in rows:
        if isinstance(v, Interval):
            out.append(
                f"<tr><td>{html.escape(name)}</td><td>{v.value:.6g}</td>"
                f"<td>{v.standard_error:.3g}</td><td>[{v.ci95[0]:.6g}, {v.ci95[1]:.6g}]</td></tr>"
            )
        else:
            out.append(f"<tr><td>{html.escape(name)}</td><td colspan=3>{html.escape(str(v))}</td></tr>")
    out.append("</table>")
    return "".join(out)


class Result:
    """Base of the result objects: `data` holds every field of the Rust result."""

    _arrays: Tuple[str, ...] = ()

    def __init__(self, data: Dict[str, Any]):
        self.data = data

    @property
    def summary(self) -> str:
        """The Rust display of the result (what the command line prints)."""
        return str(self.data.get("summary", ""))

    def to_dict(self) -> Dict[str, Any]:
        """Every field as plain JSON types (arrays as lists, NaN as None)."""
        return jsonable(self.data)

    @classmethod
    def from_dict(cls, d: Dict[str, Any]):
        """The result back from `to_dict()` (e.g. after a JSON round trip)."""
        data = dict(mapping(f"{cls.__name__}.from_dict", d, "a dict from to_dict()"))
        for key in cls._arrays:
            if data.get(key) is not None:
                data[key] = np.array([np.nan if v is None else v for v in data[key]], dtype=float)
        cls._restore(data)
        return cls(data)

    @classmethod
    def _restore(cls, data: Dict[str, Any]) -> None:
        """Restores what `_arrays` does not cover (complex arrays)."""

    def __repr__(self) -> str:
        return self.summary.rstrip("\n")

    def __eq__(self, other: object) -> bool:
        return type(other) is type(self) and self.to_dict() == other.to_dict()  # type: ignore[attr-defined]


class _PlantIntervals(Result):
    """m, c, k, fn and ζ with intervals from the result's `uncertainty`."""

    def _interval(self, name: str) -> Interval:
        return Interval.from_dict(self.data["uncertainty"][name])

    @property
    def mass(self) -> Interval:
        """Mass m, kg."""
        return self._interval("mass")

    @property
    def damping(self) -> Interval:
        """Damping c, N·s/m."""
        return self._interval("damping")

    @property
    def stiffness(self) -> Interval:
        """Stiffness k, N/m."""
        return self._interval("stiffness")

    @property
    def natural_frequency_hz(self) -> Interval:
        """Natural frequency fn, Hz (delta method)."""
        return self._interval("natural_frequency_hz")

    @property
    def damping_ratio(self) -> Interval:
        """Damping ratio ζ (delta method)."""
        return self._interval("damping_ratio")



class Estimate(_PlantIntervals):
    """`msd.estimate`'s result: m, c, k with intervals, fn, ζ, the fit and the
    optimiser's counts; every field of msd-ident's `Estimate` in `data`."""

    _arrays = ("model_output", "residuals", "t")

    @property
    def correlation(self) -> Dict[str, Dict[str, Optional[float]]]:
        """The estimates' correlation labelled by quantity: ``e.correlation["mass"]["stiffness"]``."""
        u = self.data["uncertainty"]
        names = list(u["names"])
        return {a: {b: u["correlation"][i][j] for j, b in enumerate(names)} for i, a in enumerate(names)}

    def plot(self, fig: Any = None) -> Any:
        """Draw the record: the measured displacement (points) under the model (a thin
        line on top), and the residual below; returns the matplotlib Figure."""
        if self.data.get("t") is None:
            raise ValueError("this estimate carries no time stamps (made before plot() existed)")
        title = f"displacement, fit {self.data['fit']['fit_percent']:.1f} %"
        panel = ("displacement", "m", self.model_output, self.residuals, title)
        return _plot_fits(np.asarray(self.data["t"], dtype=float), [panel], fig)

    @property
    def parameters(self) -> Plant:
        """The estimated plant."""
        p = self.data["parameters"]
        return Plant(p["mass"], p["damping"], p["stiffness"])

    @property
    def model_output(self) -> np.ndarray:
        """The model's displacement on the data (offset included)."""
        return self.data["model_output"]

    @property
    def residuals(self) -> np.ndarray:
        """Measured minus model."""
        return self.data["residuals"]

    @property
    def fit(self) -> Dict[str, Any]:
        """Fit metrics on the estimation data (r2, fit_percent, residual_rms, sse, samples)."""
        return self.data["fit"]

    @property
    def r_squared(self) -> float:
        """R² of the fit."""
        return self.data["fit"]["r2"]

    @property
    def converged(self) -> bool:
        """Whether the optimiser converged to a minimum."""
        return bool(self.data["converged"])

    @property
    def covariance(self) -> np.ndarray:
        """Covariance of the estimated quantities (order: `data['uncertainty']['names']`)."""
        return np.array(self.data["uncertainty"]["covariance"], dtype=float)

    @property
    def warnings(self) -> List[str]:
        """Identifiability warnings (empty when all is well)."""
        return list(self.data["uncertainty"]["warnings"])

    @property
    def method(self) -> str:
        """The optimiser: "nelder_mead" or "levenberg_marquardt"."""
        return self.data["method"]

    @property
    def iterations(self) -> int:
        """Optimiser iterations."""
        return self.data["iterations"]

    @property
    def evaluations(self) -> int:
        """Cost evaluations (simulations)."""
        return self.data["evaluations"]

    def _repr_html_(self) -> str:
        rows = [
            ("m [kg]", self.mass),
            ("c [N·s/m]", self.damping),
            ("k [N/m]", self.stiffness),
            ("fn [Hz]", self.natural_frequency_hz),
            ("ζ [-]", self.damping_ratio),
            ("R²", f"{self.r_squared:.6g}"),
            ("converged", self.converged),
        ]
        rows += [("warning", w) for w in self.warnings]
        return _table(f"msd.estimate ({self.method})", rows)


class Validation(Result):
    """`msd.validate`'s result: the model's prediction of fresh data, its fit (R², fit %)
    and the residual analysis (Ljung–Box whiteness, correlation with the input); every
    field of msd-ident's `Validation` in `data`."""

    _arrays = ("model_output", "residuals")

    @property
    def model_output(self) -> np.ndarray:
        """The model's prediction of the data."""
        return self.data["model_output"]

    @property
    def residuals(self) -> np.ndarray:
        """Measured minus predicted."""
        return self.data["residuals"]

    @property
    def r_squared(self) -> float:
        """R² of the prediction."""
        return self.data["fit"]["r2"]

    @property
    def fit(self) -> Dict[str, Any]:
        """Fit metrics (r2, fit_percent, residual_rms, sse, samples)."""
        return self.data["fit"]

    @property
    def residual_analysis(self) -> Dict[str, Any]:
        """Ljung–Box test, residual–input correlation and the verdicts in words."""
        return self.data["residual_analysis"]

    def _repr_html_(self) -> str:
        return f"<pre>{html.escape(self.summary)}</pre>"


class OneModeFit(_PlantIntervals):
    """`msd.one_mode_fit`'s result: m, c, k of one mode's FRF with intervals, fn, ζ, the
    gain and the half-power estimates; every field of msd-ident's `OneModeFit` in `data`."""

    @property
    def parameters(self) -> Plant:
        """The fitted plant."""
        p = self.data["parameters"]
        return Plant(p["mass"], p["damping"], p["stiffness"])

    @property
    def input_noise(self) -> Optional[Dict[str, Any]]:
        """The force's noise the coherence showed under an H1 estimate:
        ``{"h1_bias": H1's relative bias, "corrected": whether the lines were raised by
        it}`` (not under a leaking window, where it is a warning); None when none."""
        return self.data.get("input_noise")

    def _repr_html_(self) -> str:
        rows = [
            ("m", self.mass),
            ("c", self.damping),
            ("k", self.stiffness),
            ("fn [Hz]", self.natural_frequency_hz),
            ("ζ [-]", self.damping_ratio),
        ]
        return _table("msd.one_mode_fit", rows)


class FrequencyResponse(Result):
    """`msd.frf`'s result; unpacks as (frequency, h, coherence)."""

    _arrays = ("frequency", "coherence")

    @classmethod
    def _restore(cls, data: Dict[str, Any]) -> None:
        owner = "FrequencyResponse.from_dict"
        h = _key(owner, data, "h", "the frequency response as {re, im}")
        re, im = (_key(f"{owner}: h", h, k, "expected re and im") for k in ("re", "im"))
        data["h"] = np.array(re, dtype=float) + 1j * np.array(im, dtype=float)
        if data.get("variance") is not None:
            data["variance"] = np.array(data["variance"], dtype=float)
        if data.get("input_noise_variance") is not None:
            data["input_noise_variance"] = np.array(data["input_noise_variance"], dtype=float)
        if data.get("line_correlation") is not None:
            kernels = _key(owner, data, "line_correlation", "the (response, force) kernels")
            data["line_correlation"] = tuple(
                np.array(k["re"], dtype=float) + 1j * np.array(k["im"], dtype=float) for k in kernels
            )

    @property
    def frequency(self) -> np.ndarray:
        """Frequencies, Hz."""
        return self.data["frequency"]

    @property
    def h(self) -> np.ndarray:
        """The complex frequency response (output units per input unit)."""
        return self.data["h"]

    @property
    def coherence(self) -> np.ndarray:
        """γ² in [0, 1]."""
        return self.data["coherence"]

    @property
    def kind(self) -> str:
        """receptance, mobility or accelerance."""
        return self.data["kind"]

    @property
    def exponential_decay(self) -> Optional[float]:
        """τ of an exponential window applied to both channels, if any."""
        return self.data["exponential_decay"]

    @property
    def averages(self) -> int:
        """Segments K averaged into the estimate."""
        return int(self.data.get("averages", 1))

    @property
    def estimator(self) -> Optional[str]:
        """"H1", "H2" or "Hv"; None when not known."""
        return self.data.get("estimator")

    def __iter__(self) -> Iterator[np.ndarray]:
        return iter((self.frequency, self.h, self.coherence))

    def _repr_html_(self) -> str:
        d = self.data
        rows = [
            ("kind", d["kind"]),
            ("lines", f"{len(d['frequency'])}"),
            ("averages", d["averages"]),
            ("exponential window τ [s]", d["exponential_decay"]),
            ("lowest coherence", f"{float(np.min(d['coherence'])):.4g}" if len(d["coherence"]) else "–"),
        ]
        return _table(html.escape(repr(self)), rows)

    def __repr__(self) -> str:
        d = self.data
        return (
            f"FrequencyResponse({d['kind']}, {len(d['frequency'])} lines "
            f"{d['frequency'][0] if len(d['frequency']) else 0:g}–"
            f"{d['frequency'][-1] if len(d['frequency']) else 0:g} Hz, {d['averages']} averages)"
        )


@dataclass(frozen=True, eq=False)
class Mode:
    """One mode, whatever found it (msd-modal's `Mode`): natural frequency and damping
    ratio with intervals; the modal constant (one FRF), the shape over named DOFs (a set
    of FRFs, a chain's masses) with its standard errors where known, MPC, MPD, the modal
    mass; None where the method does not give it."""

    natural_frequency_hz: Interval
    damping_ratio: Interval
    stable_orders: Optional[int] = None
    modal_constant: Optional[complex] = None
    shape: Optional[np.ndarray] = None
    shape_dofs: Optional[List[Tuple[int, int]]] = None
    modal_mass: Optional[float] = None
    shape_standard_error: Optional[np.ndarray] = None
    mpc: Optional[float] = None
    mpd_deg: Optional[float] = None

    @classmethod
    def from_dict(cls, m: Dict[str, Any]) -> "Mode":
        """The mode of a result dict's entry (every field of msd-modal's `Mode`)."""
        owner = "Mode.from_dict"
        for key in ("natural_frequency_hz", "damping_ratio"):
            _key(owner, m, key, "expected natural_frequency_hz and damping_ratio")
        shape = m.get("shape") or []
        constants = m.get("modal_constants") or []
        se = [e.get("standard_error") for e in shape]
        return cls(
            Interval.from_dict(m["natural_frequency_hz"]),
            Interval.from_dict(m["damping_ratio"]),
            m.get("stable_orders"),
            complex(constants[0]["re"], constants[0]["im"]) if len(constants) == 1 and not shape else None,
            np.array([e["re"] + 1j * e["im"] for e in shape]) if shape else None,
            [(e["node"], e["direction"]) for e in shape] if shape else None,
            m.get("modal_mass"),
            np.array([s[0] + 1j * s[1] for s in se]) if shape and all(s is not None for s in se) else None,
            m.get("mpc"),
            m.get("mpd_deg"),
        )

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Mode):
            return NotImplemented
        same = lambda a, b: (a is None and b is None) or (a is not None and b is not None and np.array_equal(a, b))
        arrays = ("shape", "shape_standard_error")
        return all(
            same(getattr(self, k), getattr(other, k)) if k in arrays else getattr(self, k) == getattr(other, k)
            for k in self.__dataclass_fields__
        )

    def __repr__(self) -> str:
        return f"Mode(fn = {self.natural_frequency_hz!r} Hz, ζ = {self.damping_ratio!r})"


def _modes_table(title: str, modes: List[Mode]) -> str:
    """An HTML table of the modes' fn and ζ with their intervals."""
    rows: List[Tuple[str, Any]] = []
    for i, m in enumerate(modes):
        rows.append((f"mode {i + 1} fn [Hz]", m.natural_frequency_hz))
        rows.append((f"mode {i + 1} ζ [-]", m.damping_ratio))
    return _table(title, rows)


class ModalFit(Result):
    """`msd.modal_fit`'s result: the modes with intervals (and shapes for a set), every
    field of msd-ident's `ModalFit` or `ModeSetFit` in `data`."""

    @property
    def is_set(self) -> bool:
        """Whether several FRFs were fitted together (modes with shapes)."""
        return bool(self.data.get("set"))

    @property
    def modes(self) -> List[Mode]:
        """The modes, by frequency."""
        return [Mode.from_dict(m) for m in self.data["modes"]]

    @property
    def mac(self) -> Optional[np.ndarray]:
        """The auto-MAC of the shapes (a set only)."""
        return np.array(self.data["mac"]) if self.is_set else None

    @property
    def noise_check(self) -> Optional[Dict[str, Any]]:
        """The residuals against the FRF's own noise (one FRF, or every FRF of a set,
        whose coherence comes from two or more averages): ``{"variance_ratio":
        SSE/E[SSE], "degrees_of_freedom": the effective h, "p_value", "passed"}``; None
        otherwise."""
        return self.data.get("noise_check")

    def _repr_html_(self) -> str:
        return _modes_table("msd.modal_fit", self.modes)


class OmaFit(Result):
    """`msd.oma`'s result: the modes of an output-only record (fn, ζ and every shape
    entry with 95 % intervals), the diagram's columns the jackknife did not confirm, and
    every field of msd-modal's `OmaFit` in `data` (the diagram's poles by order)."""

    @property
    def modes(self) -> List[Mode]:
        """The modes, by frequency."""
        return [Mode.from_dict(m) for m in self.data["modes"]]

    @property
    def unconfirmed(self) -> List[Tuple[float, float]]:
        """(fn [Hz], ζ) of the columns the record less one block lost: not modes."""
        return [(c["natural_frequency_hz"], c["damping_ratio"]) for c in self.data["unconfirmed"]]

    def _repr_html_(self) -> str:
        return _modes_table("msd.oma", self.modes)


class MergedOma(Result):
    """`msd.oma_setups`'s result: every setup's `OmaFit` and the merged global modes."""

    @property
    def setups(self) -> List[OmaFit]:
        """Each setup's own fit."""
        return [OmaFit(s) for s in self.data["setups"]]

    @property
    def modes(self) -> List[Mode]:
        """The global modes, by frequency, shapes over every setup's DOFs."""
        return [Mode.from_dict(m) for m in self.data["merged"]["modes"]]

    def _repr_html_(self) -> str:
        return _modes_table("msd.oma_setups", self.modes)


class SetupFit(Result):
    """A setup fit (`fit_records`, `free_decay`, `dynamometer`): every field of the Rust
    result in `data`; `repr` is its display."""

    def _repr_html_(self) -> str:
        return f"<pre>{html.escape(self.summary)}</pre>"


def _plot_fits(t: np.ndarray, panels: List[Tuple[str, str, Any, Any, str]], fig: Any = None) -> Any:
    """Each (name, unit, model, residual, title): the measurements (model + residual) as
    points under the model as a thin line, the legend beside the data, the residual
    below; returns the matplotlib Figure."""
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("plot() needs matplotlib: pip install matplotlib") from e
    fig = fig or plt.figure(figsize=(9, 3.2 * len(panels)))
    axes = fig.subplots(2 * len(panels), 1, sharex=True, squeeze=False)[:, 0]
    for k, (name, unit, model, residual, title) in enumerate(panels):
        model = np.asarray(model, dtype=float)
        residual = np.asarray(residual, dtype=float)
        top, bottom = axes[2 * k], axes[2 * k + 1]
        top.plot(t, model + residual, ".", ms=2, color="tab:blue", label="measured")
        top.plot(t, model, "-", lw=0.8, color="tab:red", label="model")
        top.set_ylabel(f"{name} [{unit}]")
        top.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small")  # beside the data
        top.set_title(title)
        bottom.plot(t, residual, "-", lw=0.6, color="tab:gray")
        bottom.set_ylabel(f"residual [{unit}]")
    axes[-1].set_xlabel("time t [s]")
    fig.tight_layout()
    return fig


class RecordsFit(SetupFit):
    """`msd.fit_records`'s result: the plant's identifiable quantities with intervals."""

    def _channel(self, channel: Optional[str], record: int) -> Dict[str, Any]:
        records = self.data.get("records") or []
        record = integer("record", record, None)
        if not 0 <= record < len(records):
            raise OutOfRangeError(f"record = {record}: the fit has {len(records)} record(s), 0 to {len(records) - 1}")
        channels = records[record]["channels"]
        if channel is None:
            return channels[0]
        for c in channels:
            if c["channel"] == channel:
                return c
        names = ", ".join(repr(c["channel"]) for c in channels)
        raise MissingKeyError(f"channel {channel!r}: the record's channels are {names}")

    def time(self, record: int = 0) -> np.ndarray:
        """The time stamps of record `record` (0-based), s."""
        self._channel(None, record)
        return np.asarray(self.data["records"][record]["t"], dtype=float)

    def model(self, channel: Optional[str] = None, record: int = 0) -> np.ndarray:
        """The fitted plant's prediction of `channel` (by name; the first by default) in
        record `record`, at every sample, offset included, in the channel's SI unit."""
        return np.asarray(self._channel(channel, record)["model"], dtype=float)

    def residual(self, channel: Optional[str] = None, record: int = 0) -> np.ndarray:
        """Measured − model for `channel` in record `record` (see `model`)."""
        return np.asarray(self._channel(channel, record)["residual"], dtype=float)

    def plot(self, record: int = 0, fig: Any = None) -> Any:
        """Draw record `record`: each channel's measurements (points) under the model
        (a thin line on top), and the residual below it; returns the matplotlib Figure
        (matplotlib is an optional dependency: ``pip install matplotlib``)."""
        units = {"displacement": "m", "velocity": "m/s", "acceleration": "m/s²"}
        self._channel(None, record)  # an OutOfRangeError naming the records for a bad `record`
        entry = self.data["records"][record]
        panels = []
        for c in entry["channels"]:
            quantity = next((q for q in units if q in c["channel"]), "")
            title = f"{entry['name']}: {c['channel']}, fit {c['fit']['fit_percent']:.1f} %"
            panels.append((c["channel"], units.get(quantity, "SI"), c["model"], c["residual"], title))
        return _plot_fits(self.time(record), panels, fig)

    @property
    def correlation(self) -> Dict[str, Dict[str, Optional[float]]]:
        """The estimates' correlation labelled by quantity (``identifiable``'s names):
        ``fit.correlation["mass"]["stiffness"]``; a known quantity's row is zeros."""
        names = list(self.data.get("identifiable") or ())
        rows = self.data.get("correlation") or ()
        return {a: {b: rows[i][j] for j, b in enumerate(names)} for i, a in enumerate(names)}

    def to_dict(self) -> Dict[str, Any]:
        """Every field as plain JSON types, the correlation labelled (see `correlation`)."""
        d = super().to_dict()
        if "correlation" in d:
            d["correlation"] = jsonable(self.correlation)
        return d

    @classmethod
    def _restore(cls, data: Dict[str, Any]) -> None:
        labelled = data.get("correlation")
        if isinstance(labelled, dict):
            names = list(data.get("identifiable") or ())
            data["correlation"] = [[labelled[a][b] for b in names] for a in names]

    def _interval(self, name: str) -> Optional[Interval]:
        v = self.data.get(name)
        return None if v is None else Interval.from_dict(v)

    @property
    def mass(self) -> Optional[Interval]:
        """Mass, kg (None when the setup cannot give it)."""
        return self._interval("mass")

    @property
    def damping(self) -> Optional[Interval]:
        """Damping, N·s/m (None when the setup cannot give it)."""
        return self._interval("damping")

    @property
    def stiffness(self) -> Optional[Interval]:
        """Stiffness, N/m (None when the setup cannot give it)."""
        return self._interval("stiffness")

    @property
    def natural_frequency_hz(self) -> Optional[Interval]:
        """Natural frequency, Hz."""
        return self._interval("natural_frequency_hz")

    @property
    def damping_ratio(self) -> Optional[Interval]:
        """Damping ratio."""
        return self._interval("damping_ratio")

    @property
    def validation(self) -> Optional[Dict[str, Any]]:
        """The check on fresh data: with one record its held-out end (``hold_out``, a
        fifth by default) predicted by the plant fitted to the rest, as
        ``{"source", "predictions": [{"record", "channels": [{"channel", "fit": {"r2",
        "fit_percent", "residual_rms", …}}], "residual_analysis": [...]}]}``; None with
        several records (see ``data["leave_one_out"]``) or ``hold_out=0``."""
        return self.data.get("validation")

    def _repr_html_(self) -> str:
        rows: List[Tuple[str, Any]] = []
        for label, name in (
            ("m [kg]", "mass"),
            ("c [N·s/m]", "damping"),
            ("k [N/m]", "stiffness"),
            ("fn [Hz]", "natural_frequency_hz"),
            ("ζ [-]", "damping_ratio"),
        ):
            value = self._interval(name)
            rows.append((label, value if value is not None else "not identifiable by this setup"))
        return _table(f"msd.fit_records ({self.data.get('drive', '')})", rows)


@dataclass(frozen=True)
class ChainParameters:
    """Every mass m_i (kg), damper c_i (N·s/m) and spring k_i (N/m) of a chain, from the
    ground out: spring and damper i join mass i to mass i − 1 (the first to the ground);
    optionally extra springs and dampers from each mass straight to the ground (one per
    mass, ≥ 0, 0 where there is none; empty: none at all)."""

    masses: Tuple[float, ...]
    dampers: Tuple[float, ...]
    springs: Tuple[float, ...]
    ground_springs: Tuple[float, ...] = ()
    ground_dampers: Tuple[float, ...] = ()

    @classmethod
    def from_dict(cls, d: Dict[str, Any]) -> "ChainParameters":
        """From {masses, dampers, springs} and optionally {ground_springs, ground_dampers}
        (lists of numbers).

        Raises MissingKeyError (a ValueError) naming a missing key, TypeError or
        ValueError naming a key whose value is not a list of numbers."""
        owner, expected = "ChainParameters.from_dict", "expected masses, dampers, springs"

        def numbers(key: str, value: Any) -> Tuple[float, ...]:
            listed = items(f"{owner}: {key}", value, "a list of numbers")
            return tuple(number(f"{owner}: {key}[{i}]", v) for i, v in enumerate(listed))

        each = [numbers(key, _key(owner, d, key, expected)) for key in ("masses", "dampers", "springs")]
        ground = [numbers(key, d.get(key) or ()) for key in ("ground_springs", "ground_dampers")]
        return cls(*each, *ground)

    def to_dict(self) -> Dict[str, List[float]]:
        """{masses, dampers, springs} as lists, and the ground connections when there are
        any (msd-ident's `ChainParameters`)."""
        out = {"masses": list(self.masses), "dampers": list(self.dampers), "springs": list(self.springs)}
        if self.ground_springs:
            out["ground_springs"] = list(self.ground_springs)
        if self.ground_dampers:
            out["ground_dampers"] = list(self.ground_dampers)
        return out


@dataclass(frozen=True)
class ChainIntervals:
    """m_i, c_i and k_i with their 95 % intervals (a known mass, or a ground connection
    held at 0, with standard error 0); the ground connections' when the chain has them
    (else empty)."""

    masses: List[Interval]
    dampers: List[Interval]
    springs: List[Interval]
    ground_dampers: List[Interval] = field(default_factory=list)
    ground_springs: List[Interval] = field(default_factory=list)


class ChainUncertainty(Result):
    """The uncertainty of a chain's parameters at one point: `msd.predict_chain`'s result
    (predicted before the test) and the statistics of a `ChainFit`: every m, c, k with
    intervals (when identified), the modes, the estimated delays and filter cut-offs, the
    correlation of the estimated quantities; every field of msd-ident's
    `ChainUncertainty` in `data`."""

    @property
    def intervals(self) -> Optional[ChainIntervals]:
        """m_i, c_i, k_i with intervals; None when the records cannot separate them (see
        `unidentifiable`)."""
        iv = self.data["intervals"]
        if iv is None:
            return None
        keys = ("masses", "dampers", "springs", "ground_dampers", "ground_springs")
        each = {k: [Interval.from_dict(v) for v in iv.get(k) or ()] for k in keys}
        return ChainIntervals(**each)

    @property
    def identified(self) -> bool:
        """Whether every m, c and k is identified (`intervals` is not None)."""
        return self.data["intervals"] is not None

    @property
    def unidentifiable(self) -> List[str]:
        """The combinations of parameters the records cannot tell apart, in words."""
        return list(self.data["unidentifiable"])

    @property
    def modes(self) -> List[Mode]:
        """The chain's modes, by frequency, with intervals (delta method): the shape is
        the real part of each mass's displacement (DOF (i, 1) for mass i), the largest
        scaled to 1, with its standard errors in `shape_standard_error`."""
        return [Mode.from_dict(m) for m in self.data["modes"]]

    @property
    def delays(self) -> List[Optional[Interval]]:
        """Each sensor's estimated delay, s (None where it is not estimated)."""
        return [None if d is None else Interval.from_dict(d) for d in self.data["delays"]]

    @property
    def cutoffs(self) -> List[Optional[Interval]]:
        """Each sensor's estimated low-pass cut-off, Hz (None where it is not estimated)."""
        return [None if c is None else Interval.from_dict(c) for c in self.data.get("cutoffs") or ()]

    @property
    def names(self) -> List[str]:
        """The estimated quantities ("m1", "c2", "k1", "kg2", "cutoff1", "delay1", …: a
        known mass is not among them), in the order of `correlation`."""
        return list(self.data["names"])

    @property
    def correlation(self) -> np.ndarray:
        """The correlation matrix of the estimated quantities (of the logarithms for m, c,
        k; order: `names`; NaN where a quantity is not determined)."""
        return np.array(
            [[np.nan if v is None else v for v in row] for row in self.data["correlation"]], dtype=float
        ).reshape(len(self.data["names"]), len(self.data["names"]))

    @property
    def condition_number(self) -> float:
        """Condition number of the column-scaled JᵀJ (inf when singular)."""
        c = self.data["condition_number"]
        return float("inf") if c is None else float(c)

    @property
    def degrees_of_freedom(self) -> int:
        """Samples × channels − estimated quantities."""
        return int(self.data["degrees_of_freedom"])

    def _rows(self) -> List[Tuple[str, Any]]:
        rows: List[Tuple[str, Any]] = []
        iv = self.intervals
        if iv is None:
            rows.append(("m, c, k", "not identified from these records"))
            rows += [("lost", w) for w in self.unidentifiable]
        else:
            for i, (m, c, k) in enumerate(zip(iv.masses, iv.dampers, iv.springs)):
                rows += [(f"m{i + 1} [kg]", m), (f"c{i + 1} [N·s/m]", c), (f"k{i + 1} [N/m]", k)]
            # The ground connections the chain has (as the Rust display: those > 0).
            for i, c in enumerate(iv.ground_dampers):
                if c.value > 0:
                    rows.append((f"cg{i + 1} [N·s/m] (to the ground)", c))
            for i, k in enumerate(iv.ground_springs):
                if k.value > 0:
                    rows.append((f"kg{i + 1} [N/m] (to the ground)", k))
        for i, mode in enumerate(self.modes):
            rows += [(f"mode {i + 1} fn [Hz]", mode.natural_frequency_hz), (f"mode {i + 1} ζ [-]", mode.damping_ratio)]
        for i, d in enumerate(self.delays):
            if d is not None:
                rows.append((f"delay of sensor {i + 1} [s]", d))
        for i, fc in enumerate(self.cutoffs):
            if fc is not None:
                rows.append((f"filter cut-off of sensor {i + 1} [Hz]", fc))
        return rows

    def _repr_html_(self) -> str:
        return _table("msd.predict_chain", self._rows())


class ChainFit(ChainUncertainty):
    """`msd.fit_chain`'s result: the estimates, and as a `ChainUncertainty` their
    intervals (when the record identifies them), the modes, the sensors' estimated delays
    and the correlation; the channels' noise levels and the solver's record. Every field
    of msd-ident's `ChainFit` in `data` (its uncertainty's flattened, as in its JSON)."""

    _arrays = ("noise",)

    @property
    def parameters(self) -> ChainParameters:
        """The estimates (a known mass as given)."""
        return ChainParameters.from_dict(self.data["parameters"])

    @property
    def noise(self) -> np.ndarray:
        """σ̂ of each channel, in its own unit."""
        return self.data["noise"]

    @property
    def exit(self) -> str:
        """The solver's exit on the last pass (e.g. "FTolerance")."""
        return str(self.data["exit"])

    @property
    def evaluations(self) -> int:
        """Model evaluations over all passes."""
        return int(self.data["evaluations"])

    @property
    def noise_model(self) -> Dict[str, Any]:
        """Which noise model the intervals come from ("input_noise": the drive's own
        noise estimated with the sensors'; "white") and what it found (σ̂_u, its test,
        the intervals' ratio to the white-noise ones)."""
        return dict(self.data["noise_model"])

    @property
    def notes(self) -> List[str]:
        """What the reader should know: the drive's noise when it shows, residuals that
        are not white or that correlate with the drive."""
        return list(self.data["notes"])

    def _repr_html_(self) -> str:
        rows = self._rows()
        rows.append(("σ̂ per channel", ", ".join(f"{s:.3e}" for s in self.noise)))
        rows.append(("noise model", str(self.data["noise_model"]["treatment"])))
        return _table("msd.fit_chain", rows)


class RunResults(dict):
    """The `results.json` content of a run (a dict), with `summary` (what the command
    prints) and `out_dir` (where the folder was written)."""

    summary: str
    out_dir: str

    def __init__(self, results: Dict[str, Any], summary: str, out_dir: str):
        super().__init__(results)
        self.summary = summary
        self.out_dir = out_dir

    def _repr_html_(self) -> str:
        return f"<pre>{html.escape(self.summary)}</pre><p>written to <code>{html.escape(self.out_dir)}</code></p>"
