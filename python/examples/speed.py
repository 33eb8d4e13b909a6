"""The speed figures of docs/results/python-speed.md.

    scripts/results python-speed        (the page, from a release build)
    target/python-release-venv/bin/python python/examples/speed.py

1. symlab.integrate on Kepler with a library scheme against the same run
   timed in Rust (the comparison library's timed run, `time_s`): the fixed
   overhead per call and the ratio beyond it.
2. A NumPy-vectorised Python problem (Kepler written with NumPy): the cost
   per step beside the built-in Kepler.
3. The Dask path: a sweep of at least 100 runs on a 2-worker LocalCluster
   against one process, and the overhead per run.

Figures depend on the build: `scripts/python-release` (what the page runs
first) builds the release profile, as `pip install ./python` does; the
`.venv` that `scripts/test` makes holds a dev-profile build (the bindings
and the comparison library at opt-level 0, for a fast test build), where
the same script runs many times slower.
"""

import math
import statistics
import time

import numpy as np

import symlab


def median_time(f, repeats):
    ts = []
    for _ in range(repeats):
        t = time.perf_counter()
        f()
        ts.append(time.perf_counter() - t)
    return statistics.median(ts)


def integrate_overhead():
    # The same run in Rust: compare's timed bare run of n steps of h.
    n, T = 200_000, 20 * math.pi
    h = T / n
    row = symlab.compare("kepler", ["kahan-li8"], {"t_end": T, "h_min": h, "h_max": h, "points": 1,
                                                   "repeats": 5}, as_frame=False)[0]
    rust = row["time_s"]
    assert row["steps"] == n
    py = median_time(lambda: symlab.integrate("kahan-li8", "kepler", None, 0.0, row["h"], n), 5)
    overhead = median_time(lambda: symlab.integrate("kahan-li8", "kepler", None, 0.0, h, 1), 2000)
    print(f"1. integrate(kahan-li8, kepler, n={n}): Python {py*1e3:.2f} ms, Rust {rust*1e3:.2f} ms; "
          f"fixed overhead per call {overhead*1e6:.1f} µs (n = 1); "
          f"(Python - overhead)/Rust = {(py - overhead)/rust:.3f}")


def vectorised_problem():
    def force(q):
        r3 = np.sum(q * q, axis=-1, keepdims=True) ** 1.5
        return -q / r3

    kepler = symlab.Problem("kepler-numpy", dof=2, force=force)
    e = 0.6
    y0 = [1 - e, 0.0, 0.0, math.sqrt((1 + e) / (1 - e))]
    n = 20_000
    py = median_time(lambda: symlab.integrate("leapfrog", kepler, y0, 0.0, 1e-3, n), 3)
    rs = median_time(lambda: symlab.integrate("leapfrog", "kepler", y0, 0.0, 1e-3, n), 3)
    _, a = symlab.integrate("leapfrog", kepler, y0, 0.0, 1e-3, n)
    _, b = symlab.integrate("leapfrog", "kepler", y0, 0.0, 1e-3, n)
    print(f"2. leapfrog on Kepler, per step: NumPy problem {py/n*1e6:.2f} µs, built-in {rs/n*1e6:.3f} µs "
          f"({py/rs:.0f}×); end states differ by {np.abs(a - b).max():.1e}")
    m = 1000
    ys = np.tile(np.array(y0), (m, 1))
    ens = median_time(lambda: symlab.integrate_ensemble("leapfrog", kepler, ys, 1e-3, 2000), 3)
    print(f"   ensemble of {m} conditions in one vectorised call per step: "
          f"{ens/(2000*m)*1e6:.3f} µs per condition-step")


def dask_sweep():
    from distributed import Client, LocalCluster

    methods = ["leapfrog", "forest-ruth", "rk4", "gauss2", "kahan-li8", "mclachlan8",
               "sofroniou-spaletta10", "yoshida6", "blanes-moan6", "dop853"]
    ids = {t["id"] for t in symlab.list_tables()} | {"dop853"}
    methods = [m for m in methods if m in ids]
    s = {"t_end": 200 * math.pi, "h_min": 1e-3, "h_max": 0.05, "points": 12, "repeats": 3}
    t = time.perf_counter()
    local = symlab.compare("kepler", methods, s, as_frame=False)
    t_local = time.perf_counter() - t
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        symlab.compare("kepler", ["leapfrog"], {"quick": True}, client=client)  # warm the workers
        t = time.perf_counter()
        dist = symlab.compare("kepler", methods, s, client=client, as_frame=False)
        t_dist = time.perf_counter() - t
        # Overhead per run: runs of almost no work.
        tiny = {"t_end": 0.1, "h_min": 0.01, "h_max": 0.1, "points": 10, "repeats": 1}
        t = time.perf_counter()
        rt = symlab.compare("kepler", methods, tiny, client=client, as_frame=False)
        t_tiny = time.perf_counter() - t
        t = time.perf_counter()
        symlab.compare("kepler", methods, tiny, as_frame=False)
        t_tiny_local = time.perf_counter() - t
    same = all(a["error"] == b["error"] or (a["error"] != a["error"] and b["error"] != b["error"])
               for a, b in zip(local, dist))
    print(f"3. sweep of {len(local)} runs: one process {t_local:.2f} s, 2-worker LocalCluster "
          f"{t_dist:.2f} s (speed-up {t_local/t_dist:.2f}×); errors identical: {same}; "
          f"overhead per run {(t_tiny - t_tiny_local/2)/len(rt)*1e3:.2f} ms ({len(rt)} tiny runs)")


if __name__ == "__main__":
    integrate_overhead()
    vectorised_problem()
    dask_sweep()
