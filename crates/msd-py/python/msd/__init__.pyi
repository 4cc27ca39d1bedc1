import os
from typing import Any, Dict, Iterable, Iterator, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import uff as uff
from ._msd import IdentificationError as IdentificationError

__version__: str

ArrayLike = npt.ArrayLike
F64 = npt.NDArray[np.float64]
PathLike = Union[str, "os.PathLike[str]"]

class Interval:
    value: float
    standard_error: float
    ci95: Tuple[float, float]
    def __init__(self, value: float, standard_error: float, ci95: Tuple[float, float]) -> None: ...
    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Interval: ...
    def contains(self, x: float) -> bool: ...
    def to_dict(self) -> Dict[str, Any]: ...

class Plant:
    mass: float
    damping: float
    stiffness: float
    def __init__(self, mass: float, damping: float, stiffness: float) -> None: ...
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
    def model_output(self) -> F64: ...
    @property
    def residuals(self) -> F64: ...
    @property
    def fit(self) -> Dict[str, Any]: ...
    @property
    def r_squared(self) -> float: ...
    @property
    def converged(self) -> bool: ...
    @property
    def covariance(self) -> F64: ...
    @property
    def warnings(self) -> List[str]: ...
    @property
    def method(self) -> str: ...
    @property
    def iterations(self) -> int: ...
    @property
    def evaluations(self) -> int: ...
    def _repr_html_(self) -> str: ...

class FrequencyResponse(Result):
    @property
    def frequency(self) -> F64: ...
    @property
    def h(self) -> npt.NDArray[np.complex128]: ...
    @property
    def coherence(self) -> F64: ...
    @property
    def kind(self) -> str: ...
    @property
    def exponential_decay(self) -> Optional[float]: ...
    def __iter__(self) -> Iterator[np.ndarray]: ...

class Mode:
    natural_frequency_hz: Interval
    damping_ratio: Interval
    stable_orders: int
    modal_constant: Optional[complex]
    shape: Optional[npt.NDArray[np.complex128]]
    shape_dofs: Optional[List[Tuple[int, int]]]
    modal_mass: Optional[float]

class ModalFit(Result):
    @property
    def is_set(self) -> bool: ...
    @property
    def modes(self) -> List[Mode]: ...
    @property
    def mac(self) -> Optional[F64]: ...
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

class RunResults(Dict[str, Any]):
    summary: str
    out_dir: str

def estimate(t: ArrayLike, force: ArrayLike, displacement: ArrayLike, *, preset: str = ..., **options: Any) -> Estimate: ...
def simulate(
    plant: PlantLike,
    t: ArrayLike,
    force: ArrayLike,
    *,
    initial_state: Sequence[float] = ...,
    backend: Union[str, Dict[str, Any]] = ...,
) -> F64: ...
def frf(
    t: ArrayLike,
    force: ArrayLike,
    response: ArrayLike,
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
    frequencies: Union[ArrayLike, FrequencyResponse],
    frfs: Any = ...,
    *,
    coherence: Any = ...,
    kind: Optional[str] = ...,
    exponential_decay: Optional[float] = ...,
    dofs: Optional[Sequence[Any]] = ...,
    **options: Any,
) -> ModalFit: ...
def fit_records(
    records: Union[Mapping[str, Any], Iterable[Mapping[str, Any]]],
    *,
    drive: str = ...,
    responses: Optional[Mapping[str, Any]] = ...,
    **options: Any,
) -> RecordsFit: ...
def free_decay(
    t: ArrayLike,
    response: ArrayLike,
    *,
    quantity: str = ...,
    known_mass: Optional[float] = ...,
    known_stiffness: Optional[float] = ...,
) -> SetupFit: ...
def dynamometer(conditions: Iterable[Mapping[str, Any]], **options: Any) -> SetupFit: ...
def run(config: PathLike, out: Optional[PathLike] = ..., seed: Optional[int] = ..., threads: Optional[int] = ...) -> RunResults: ...
def plan(config: PathLike, target: float = ..., verify: int = ...) -> SetupFit: ...
def design(config: PathLike, out: Optional[PathLike] = ..., verify: int = ..., write: bool = ...) -> SetupFit: ...
def paper_data(seed: int = ...) -> Dict[str, Dict[str, F64]]: ...
