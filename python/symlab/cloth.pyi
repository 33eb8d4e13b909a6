from os import PathLike
from typing import Any, Sequence

def run(
    scene: str | PathLike[str],
    method: str | None = None,
    frames: int | None = None,
    *,
    substeps: int | None = None,
    dt: float | None = None,
    grid: str | None = None,
    out: str | PathLike[str] | None = None,
    obj_every: int = 10,
    render: str | Sequence[int] | None = None,
    tolerance: float | None = None,
    solver: str | None = None,
    checkpoint_every: str | None = None,
) -> dict[str, Any]: ...
def resume(dir: str | PathLike[str]) -> dict[str, Any]: ...
