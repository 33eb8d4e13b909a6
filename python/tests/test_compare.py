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


# A checkpointed sweep (issue 35): rows written as they finish, read back
# bit for bit, only the missing ones run again.

def _same_exact(a, b):
    assert len(a) == len(b)
    for x, y in zip(a, b):
        for k in EXACT:
            vx, vy = x[k], y[k]
            if isinstance(vx, float) and math.isnan(vx):
                assert isinstance(vy, float) and math.isnan(vy), k
            else:
                assert vx == vy, (k, vx, vy)


def _interrupted_copy(src, dst, keep_rows, torn=False):
    """The checkpoint as an interruption after `keep_rows` rows leaves it
    (with `torn`, the next row's line cut off half-way)."""
    lines = src.read_text().splitlines(keepends=True)
    text = "".join(lines[:1 + keep_rows])
    if torn:
        text += lines[1 + keep_rows][: len(lines[1 + keep_rows]) // 2]
    dst.write_text(text)


@pytest.mark.parametrize("distributed", [False, True])
def test_checkpointed_sweep_resumes_without_running_the_finished_rows(tmp_path, client,
                                                                       distributed):
    c = client if distributed else None
    plain = as_rows(symlab.compare("kepler", METHODS, SETTINGS, as_frame=False))
    full = tmp_path / "full.jsonl"
    first = symlab.compare("kepler", METHODS, SETTINGS, client=c, checkpoint=full,
                           as_frame=False)
    _same_exact(first, plain)
    assert len(full.read_text().splitlines()) == 1 + len(plain)

    for torn in (False, True):
        cut = tmp_path / f"cut-{torn}.jsonl"
        _interrupted_copy(full, cut, 3, torn=torn)
        kept = {json_row["index"]: json_row["row"] for json_row in _rows_of(cut)}
        assert len(kept) == 3
        resumed = symlab.compare("kepler", METHODS, SETTINGS, client=c, checkpoint=cut,
                                 as_frame=False)
        _same_exact(resumed, plain)
        # The finished rows were read back, not run again: their wall times
        # and workers are the ones written, to the bit.
        for i, row in kept.items():
            assert resumed[i]["time_s"] == row["time_s"]
            assert resumed[i]["worker"] == row["worker"]
        # The file now holds every row once, the cut-off line dropped.
        assert sorted(r["index"] for r in _rows_of(cut)) == list(range(len(plain)))
        # A third call runs nothing: every row is read back.
        again = symlab.compare("kepler", METHODS, SETTINGS, client=c, checkpoint=cut,
                               as_frame=False)
        assert [r["time_s"] for r in again] == [r["time_s"] for r in resumed]


def _rows_of(path):
    import json

    out = []
    # Whole lines only: a last line without its newline was cut off.
    for line in path.read_text().split("\n")[1:-1]:
        out.append(json.loads(json.loads(line)["data"]))
    return out


def test_checkpoint_of_another_sweep_or_damaged_is_refused(tmp_path):
    path = tmp_path / "sweep.jsonl"
    symlab.compare("kepler", ["leapfrog"], SETTINGS, checkpoint=path, as_frame=False)
    with pytest.raises(ValueError, match=r"sweep\.jsonl: written for another sweep \(points differs\)"):
        symlab.compare("kepler", ["gauss2"], SETTINGS, checkpoint=path)
    with pytest.raises(ValueError, match=r"another sweep \(problem differs\)"):
        symlab.compare("oscillator", ["leapfrog"], SETTINGS, checkpoint=path)
    lines = path.read_text().splitlines(keepends=True)
    # One digit changed inside a row: the checksum finds it.
    damaged = lines[2].replace("1", "2", 1) if "1" in lines[2] else lines[2].replace("0", "9", 1)
    assert damaged != lines[2]
    path.write_text("".join(lines[:2] + [damaged] + lines[3:]))
    with pytest.raises(ValueError, match=r"sweep\.jsonl: line 3 is damaged"):
        symlab.compare("kepler", ["leapfrog"], SETTINGS, checkpoint=path)
    path.write_text("garbage\n")
    with pytest.raises(ValueError, match=r"sweep\.jsonl: line 1 is damaged"):
        symlab.compare("kepler", ["leapfrog"], SETTINGS, checkpoint=path)
    with pytest.raises(ValueError, match="checkpoint: a sweep with out="):
        symlab.compare("kepler", ["leapfrog"], SETTINGS, checkpoint=path, out=tmp_path / "o")
