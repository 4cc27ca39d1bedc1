"""Type stubs of the compiled core `msd._msd` (use the `msd` package instead)."""

from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

__version__: str

class IdentificationError(ValueError):
    """The data cannot identify what was asked."""

F64 = npt.NDArray[np.float64]
C128 = npt.NDArray[np.complex128]

def estimate(t: F64, force: F64, displacement: F64, preset: str, options_json: str) -> Dict[str, Any]: ...
def simulate(
    mass: float, damping: float, stiffness: float, t: F64, force: F64, x0: float, v0: float, backend_json: str
) -> F64: ...
def paper_data(seed: int) -> Dict[str, Dict[str, F64]]: ...
def fit_records(
    records: Sequence[Tuple[str, F64, Optional[F64], Sequence[Tuple[str, str, str, F64]]]], options_json: str
) -> Dict[str, Any]: ...
def free_decay(t: F64, response: F64, options_json: str) -> Dict[str, Any]: ...
def dynamometer(
    conditions: Sequence[Tuple[str, float, F64, F64, Optional[float]]], options_json: str
) -> Dict[str, Any]: ...
def frf(t: F64, forces: Sequence[F64], responses: Sequence[F64], options_json: str) -> Dict[str, Any]: ...
def modal_fit(
    frequency: F64,
    frfs: Sequence[C128],
    coherences: Optional[Sequence[F64]],
    kind: str,
    exponential_decay: Optional[float],
    dofs: Optional[Sequence[Tuple[Tuple[int, int], Tuple[int, int]]]],
    options_json: str,
) -> Dict[str, Any]: ...
def one_mode_fit(
    frequency: F64,
    h: C128,
    coherence: Optional[F64],
    kind: str,
    exponential_decay: Optional[float],
    options_json: str,
) -> Dict[str, Any]: ...
def uff_read(path: str) -> Tuple[List[Dict[str, Any]], List[Dict[str, Any]]]: ...
def uff_write(path: str, datasets: Sequence[Dict[str, Any]], exact: bool) -> None: ...
def run(config: str, out: Optional[str] = None, seed: Optional[int] = None, threads: Optional[int] = None) -> Dict[str, Any]: ...
def plan(config: str, target: float = 0.01, verify: int = 0) -> Dict[str, Any]: ...
def design(config: str, out: Optional[str] = None, verify: int = 0, write: bool = True) -> Dict[str, Any]: ...
