import os
from typing import Any, Dict, List, Mapping, Sequence, Union

__all__ = ["read", "read_skipped", "write"]

_PathLike = Union[str, "os.PathLike[str]"]

def read(path: _PathLike) -> List[Dict[str, Any]]: ...
def read_skipped(path: _PathLike) -> List[Dict[str, Any]]: ...
def write(path: _PathLike, datasets: Sequence[Mapping[str, Any]], *, exact: bool = ...) -> None: ...
