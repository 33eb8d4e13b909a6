"""symlab.compare: the rows of `symlab compare`, locally and on a Dask
LocalCluster of two workers."""

import csv
import math
import subprocess

import numpy as np
import pytest

import symlab

SETTINGS = {"t_end": 2 * math.pi, "h_min": 0.01, "h_max": 0.1, "points": 4, "repeats": 1}
METHODS = ["leapfrog", "gauss2", "dop853"]
EXACT = ["problem", "method", "order", "symplectic", "h", "tol", "steps", "error",
         "energy_error", "evals", "newton_iterations", "fixed_point_iterations",
         "factorizations", "status"]


def as_rows(x):
    return x.to_dict("records") if hasattr(x, "to_dict") else x


def test_rows_equal_the_cli(tmp_path, symlab_bin):
    out = tmp_path / "cli"
    subprocess.run(
        [symlab_bin, "compare", "--problem", "kepler", "--methods", ",".join(METHODS),
         "--t-end", repr(SETTINGS["t_end"]), "--h-min", "0.01", "--h-max", "0.1",
         "--points", "4", "--repeats", "1", "--out", str(out)],
        check=True, capture_output=True, text=True)
    with open(out / "runs.csv") as f:
        cli = list(csv.DictReader(f))
    py = as_rows(symlab.compare("kepler", METHODS, SETTINGS))
    assert len(py) == len(cli) > 0
    for a, b in zip(py, cli):
        for k in EXACT:
            if isinstance(a[k], bool):
                assert str(a[k]).lower() == b[k], k
            elif isinstance(a[k], (int, float)):
                va, vb = float(a[k]), float(b[k])
                assert (math.isnan(va) and math.isnan(vb)) or va == vb, (k, a[k], b[k])
            else:
                assert a[k] == b[k], k


def test_writes_the_cli_files(tmp_path):
    symlab.compare("oscillator", ["leapfrog"], {"quick": True}, out=tmp_path)
    assert (tmp_path / "runs.csv").exists()
    assert (tmp_path / "report.md").exists()


def test_list_of_dicts_without_pandas():
    rows = symlab.compare("oscillator", ["leapfrog", "rk4"], {"quick": True}, as_frame=False)
    assert isinstance(rows, list) and set(rows[0]) >= set(symlab.COLUMNS)
    assert {r["method"] for r in rows} == {"leapfrog", "rk4"}


def test_table_in_compare_is_interpreted(tables):
    t = symlab.Table.from_toml((tables / "gauss2.toml").read_text(), id="my-gauss2")
    rows = symlab.compare("kepler", [t, "gauss2"], {"quick": True}, as_frame=False)
    interp = [r for r in rows if r["interpreted"]]
    assert interp and all(r["method"] == "my-gauss2" for r in interp)
    # The table and the library scheme step the same coefficients.
    lib = [r for r in rows if not r["interpreted"]]
    assert [r["status"] for r in interp] == [r["status"] for r in lib]
    np.testing.assert_allclose([r["error"] for r in interp], [r["error"] for r in lib], rtol=1e-6)


def test_python_problem_reference_wrong_length():
    p = symlab.Problem("osc", dof=1, force=lambda q: -q,
                       potential=lambda q: 0.5 * (q * q).sum(-1), kinetic=lambda p: 0.5 * (p * p).sum(-1),
                       y0=[1.0, 0.0], reference=np.zeros(3), t_end=1.0, h_min=0.01, h_max=0.1)
    with pytest.raises(symlab.ProblemError, match="reference: expected 2 components"):
        symlab.compare(p, ["leapfrog"], {"quick": True})


def test_python_problem_compare_matches_builtin():
    p = symlab.Problem("oscillator", dof=1, force=lambda q: -q,
                       potential=lambda q: 0.5 * (q * q).sum(-1), kinetic=lambda p: 0.5 * (p * p).sum(-1),
                       y0=[1.0, 0.0],
                       reference=lambda y0, t: np.array([math.cos(t), -math.sin(t)]),
                       t_end=2 * math.pi, h_min=0.01, h_max=0.1)
    s = {"points": 3, "repeats": 1}
    a = as_rows(symlab.compare(p, ["leapfrog"], s))
    b = as_rows(symlab.compare("oscillator", ["leapfrog"], {**s, "t_end": 2 * math.pi, "h_min": 0.01, "h_max": 0.1}))
    assert [r["steps"] for r in a] == [r["steps"] for r in b]
    assert [r["evals"] for r in a] == [r["evals"] for r in b]
    np.testing.assert_allclose([r["error"] for r in a], [r["error"] for r in b], rtol=1e-9)


def test_bad_settings_name_the_key():
    with pytest.raises(ValueError, match="h_min"):
        symlab.compare("kepler", ["leapfrog"], {"h_min": -1.0})
    with pytest.raises(ValueError, match='unknown key "hmin"'):
        symlab.compare("kepler", ["leapfrog"], {"hmin": 0.1})
    with pytest.raises(TypeError, match="methods"):
        symlab.compare("kepler", "leapfrog")


@pytest.fixture(scope="module")
def client():
    # scripts/test installs dask[distributed]: a missing one is a failure,
    # never a skip.
    import distributed

    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=None)
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()


def test_dask_two_workers_same_errors_and_counts(client):
    local = as_rows(symlab.compare("kepler", METHODS, SETTINGS))
    dist = as_rows(symlab.compare("kepler", METHODS, SETTINGS, client=client))
    assert len(local) == len(dist)
    for a, b in zip(local, dist):
        for k in EXACT:
            va, vb = a[k], b[k]
            if isinstance(va, float) and math.isnan(va):
                assert math.isnan(vb), k
            else:
                assert va == vb, (k, va, vb)
    workers = {r["worker"] for r in dist}
    assert workers <= set(client.scheduler_info()["workers"])
    assert len(workers) == 2
