"""Type stubs of the compiled core `msd._msd` (use the `msd` package instead)."""

from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

__version__: str
__all__ = [
    "IdentificationError", "__version__", "design", "dynamometer", "estimate", "fit_chain", "fit_records",
    "free_decay", "frf", "init", "inspect", "inverse_dynamics", "modal_fit", "oma", "oma_setups", "one_mode_fit", "paper_data", "plan", "predict_chain", "read_file", "run", "simulate", "simulate_motion",
    "simulate_chain", "uff_read", "uff_write", "validate",
]

class IdentificationError(ValueError):
    """The data cannot identify what was asked."""

_F64 = npt.NDArray[np.float64]
_C128 = npt.NDArray[np.complex128]

def estimate(t: _F64, force: _F64, displacement: _F64, preset: str, options_json: str) -> Dict[str, Any]: ...
def simulate(
    mass: float, damping: float, stiffness: float, t: _F64, force: _F64, x0: float, v0: float, backend_json: str
) -> _F64: ...
def simulate_motion(mass: float, damping: float, stiffness: float, t: _F64, force: _F64, x0: float, v0: float) -> Dict[str, _F64]: ...
def validate(
    mass: float, damping: float, stiffness: float, t: _F64, force: _F64, displacement: _F64, options_json: str
) -> Dict[str, Any]: ...
def paper_data(seed: int) -> Dict[str, Dict[str, _F64]]: ...
def fit_records(
    records: Sequence[Tuple[str, _F64, Optional[_F64], Sequence[Tuple[str, str, str, _F64]]]], options_json: str
) -> Dict[str, Any]: ...
def free_decay(t: _F64, response: _F64, options_json: str) -> Dict[str, Any]: ...
def dynamometer(
    conditions: Sequence[Tuple[str, Optional[float], Optional[_F64], _F64, _F64, Optional[float]]],
    options_json: str,
) -> Dict[str, Any]: ...
def simulate_chain(setup_json: str, parameters_json: str, input: _F64, dt: float) -> _F64: ...
def fit_chain(
    setup_json: str, input: _F64, outputs: Sequence[_F64], dt: float, guess_json: str, options_json: str
) -> Dict[str, Any]: ...
def predict_chain(
    setup_json: str, truth_json: str, input: _F64, dt: float, noise: _F64, options_json: str
) -> Dict[str, Any]: ...
def frf(t: _F64, forces: Sequence[_F64], responses: Sequence[_F64], options_json: str) -> Dict[str, Any]: ...
def modal_fit(
    frequency: _F64,
    frfs: Sequence[_C128],
    coherences: Optional[Sequence[_F64]],
    kind: str,
    exponential_decay: Optional[float],
    averages: int,
    estimator: Optional[str],
    noise_bandwidth: float,
    line_correlation: Optional[Tuple[Any, Any]],
    input_noise_variance: Optional[_F64],
    dofs: Optional[Sequence[Tuple[Tuple[int, int], Tuple[int, int]]]],
    options_json: str,
) -> Dict[str, Any]: ...
def oma(
    data: npt.NDArray[np.float64],
    sample_rate_hz: float,
    references: Optional[Sequence[int]],
    dofs: Sequence[Tuple[int, int]],
    directions: Sequence[Optional[Tuple[float, float, float]]],
    quantities: Sequence[str],
    names: Sequence[str],
    method: str,
    options_json: str,
) -> Dict[str, Any]: ...
def oma_setups(setups: Sequence[Tuple[Any, ...]], tolerance: float, method: str, options_json: str) -> Dict[str, Any]: ...
def one_mode_fit(
    frequency: _F64,
    h: _C128,
    coherence: Optional[_F64],
    kind: str,
    exponential_decay: Optional[float],
    averages: int,
    estimator: Optional[str],
    noise_bandwidth: float,
    line_correlation: Optional[Tuple[Any, Any]],
    input_noise_variance: Optional[_F64],
    options_json: str,
) -> Dict[str, Any]: ...
def read_file(path: str) -> Tuple[List[Dict[str, Any]], List[str]]: ...
def init(path: str, input: Optional[str] = None, outputs: List[str] = ..., sample_rate: Optional[float] = None, config: Optional[str] = None, overwrite: bool = False) -> Tuple[str, str, str]: ...
def inspect(path: str) -> str: ...
def inverse_dynamics(records: List[Tuple[str, float, _F64, _F64]], validation: List[Tuple[str, float, _F64, _F64]], options_json: str) -> Dict[str, Any]: ...
def uff_read(path: str) -> Tuple[List[Dict[str, Any]], List[Dict[str, Any]]]: ...
def uff_write(path: str, datasets: Sequence[Dict[str, Any]], exact: bool) -> None: ...
def run(config: Optional[str], config_json: Optional[str], out: Optional[str] = None, seed: Optional[int] = None, threads: Optional[int] = None, files: Optional[Dict[str, bytes]] = None, tables: Optional[Dict[str, List[Tuple[str, npt.NDArray[np.float64]]]]] = None) -> Dict[str, Any]: ...
def plan(config: str, target: float = 0.01, verify: int = 0) -> Dict[str, Any]: ...
def design(config: str, out: Optional[str] = None, verify: int = 0, write: bool = True) -> Dict[str, Any]: ...
