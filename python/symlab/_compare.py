"""symlab.compare: the work–precision sweep of ``symlab compare``, locally
or with its independent runs spread over a Dask cluster."""

from __future__ import annotations

from . import _symlab

#: The columns of runs.csv (``symlab compare``), then ``interpreted``; a
#: distributed sweep adds ``worker``.
COLUMNS = [
    "problem", "method", "order", "symplectic", "h", "tol", "steps", "error",
    "energy_error", "time_s", "evals", "newton_iterations",
    "fixed_point_iterations", "factorizations", "status", "interpreted",
]


def _frame(rows, as_frame):
    if as_frame is False:
        return rows
    try:
        import pandas as pd
    except ImportError:
        if as_frame:
            raise
        return rows
    return pd.DataFrame(rows)


def _run_point(problem, t_end, repeats, point):
    """One run of a sweep on a worker: its row, with the worker that timed it."""
    row = _symlab.run_point(problem, t_end, repeats, point["method"], point["kind"],
                            point["value"], point["max_steps"])
    try:
        from distributed import get_worker

        row["worker"] = get_worker().address
    except (ImportError, ValueError):
        import socket, os

        row["worker"] = f"{socket.gethostname()}:{os.getpid()}"
    return row


def compare(problem, methods=None, settings=None, *, client=None, out=None, as_frame=None):
    """A work–precision sweep: every method over a range of step sizes (DOP853
    over tolerances), one row per run — the rows of ``symlab compare``'s
    runs.csv for the same settings.

    ``problem``: a built-in name (``symlab.problems()``) or a
    ``symlab.Problem`` with ``t_end``, ``h_min``, ``h_max`` and a
    ``reference``. ``methods``: ids or ``symlab.Table`` objects (default: as
    the command line). ``settings``: a dict of ``t_end``, ``h_min``,
    ``h_max``, ``points``, ``repeats``, ``target``, ``quick`` (the flags of
    ``symlab compare``). ``out``: a directory to write runs.csv, the plots
    and report.md into, as the command line does (local sweeps only).

    ``client``: a ``dask.distributed.Client``. Each run (method × step size)
    is then a task: errors and evaluation counts are those of the local
    sweep, bit for bit; wall times are measured one run at a time on the
    worker that ran it, recorded in the column ``worker`` — times from
    different workers are not comparable. Built-in problems and scheme ids
    only.

    Returns a pandas DataFrame when pandas is installed (``as_frame=False``:
    a list of dicts).

    >>> import symlab
    >>> rows = symlab.compare("kepler", ["leapfrog", "gauss2"], {"quick": True}, as_frame=False)
    >>> sorted({r["method"] for r in rows})
    ['gauss2', 'leapfrog']
    """
    if settings is not None and not isinstance(settings, dict):
        raise TypeError(f"settings: expected a dict, got {type(settings).__name__}")
    if methods is not None and not isinstance(methods, str):
        methods = list(methods)
    if client is None:
        rows, _summary, _files = _symlab.compare_local(problem, methods, settings,
                                                       None if out is None else str(out))
        return _frame(list(rows), as_frame)
    if out is not None:
        raise ValueError("out: the distributed sweep returns rows; write them with DataFrame.to_csv")
    if not isinstance(problem, str):
        raise TypeError("problem: the distributed sweep takes a built-in problem's name")
    points, t_end, repeats = _symlab.sweep_plan(problem, methods, settings)
    futures = client.map(_run_point, [problem] * len(points), [t_end] * len(points),
                         [repeats] * len(points), points, pure=False)
    rows = client.gather(futures)
    return _frame(rows, as_frame)
