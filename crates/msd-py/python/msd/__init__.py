"""msd-toolkit in Python: identify the mass, damping and stiffness of a
mass–spring–damper from vibration test data, on NumPy arrays.

Every computation runs in the Rust crates of msd-toolkit (msd-ident, msd-signal,
msd-uff, msd-experiment) with the GIL released; this package only converts.

Functions: `estimate`, `simulate`, `validate`, `frf`, `modal_fit`, `one_mode_fit`, `fit_records`, `free_decay`,
`dynamometer`, `simulate_chain`, `fit_chain`, `predict_chain`, `run`, `plan`, `design`, `paper_data`; the
module `msd.uff` reads and writes Universal File Format files.

Errors: a bad argument raises `ValueError` (a bad value) or `TypeError` (a value of
the wrong type), each message naming the argument (``segment_length = -1: expected an
integer from 0 to …``, ``force: input sample 3750 is NaN``); their subclasses
`MissingKeyError` (a dict argument without a key it needs; also a `KeyError`) and
`OutOfRangeError` (an index out of range; also an `IndexError`). `IdentificationError`
(a subclass of `ValueError`) when the data cannot identify what is asked.
"""

from __future__ import annotations

import os
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _msd
from ._convert import (
    MissingKeyError,
    OutOfRangeError,
    _shown,
    complex_vector,
    field,
    integer,
    items,
    mapping,
    number,
    options_json,
    path as _path,
    rows,
    text,
    value_json,
    vector,
)
from ._msd import IdentificationError
from ._results import (
    ChainFit,
    ChainIntervals,
    ChainParameters,
    ChainUncertainty,
    Estimate,
    FrequencyResponse,
    Interval,
    ModalFit,
    Mode,
    MergedOma,
    OmaFit,
    OneModeFit,
    Plant,
    RecordsFit,
    Result,
    RunResults,
    SetupFit,
    Validation,
)
from . import uff

__version__: str = _msd.__version__

__all__ = [
    "IdentificationError",
    "MissingKeyError",
    "OutOfRangeError",
    "ChainFit",
    "ChainIntervals",
    "ChainParameters",
    "ChainUncertainty",
    "Estimate",
    "FrequencyResponse",
    "Interval",
    "ModalFit",
    "Mode",
    "MergedOma",
    "OmaFit",
    "OneModeFit",
    "Plant",
    "RecordsFit",
    "Result",
    "RunResults",
    "SetupFit",
    "Validation",
    "estimate",
    "simulate",
    "validate",
    "frf",
    "modal_fit",
    "one_mode_fit",
    "oma",
    "oma_setups",
    "fit_records",
    "free_decay",
    "dynamometer",
    "inverse_dynamics",
    "simulate_chain",
    "fit_chain",
    "predict_chain",
    "run",
    "plan",
    "design",
    "paper_data",
    "read_file",
    "inspect",
    "init",
    "uff",
]

PlantLike = Union[Plant, Mapping[str, float], Sequence[float]]


def _plant(plant: PlantLike, name: str = "plant") -> Plant:
    if isinstance(plant, Plant):
        return plant
    if isinstance(plant, Mapping):
        keys = ("mass", "damping", "stiffness")
        for key in keys:
            if key not in plant:
                raise MissingKeyError(f"{name}: missing {key!r} (expected mass, damping, stiffness)")
        return Plant(*(number(f"{name}[{key!r}]", plant[key]) for key in keys))
    try:
        m, c, k = plant  # type: ignore[misc]
    except (TypeError, ValueError):
        raise ValueError(
            f"{name}: expected msd.Plant(mass, damping, stiffness), a dict or a 3-sequence, got {plant!r}"
        ) from None
    return Plant(*(number(f"{name}[{i}]", v) for i, v in enumerate((m, c, k))))


def _options(options: Dict[str, Any]) -> Dict[str, Any]:
    """Plants given as Plant objects or 3-sequences become {mass, damping, stiffness}."""
    out = dict(options)
    guess = out.get("initial_guess")
    if guess is not None and guess != "auto":
        out["initial_guess"] = _plant(guess, "initial_guess").to_dict()
    return out


def estimate(
    t: Any,
    force: Any,
    displacement: Any,
    *,
    preset: str = "default",
    **options: Any,
) -> Estimate:
    """Estimate m, c, k (with 95 % intervals, fn, ζ, fit and residuals) from one record.

    Parameters
    ----------
    t, force, displacement
        1-D arrays of equal length: uniform time stamps (s), the force (N) and the
        measured displacement (m).
    preset
        The starting options: ``"default"`` (Levenberg–Marquardt on the exact simulator,
        automatic ARX initial guess), ``"fast"`` (the same from the paper's θ0 = (2, 1,
        100)) or ``"paper"`` (the paper's method: Nelder–Mead with fminsearch's defaults on
        ode45, RelTol 1e-6, AbsTol 1e-9, from θ0).
    **options
        Any field of msd-ident's ``EstimationOptions``, replacing the preset's:
        ``method`` ("nelder_mead" or "levenberg_marquardt"), ``backend`` ("ode45",
        "exact", or a dict such as ``{"kind": "exact", "hold": "first"}``),
        ``initial_guess`` (a Plant, (m, c, k), a dict or "auto"), ``fixed`` (e.g.
        ``{"mass": 2.5}``), ``bounds`` (e.g. ``{"stiffness": [50, 200]}``),
        ``initial_state`` ({"displacement", "velocity"}), ``estimate_initial_state``,
        ``offset``, ``estimate_offset``, ``nelder_mead``, ``levenberg_marquardt``,
        ``multistart``. Unknown names are refused.

    Raises
    ------
    ValueError
        Bad arrays (NaN, non-uniform time, lengths, too few samples) or options.
    IdentificationError
        The data cannot identify the parameters.
    """
    times = vector("t", t, "time")
    try:
        result = Estimate(
            _msd.estimate(
                times,
                vector("force", force, "input"),
                vector("displacement", displacement, "output"),
                text("preset", preset),
                options_json(_options(options)),
            )
        )
        result.data["t"] = times
        return result
    except IdentificationError as e:
        raise IdentificationError(
            f"{e}. msd.estimate fits a displacement in m: if the third array is an "
            "acceleration or a velocity (an accelerometer, a vibrometer), fit it with "
            'msd.fit_records({"t": t, "force": force, "acceleration": a}) (or "velocity"); '
            "a displacement in mm is scaled by 1e-3 first"
        ) from e


def simulate(
    plant: PlantLike,
    t: Any,
    force: Any,
    *,
    initial_state: Sequence[float] = (0.0, 0.0),
    backend: Union[str, Dict[str, Any]] = "exact",
    quantity: str = "displacement",
) -> Any:
    """Simulate the displacement of `plant` under the sampled `force` on the uniform grid `t`.

    `quantity`: "displacement" (m, the default), "velocity" (m/s), "acceleration" (m/s²),
    or "all" for a dict of the three arrays; velocity and acceleration come from the
    exact simulator (cubic hold), the acceleration being the equation of motion's value.

    `plant` is a ``msd.Plant(mass, damping, stiffness)``, a dict with those keys or a
    3-sequence. `initial_state` is (x(t0), x'(t0)). `backend` is "exact" (the exact
    solution with a cubic hold of the force; ``{"kind": "exact", "hold": "zero" |
    "first" | "cubic"}`` for another hold) or "ode45" (Dormand–Prince with MATLAB's
    semantics, RelTol 1e-6, AbsTol 1e-9; or ``{"kind": "ode45", "rel_tol": …,
    "abs_tol": …}``). The force is linear between samples for ode45.
    """
    p = _plant(plant)
    try:
        x0, v0 = (float(v) for v in initial_state)
    except (TypeError, ValueError):
        raise ValueError(f"initial_state: expected (displacement, velocity), got {initial_state!r}") from None
    if quantity != "displacement":
        kinds = ("displacement", "velocity", "acceleration", "all")
        if quantity not in kinds:
            raise ValueError(f"quantity = {quantity!r}: expected one of {', '.join(map(repr, kinds))}")
        if backend != "exact":
            raise ValueError(f"quantity = {quantity!r}: the velocity and acceleration come from the exact simulator (backend = 'exact')")
        motion = _msd.simulate_motion(
            p.mass, p.damping, p.stiffness, vector("t", t, "time"), vector("force", force, "input"), x0, v0
        )
        return motion if quantity == "all" else motion[quantity]
    return _msd.simulate(
        p.mass, p.damping, p.stiffness, vector("t", t, "time"), vector("force", force, "input"), x0, v0,
        value_json("backend", backend),
    )


def validate(
    plant: PlantLike,
    t: Any,
    force: Any,
    displacement: Any,
    **options: Any,
) -> Validation:
    """How well `plant` (e.g. ``fit.parameters``) predicts fresh data: the simulated
    displacement, R² and fit %, and the residual analysis (Ljung–Box whiteness and the
    residuals' correlation with the input, with verdicts in words), as msd-ident's
    `validate_model`.

    `**options`: msd-ident's ``ValidationOptions``: ``initial_state`` ({"displacement",
    "velocity"}), ``offset``, ``backend`` ("exact", "ode45" or a dict), ``residuals``
    ({"max_lag", "confidence"}).
    """
    p = _plant(plant)
    return Validation(
        _msd.validate(
            p.mass, p.damping, p.stiffness,
            vector("t", t, "time"), vector("force", force, "input"), vector("displacement", displacement, "output"),
            options_json(options),
        )
    )


def frf(
    t: Any,
    force: Any,
    response: Any,
    estimator: str = "H1",
    *,
    kind: str = "receptance",
    segment_length: Optional[int] = None,
    overlap: float = 0.5,
    window: str = "hann",
    detrend: str = "mean",
    impact: Optional[Dict[str, Optional[float]]] = None,
) -> FrequencyResponse:
    """The frequency response (H1, H2 or Hv) with its coherence from time records.

    `force` and `response` are 1-D (one record) or 2-D (one record per row, averaged),
    sampled on the uniform grid `t` (one row's length). `kind` says what the response
    measures: "receptance" (displacement), "mobility" (velocity) or "accelerance"
    (acceleration). Welch segmenting: `segment_length` samples (None: each record whole),
    `overlap`, `window` ("hann" or "rectangular"), `detrend` ("none", "mean", "linear").
    `impact` (e.g. ``{"force_width": 0.01, "decay_time": 0.5}``, or ``{}`` for the
    defaults) applies a force window and an exponential window for hammer tests.

    Returns a `FrequencyResponse`, which unpacks as ``frequency, h, coherence``.
    """
    opts: Dict[str, Any] = {
        "estimator": estimator,
        "kind": kind,
        "welch": {
            "segment_length": segment_length,
            "overlap": overlap,
            "window": window,
            "detrend": detrend,
        },
    }
    if impact is not None:
        opts["impact"] = dict(mapping("impact", impact, 'a dict such as {"force_width": 0.01, "decay_time": 0.5}, or {}'))
    return FrequencyResponse(
        _msd.frf(
            vector("t", t, "time"), rows("force", force, role="input"), rows("response", response, role="output"),
            options_json(opts),
        )
    )


def _unpacked(name: str, frequencies: Any, frf: Any, coherence: Any, kind: Optional[str],
              exponential_decay: Optional[float]) -> Tuple[Any, Any, Any, Optional[str], Optional[float]]:
    """The fits' inputs, taken from a `FrequencyResponse` when `frequencies` is one (what
    is given by name wins over its coherence, kind and window), else as given."""
    if not isinstance(frequencies, FrequencyResponse):
        return frequencies, frf, coherence, kind, exponential_decay
    if frf is not None:
        raise ValueError(f"{name}: not expected with a FrequencyResponse (it holds the FRF)")
    fr = frequencies
    return (
        fr.frequency,
        fr.h,
        fr.coherence if coherence is None else coherence,
        kind or fr.kind,
        fr.exponential_decay if exponential_decay is None else exponential_decay,
    )


def _made(
    frequencies: Any, averages: Any, estimator: Optional[str], input_noise_variance: Any = None
) -> Tuple[int, Optional[str], float, Optional[Tuple[Any, Any]], Any]:
    """How the FRF was made: the segments averaged (1 when not known), the estimator
    ("H1", "H2", "Hv"; None for a measured table), the window's noise bandwidth in
    lines (1 rectangular, 1.5 Hann), how the windows correlate the lines' errors
    (the response's and the force's kernels) and each line's variance from the force's
    noise where it was measured (an impact test's force channel after the force window),
    from a `FrequencyResponse` unless given by name. With them a coherence-weighted fit
    takes the force's noise apart from the response's, corrects an H1 for it, and gives
    intervals that hold on lines whose errors the windows correlate."""
    noise_bandwidth = 1.0
    line_correlation = None
    if isinstance(frequencies, FrequencyResponse):
        if averages is None:
            averages = frequencies.averages
        if estimator is None:
            estimator = frequencies.estimator
        noise_bandwidth = float(frequencies.data.get("noise_bandwidth", 1.0))
        line_correlation = frequencies.data.get("line_correlation")
        if input_noise_variance is None:
            input_noise_variance = frequencies.data.get("input_noise_variance")
    k = 1 if averages is None else integer("averages", averages, low=1)
    name = None if estimator is None else text("estimator", estimator)
    if input_noise_variance is not None:
        input_noise_variance = vector("input_noise_variance", input_noise_variance)
    return k, name, noise_bandwidth, line_correlation, input_noise_variance


def modal_fit(
    frequencies: Any,
    frfs: Any = None,
    *,
    coherence: Any = None,
    kind: Optional[str] = None,
    exponential_decay: Optional[float] = None,
    dofs: Optional[Sequence[Any]] = None,
    averages: Optional[int] = None,
    estimator: Optional[str] = None,
    input_noise_variance: Any = None,
    **options: Any,
) -> ModalFit:
    """Modes (fn, ζ with intervals) of one FRF, or modes with shapes of a set of FRFs.

    `frequencies` (Hz, increasing) and `frfs`: one complex 1-D array, or a 2-D array /
    list of arrays (one FRF per row) for a set, then with `dofs`, one
    ``((response node, direction), (reference node, direction))`` per FRF (directions
    ±1, ±2, ±3 for x, y, z, ±4, ±5, ±6 for the rotations, as UFF numbers them). A
    `FrequencyResponse` from `msd.frf` may be passed as `frequencies` alone (its
    coherence, kind and window are used). `coherence` weights the lines (one array per
    FRF); `kind` is "receptance" (default), "mobility" or "accelerance";
    `exponential_decay` the τ (s) of an exponential window to take off the damping.
    `**options`: msd-ident's ``ModalOptions`` (``band_hz``, ``weighting``, ``orders``,
    ``order_step``, ``frequency_tolerance``, ``damping_tolerance``,
    ``max_damping_ratio``, ``min_stable_share``, ``mode_count``).

    `averages`, `estimator` and `input_noise_variance`: how the FRFs were made (see
    `one_mode_fit`).

    Raises `IdentificationError` when no mode can be selected.
    """
    made = _made(frequencies, averages, estimator, input_noise_variance)
    frequencies, frfs, coherence, kind, exponential_decay = _unpacked(
        "frfs", frequencies, frfs, coherence, kind, exponential_decay
    )
    if frfs is None:
        raise ValueError("frfs: expected the complex frequency response(s)")
    members = rows("frfs", frfs, complex_=True)
    coherences = None if coherence is None else rows("coherence", coherence)
    pairs = None
    if dofs is not None:
        expected = "one ((response node, direction), (reference node, direction)) per FRF"
        pairs = [
            (_dof(f"dofs[{i}] response", response), _dof(f"dofs[{i}] reference", reference))
            for i, (response, reference) in enumerate(_pairs("dofs", dofs, expected))
        ]
    return ModalFit(
        _msd.modal_fit(
            vector("frequencies", frequencies),
            members,
            coherences,
            text("kind", kind or "receptance"),
            None if exponential_decay is None else number("exponential_decay", exponential_decay),
            *made,
            pairs,
            options_json(options),
        )
    )


def _pairs(name: str, value: Any, expected: str) -> List[Tuple[Any, Any]]:
    """The items of `value`, each a pair; ValueError (TypeError) naming `name` else."""
    out = []
    for i, item in enumerate(items(name, value, expected)):
        try:
            a, b = item
        except (TypeError, ValueError):
            raise ValueError(f"{name}[{i}] = {item!r:.60}: expected {expected}") from None
        out.append((a, b))
    return out


def _dof(name: str, value: Any) -> Tuple[Any, Any]:
    """A (node, direction) pair as given: the core checks both (an integer node from 0,
    a direction as the function allows), naming the DOF `name`."""
    try:
        node, direction = value
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {value!r:.60}: expected (node, direction)") from None
    return node, direction


def oma(
    data: Any,
    sample_rate_hz: float,
    *,
    references: Optional[Sequence[int]] = None,
    dofs: Optional[Sequence[Tuple[int, int]]] = None,
    quantities: Union[str, Sequence[str]] = "acceleration",
    names: Optional[Sequence[str]] = None,
    directions: Optional[Sequence[Optional[Sequence[float]]]] = None,
    method: str = "ssi-cov",
    **options: Any,
) -> OmaFit:
    """Output-only modal analysis: the modes of a structure from its response alone
    (msd-modal's SSI-cov/ref with automatic selection; ``method="ssi-dat"``: data-driven
    SSI/ref, the same options; ``method="efdd"``: frequency domain decomposition with
    EFDD's damping, the quick look; jackknife intervals).

    `data`: samples × channels (a 2-D array, as pyOMA takes it); `sample_rate_hz`;
    `references`: the reference channels' indices (default: every channel); `dofs`: one
    (node, direction) per channel (default: node i + 1, direction 1; a direction ±1 …
    ±6, or 0 for a channel along no axis, given by its `directions` entry); `quantities`:
    "acceleration" (default), "velocity" or "displacement", one for all or one per
    channel (shapes are reported as displacement shapes); `names`: the channels' names;
    `directions`: per channel None (along its DOF's direction) or the unit vector (x, y,
    z) of an oblique measuring direction.
    `**options`: msd-modal's ``OmaOptions`` (``orders``, ``order_step``, ``block_rows``,
    ``band_hz``, ``max_damping_ratio``, ``min_mpc``, ``frequency_tolerance``,
    ``damping_tolerance``, ``mac_tolerance``, ``cluster_distance``,
    ``min_stable_share``, ``blocks``, ``frequencies_hz``); for EFDD its ``FddOptions``
    (``lags``, ``band_hz``, ``min_peak_ratio``, ``min_prominence``, ``bell_mac``,
    ``skip_extremes``, ``max_extremes``, ``min_correlation``, ``max_damping_ratio``,
    ``blocks``, ``frequencies_hz``). EFDD's result holds ``data["spectrum"]``: the
    singular values line by line and the peaks picked.

    Raises `ValueError` on a bad record (NaN, a constant channel, one channel, a
    reference that is not a channel, a DOF out of range) and `IdentificationError` when
    no mode is found.
    """
    return OmaFit(
        _msd.oma(
            *_setup(data, sample_rate_hz, references, dofs, quantities, names, directions),
            text("method", method),
            options_json(options),
        )
    )


def _setup(
    data: Any, sample_rate_hz: float, references: Any, dofs: Any, quantities: Any, names: Any, directions: Any,
    prefix: str = "",
) -> tuple:
    """One record's arguments for the core: the array and every channel's description
    (each named after `prefix`: "" for `oma`'s arguments, ``setups[i].`` for a setup's;
    the core checks the references' and DOFs' values, naming them alike)."""
    try:
        a = np.asarray(data)
    except Exception as e:
        raise ValueError(f"{prefix}data: expected a 2-D array of numbers ({e})") from None
    if a.dtype.kind not in "iuf" or a.ndim != 2:
        raise ValueError(
            f"{prefix}data: expected a 2-D array of real numbers (samples × channels), got shape {a.shape} and dtype {a.dtype}"
        )
    a = np.ascontiguousarray(a, dtype=np.float64)
    channels = a.shape[1]
    if dofs is None:
        pairs = [(i + 1, 1) for i in range(channels)]
    else:
        pairs = [_dof(f"{prefix}dofs[{i}]", d) for i, d in enumerate(items(f"{prefix}dofs", dofs, "one (node, direction) per channel"))]
    if isinstance(quantities, str):
        kinds = [quantities] * channels
    else:
        kinds = [str(q) for q in items(f"{prefix}quantities", quantities, "a quantity, or one per channel")]
    if names is None:
        labels = [f"channel {i}" for i in range(channels)]
    else:
        labels = [str(n) for n in items(f"{prefix}names", names, "one name per channel")]
    refs = None if references is None else items(f"{prefix}references", references, "a list of channel indices from 0")
    if directions is None:
        units = [None] * channels
    else:
        units = []
        for i, d in enumerate(items(f"{prefix}directions", directions, "per channel None or a unit vector (x, y, z)")):
            u = None if d is None else tuple(
                number(f"{prefix}directions[{i}][{j}]", x)
                for j, x in enumerate(items(f"{prefix}directions[{i}]", d, "None or a unit vector (x, y, z)"))
            )
            if u is not None and len(u) != 3:
                raise ValueError(f"{prefix}directions[{i}]: expected None or a unit vector (x, y, z), got {len(u)} values")
            units.append(u)
    bad = ~np.isfinite(a)
    if bad.any():
        i, c = (int(v) for v in np.argwhere(bad)[0])
        label = labels[c] if c < len(labels) else f"channel {c}"
        raise ValueError(
            f"{prefix}data[:, {c}] ({label!r}): sample {i} is {_shown(a[i, c])}: expected a finite number"
        )
    return a, number(f"{prefix}sample_rate_hz", sample_rate_hz), refs, pairs, units, kinds, labels


def oma_setups(setups: Sequence[Mapping[str, Any]], *, tolerance: float = 0.01, method: str = "ssi-cov", **options: Any) -> MergedOma:
    """Several setups of one structure (a roving sensor and fixed references) analysed one
    by one with `msd.oma` and merged into global modes (PoSER: each setup's shapes scaled
    onto the DOFs every setup measures; a node with three or more independent directions
    given as its x, y, z components).

    `setups`: dicts with `data` and `sample_rate_hz`, and `references`, `dofs`,
    `quantities`, `names`, `directions` as `msd.oma` takes them; `tolerance`: how close
    (relative) two setups' frequencies must be to be one mode. `method` and `**options`: as
    `msd.oma`.
    """
    args = []
    for i, s in enumerate(items("setups", setups, "a list of dicts with data and sample_rate_hz")):
        owner, expected = f"setups[{i}]", "expected data and sample_rate_hz"
        args.append(_setup(field(owner, s, "data", expected), field(owner, s, "sample_rate_hz", expected),
                           s.get("references"), s.get("dofs"), s.get("quantities", "acceleration"), s.get("names"),
                           s.get("directions"), prefix=f"setups[{i}]."))
    return MergedOma(_msd.oma_setups(args, number("tolerance", tolerance), text("method", method), options_json(options)))


def one_mode_fit(
    frequencies: Any,
    frf: Any = None,
    *,
    coherence: Any = None,
    kind: Optional[str] = None,
    exponential_decay: Optional[float] = None,
    band_hz: Optional[Sequence[float]] = None,
    weighting: Optional[str] = None,
    averages: Optional[int] = None,
    estimator: Optional[str] = None,
    input_noise_variance: Any = None,
) -> OneModeFit:
    """m, c, k (with fn, ζ and 95 % intervals) of a single mode's frequency response:
    msd-ident's `fit_one_mode` (weighted Levenberg–Marquardt from Levy's linear start,
    the classroom half-power estimates beside it).

    `frequencies` (Hz) and `frf` (complex), or a `FrequencyResponse` from `msd.frf` alone;
    `kind` "receptance" (default), "mobility" or "accelerance"; `band_hz` the band to fit;
    `weighting` "coherence" (default), "uniform", "relative" or "variance";
    `averages` the segments K the coherence was averaged over and `estimator` ("H1",
    "H2", "Hv") how the FRF was formed (a `FrequencyResponse` carries both): with them
    the lines are weighted by the coherence's noise model, and an H1 whose coherence
    shows noise on the force is corrected for it (`OneModeFit.input_noise`).
    `input_noise_variance`: each line's variance of H's relative error from the force's
    noise, where it was measured (an impact test's force channel after the force window;
    a `FrequencyResponse` from impact records carries it): the weights then take the
    force's share as known, and H1 is raised line by line.
    """
    made = _made(frequencies, averages, estimator, input_noise_variance)
    frequencies, frf, coherence, kind, exponential_decay = _unpacked(
        "frf", frequencies, frf, coherence, kind, exponential_decay
    )
    if frf is None:
        raise ValueError("frf: expected the complex frequency response")
    opts: Dict[str, Any] = {}
    if band_hz is not None:
        opts["band_hz"] = items("band_hz", band_hz, "[low, high] in Hz")
    if weighting is not None:
        opts["weighting"] = weighting
    return OneModeFit(
        _msd.one_mode_fit(
            vector("frequencies", frequencies),
            complex_vector("frf", frf),
            None if coherence is None else vector("coherence", coherence),
            text("kind", kind or "receptance"),
            None if exponential_decay is None else number("exponential_decay", exponential_decay),
            *made,
            options_json(opts),
        )
    )


_QUANTITIES = ("displacement", "velocity", "acceleration")


def fit_records(
    records: Union[Mapping[str, Any], Iterable[Mapping[str, Any]]],
    *,
    drive: str = "force",
    responses: Optional[Mapping[str, Any]] = None,
    **options: Any,
) -> RecordsFit:
    """Fit one plant to one or several records jointly (msd-ident's `fit_records`).

    Each record is a dict with ``"t"`` (uniform time stamps), the drive's samples under
    ``"drive"`` (or ``"force"``; none for ``drive="none"``), an optional ``"name"``, and
    one array per sensor channel. `drive`: "force", "base_acceleration",
    "base_displacement" or "none" (free decay). `responses` maps each channel's key to
    its quantity ("displacement", "velocity", "acceleration") or to (quantity, frame)
    with frame "absolute" or "relative"; by default the keys named "displacement",
    "velocity" or "acceleration", absolute. `**options`: msd-ident's ``RecordsOptions``
    (``known`` e.g. ``{"mass": 2.5}``, ``require_physical``, ``initial_guess``,
    ``estimate_initial_state``, ``estimate_offset``, ``leave_one_out``, ``hold``,
    ``hold_out`` (with one record, the share at its end predicted by the plant fitted
    to the rest; 0.2 by default, 0 for none), ``residuals`` (``{"max_lag": 25,
    "confidence": 0.99}``), ``max_passes``, ``noise_model``: ``"input_noise"``, the
    default, estimates the measured drive's own noise and widens the intervals by it;
    ``"white"`` takes the drive as exact; where that noise shows, the estimate is
    the one weighting each frequency line by its noise, ``noise_model["estimator"]``
    says ``"weighted"``). The result's ``noise_model``, ``output_error_plant`` (the
    output-error estimate the weighted one replaced), ``white_noise_plant`` and
    ``whiteness`` (each channel's Ljung–Box and residual–drive correlation tests) say
    what was found; ``validation`` (one record)
    or ``leave_one_out`` (several) the predictions of fresh data, with their tests.
    """
    if isinstance(records, Mapping):
        records = [records]
    if responses is not None:
        mapping("responses", responses, "a dict of channel key to quantity or (quantity, frame)")
    built = []
    for i, r in enumerate(items("records", records, "a dict or a list of dicts (t, the drive and the channels)")):
        if not isinstance(r, Mapping):
            raise ValueError(f"records[{i}]: expected a dict with 't', the drive and the channels")
        name = str(r.get("name", f"record {i + 1}"))
        if "t" not in r:
            keys = ", ".join(repr(k) for k in r)
            raise ValueError(
                f"records[{i}]: no key 't' (the uniform time stamps, s); the record's keys are {keys}"
            )
        t = vector(f"records[{i}]['t']", r["t"], "time")
        key = "drive" if "drive" in r else "force"
        samples = r.get(key)
        drive_samples = None if samples is None else vector(f"records[{i}][{key!r}]", samples, "input")
        if drive != "none" and drive_samples is None:
            raise ValueError(f"records[{i}]: the drive {drive!r} needs its samples under 'drive' (or 'force')")
        channels_of = responses or {q: q for q in _QUANTITIES if q in r}
        if not channels_of:
            raise ValueError(f"records[{i}]: no channels (give responses={{key: quantity}})")
        channels = []
        for cname, spec in channels_of.items():
            if isinstance(spec, str):
                quantity, frame = spec, "absolute"
            else:
                try:
                    quantity, frame = spec
                except (TypeError, ValueError):
                    raise ValueError(
                        f"responses[{cname!r}] = {spec!r:.60}: expected a quantity or (quantity, frame)"
                    ) from None
            if cname not in r:
                raise ValueError(f"records[{i}]: no channel {cname!r}")
            channels.append((str(cname), str(quantity), str(frame), vector(f"records[{i}][{cname!r}]", r[cname], "output")))
        built.append((name, t, drive_samples, channels))
    opts = _options(options)
    opts["drive"] = drive
    fit = RecordsFit(_msd.fit_records(built, options_json(opts)))
    for entry, (_, t, _, _) in zip(fit.data.get("records") or (), built):
        entry["t"] = t
    return fit


def free_decay(
    t: Any,
    response: Any,
    *,
    quantity: str = "displacement",
    known_mass: Optional[float] = None,
    known_stiffness: Optional[float] = None,
) -> SetupFit:
    """fn, ζ (and c, k or m, c with a known mass or stiffness) of a ring-down: the fit
    and the classroom estimates (logarithmic decrement, zero crossings) of msd-ident's
    `free_decay`. `quantity`: what the sensor measures."""
    opts: Dict[str, Any] = {"response": quantity}
    if known_mass is not None and known_stiffness is not None:
        raise ValueError("give known_mass or known_stiffness, not both")
    if known_mass is not None:
        opts["known"] = {"mass": known_mass}
    if known_stiffness is not None:
        opts["known"] = {"stiffness": known_stiffness}
    return SetupFit(_msd.free_decay(vector("t", t, "time"), vector("response", response), options_json(opts)))


def dynamometer(conditions: Iterable[Mapping[str, Any]], **options: Any) -> SetupFit:
    """A damper test machine (imposed stroke, measured force), msd-ident's `dynamometer`:
    each condition's loop energy, c_eq, k′, η, and the damping laws fitted and ranked.

    Each condition is a dict with ``"displacement"`` (m) and ``"force"`` (N) arrays, the
    sampling interval ``"dt"`` (s) or time stamps ``"t"``, an optional ``"name"`` and
    ``"frequency_hz"`` (else estimated). `**options`: ``DynamometerOptions``
    (``harmonics``, ``laws``, ``known_mass``, ``force_offset``, ``smoothing_velocity``).
    """
    built = []
    for i, c in enumerate(items("conditions", conditions, "a list of dicts (displacement, force, dt or t)")):
        if not isinstance(c, Mapping):
            raise ValueError(f"conditions[{i}]: expected a dict with the displacement, the force and dt or t")
        if ("dt" in c) == ("t" in c):
            raise ValueError(f"conditions[{i}]: give 'dt' or 't' (one of them)")
        hz = c.get("frequency_hz")
        built.append(
            (
                str(c.get("name", f"condition {i + 1}")),
                number(f"conditions[{i}]['dt']", c["dt"]) if "dt" in c else None,
                vector(f"conditions[{i}]['t']", c["t"], "time") if "t" in c else None,
                vector(f"conditions[{i}]['displacement']", c.get("displacement")),
                vector(f"conditions[{i}]['force']", c.get("force")),
                None if hz is None else number(f"conditions[{i}]['frequency_hz']", hz),
            )
        )
    return SetupFit(_msd.dynamometer(built, options_json(options)))


def _strokes(records: Iterable[Mapping[str, Any]], name: str) -> List[Tuple[str, float, np.ndarray, np.ndarray]]:
    built = []
    for i, r in enumerate(items(name, records, "a list of dicts (stroke, force, dt or t)")):
        if not isinstance(r, Mapping):
            raise ValueError(f"{name}[{i}]: expected a dict with 'stroke', 'force' and 'dt' or 't'")
        if ("dt" in r) == ("t" in r):
            raise ValueError(f"{name}[{i}]: give 'dt' or 't' (one of them)")
        for key in ("stroke", "force"):
            if key not in r:
                raise ValueError(f"{name}[{i}]: missing {key!r} (expected 'stroke' in m and 'force' in N)")
        if "dt" in r:
            dt = number(f"{name}[{i}]['dt']", r["dt"])
        else:
            t = vector(f"{name}[{i}]['t']", r["t"], "time")
            if len(t) < 2:
                raise ValueError(f"{name}[{i}]['t']: expected at least two time stamps")
            dt = float((t[-1] - t[0]) / (len(t) - 1))
        built.append(
            (
                str(r.get("name", f"record {i + 1}")),
                dt,
                vector(f"{name}[{i}]['stroke']", r["stroke"]),
                vector(f"{name}[{i}]['force']", r["force"]),
            )
        )
    return built


def inverse_dynamics(
    records: Iterable[Mapping[str, Any]], validation: Iterable[Mapping[str, Any]] = (), **options: Any
) -> SetupFit:
    """A test machine under any stroke (a positioning move, a random or swept stroke):
    msd-ident's ``inverse_dynamics``. Stroke and force are low-passed alike (a zero-phase
    4th-order Butterworth), velocity and acceleration taken by central differences, and
    every damping law fitted by least squares and ranked by BIC, with intervals from the
    sandwich over blocks of samples (honest for coloured residuals).

    Each record is a dict with ``"stroke"`` (m) and ``"force"`` (N) arrays, ``"dt"`` (s)
    or ``"t"``, and an optional ``"name"``; ``validation`` records are not fitted but
    predicted (``data["validation"]``: RMS error, measured and predicted force).
    ``**options``: ``InverseOptions`` (``laws``, ``cutoff_hz``, ``stiffness``,
    ``force_offset``, ``known_mass``, ``blocks``).
    """
    fitted = _strokes(records, "records")
    fresh = _strokes(validation, "validation")
    return SetupFit(_msd.inverse_dynamics(fitted, fresh, options_json(options)))


ChainParametersLike = Union[ChainParameters, Mapping[str, Any]]


def _chain_parameters(parameters: ChainParametersLike, name: str) -> Dict[str, Any]:
    """{masses, dampers, springs} of a `ChainParameters` or a dict (checked in Rust)."""
    if isinstance(parameters, ChainParameters):
        return parameters.to_dict()
    if isinstance(parameters, Mapping):
        return dict(parameters)
    raise ValueError(
        f"{name}: expected msd.ChainParameters or a dict with masses, dampers, springs, got {parameters!r}"
    )


def _chain_setup(
    setup: Optional[Mapping[str, Any]],
    keys: Dict[str, Any],
    parameters: Dict[str, Any],
) -> str:
    """The setup's JSON: `setup` (serde's shape), its keys given by name replacing its
    own, the number of masses by default that of `parameters`."""
    if setup is None:
        out: Dict[str, Any] = {}
    elif isinstance(setup, Mapping):
        out = dict(setup)
    else:
        raise ValueError(f"setup: expected a dict (masses, drive, force_at, sensors), got {setup!r}")
    out.update({k: v for k, v in keys.items() if v is not None})
    masses = parameters.get("masses")
    if "masses" not in out and masses is not None and not isinstance(masses, (str, bytes)):
        try:
            out["masses"] = len(masses)
        except TypeError:
            pass
    return options_json(out)


def _seconds(name: str, value: Any) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {value!r:.60}: expected a number of seconds") from None


def _known_masses(known_masses: Any) -> List[int]:
    try:
        return [known_masses] if isinstance(known_masses, int) else list(known_masses)
    except TypeError:
        raise ValueError(f"known_masses = {known_masses!r}: expected a list of masses, numbered from 1") from None


def simulate_chain(
    parameters: ChainParametersLike,
    input: Any,
    dt: float,
    *,
    setup: Optional[Mapping[str, Any]] = None,
    masses: Optional[int] = None,
    drive: Optional[str] = None,
    force_at: Optional[int] = None,
    sensors: Optional[Sequence[Mapping[str, Any]]] = None,
) -> np.ndarray:
    """Every sensor's noise-free reading of a chain of masses driven by `input` (msd-ident's
    `simulate_chain`): a 2-D array, one row per sensor.

    `parameters`: ``msd.ChainParameters`` or a dict ``{"masses": [...], "dampers": [...],
    "springs": [...]}``, from the ground out (spring and damper i join mass i to mass
    i − 1, the first to the ground), optionally with ``"ground_springs"`` and
    ``"ground_dampers"`` (extra connections from each mass straight to the ground, one
    per mass, 0 where there is none). `input`: the force (N) or base acceleration (m/s²)
    every `dt` seconds, linear between samples, the chain at rest before it.

    The setup (msd-ident's ``ChainSetup``), as a dict `setup` in its serde shape or by its
    keys (which replace the dict's): `masses` (the number of masses, 1 to 8; by default
    one per value of ``parameters["masses"]``), `drive` ("force", the default, or
    "base_acceleration"), `force_at` (the mass the force acts on, from 1 at the ground;
    default 1), `sensors` (default one displacement sensor on mass 1): a list of dicts
    with ``at`` (the mass, default 1), ``quantity`` ("displacement", the default,
    "velocity" or "acceleration"; under a base acceleration a displacement or velocity
    is relative to the ground, an acceleration absolute), ``delay`` (s, default none),
    ``estimate_delay`` (for `fit_chain`; default False), ``low_pass`` (default none;
    ``{"cutoff_hz": …, "order": 1 or 2, "damping_ratio": …}``, order 1 and ζ 1/√2 by
    default) and ``estimate_cutoff`` (for `fit_chain`: the filter's cut-off estimated
    from ``low_pass``'s; default False).

    Raises ValueError for a bad setup (the message names the key, e.g. ``sensors[1].at =
    4``), bad parameters, a non-finite input, or a delay not shorter than the record (a
    fit needs it shorter than half the record). An empty input gives one empty row per
    sensor.
    """
    p = _chain_parameters(parameters, "parameters")
    setup_json = _chain_setup(
        setup, {"masses": masses, "drive": drive, "force_at": force_at, "sensors": sensors}, p
    )
    return _msd.simulate_chain(setup_json, options_json(p), vector("input", input, "input"), _seconds("dt", dt))


def fit_chain(
    input: Any,
    outputs: Any,
    dt: float,
    guess: ChainParametersLike,
    *,
    setup: Optional[Mapping[str, Any]] = None,
    masses: Optional[int] = None,
    drive: Optional[str] = None,
    force_at: Optional[int] = None,
    sensors: Optional[Sequence[Mapping[str, Any]]] = None,
    known_masses: Sequence[int] = (),
    passes: int = 4,
    noise_model: str = "input_noise",
) -> ChainFit:
    """Every m, c and k of a chain of masses (and the sensor delays asked for) from one
    record, with 95 % intervals and the modes: msd-ident's `fit_chain` (weighted output
    error, exact simulation and sensitivities, Levenberg–Marquardt from `guess`, each
    channel weighted by its own noise level, re-estimated between passes).

    `input`: the drive's samples (force, N, or base acceleration, m/s²) every `dt` s;
    `outputs`: one series per sensor, in the setup's order (a 2-D array, one row per
    sensor, or a list of 1-D arrays); the chain at rest before the record. `guess`:
    ``msd.ChainParameters`` or ``{"masses", "dampers", "springs"}`` (with
    ``"ground_springs"``/``"ground_dampers"``: those > 0 in the guess are estimated, the
    others held at 0). The setup as for `simulate_chain` (`setup` dict or `masses`,
    `drive`, `force_at`, `sensors`; a sensor's ``estimate_delay`` estimates its delay from
    ``delay`` or 0, its ``estimate_cutoff`` its filter's cut-off from ``low_pass``'s).
    `known_masses`: masses (numbered from 1) held at the guess's value (under a base
    acceleration one must be known to set the scale); `passes`: at most this many fits,
    each re-estimating the channels' noise levels (default 4). `noise_model`: which
    noise the intervals assume — ``"input_noise"`` (the default: white noise on every
    sensor plus the drive's own noise, a load cell's, seen through the chain and
    estimated with the sensors'; errors-in-variables) or ``"white"`` (the drive taken
    as exact).

    Returns a `ChainFit` (the estimates, σ̂ per channel, the noise model found and its
    notes, and as a `ChainUncertainty` the
    intervals, modes, delays, cut-offs and the correlation of the estimated quantities
    in the order of its ``names``); when the record cannot separate the parameters its
    ``intervals`` is None and ``unidentifiable`` says which combinations are lost (the
    modes are still given).

    Raises ValueError for bad input (the message names the key: ``sensors[1].at = 4``,
    ``sensors[0].low_pass.cutoff_hz = -50``, ``sensors[0].delay = 20 s``; a drive that is
    zero throughout, a channel that is zero throughout or beyond 1e150),
    IdentificationError when the fit fails (it did not converge, or a parameter ran more
    than 10⁴ times from its guess: a wrong minimum, start from a closer guess).
    """
    g = _chain_parameters(guess, "guess")
    setup_json = _chain_setup(
        setup, {"masses": masses, "drive": drive, "force_at": force_at, "sensors": sensors}, g
    )
    if noise_model not in ("input_noise", "white"):
        raise ValueError(f"noise_model = {noise_model!r}: expected \"input_noise\" or \"white\"")
    opts = {"known_masses": _known_masses(known_masses), "passes": passes, "noise_model": noise_model}
    return ChainFit(
        _msd.fit_chain(
            setup_json,
            vector("input", input, "input"),
            rows("outputs", outputs, role="output"),
            _seconds("dt", dt),
            options_json(g),
            options_json(opts),
        )
    )


def _noise(noise: Any) -> np.ndarray:
    """Each sensor's σ as a 1-D array (a number for a single sensor)."""
    if isinstance(noise, (int, float, np.integer, np.floating)):
        noise = [noise]
    return vector("noise", noise, finite=False)  # σ NaN: the core names the sensor


def predict_chain(
    truth: ChainParametersLike,
    input: Any,
    dt: float,
    noise: Any,
    *,
    setup: Optional[Mapping[str, Any]] = None,
    masses: Optional[int] = None,
    drive: Optional[str] = None,
    force_at: Optional[int] = None,
    sensors: Optional[Sequence[Mapping[str, Any]]] = None,
    known_masses: Sequence[int] = (),
) -> ChainUncertainty:
    """The uncertainty a `fit_chain` of one record will have, before the test: msd-ident's
    `predict_chain`, the Cramér–Rao bound σ²(JᵀJ)⁻¹ from the exact sensitivities at the
    truth (the fit's own linearisation, with the true noise levels instead of σ̂).

    `truth`: the chain (``msd.ChainParameters`` or ``{"masses", "dampers", "springs"}``);
    `input`: the planned drive (force, N, or base acceleration, m/s²) every `dt` s;
    `noise`: each sensor's noise σ in its own unit, one per sensor in the setup's order
    (a number for a single sensor). The setup as for `simulate_chain` (`setup` dict or
    `masses`, `drive`, `force_at`, `sensors`): a sensor's ``delay`` and ``low_pass`` are
    its true ones, and ``estimate_delay`` and ``estimate_cutoff`` ask for their intervals
    too; ground connections > 0 in `truth` are estimated. `known_masses`: masses
    (numbered from 1) the fit will hold.

    Returns a `ChainUncertainty`: every m, c, k with its predicted 95 % interval (about
    the truth), the modes, the delays and cut-offs, the correlation; when the test cannot separate
    the parameters, ``intervals`` is None and ``unidentifiable`` says which combinations
    are lost.

    Raises ValueError for bad input (the setup's key named as in `fit_chain`; noise
    levels not one per sensor, not finite, or below 1e-300) and for a test `fit_chain`
    could not fit: a drive that is zero throughout, a sensor that reads nothing, or
    readings that overflow (beyond 1e150) or stand more than 1e100 above their σ.
    """
    t = _chain_parameters(truth, "truth")
    setup_json = _chain_setup(
        setup, {"masses": masses, "drive": drive, "force_at": force_at, "sensors": sensors}, t
    )
    opts = {"known_masses": _known_masses(known_masses)}
    return ChainUncertainty(
        _msd.predict_chain(
            setup_json,
            options_json(t),
            vector("input", input, "input"),
            _seconds("dt", dt),
            _noise(noise),
            options_json(opts),
        )
    )


def run(
    config: Union[str, "os.PathLike[str]", Mapping[str, Any]],
    out: Optional[Union[str, "os.PathLike[str]"]] = None,
    seed: Optional[int] = None,
    threads: Optional[int] = None,
    data: Optional[Mapping[str, Any]] = None,
) -> RunResults:
    """Run an experiment as ``msd run`` does: every stage, the result folder written
    atomically (into `out`, else the config's ``output.dir``, else
    ``msd-results/<name>``), and the ``results.json`` content returned as a dict (with
    ``.summary`` and ``.out_dir``). `seed` and `threads` override the config's.

    `config` is a TOML file's path or the config itself as a dict (as ``tomllib`` reads
    one; its relative paths start from the working folder). `data` gives the config's
    data files in memory, by the path the config writes (``data.path``,
    ``frequency_response.uff.path``, …), each either as ``bytes`` (the file's content,
    read as the file would be) or as a mapping of column name to 1-D array (the
    config's columns found by name or 0-based position; the CSV format keys do not
    apply). Every experiment kind runs so, with no data file on disk::

        cfg = tomllib.load(open("configs/templates/accelerometer.toml", "rb"))
        cfg["data"]["path"] = "shaker.csv"
        msd.run(cfg, data={"shaker.csv": {"t": t, "force": f, "accel": a}})

    Raises ValueError for a bad config or data (the message names the file and key),
    IdentificationError when the data cannot identify, RuntimeError or OSError for a
    failure during the run.
    """
    if isinstance(config, Mapping):
        path, text = None, options_json(dict(config))
    else:
        path, text = _path("config", config), None
    files: Dict[str, bytes] = {}
    tables: Dict[str, List[Tuple[str, np.ndarray]]] = {}
    given_data = {} if data is None else mapping("data", data, "a dict of path to bytes or to columns")
    for name, given in given_data.items():
        if isinstance(given, (bytes, bytearray, memoryview)):
            files[str(name)] = bytes(given)
        elif isinstance(given, Mapping):
            # Not checked finite here: the run names the config's column and row.
            tables[str(name)] = [(str(c), vector(f"data[{name!r}][{c!r}]", v, finite=False)) for c, v in given.items()]
        else:
            raise ValueError(
                f"data[{name!r}]: expected the file's bytes or a mapping of column name to 1-D array, got {type(given).__name__}"
            )
    r = _msd.run(path, text, None if out is None else _path("out", out), seed, threads, files, tables)
    return RunResults(r["results"], r["summary"], str(r["out_dir"]))


def plan(
    config: Union[str, "os.PathLike[str]"], target: float = 0.01, verify: int = 0
) -> SetupFit:
    """Predict the precision of a synthetic config's test (``msd plan``): each
    quantity's predicted 95 % half-width and the record length that reaches `target`
    (relative); `verify` simulated experiments check the prediction."""
    return SetupFit(_msd.plan(_path("config", config), number("target", target), verify))


def design(
    config: Union[str, "os.PathLike[str]"],
    out: Optional[Union[str, "os.PathLike[str]"]] = None,
    verify: int = 0,
    write: bool = True,
) -> SetupFit:
    """Design the input of a config with a ``[design]`` section (``msd design``): the
    multisine that minimises the Cramér–Rao bound within the rig's limits; written into
    `out` (else ``msd-results/<name>-design``) unless ``write=False``."""
    r = _msd.design(_path("config", config), None if out is None else _path("out", out), verify, bool(write))
    r["out_dir"] = None if r["out_dir"] is None else str(r["out_dir"])
    return SetupFit(r)


def paper_data(seed: int = 1) -> Dict[str, Dict[str, np.ndarray]]:
    """The paper's synthetic records (m = 2.5 kg, c = 1.8 N·s/m, k = 120 N/m; 0–15 s at
    2 ms; σ = 2.5 mm noise from `seed`): ``{"identification": {...}, "validation":
    {...}}``, each with ``t``, ``force``, ``displacement`` and ``true_displacement``."""
    return _msd.paper_data(seed)


def read_file(path: Union[str, "os.PathLike[str]"], details: bool = False) -> Union[Dict[str, np.ndarray], List[Dict[str, Any]]]:
    """The channels of a MATLAB ``.mat`` (levels 5 and 7), NumPy ``.npy``/``.npz`` or NI
    TDMS file, as ``{name: array}`` in the file's order.

    A vector is one channel named as its variable; a matrix is split along its shorter
    dimension into ``name[0]``, ``name[1]``, … (0-based); a complex variable gives
    ``name.re`` and ``name.im``; a TDMS channel is named ``channel`` (``group/channel``
    where two groups share the name). The same names pick columns in a config's
    ``[data]`` section. With ``details=True``: a list of dicts with ``name``, ``unit``,
    ``sample_rate_hz`` (where the file gives them) and ``values``.

    Raises OSError for a file that cannot be opened, ValueError (naming the file and what
    was expected) for one that is not what its extension says, truncated or corrupt.
    """
    channels, _skipped = _msd.read_file(_path("path", path))
    if details:
        return channels
    return {c["name"]: c["values"] for c in channels}


def inspect(path: Union[str, "os.PathLike[str]"]) -> str:
    """What a data file holds (``msd inspect FILE``): its channels or columns, units,
    lengths and sampling rate, how a text file is written, and the config lines that
    read it."""
    return _msd.inspect(_path("path", path))


def init(
    path: Union[str, "os.PathLike[str]"],
    input: Optional[str] = None,
    outputs: Sequence[str] = (),
    sample_rate: Optional[float] = None,
    config: Optional[Union[str, "os.PathLike[str]"]] = None,
    overwrite: bool = False,
) -> str:
    """Write a config for your own data file (``msd init FILE``) and return its path.

    The file is read as :func:`inspect` reads it; the experiment comes from its columns'
    units and names (a force and responses: a force test; a base sensor: base
    excitation; one response: a free decay), each column scaled to SI from its unit
    (g, mm, kN, …). `input` and `outputs` name the columns when they cannot say,
    `sample_rate` (Hz) gives the rate of a file with no time column; the
    config goes to `config`, else beside the file with the extension ``.toml`` (an
    existing one only with `overwrite`). Then ``msd.run(path)`` runs it::

        results = msd.run(msd.init("shaker.csv"))

    Raises ValueError naming the file when its columns do not say what they are (with
    the columns to choose from) or the config exists.
    """
    written, _text, _summary = _msd.init(
        _path("path", path),
        None if input is None else text("input", input),
        [outputs] if isinstance(outputs, str) else [str(o) for o in items("outputs", outputs, "a list of column names")],
        None if sample_rate is None else number("sample_rate", sample_rate),
        None if config is None else _path("config", config),
        bool(overwrite),
    )
    return os.fspath(written)


def __dir__() -> List[str]:
    """The package's public names only (``__all__``), not its imports."""
    return sorted(__all__)
