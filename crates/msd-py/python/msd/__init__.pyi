import os
from dataclasses import dataclass
from typing import Any, Dict, Iterable, Iterator, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import uff as uff
from ._msd import IdentificationError as IdentificationError

__version__: str

__all__ = [
    "IdentificationError", "ChainFit", "ChainIntervals", "ChainMode", "ChainParameters", "Estimate",
    "FrequencyResponse", "Interval", "ModalFit", "Mode",
    "OneModeFit", "Plant", "RecordsFit", "Result", "RunResults", "SetupFit", "Validation",
    "estimate", "simulate", "validate", "frf", "modal_fit", "one_mode_fit", "fit_records", "free_decay", "dynamometer",
    "simulate_chain", "fit_chain", "run", "plan", "design", "paper_data", "uff",
]

_ArrayLike = npt.ArrayLike
_F64 = npt.NDArray[np.float64]
_PathLike = Union[str, "os.PathLike[str]"]

@dataclass(frozen=True)
class Interval:
    value: float
    standard_error: float
    ci95: Tuple[float, float]
    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Interval: ...
    def contains(self, x: float) -> bool: ...
    def to_dict(self) -> Dict[str, Any]: ...

@dataclass(frozen=True)
class Plant:
    mass: float
    damping: float
    stiffness: float
    def to_dict(self) -> Dict[str, float]: ...

PlantLike = Union[Plant, Mapping[str, float], Sequence[float]]

class Result:
    data: Dict[str, Any]
    def __init__(self, data: Dict[str, Any]) -> None: ...
    @property
    def summary(self) -> str: ...
    def to_dict(self) -> Dict[str, Any]: ...
    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Any: ...

class Estimate(Result):
    @property
    def mass(self) -> Interval: ...
    @property
    def damping(self) -> Interval: ...
    @property
    def stiffness(self) -> Interval: ...
    @property
    def natural_frequency_hz(self) -> Interval: ...
    @property
    def damping_ratio(self) -> Interval: ...
    @property
    def parameters(self) -> Plant: ...
    @property
    def model_output(self) -> _F64: ...
    @property
    def residuals(self) -> _F64: ...
    @property
    def fit(self) -> Dict[str, Any]: ...
    @property
    def r_squared(self) -> float: ...
    @property
    def converged(self) -> bool: ...
    @property
    def covariance(self) -> _F64: ...
    @property
    def warnings(self) -> List[str]: ...
    @property
    def method(self) -> str: ...
    @property
    def iterations(self) -> int: ...
    @property
    def evaluations(self) -> int: ...
    def _repr_html_(self) -> str: ...

class Validation(Result):
    @property
    def model_output(self) -> _F64: ...
    @property
    def residuals(self) -> _F64: ...
    @property
    def r_squared(self) -> float: ...
    @property
    def fit(self) -> Dict[str, Any]: ...
    @property
    def residual_analysis(self) -> Dict[str, Any]: ...
    def _repr_html_(self) -> str: ...

class OneModeFit(Result):
    @property
    def mass(self) -> Interval: ...
    @property
    def damping(self) -> Interval: ...
    @property
    def stiffness(self) -> Interval: ...
    @property
    def natural_frequency_hz(self) -> Interval: ...
    @property
    def damping_ratio(self) -> Interval: ...
    @property
    def parameters(self) -> Plant: ...
    def _repr_html_(self) -> str: ...

class FrequencyResponse(Result):
    @property
    def frequency(self) -> _F64: ...
    @property
    def h(self) -> npt.NDArray[np.complex128]: ...
    @property
    def coherence(self) -> _F64: ...
    @property
    def kind(self) -> str: ...
    @property
    def exponential_decay(self) -> Optional[float]: ...
    def __iter__(self) -> Iterator[np.ndarray]: ...
    def _repr_html_(self) -> str: ...

@dataclass(frozen=True)
class Mode:
    natural_frequency_hz: Interval
    damping_ratio: Interval
    stable_orders: int
    modal_constant: Optional[complex] = ...
    shape: Optional[npt.NDArray[np.complex128]] = ...
    shape_dofs: Optional[List[Tuple[int, int]]] = ...
    modal_mass: Optional[float] = ...

class ModalFit(Result):
    @property
    def is_set(self) -> bool: ...
    @property
    def modes(self) -> List[Mode]: ...
    @property
    def mac(self) -> Optional[_F64]: ...
    def _repr_html_(self) -> str: ...

class SetupFit(Result):
    def _repr_html_(self) -> str: ...

class RecordsFit(SetupFit):
    @property
    def mass(self) -> Optional[Interval]: ...
    @property
    def damping(self) -> Optional[Interval]: ...
    @property
    def stiffness(self) -> Optional[Interval]: ...
    @property
    def natural_frequency_hz(self) -> Optional[Interval]: ...
    @property
    def damping_ratio(self) -> Optional[Interval]: ...
    def _repr_html_(self) -> str: ...

@dataclass(frozen=True)
class ChainParameters:
    masses: Tuple[float, ...]
    dampers: Tuple[float, ...]
    springs: Tuple[float, ...]
    @classmethod
    def from_dict(cls, d: Dict[str, Any]) -> ChainParameters: ...
    def to_dict(self) -> Dict[str, List[float]]: ...

ChainParametersLike = Union[ChainParameters, Mapping[str, Any]]

@dataclass(frozen=True)
class ChainIntervals:
    masses: List[Interval]
    dampers: List[Interval]
    springs: List[Interval]

@dataclass(frozen=True)
class ChainMode:
    natural_frequency_hz: Interval
    damping_ratio: Interval
    shape: List[Interval]

class ChainFit(Result):
    @property
    def parameters(self) -> ChainParameters: ...
    @property
    def intervals(self) -> Optional[ChainIntervals]: ...
    @property
    def identified(self) -> bool: ...
    @property
    def unidentifiable(self) -> List[str]: ...
    @property
    def modes(self) -> List[ChainMode]: ...
    @property
    def delays(self) -> List[Optional[Interval]]: ...
    @property
    def noise(self) -> _F64: ...
    @property
    def condition_number(self) -> float: ...
    @property
    def degrees_of_freedom(self) -> int: ...
    @property
    def exit(self) -> str: ...
    @property
    def evaluations(self) -> int: ...
    def _repr_html_(self) -> str: ...

class RunResults(Dict[str, Any]):
    summary: str
    out_dir: str
    def __init__(self, results: Dict[str, Any], summary: str, out_dir: str) -> None: ...
    def _repr_html_(self) -> str: ...

def estimate(t: _ArrayLike, force: _ArrayLike, displacement: _ArrayLike, *, preset: str = ..., **options: Any) -> Estimate: ...
def simulate(
    plant: PlantLike,
    t: _ArrayLike,
    force: _ArrayLike,
    *,
    initial_state: Sequence[float] = ...,
    backend: Union[str, Dict[str, Any]] = ...,
) -> _F64: ...
def validate(plant: PlantLike, t: _ArrayLike, force: _ArrayLike, displacement: _ArrayLike, **options: Any) -> Validation: ...
def frf(
    t: _ArrayLike,
    force: _ArrayLike,
    response: _ArrayLike,
    estimator: str = ...,
    *,
    kind: str = ...,
    segment_length: Optional[int] = ...,
    overlap: float = ...,
    window: str = ...,
    detrend: str = ...,
    impact: Optional[Dict[str, Optional[float]]] = ...,
) -> FrequencyResponse: ...
def modal_fit(
    frequencies: Union[_ArrayLike, FrequencyResponse],
    frfs: Any = ...,
    *,
    coherence: Any = ...,
    kind: Optional[str] = ...,
    exponential_decay: Optional[float] = ...,
    dofs: Optional[Sequence[Any]] = ...,
    **options: Any,
) -> ModalFit: ...
def one_mode_fit(
    frequencies: Union[_ArrayLike, FrequencyResponse],
    frf: Any = ...,
    *,
    coherence: Any = ...,
    kind: Optional[str] = ...,
    exponential_decay: Optional[float] = ...,
    band_hz: Optional[Sequence[float]] = ...,
    weighting: Optional[str] = ...,
) -> OneModeFit: ...
def fit_records(
    records: Union[Mapping[str, Any], Iterable[Mapping[str, Any]]],
    *,
    drive: str = ...,
    responses: Optional[Mapping[str, Any]] = ...,
    **options: Any,
) -> RecordsFit: ...
def free_decay(
    t: _ArrayLike,
    response: _ArrayLike,
    *,
    quantity: str = ...,
    known_mass: Optional[float] = ...,
    known_stiffness: Optional[float] = ...,
) -> SetupFit: ...
def dynamometer(conditions: Iterable[Mapping[str, Any]], **options: Any) -> SetupFit: ...
def simulate_chain(
    parameters: ChainParametersLike,
    input: _ArrayLike,
    dt: float,
    *,
    setup: Optional[Mapping[str, Any]] = ...,
    masses: Optional[int] = ...,
    drive: Optional[str] = ...,
    force_at: Optional[int] = ...,
    sensors: Optional[Sequence[Mapping[str, Any]]] = ...,
) -> _F64: ...
def fit_chain(
    input: _ArrayLike,
    outputs: Any,
    dt: float,
    guess: ChainParametersLike,
    *,
    setup: Optional[Mapping[str, Any]] = ...,
    masses: Optional[int] = ...,
    drive: Optional[str] = ...,
    force_at: Optional[int] = ...,
    sensors: Optional[Sequence[Mapping[str, Any]]] = ...,
    known_masses: Sequence[int] = ...,
    passes: int = ...,
) -> ChainFit: ...
def run(config: _PathLike, out: Optional[_PathLike] = ..., seed: Optional[int] = ..., threads: Optional[int] = ...) -> RunResults: ...
def plan(config: _PathLike, target: float = ..., verify: int = ...) -> SetupFit: ...
def design(config: _PathLike, out: Optional[_PathLike] = ..., verify: int = ..., write: bool = ...) -> SetupFit: ...
def paper_data(seed: int = ...) -> Dict[str, Dict[str, _F64]]: ...
