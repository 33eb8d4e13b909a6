"""REBOUND's side of the outer solar system's long run (issue 21, "Speed": the
energy error over 10⁷ days at Jupiter's period / 20, with the fitted growth
exponent for ours and REBOUND's).

    cargo test -p integrator-core --test integration wisdom_holman::ten_million_days -- --ignored --nocapture
    python3 compare/peers/rebound_long.py PATH [--integrator whfast]
    python3 compare/peers/rebound_long.py PATH --time-step 10


PATH is the JSON file the Rust test writes (G, masses, positions,
velocities as exact decimal strings, the step h and the number of steps,
and our figures). This script integrates the same state with REBOUND
(WHFast by default: Jacobi coordinates, no corrector, safe mode, so that the
state is synchronised after every step), takes the energy error
|E − E₀|/|E₀| (REBOUND's `sim.energy()`) after every step, and reduces it
the way `symlab compare --long` and the Rust test do: the largest error in
log-spaced windows of steps (20 per decade), and the least-squares slope of
its logarithm against log t over the last two decades of time.

With `--time-step H` it times REBOUND's step instead, on the same state: the
integrator in its fast mode (`safe_mode = 0`, as REBOUND says to time it),
60 runs of 2000 steps of H days, only `sim.integrate` timed, the best run
reported in µs per step (the best, because this machine is shared); for
ours, `cargo bench -p integrator-core --bench kepler` (wisdom_holman_step,
h = 10 days).
"""

import argparse
import json
import math
import sys


def windowed_growth(errors, h):
    n = len(errors)
    ends = []
    j = 0
    while True:
        b = int(round(10 ** (j / 20.0)))
        j += 1
        if b >= n:
            break
        if not ends or ends[-1] != b:
            ends.append(b)
    ends.append(n)
    samples = []
    start = 0
    for end in ends:
        samples.append((end, max(errors[start:end])))
        start = end
    t_last = n * h
    pts = [(math.log(e * h), math.log(w)) for e, w in samples
           if e * h >= t_last / 100.0 and w > 0.0]
    m = len(pts)
    mx = sum(p[0] for p in pts) / m
    my = sum(p[1] for p in pts) / m
    sxy = sum((p[0] - mx) * (p[1] - my) for p in pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return samples, sxy / sxx


def build(rebound, spec):
    sim = rebound.Simulation()
    sim.G = float(spec["G"])
    for m, x, v in zip(spec["masses"], spec["positions"], spec["velocities"]):
        sim.add(m=float(m), x=float(x[0]), y=float(x[1]), z=float(x[2]),
                vx=float(v[0]), vy=float(v[1]), vz=float(v[2]))
    return sim


def time_steps(rebound, spec, integrator, h, runs=60, n=2000):
    import time
    best = float("inf")
    for _ in range(runs):
        sim = build(rebound, spec)
        sim.integrator = integrator
        sim.integrator.safe_mode = 0
        sim.dt = h
        start = time.perf_counter()
        sim.integrate((n - 0.5) * h, exact_finish_time=0)
        elapsed = time.perf_counter() - start
        if sim.steps_done != n:
            sys.exit("REBOUND took %d steps where %d were asked for" % (sim.steps_done, n))
        best = min(best, elapsed / n)
    print("REBOUND %s %s, h = %r days, safe_mode 0: %.3f us per step (best of %d runs of %d steps)"
          % (rebound.__version__, integrator, h, best * 1e6, runs, n))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("path")
    ap.add_argument("--integrator", default="whfast")
    ap.add_argument("--time-step", type=float, metavar="H",
                    help="time REBOUND's steps of H days instead of the long run")
    args = ap.parse_args()
    try:
        import rebound
    except ImportError:
        sys.exit("REBOUND is not installed: pip install rebound==5.2.2")
    with open(args.path) as f:
        spec = json.load(f)
    if args.time_step is not None:
        time_steps(rebound, spec, args.integrator, args.time_step)
        return
    sim = build(rebound, spec)
    sim.integrator = args.integrator
    h = float(spec["h"])
    n = int(spec["steps"])
    sim.dt = h
    e0 = sim.energy()
    errors = []
    for _ in range(n):
        sim.steps(1)
        errors.append(abs((sim.energy() - e0) / e0))
    if sim.steps_done != n:
        sys.exit("REBOUND took %d steps where %d were asked for" % (sim.steps_done, n))
    samples, exponent = windowed_growth(errors, h)
    print("REBOUND %s %s h = %r days, %d steps: max |dE/E| %.3e, final %.3e, "
          "growth exponent over the last two decades %.3f"
          % (rebound.__version__, args.integrator, h, n, max(errors), errors[-1], exponent))
    for end, w in samples[::10]:
        print("  t = %.4e days: window max %.3e" % (end * h, w))
    ours = spec.get("ours")
    if ours:
        print("ours (from %s): max %.3e, final %.3e, exponent %.3f"
              % (args.path, float(ours["max"]), float(ours["final"]), float(ours["exponent"])))


if __name__ == "__main__":
    main()
