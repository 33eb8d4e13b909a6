"""REBOUND as a peer of `symlab compare` (the `rebound:` methods).

The comparison library (compare/src/rebound.rs) embeds this file and runs it
as `python3 -c <this file>`, one process per run, with one JSON request on
standard input; it writes one JSON answer on standard output. Every double
crosses the pipe as a hexadecimal float (`float.hex`), so the initial state
REBOUND integrates and the final state the library measures are the bits each
side holds. The library computes the error with the project's own measure and
reference; this script only integrates and times.

One process per run because WHFast512 leaves the AVX upper registers dirty
and sets flush-to-zero, which would slow (and could alter) whatever ran after
it in the same process.

Requests:

* `{"probe": "version"}`: REBOUND's version, or why it cannot be imported.
* `{"probe": "whfast512"}`: a few WHFast512 steps on a small system (the
  caller checks first that the CPU has AVX-512).
* `{"echo": SYSTEM}`: the particles REBOUND holds after building SYSTEM, read
  back (the round trip of the initial state).
* `{"run": SYSTEM, "integrator": NAME, "settings": [[KEY, VALUE], ...],
  "steps": N | null, "tolerance": HEX | null, "dt": HEX, "t_end": HEX,
  "repeats": R, "samples": K}`: an observed run (the state at about K evenly
  spaced points, for the energy error), one untimed warm-up run (its final
  state is the answer's) and R timed runs, each on a freshly built
  simulation; only `sim.integrate` is timed. A fixed-step run (`steps`) takes
  exactly N steps of `dt` (checked); an adaptive one (`tolerance`) integrates
  to `t_end` exactly.

SYSTEM is `{"G": HEX, "masses": [HEX], "positions": [[HEX x3]],
"velocities": [[HEX x3]]}`. Answers carry `"ok": true` or `"ok": false` with
`"error"` (and `"missing": true` when REBOUND cannot be imported).
"""

import json
import sys
import time


def unhex(s):
    return float.fromhex(s)


def hexed(x):
    return float(x).hex()


def answer(obj):
    sys.stdout.write(json.dumps(obj))
    sys.stdout.flush()


def fail(message, **extra):
    out = {"ok": False, "error": message}
    out.update(extra)
    answer(out)
    sys.exit(0)


def system_of(spec):
    g = unhex(spec["G"])
    masses = [unhex(m) for m in spec["masses"]]
    positions = [[unhex(c) for c in p] for p in spec["positions"]]
    velocities = [[unhex(c) for c in v] for v in spec["velocities"]]
    if not (len(masses) == len(positions) == len(velocities)):
        fail("the request has %d masses, %d positions and %d velocities"
             % (len(masses), len(positions), len(velocities)))
    return g, masses, positions, velocities


def build(rebound, system):
    g, masses, positions, velocities = system
    sim = rebound.Simulation()
    sim.G = g
    for m, x, v in zip(masses, positions, velocities):
        sim.add(m=m, x=x[0], y=x[1], z=x[2], vx=v[0], vy=v[1], vz=v[2])
    # The particles must be the requested bits: REBOUND stores doubles, and
    # a conversion on the way (a unit, a frame) would compare other problems.
    for i, (m, x, v) in enumerate(zip(masses, positions, velocities)):
        p = sim.particles[i]
        held = [p.m, p.x, p.y, p.z, p.vx, p.vy, p.vz]
        asked = [m] + list(x) + list(v)
        if any(a != b for a, b in zip(held, asked)):
            fail("body %d: REBOUND holds %r, the request asked for %r" % (i, held, asked))
    return sim


def state(sim):
    ps = sim.particles
    return ([[hexed(p.x), hexed(p.y), hexed(p.z)] for p in ps],
            [[hexed(p.vx), hexed(p.vy), hexed(p.vz)] for p in ps])


def configure(sim, req, observed=False):
    name = req["integrator"]
    sim.integrator = name
    for key, value in req["settings"]:
        setattr(sim.integrator, key, value)
    if name == "whfast512":
        # WHFast512 runs `concatenate_steps` steps per REBOUND step: all of
        # them at once when timed, one at a time when observed.
        sim.integrator.concatenate_steps = 1 if observed else req["steps"]
    if req["tolerance"] is not None:
        tol = unhex(req["tolerance"])
        if name == "ias15":
            sim.integrator.epsilon = tol
        elif name == "bs":
            sim.integrator.eps_abs = tol
            sim.integrator.eps_rel = tol
        else:
            fail("a tolerance was given for the fixed-step integrator %s" % name)
    sim.dt = unhex(req["dt"])


def integrate_to_end(sim, req):
    """The timed call: exactly N steps of dt (stopping past t_end − dt/2),
    or an adaptive run landing on t_end."""
    t_end = unhex(req["t_end"])
    if req["steps"] is not None:
        sim.integrate(t_end - 0.5 * sim.dt, exact_finish_time=0)
    else:
        sim.integrate(t_end, exact_finish_time=1)


def steps_taken(sim, req):
    n = sim.steps_done
    if req["integrator"] == "whfast512":
        n *= sim.integrator.concatenate_steps
    return n


def observe(rebound, system, req):
    """The state at about `samples` evenly spaced points (energy errors)."""
    sim = build(rebound, system)
    configure(sim, req, observed=True)
    t_end = unhex(req["t_end"])
    k = max(1, int(req["samples"]))
    out = []
    if req["steps"] is not None:
        n = req["steps"]
        k = min(k, n)
        dt = sim.dt
        for j in range(1, k + 1):
            done = (j * n) // k
            sim.integrate((done - 0.5) * dt, exact_finish_time=0)
            out.append(state(sim))
    else:
        for j in range(1, k + 1):
            sim.integrate(t_end * j / k, exact_finish_time=0)
            out.append(state(sim))
    return out


def units_for(req, system):
    """WHFast512 refuses G != 1: the same system in the mass unit that makes
    G = 1 (masses G·m). Positions, velocities and time keep their units and
    their bits, and G·m is the product every integrator forms anyway."""
    g, masses, positions, velocities = system
    if req["integrator"] == "whfast512" and g != 1.0:
        return 1.0, [g * m for m in masses], positions, velocities
    return system


def run(rebound, req):
    system = units_for(req, system_of(req["run"]))
    samples = observe(rebound, system, req)
    sim = build(rebound, system)
    configure(sim, req)
    integrate_to_end(sim, req)
    steps = steps_taken(sim, req)
    if req["steps"] is not None and steps != req["steps"]:
        fail("REBOUND took %d steps where %d were asked for" % (steps, req["steps"]))
    positions, velocities = state(sim)
    times = []
    reproducible = True
    import gc
    for _ in range(int(req["repeats"])):
        sim = build(rebound, system)
        configure(sim, req)
        gc.disable()
        start = time.perf_counter()
        integrate_to_end(sim, req)
        times.append(time.perf_counter() - start)
        gc.enable()
        if state(sim) != (positions, velocities):
            reproducible = False
    answer({
        "ok": True,
        "rebound": rebound.__version__,
        "positions": positions,
        "velocities": velocities,
        "t": hexed(sim.t),
        "steps": steps,
        "times": times,
        "reproducible": reproducible,
        "samples": [{"positions": p, "velocities": v} for p, v in samples],
    })


def probe_whfast512(rebound):
    sim = rebound.Simulation()
    sim.add(m=1.0)
    sim.add(m=1e-3, a=1.0)
    sim.add(m=1e-3, a=2.0)
    sim.integrator = "whfast512"
    sim.dt = 0.01
    sim.integrator.concatenate_steps = 10
    sim.integrate(0.095, exact_finish_time=0)
    if sim.steps_done * sim.integrator.concatenate_steps != 10:
        fail("WHFast512 took %d steps where 10 were asked for" % sim.steps_done)
    answer({"ok": True, "rebound": rebound.__version__})


def main():
    try:
        req = json.loads(sys.stdin.read())
    except ValueError as e:
        fail("the request is not JSON: %s" % e)
    try:
        import rebound
    except ImportError as e:
        fail("cannot import rebound (%s)" % e, missing=True)
    try:
        if "probe" in req:
            if req["probe"] == "whfast512":
                probe_whfast512(rebound)
            else:
                answer({"ok": True, "rebound": rebound.__version__})
        elif "echo" in req:
            sim = build(rebound, system_of(req["echo"]))
            positions, velocities = state(sim)
            answer({"ok": True, "rebound": rebound.__version__,
                    "positions": positions, "velocities": velocities})
        elif "run" in req:
            run(rebound, req)
        else:
            fail("the request has none of probe, echo, run")
    except SystemExit:
        raise
    except Exception as e:  # REBOUND's errors: an unknown setting, a failed run
        fail("%s: %s" % (type(e).__name__, e))


main()
