from os import PathLike
from typing import Any, Literal, Mapping, Sequence, Callable

import numpy as np
import numpy.typing as npt

from . import cloth as cloth

__version__: str
COLUMNS: list[str]

class SymlabError(Exception): ...
class TableError(ValueError): ...
class BudgetError(TableError): ...
class ClaimError(ValueError): ...
class IntegrationError(SymlabError): ...
class ProblemError(ValueError): ...
class DesignError(ValueError): ...

class Table:
    """A Butcher table (or pair, drift–kick sequence, composition), read exactly."""
    def __init__(self, *, id: str | None = None, **fields: Any) -> None: ...
    @staticmethod
    def from_toml(text: str, *, origin: str = "<string>", id: str = "table") -> Table: ...
    @staticmethod
    def from_file(path: str | PathLike[str]) -> Table: ...
    @staticmethod
    def builtin(id: str) -> Table: ...
    @staticmethod
    def generate(generator: str) -> Table: ...
    @property
    def name(self) -> str: ...
    @property
    def origin(self) -> str: ...
    @property
    def id(self) -> str: ...
    @property
    def entries(self) -> Literal["classic", "generated", "algebraic"]: ...

class Problem:
    """A problem written in Python as NumPy-vectorised callables."""
    def __init__(
        self,
        name: str,
        *,
        dof: int | None = None,
        dim: int | None = None,
        force: Callable[[np.ndarray], np.ndarray] | None = None,
        velocity: Callable[[np.ndarray], np.ndarray] | None = None,
        potential: Callable[[np.ndarray], Any] | None = None,
        kinetic: Callable[[np.ndarray], Any] | None = None,
        rhs: Callable[[float, np.ndarray], np.ndarray] | None = None,
        energy: Callable[[np.ndarray], Any] | None = None,
        y0: Sequence[float] | None = None,
        reference: npt.ArrayLike | Callable[[np.ndarray, float], npt.ArrayLike] | None = None,
        t_end: float | None = None,
        h_min: float | None = None,
        h_max: float | None = None,
    ) -> None: ...
    @property
    def name(self) -> str: ...
    @property
    def dim(self) -> int: ...

def check(table: Table, *, claims: Literal["raise", "report"] = "raise") -> dict[str, Any]: ...
def list_tables() -> list[dict[str, Any]]: ...
def problems() -> list[str]: ...
def integrate(
    scheme: str | Table,
    problem: str | Problem,
    y0: npt.ArrayLike | None,
    t0: float,
    h: float,
    n: int,
    *,
    every: int | None = None,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
def integrate_ensemble(
    scheme: str | Table, problem: str | Problem, y0: npt.ArrayLike, h: float, n: int
) -> npt.NDArray[np.float64]: ...
def compare(
    problem: str | Problem,
    methods: Sequence[str | Table] | None = None,
    settings: Mapping[str, Any] | None = None,
    *,
    client: Any = None,
    out: str | PathLike[str] | None = None,
    as_frame: bool | None = None,
    checkpoint: str | PathLike[str] | None = None,
) -> Any: ...
def design(
    family: str | PathLike[str],
    *,
    seed: int | None = None,
    starts: int | None = None,
    out: str | PathLike[str] | None = None,
) -> dict[str, Any]: ...
