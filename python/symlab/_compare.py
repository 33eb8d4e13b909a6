"""symlab.compare: the work–precision sweep of ``symlab compare``, locally
or with its independent runs spread over a Dask cluster."""

from __future__ import annotations

import json
import os
import zlib

from . import _symlab

#: The first line of a sweep checkpoint names its format and version.
CHECKPOINT_FORMAT = "symlab-sweep-checkpoint"
CHECKPOINT_VERSION = 1

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


def _point_key(point):
    """A point of the plan as it is written in a checkpoint: exact (the step
    size or tolerance as the hex of its double)."""
    return [point["method"], point["kind"], float(point["value"]).hex(), int(point["max_steps"])]


def _plan_header(problem, t_end, repeats, points):
    return {
        "format": CHECKPOINT_FORMAT,
        "version": CHECKPOINT_VERSION,
        "problem": problem,
        "t_end": float(t_end).hex(),
        "repeats": int(repeats),
        "points": [_point_key(p) for p in points],
    }


def _line(obj):
    """One checkpoint line: the JSON text and its CRC-32, so that a line
    damaged after it was written is found, never loaded."""
    text = json.dumps(obj, sort_keys=True, allow_nan=True)
    return json.dumps({"crc32": zlib.crc32(text.encode()), "data": text}) + "\n"


def _read_checkpoint(path, header):
    """The rows a checkpoint holds, by point index. A missing file holds
    none. The plan it was written for must be this sweep's; every line must
    be intact, except that a last line without its newline (a write cut off
    by the interruption) is dropped, and its point runs again."""
    try:
        with open(path, "rb") as f:
            raw = f.read()
    except FileNotFoundError:
        return {}
    text = raw.decode("utf-8", errors="replace")
    lines = text.split("\n")
    # The text after the last newline is a line whose write was cut off.
    lines = lines[:-1]
    if not lines:
        return {}

    def data(k, line):
        try:
            outer = json.loads(line)
            inner = outer["data"]
            if not isinstance(inner, str) or zlib.crc32(inner.encode()) != outer["crc32"]:
                raise ValueError("its checksum does not match its contents")
            return json.loads(inner)
        except (ValueError, KeyError, TypeError) as e:
            raise ValueError(f"checkpoint {path}: line {k} is damaged ({e}); "
                             "not loaded (delete the file to start the sweep again)") from None

    first = data(1, lines[0])
    if not isinstance(first, dict) or first.get("format") != CHECKPOINT_FORMAT:
        raise ValueError(f"checkpoint {path}: not a symlab sweep checkpoint")
    if first.get("version") != CHECKPOINT_VERSION:
        raise ValueError(f"checkpoint {path}: format version {first.get('version')!r}, "
                         f"this symlab reads version {CHECKPOINT_VERSION}")
    for field in ("problem", "t_end", "repeats", "points"):
        if first.get(field) != header[field]:
            raise ValueError(
                f"checkpoint {path}: written for another sweep ({field} differs); "
                "resume with the problem, methods and settings it was written for, "
                "or give another checkpoint path")
    rows = {}
    for k, line in enumerate(lines[1:], start=2):
        entry = data(k, line)
        try:
            index, row = entry["index"], entry["row"]
        except (KeyError, TypeError):
            raise ValueError(f"checkpoint {path}: line {k} is no row") from None
        if not isinstance(index, int) or not 0 <= index < len(header["points"]) \
                or not isinstance(row, dict):
            raise ValueError(f"checkpoint {path}: line {k} names no point of the plan")
        rows[index] = row
    return rows


class _Log:
    """The checkpoint being written: its header once, then each row as it
    arrives, each line flushed and synced before the next run's result is
    taken, so an interruption loses at most the line being written."""

    def __init__(self, path, header, fresh):
        self.path = path
        if fresh:
            with open(path, "w") as f:
                f.write(_line(header))
                f.flush()
                os.fsync(f.fileno())
        else:
            # Drop a last line cut off by the interruption before appending.
            with open(path, "rb+") as f:
                raw = f.read()
                end = raw.rfind(b"\n") + 1
                f.truncate(end)
        self.file = open(path, "a")

    def write(self, index, row):
        self.file.write(_line({"index": index, "row": row}))
        self.file.flush()
        os.fsync(self.file.fileno())

    def close(self):
        self.file.close()


def _run_checkpointed(problem, t_end, repeats, points, path, run_all):
    """The rows of `points`, those in the checkpoint at `path` read from it,
    the others run by `run_all(indices)` (an iterator of (index, row) as the
    runs finish) and written to it as they come."""
    path = os.fspath(path)
    header = _plan_header(problem, t_end, repeats, points)
    done = _read_checkpoint(path, header)
    fresh = not done and not _has_header(path, header)
    log = _Log(path, header, fresh)
    try:
        todo = [i for i in range(len(points)) if i not in done]
        for index, row in run_all(todo):
            log.write(index, row)
            done[index] = row
    finally:
        log.close()
    return [done[i] for i in range(len(points))]


def _has_header(path, header):
    try:
        with open(path, "rb") as f:
            first = f.readline()
    except FileNotFoundError:
        return False
    return first.endswith(b"\n")


def compare(problem, methods=None, settings=None, *, client=None, out=None, as_frame=None,
            checkpoint=None):
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

    ``checkpoint``: a file path. Each finished run's row is written to it as
    it finishes (JSON lines, each with a CRC-32, synced to disk), after a
    first line that names the sweep's plan. Called again with the same
    problem, methods, settings and path, the sweep reads the rows there and
    runs only the others — after an interruption (Ctrl-C, a lost client, a
    cluster's time limit) nothing finished is run again. The rows read back
    are the rows written, bit for bit (their times and workers too); a file
    written for another plan, or with a damaged line, is refused with a
    ValueError naming the file and line, never loaded. With ``client``, or
    without it (the runs then go one after another in this process, each
    the same run as a worker's); not with ``out``.

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
    if checkpoint is not None and out is not None:
        raise ValueError("checkpoint: a sweep with out= writes the command line's files and "
                         "does not checkpoint; write the rows with DataFrame.to_csv, or run "
                         "`symlab compare --out DIR` (its checkpoint: `symlab resume DIR`)")
    if client is None and checkpoint is None:
        rows, _summary, _files = _symlab.compare_local(problem, methods, settings,
                                                       None if out is None else str(out))
        return _frame(list(rows), as_frame)
    if out is not None:
        raise ValueError("out: the distributed sweep returns rows; write them with DataFrame.to_csv")
    if not isinstance(problem, str):
        raise TypeError("problem: the distributed sweep and a checkpointed sweep take a "
                        "built-in problem's name")
    points, t_end, repeats = _symlab.sweep_plan(problem, methods, settings)

    def on_client(indices):
        from distributed import as_completed

        futures = client.map(_run_point, [problem] * len(indices), [t_end] * len(indices),
                             [repeats] * len(indices), [points[i] for i in indices],
                             pure=False)
        index = {f.key: i for f, i in zip(futures, indices)}
        for future in as_completed(futures):
            yield index[future.key], future.result()

    def here(indices):
        for i in indices:
            yield i, _run_point(problem, t_end, repeats, points[i])

    if checkpoint is None:
        futures = client.map(_run_point, [problem] * len(points), [t_end] * len(points),
                             [repeats] * len(points), points, pure=False)
        return _frame(client.gather(futures), as_frame)
    rows = _run_checkpointed(problem, t_end, repeats, points, checkpoint,
                             here if client is None else on_client)
    return _frame(rows, as_frame)
