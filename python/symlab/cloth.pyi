from os import PathLike
from typing import Any

def run(
    scene: str | PathLike[str], method: str | None = None, frames: int | None = None, *, substeps: int | None = None
) -> dict[str, Any]: ...
