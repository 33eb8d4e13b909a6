"""The cost of one call of REBOUND's Kepler solver, on the orbits and steps
of integrator-core/benches/kepler.rs (`kepler_drift`), for the comparison
of issue 21 ("the Kepler flow's cost per call against REBOUND's").

    python3 compare/peers/rebound_kepler_bench.py [--calls N] [--repeats R]
        [--keep DIR [--build-only]] [--run-only DIR]

REBOUND's Python wheel ships its C library (librebound*.so) with the solver
WHFast calls for every planet and every step,

    void reb_integrator_whfast_kepler_solver(struct reb_particle* p,
                                             double mu, double dt,
                                             const struct reb_simulation* r);

(REBOUND 5.x, src/integrator_whfast.c; `r` is only read for variational
particles and a warning, and may be NULL). Timing it through ctypes would
measure Python's call overhead, so this script writes a small C harness,
compiles it with the system's C compiler against that library, and runs it:
each call drifts the same starting state (as the Rust bench does, so the
cost does not wander with the phase), N calls timed together, the best of R
repeats reported in ns per call (the best, not the mean: on a shared
machine the other repeats carry other processes' time slices). The particle struct's size is read from
rebound's own ctypes description, so the harness passes memory of the
right size. Before timing, the harness checks the solver on a circular
orbit (a quarter period must move x = (1, 0, 0) to (0, 1, 0)), so that a
changed signature is an error, not a wrong number.

Orbits (GM = 1): a = 1 with e = 0.05, 0.5, 0.9 and the hyperbola e = 1.5,
a = −1, all starting at true anomaly 1 with z = 0.1 r (the bench's
`state`); steps P/400, P/20 and 3P with P = 2π.
"""

import argparse
import ctypes
import os
import shutil
import subprocess
import sys
import tempfile

HARNESS = r"""
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

/* A particle as REBOUND lays it out: six doubles first, then the rest
   (padded to the size rebound's ctypes reports). */
struct particle {
    double x, y, z, vx, vy, vz;
    char rest[PARTICLE_SIZE - 6 * sizeof(double)];
};

void reb_integrator_whfast_kepler_solver(struct particle *p, double mu,
                                         double dt, const void *r);

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static struct particle state(double a, double e, double nu) {
    struct particle p;
    memset(&p, 0, sizeof p);
    double sl = a * (1.0 - e * e);
    double r = sl / (1.0 + e * cos(nu));
    double w = sqrt(1.0 / sl);
    p.x = r * cos(nu);
    p.y = r * sin(nu);
    p.z = 0.1 * r;
    p.vx = -w * sin(nu);
    p.vy = w * (e + cos(nu));
    p.vz = 0.0;
    return p;
}

int main(int argc, char **argv) {
    long calls = atol(argv[1]);
    int repeats = atoi(argv[2]);
    /* The signature check: a quarter of a circular orbit. */
    struct particle c;
    memset(&c, 0, sizeof c);
    c.x = 1.0;
    c.vy = 1.0;
    reb_integrator_whfast_kepler_solver(&c, 1.0, M_PI / 2.0, 0);
    if (fabs(c.x) > 1e-12 || fabs(c.y - 1.0) > 1e-12 || fabs(c.vx + 1.0) > 1e-12) {
        fprintf(stderr, "the solver did not move a circular orbit by a quarter turn "
                        "(x = %g, y = %g, vx = %g): its signature differs\n", c.x, c.y, c.vx);
        return 1;
    }
    const char *names[] = {"e0.05", "e0.5", "e0.9", "hyperbolic_e1.5"};
    double as[] = {1.0, 1.0, 1.0, -1.0};
    double es[] = {0.05, 0.5, 0.9, 1.5};
    const char *labels[] = {"P/400", "P/20", "3P"};
    double hs[] = {2.0 * M_PI / 400.0, 2.0 * M_PI / 20.0, 3.0 * 2.0 * M_PI};
    volatile double sink = 0.0;
    for (int o = 0; o < 4; o++) {
        struct particle p0 = state(as[o], es[o], 1.0);
        for (int k = 0; k < 3; k++) {
            double best = INFINITY;
            for (int rep = 0; rep < repeats; rep++) {
                double t0 = now();
                for (long i = 0; i < calls; i++) {
                    struct particle p = p0;
                    reb_integrator_whfast_kepler_solver(&p, 1.0, hs[k], 0);
                    sink += p.x;
                }
                double dt = (now() - t0) / calls * 1e9;
                if (dt < best) best = dt;
            }
            printf("rebound kepler_drift/%s/%s: %.1f ns/call\n", names[o], labels[k], best);
        }
    }
    return sink == 12345.678;
}
"""


def build(d, cc):
    """Compile the harness into directory `d` beside a copy of REBOUND's
    library (found through `rebound`), linked by `$ORIGIN`, so that `d`
    can be moved to another machine of the same architecture."""
    try:
        import rebound
    except ImportError:
        sys.exit("REBOUND is not installed: pip install rebound==5.2.2")
    lib = rebound.clibrebound._name
    size = ctypes.sizeof(rebound.Particle)
    print("REBOUND %s, %s, particle %d bytes" % (rebound.__version__, lib, size))
    shutil.copy(lib, os.path.join(d, "librebound.so"))
    src = os.path.join(d, "harness.c")
    with open(src, "w") as f:
        f.write("#include <stdlib.h>\n#define PARTICLE_SIZE %d\n" % size + HARNESS)
    cmd = [cc, "-O2", "-o", os.path.join(d, "harness"), src, "-L" + d, "-lrebound",
           "-Wl,-rpath,$ORIGIN", "-lm"]
    subprocess.run(cmd, check=True)


def run(d, calls, repeats):
    out = subprocess.run([os.path.join(d, "harness"), str(calls), str(repeats)],
                         check=False, capture_output=True, text=True)
    sys.stdout.write(out.stdout)
    sys.stderr.write(out.stderr)
    return out.returncode


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--calls", type=int, default=200000)
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--cc", default=os.environ.get("CC", "cc"))
    ap.add_argument("--keep", metavar="DIR",
                    help="build into DIR and keep it (harness and library), then run")
    ap.add_argument("--build-only", action="store_true", help="with --keep: do not run")
    ap.add_argument("--run-only", metavar="DIR", help="run a harness built with --keep")
    args = ap.parse_args()
    if args.run_only:
        sys.exit(run(args.run_only, args.calls, args.repeats))
    if args.keep:
        os.makedirs(args.keep, exist_ok=True)
        build(args.keep, args.cc)
        if not args.build_only:
            sys.exit(run(args.keep, args.calls, args.repeats))
        return
    with tempfile.TemporaryDirectory() as d:
        build(d, args.cc)
        sys.exit(run(d, args.calls, args.repeats))


if __name__ == "__main__":
    main()
