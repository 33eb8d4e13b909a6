"""Cloth scenes (scenes/*.toml) stepped by symlab's cloth crate."""

from __future__ import annotations

import os

from . import _symlab


def run(scene, method=None, frames=None, *, substeps=None):
    """Run a cloth ``scene`` (a path to a scene file, or its TOML text) with
    ``method`` (a scheme id; default: the scene's) for ``frames`` frames
    (default: the scene's). Returns a dict whose ``positions`` is a float64
    array of shape ``(frames + 1, particles, 3)`` (the initial state first;
    pinned particles included), with ``time``, ``energy`` and
    ``max_strain`` per frame, and ``method``, ``h``, ``steps``,
    ``stepping_seconds``.

    >>> import symlab
    >>> out = symlab.cloth.run("scenes/corners.toml", "stormer-verlet", frames=2)  # doctest: +SKIP
    >>> out["positions"].shape[0]  # doctest: +SKIP
    3
    """
    if isinstance(scene, os.PathLike):
        scene = os.fspath(scene)
    if not isinstance(scene, str):
        raise TypeError(f"scene: expected a path or the scene's TOML text, got {type(scene).__name__}")
    for name, v in (("frames", frames), ("substeps", substeps)):
        if v is not None and (isinstance(v, bool) or not isinstance(v, int) or v < 1):
            raise ValueError(f"{name} must be an int ≥ 1, got {v!r}")
    return _symlab.cloth_run(scene, method, frames, substeps)
