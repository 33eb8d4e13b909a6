"""Cloth scenes (scenes/*.toml) run by the same job as ``symlab cloth``."""

from __future__ import annotations

import os

from . import _symlab


def run(scene, method=None, frames=None, *, substeps=None, dt=None, grid=None, out=None,
        obj_every=10, render=None, tolerance=None, solver=None, checkpoint_every=None):
    """Run a cloth ``scene`` (a path to a scene file, or its TOML text) as
    ``symlab cloth`` does: the same plan (``method``, ``frames``,
    ``substeps`` or ``dt``, ``grid``, ``tolerance``, ``solver`` mean what
    the flags of the same names mean, and are refused with the same
    messages naming the keyword), the same energy guard, and the same files
    in ``out`` (default ``out/cloth/<scene name>/``, as the command line):
    ``energy.csv``, ``energy.svg``, an OBJ every ``obj_every`` frames (0:
    none), the PNG renderings ``render`` asks for (``"none"``, or frames
    comma-separated; default first, middle and last), and checkpoints
    (``checkpoint_every``: ``"30s"``, ``"5m"``, ``"off"``, …; Ctrl-C writes
    one, then raises ``KeyboardInterrupt``; :func:`resume` goes on).

    Returns a dict whose ``positions`` is a float64 array of shape
    ``(frames + 1, particles, 3)`` (the initial state first; pinned
    particles included), with ``time``, ``energy`` and ``max_strain`` per
    frame, ``method``, ``h``, ``steps``, ``stepping_seconds``, the
    ``summary`` that ``symlab cloth`` prints, ``notes`` and ``dir``. A run
    that blows up raises ``IntegrationError`` saying where, after writing
    what was good up to its last good frame.

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
    if isinstance(obj_every, bool) or not isinstance(obj_every, int) or obj_every < 0:
        raise ValueError(f"obj_every must be an int ≥ 0, got {obj_every!r}")
    if isinstance(render, (list, tuple)):
        render = ",".join(str(int(k)) for k in render) if render else "none"
    if out is not None:
        out = os.fspath(out)
    return _symlab.cloth_run(scene, method, frames, substeps, dt, grid, out, obj_every, render,
                             tolerance, solver, checkpoint_every)


def resume(dir):
    """Continue the interrupted cloth run whose output folder is ``dir``
    from its checkpoint (as ``symlab resume DIR``), to the same bits and
    the same files as a run never stopped. Returns what :func:`run` returns;
    the arrays hold the frames this call ran."""
    return _symlab.cloth_resume(os.fspath(dir))
