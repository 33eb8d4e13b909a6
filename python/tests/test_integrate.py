"""symlab.integrate and the ensemble call: library schemes, tables and
Python problems; bad input as Python exceptions naming the argument."""

import math

import numpy as np
import pytest

import symlab


def osc(**kw):
    return symlab.Problem(
        "osc", dof=1, force=lambda q: -q,
        potential=lambda q: 0.5 * (q * q).sum(-1), kinetic=lambda p: 0.5 * (p * p).sum(-1), **kw)


def test_kepler_library_scheme_one_orbit():
    n = 2000
    t, y = symlab.integrate("gauss2", "kepler", None, 0.0, 2 * math.pi / n, n)
    assert t.shape == (2,) and y.shape == (2, 4)
    assert t[-1] == pytest.approx(2 * math.pi)
    # After one period the orbit closes.
    assert np.linalg.norm(y[-1] - y[0]) < 1e-6


def test_every_records_trajectory():
    t, y = symlab.integrate("leapfrog", "oscillator", [1.0, 0.0], 0.5, 0.1, 10, every=5)
    assert list(t) == pytest.approx([0.5, 1.0, 1.5])
    assert y.shape == (3, 2)


def test_python_problem_matches_builtin_oscillator():
    # The built-in oscillator is H = (p² + q²)/2: the same steps, the same numbers.
    _, yb = symlab.integrate("forest-ruth", "oscillator", [1.0, 0.0], 0.0, 0.01, 500)
    _, yp = symlab.integrate("forest-ruth", osc(), [1.0, 0.0], 0.0, 0.01, 500)
    np.testing.assert_array_equal(yb, yp)


def test_rhs_problem_time_dependent_uses_t0():
    # y' = cos t from t0 = 1: y(t) = sin t - sin 1
    p = symlab.Problem("forced", dim=1, rhs=lambda t, y: np.full_like(y, math.cos(t)))
    t, y = symlab.integrate("rk4", p, [0.0], 1.0, 0.01, 100)
    assert y[-1, 0] == pytest.approx(math.sin(2.0) - math.sin(1.0), abs=1e-10)


def test_table_as_scheme_equals_library():
    _, y1 = symlab.integrate(symlab.Table.builtin("rk4"), "oscillator", [1.0, 0.0], 0.0, 0.05, 100)
    _, y2 = symlab.integrate("rk4", "oscillator", [1.0, 0.0], 0.0, 0.05, 100)
    np.testing.assert_allclose(y1, y2, rtol=0, atol=1e-14)


def test_false_claim_table_refused_before_stepping():
    t = symlab.Table(name="euler", a=[["0"]], b=["1"], claims=["order = 2"])
    with pytest.raises(symlab.ClaimError, match="order = 2"):
        symlab.integrate(t, "oscillator", None, 0.0, 0.1, 10)


def test_ensemble_builtin_equals_single_runs():
    y0 = np.array([[1.0, 0.0, 0.0, 1.0], [0.8, 0.0, 0.0, 1.3]])
    out = symlab.integrate_ensemble("kahan-li8", "kepler", y0, 0.01, 200)
    for i in range(2):
        _, y = symlab.integrate("kahan-li8", "kepler", y0[i], 0.0, 0.01, 200)
        np.testing.assert_array_equal(out[i], y[-1])


def test_ensemble_vectorised_python_problem():
    calls = []

    def force(q):
        calls.append(q.shape)
        return -q

    p = symlab.Problem("osc", dof=1, force=force)
    y0 = np.array([[1.0, 0.0], [2.0, 0.5], [0.0, 1.0]])
    out = symlab.integrate_ensemble("leapfrog", p, y0, 0.01, 100)
    assert all(s == (3, 1) for s in calls)
    for i in range(3):
        _, y = symlab.integrate("leapfrog", "oscillator", y0[i], 0.0, 0.01, 100)
        np.testing.assert_allclose(out[i], y[-1], rtol=0, atol=1e-15)


@pytest.mark.parametrize(
    "y0, exc, match",
    [
        ([1.0, 0.0, 3.0], ValueError, r"y0: expected 2 components"),
        ([[1.0, 0.0]], ValueError, r"y0: expected shape \(dim,\)"),
        (np.array([1 + 1j, 0]), TypeError, r"y0: expected real numbers"),
        (["a", "b"], TypeError, r"y0: expected real numbers"),
        ([float("nan"), 0.0], ValueError, r"y0\[0\] is NaN|y0\[0\] is nan"),
        ([1.0, float("inf")], ValueError, r"y0\[1\]"),
    ],
)
def test_bad_y0(y0, exc, match):
    with pytest.raises(exc, match=match):
        symlab.integrate("leapfrog", "oscillator", y0, 0.0, 0.1, 10)


@pytest.mark.parametrize(
    "kw, exc, match",
    [
        (dict(h=0.0), ValueError, "h must be"),
        (dict(h=float("nan")), ValueError, "h must be"),
        (dict(n=0), ValueError, "n must be at least 1"),
        (dict(n=2.5), TypeError, "n: expected an int"),
        (dict(t0="zero"), TypeError, "t0: expected a number"),
    ],
)
def test_bad_numbers(kw, exc, match):
    args = dict(t0=0.0, h=0.1, n=10)
    args.update(kw)
    with pytest.raises(exc, match=match):
        symlab.integrate("leapfrog", "oscillator", [1.0, 0.0], args["t0"], args["h"], args["n"])


def test_unknown_scheme_and_problem():
    with pytest.raises(symlab.ProblemError, match="unknown method 'nope'"):
        symlab.integrate("nope", "oscillator", None, 0.0, 0.1, 10)
    with pytest.raises(symlab.ProblemError, match="problem: unknown problem 'nope'"):
        symlab.integrate("leapfrog", "nope", None, 0.0, 0.1, 10)
    with pytest.raises(TypeError, match="scheme: expected a scheme id"):
        symlab.integrate(3, "oscillator", None, 0.0, 0.1, 10)


def test_callable_that_raises_names_it():
    def force(q):
        raise RuntimeError("boom")

    p = symlab.Problem("bad", dof=1, force=force)
    with pytest.raises(symlab.ProblemError, match="force raised RuntimeError") as e:
        symlab.integrate("leapfrog", p, [1.0, 0.0], 0.0, 0.1, 10)
    assert isinstance(e.value.__cause__, RuntimeError)


@pytest.mark.parametrize(
    "ret, match",
    [
        (lambda q: np.zeros(3), r"force must return a float64 NumPy array of shape \[1\], got shape \[3\]"),
        (lambda q: [0.0], r"force must return a float64 NumPy array"),
        (lambda q: np.zeros(1, dtype=np.int64), r"dtype int64"),
    ],
)
def test_callable_wrong_return(ret, match):
    p = symlab.Problem("bad", dof=1, force=ret)
    with pytest.raises(symlab.ProblemError, match=match):
        symlab.integrate("leapfrog", p, [1.0, 0.0], 0.0, 0.1, 10)


def test_rhs_wrong_shape():
    p = symlab.Problem("bad", dim=2, rhs=lambda t, y: y[:1])
    with pytest.raises(symlab.ProblemError, match="rhs must return"):
        symlab.integrate("rk4", p, [1.0, 0.0], 0.0, 0.1, 10)


def test_divergence_is_integration_error():
    p = symlab.Problem("blowup", dim=1, rhs=lambda t, y: y * y)
    with pytest.raises(symlab.IntegrationError, match="diverged"):
        symlab.integrate("rk4", p, [1.0], 0.0, 0.5, 100)


def test_problem_constructor_errors():
    with pytest.raises(ValueError, match="dof"):
        symlab.Problem("x", force=lambda q: -q)
    with pytest.raises(TypeError, match="force must be callable"):
        symlab.Problem("x", dof=1, force=3)
    with pytest.raises(ValueError, match="y0: expected 2 components"):
        symlab.Problem("x", dof=1, force=lambda q: -q, y0=[1.0])


def test_gil_released_during_long_run():
    import threading
    import time

    ticks = []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    th = threading.Thread(target=ticker)
    th.start()
    t0 = time.perf_counter()
    symlab.integrate("kahan-li8", "kepler", None, 0.0, 1e-3, 300_000)
    dt = time.perf_counter() - t0
    stop.set()
    th.join()
    during = [x for x in ticks if t0 < x < t0 + dt]
    # With the GIL held the ticker could not run at all during the call.
    assert dt < 0.05 or len(during) >= 5, (dt, len(during))
