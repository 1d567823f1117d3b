"""Type stubs of the extension module `wedged._wedged` (the Rust side of `wedged`).

An enumeration returns its run (arrays, and the command's JSON on demand); `critical` returns
the command's JSON document. `wedged/__init__.py` builds the result objects from them. Use the
functions of `wedged`, not these.
"""

from typing import Any, Dict, List, Optional, Tuple

import numpy as np
import numpy.typing as npt

__version__: str

class InputError(ValueError):
    """Bad input: the command's one-line message (its exit code 2)."""

class InternalError(RuntimeError):
    """A failed internal check, a bug in wedged (the command's exit code 1)."""

class EnumerationRun:
    """A finished enumeration: its parts as arrays, its JSON on demand."""

    library_seconds: float

    def to_json(self) -> str: ...
    def header(self) -> Dict[str, Any]: ...
    def parts(self) -> Dict[str, Any]: ...

def enumerate(
    k: npt.NDArray[np.float64],
    mu: float,
    dim: int = 2,
    method: Optional[str] = None,
    time_limit: Optional[float] = None,
    certify: bool = False,
    zero_tol: Optional[float] = None,
    progress: bool = False,
    rigid_modes: Optional[npt.NDArray[np.float64]] = None,
    shard: Optional[str] = None,
    jsonl: Optional[str] = None,
) -> EnumerationRun: ...
def critical(
    k: npt.NDArray[np.float64],
    dim: int = 2,
    method: Optional[str] = None,
    time_limit: Optional[float] = None,
    certify: bool = False,
    tol: Optional[float] = None,
    progress: bool = False,
    rigid_modes: Optional[npt.NDArray[np.float64]] = None,
    shard: Optional[str] = None,
    start: Optional[List[bool]] = None,
    start_file: Optional[str] = None,
    start_json: Optional[str] = None,
    chain: bool = True,
) -> str: ...
def load(path: str) -> LoadedProblem: ...
def merge(parts: List[Tuple[str, str]]) -> Tuple[str, bool, str]: ...

class LoadedProblem:
    @property
    def K(self) -> npt.NDArray[np.float64]: ...
    @property
    def mu(self) -> Optional[float]: ...
    @property
    def dim(self) -> int: ...
    @property
    def source(self) -> str: ...
    @property
    def is_mesh(self) -> bool: ...
    def enumerate(
        self,
        mu: Optional[float] = None,
        method: Optional[str] = None,
        time_limit: Optional[float] = None,
        certify: bool = False,
        zero_tol: Optional[float] = None,
        progress: bool = False,
        shard: Optional[str] = None,
        jsonl: Optional[str] = None,
    ) -> EnumerationRun: ...
    def critical(
        self,
        method: Optional[str] = None,
        time_limit: Optional[float] = None,
        certify: bool = False,
        tol: Optional[float] = None,
        progress: bool = False,
        shard: Optional[str] = None,
        start: Optional[List[bool]] = None,
        start_file: Optional[str] = None,
        start_json: Optional[str] = None,
        chain: bool = True,
    ) -> str: ...
    def mesh(self) -> Dict[str, Any]: ...
    def recover(
        self, u: npt.NDArray[np.float64]
    ) -> Tuple[
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
    ]: ...
