# %% [markdown]
# # symlab from Python: check a table, compare it, plot work against precision
#
# Run as a script (`python python/examples/work_precision.py`) or cell by
# cell in Jupyter/VS Code (the `# %%` markers). Needs the package
# (`pip install ./python`), pandas and matplotlib (`pip install pandas
# matplotlib`). Writes work_precision.png in the current directory.

# %%
import math

import symlab

# A table of your own, written exactly. The claims are verified, not trusted.
gauss2 = symlab.Table(
    name="Gauss–Legendre, 2 stages",
    let={"r": "sqrt(3)/6"},
    a=[["1/4", "1/4 - r"], ["1/4 + r", "1/4"]],
    b=["1/2", "1/2"],
    claims=["symplectic", "symmetric", "order = 4"],
    id="my-gauss2",
)
v = symlab.check(gauss2)
print(v["report"])

# %% [markdown]
# A near miss: a[0][1] off by 1e-17. Every entry of W is about 1e-17, so a
# check in floating point with a tolerance of 1e-14 calls it symplectic;
# the exact check does not.

# %%
near = symlab.Table(
    name="Gauss 2, a[0][1] + 1e-17",
    a=[["1/4", "1/4 - sqrt(3)/6 + 1/100000000000000000"], ["1/4 + sqrt(3)/6", "1/4"]],
    b=["1/2", "1/2"],
    claims=["symplectic"],
)
try:
    symlab.check(near)
except symlab.ClaimError as e:
    print("refused:", e)
print([(w["i"], w["j"], w["value"], w["value_f64"]) for w in symlab.check(near, claims="report")["w_nonzero"]])

# %% [markdown]
# Compare the table (stepped by the run-time interpreter) with the library's
# schemes and DOP853 on Kepler (e = 0.6), ten orbits.

# %%
rows = symlab.compare(
    "kepler",
    [gauss2, "gauss2", "kahan-li8", "leapfrog", "dop853"],
    {"t_end": 20 * math.pi, "h_min": 2e-3, "h_max": 0.1, "points": 8, "repeats": 1},
)
print(rows[["method", "h", "steps", "error", "evals", "time_s", "status"]].to_string())

# %% [markdown]
# The same sweep on a Dask cluster: `client = dask.distributed.Client(...)`
# and `symlab.compare(..., client=client)` — each run a task, each row the
# worker that timed it.

# %%
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

fig, ax = plt.subplots(figsize=(6, 4.5))
for method, g in rows[rows.status == "ok"].groupby("method", sort=False):
    ax.loglog(g["evals"], g["error"], "o-", label=method)
ax.set_xlabel("force evaluations")
ax.set_ylabel("relative error at T")
ax.set_title("Kepler e = 0.6, 10 orbits")
ax.legend()
fig.tight_layout()
fig.savefig("work_precision.png", dpi=120)
print("wrote work_precision.png")
