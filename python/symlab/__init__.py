"""symlab from Python: the exact verifier of Butcher tables, the library's
schemes, the comparisons (locally or on a Dask cluster) and the cloth.

>>> import symlab
>>> v = symlab.check(symlab.Table.builtin("gauss2"))
>>> v["symplectic"], v["order"]
(True, 4)
"""

from __future__ import annotations

import numpy as _np

from . import _symlab
from ._symlab import (
    BudgetError,
    ClaimError,
    DesignError,
    IntegrationError,
    Problem,
    ProblemError,
    SymlabError,
    Table,
    TableError,
    __version__,
    check,
    list_tables,
    problems,
)
from . import cloth
from ._compare import compare, COLUMNS

__all__ = [
    "BudgetError",
    "COLUMNS",
    "ClaimError",
    "DesignError",
    "IntegrationError",
    "Problem",
    "ProblemError",
    "SymlabError",
    "Table",
    "TableError",
    "check",
    "cloth",
    "compare",
    "design",
    "integrate",
    "integrate_ensemble",
    "list_tables",
    "problems",
    "__version__",
]


def _real_array(y, name, ndim):
    """``y`` as a float64 array of ``ndim`` dimensions, or an exception
    naming ``name``: complex, object, string and boolean dtypes are refused
    (a bool is not a coordinate), ints are converted."""
    try:
        a = _np.asarray(y)
    except Exception as e:  # ragged lists and the like
        raise ValueError(f"{name}: not an array of numbers ({e})") from None
    if a.dtype.kind not in "fiu":
        raise TypeError(f"{name}: expected real numbers (float64), got an array of dtype {a.dtype}")
    if a.ndim != ndim:
        want = "(dim,)" if ndim == 1 else "(m, dim)"
        raise ValueError(f"{name}: expected shape {want}, got shape {a.shape}")
    return _np.ascontiguousarray(a, dtype=_np.float64)


def _number(x, name):
    if isinstance(x, bool) or not isinstance(x, (int, float, _np.integer, _np.floating)):
        raise TypeError(f"{name}: expected a number, got {type(x).__name__}")
    return float(x)


def _count(n, name):
    if isinstance(n, bool) or not isinstance(n, (int, _np.integer)):
        raise TypeError(f"{name}: expected an int, got {type(n).__name__}")
    if n < 1:
        raise ValueError(f"{name} must be at least 1, got {n}")
    return int(n)


def integrate(scheme, problem, y0, t0, h, n, *, every=None):
    """Step ``problem`` with ``scheme`` from ``y0`` at ``t0``: ``n`` steps of
    size ``h``. Returns ``(t, y)``, the times and the states (one row each)
    at every ``every``-th step (default: the start and the end).

    ``scheme``: a library id (``symlab.list_tables()``) or a ``symlab.Table``
    (interpreted, its claims verified first). ``problem``: a built-in name
    (``symlab.problems()``) or a ``symlab.Problem``. ``y0=None``: the
    problem's default start. The GIL is released while Rust steps.

    >>> import symlab
    >>> t, y = symlab.integrate("gauss2", "kepler", None, 0.0, 0.01, 100)
    >>> y.shape
    (2, 4)
    """
    if y0 is not None:
        y0 = _real_array(y0, "y0", 1)
    t0 = _number(t0, "t0")
    h = _number(h, "h")
    n = _count(n, "n")
    if every is not None:
        every = _count(every, "every")
    return _symlab.integrate(scheme, problem, y0, t0, h, n, every=every)


def integrate_ensemble(scheme, problem, y0, h, n):
    """Step every row of ``y0`` (shape ``(m, dim)``) ``n`` steps of size
    ``h`` in one Rust loop; returns the final states, shape ``(m, dim)``.
    A ``symlab.Problem`` steps all rows at once: its callables see arrays of
    shape ``(m, dof)``.

    >>> import numpy as np, symlab
    >>> y = symlab.integrate_ensemble("leapfrog", "oscillator", np.array([[1.0, 0.0], [0.5, 0.0]]), 0.01, 10)
    >>> y.shape
    (2, 2)
    """
    y0 = _real_array(y0, "y0", 2)
    return _symlab.integrate_ensemble(scheme, problem, y0, _number(h, "h"), _count(n, "n"))


def design(family, *, seed=None, starts=None, out=None):
    r"""Find the coefficients of a family of methods, as ``symlab design FILE``
    does: the same pipeline (``design::design``: conditions, seeded
    multi-start search, 50-digit polish, exact value or Krawczyk
    certificate, table files).

    ``family``: a family file's path, or its TOML text (a string with a line
    break). ``seed`` and ``starts`` override the file's. ``out``: a folder to
    write the tables (``*.toml``) and ``report.md`` into, as the command line
    does. Returns a dict: ``family``, ``order``, ``unknowns``,
    ``conditions`` (their Lie words), ``starts_run``, ``distinct``,
    ``capped``, ``seconds``, ``written`` (paths) and ``designs``, best
    first, each with ``rank``, ``effective_error``, ``objective``, ``hits``,
    ``stability_per_stage`` (the emitted table's linear stability threshold
    hω on the harmonic oscillator per force evaluation, or ``None`` without
    a table), ``x`` (the unknowns, doubles), ``proof`` (``"exact"``, ``"certified"``,
    ``"not certified"``, ``"not polished"``), ``exact`` (the value in
    radicals or as ``root(...)``), ``radius`` (the certificate's, an exact
    rational as text), ``claims``, ``name`` and ``toml`` (the table file's
    text, which ``symlab.Table.from_toml`` and ``symlab.check`` read). A
    second-corrector family (``form = "second-corrector"``) is solved
    exactly with no search (``seed`` and ``starts`` are refused) and returns
    ``family``, ``form``, ``kernel``, ``c_squared`` and ``c`` (exact, as
    text), ``c_value``, ``orders_before``, ``orders_after``, ``written``
    and ``designs`` (the one table, ``proof`` ``"exact"``). A
    family that does not parse or cannot be designed raises
    ``DesignError`` (a ``ValueError``) naming the file and the field.

    >>> import symlab
    >>> text = 'name = "Yoshida"\nform = "composition"\nstages = 3\norder = 4\nrange = 2.0\n'
    >>> d = symlab.design(text, starts=20)
    >>> d["designs"][0]["exact"]
    '2/3 + cbrt(2/27) + cbrt(1/54)'
    """
    import os

    if isinstance(family, os.PathLike):
        family = os.fspath(family)
    if not isinstance(family, str):
        raise TypeError(f"family: expected a path or TOML text, got {type(family).__name__}")
    if seed is not None:
        if isinstance(seed, bool) or not isinstance(seed, (int, _np.integer)):
            raise TypeError(f"seed: expected an int, got {type(seed).__name__}")
        if seed < 0 or seed >= 2**64:
            raise ValueError(f"seed must be from 0 to 2**64 - 1, got {seed}")
        seed = int(seed)
    if starts is not None:
        # 0 goes on to the library, whose refusal names the field as the
        # command line's does.
        if isinstance(starts, bool) or not isinstance(starts, (int, _np.integer)):
            raise TypeError(f"starts: expected an int, got {type(starts).__name__}")
        if starts < 0:
            raise ValueError(f"starts must be at least 1, got {starts}")
        starts = int(starts)
    if out is not None:
        if not isinstance(out, (str, os.PathLike)):
            raise TypeError(f"out: expected a path, got {type(out).__name__}")
        out = os.fspath(out)
    return _symlab.design(family, seed=seed, starts=starts, out=out)
