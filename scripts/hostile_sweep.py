#!/usr/bin/env python3
"""A hostile sweep of the `symlab` command line: hundreds of bad, huge and
borderline inputs to `check`, `compare`, `paper` and `cloth`, each run with a
time limit and a memory limit, sorted into classes. Besides flags, scene and
table files it covers the newer surfaces: every collocation family with
s <= 8 written as root(...) files (c given or not, exact and perturbed;
written by `cargo run --release -p tableau --example write_root_files`) and
random mutations of them and of `generate = ...` files through `check`,
`check --json` and `compare --table`; hostile `--problem-file`s; `logh:ID` and
`adaptive:ID` methods on every built-in problem; the energy schemes and the
midpoint family on every scene with both `--solver`s and hostile
`--tolerance`s, and `cloth --stability` with them.

    python3 scripts/hostile_sweep.py [--bin target/release/symlab] [--timeout 20] [--mem-gb 4]

Classes (per subcommand):
  ok        exit 0 (and no NaN printed where a number was due)
  error     exit 1 or 2 with a message on stderr that starts with "error"
  panic     a Rust panic (exit 101 or "panicked" on stderr)
  abort     killed by a signal (out of memory, stack overflow, ...)
  hang      ran past the time limit
  silent    exit 0 but "NaN" or "inf" printed in the summary, or an error
            exit without a message
The sweep is clean when only `ok` and `error` occur. Exit status: 0 when
clean, 1 otherwise; the failing cases are listed with their command lines.
"""

import argparse
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
from collections import Counter, defaultdict

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

EXTREME_FLOATS = ["0", "-0", "-1", "1e-300", "-1e-300", "1e300", "1e308", "1.7976931348623157e308",
                  "5e-324", "nan", "NaN", "inf", "-inf", "abc", "", "1e", "0x10", "1_000", " 1"]
EXTREME_INTS = ["0", "-1", "1", "18446744073709551615", "18446744073709551616", "9999999999999999999999",
                "4294967296", "abc", "", "1.5", "-0", "1e3"]


def run(binary, args, timeout, mem_bytes, cwd):
    cmd = ["prlimit", f"--as={mem_bytes}", "--", binary] + args
    try:
        p = subprocess.run(cmd, cwd=cwd, capture_output=True, timeout=timeout, text=True, errors="replace")
    except subprocess.TimeoutExpired:
        return "hang", "", ""
    out, err = p.stdout, p.stderr
    if p.returncode == 101 or "panicked" in err:
        return "panic", out, err
    if p.returncode < 0 or "memory allocation" in err:
        return "abort", out, err
    if p.returncode == 0:
        # A number that should have been one: NaN or inf in the printed
        # summary (a message quoting the non-finite state that stopped a
        # run, "z[0] = -inf", is not one).
        lines = [l for l in out.splitlines()
                 if not re.search(r"diverged|stopped|blew up|blown up|not finite|no NaN", l)]
        if any(re.search(r"(^|[\s(,])(NaN|nan|-?inf)([\s),]|$)", l) for l in lines):
            return "silent", out, err
        return "ok", out, err
    if p.returncode in (1, 2) and err.strip().startswith("error"):
        return "error", out, err
    if p.returncode in (1, 2) and err.strip():
        # clap's usage errors start with "error:" too; anything else is odd
        return "error" if "error" in err.lower() else "silent", out, err
    return "silent", out, err


def table_files(tmp, rng):
    """Bad, huge and borderline table files."""
    files = []

    def put(name, text):
        path = os.path.join(tmp, name)
        with open(path, "w") as f:
            f.write(text)
        files.append(path)

    put("empty.toml", "")
    put("garbage.toml", "\x00\x01\x02 not toml [[[")
    put("float.toml", 'a = [[0.5]]\nb = [1.0]\n')
    put("ragged.toml", 'a = [["0", "0"], ["1"]]\nb = ["1/2", "1/2"]\n')
    put("bhat.toml", 'a = [["0","0"],["1","0"]]\nb = ["1/2","1/2"]\na_hat = [["0","0","0"],["1","0","0"],["0","1","0"]]\nb_hat = ["1/2","1/2"]\n')
    put("div0.toml", 'a = [["1/0"]]\nb = ["1"]\n')
    put("neg-sqrt.toml", 'a = [["sqrt(-1)"]]\nb = ["1"]\n')
    put("nested.toml", 'a = [["sqrt(1 + sqrt(2))"]]\nb = ["1"]\n')
    put("deep.toml", 'a = [["' + "(" * 5000 + "1" + ")" * 5000 + '"]]\nb = ["1"]\n')
    put("bigint.toml", 'a = [["0"]]\nb = ["' + "9" * 1000000 + '"]\n')
    put("bigpow.toml", 'a = [["2^1000000000"]]\nb = ["1"]\n')
    put("bigexp.toml", 'a = [["1e-1000000000"]]\nb = ["1"]\n')
    put("sqrt-primes.toml", "a = [" + ",".join(
        "[" + ",".join(f'"sqrt({p})"' if j < i else '"0"' for j in range(6)) + "]"
        for i, p in enumerate([2, 3, 5, 7, 11, 13])) + ']\nb = ["1/6","1/6","1/6","1/6","1/6","1/6"]\n')
    put("cbrt-sum.toml", 'a = [["0","0"],["1/(cbrt(2)+cbrt(3)+cbrt(5)+cbrt(7)+cbrt(11))","0"]]\nb = ["1/2","1/2"]\n')
    put("sqrt8.toml", 'a = [["0","0"],["' + "+".join(f"sqrt({p})" for p in [2, 3, 5, 7, 11, 13, 17, 19]) + '","0"]]\nb = ["1/2","1/2"]\n')
    for s in (20, 50, 100):
        rows = [[f'"{1}/{(i + j + 2)}"' for j in range(s)] for i in range(s)]
        put(f"dense{s}.toml", "a = [" + ",".join("[" + ",".join(r) + "]" for r in rows) + "]\nb = [" + ",".join(f'"1/{s}"' for _ in range(s)) + "]\n")
    put("compose10k.toml", "compose = [" + ",".join('"1/10000"' for _ in range(10000)) + "]\n")
    put("bigprime.toml", 'a = [["sqrt(1000000000000000003)"]]\nb = ["1"]\n')
    put("claims-bad.toml", 'claims = ["order = 99", "symplectic", "bogus"]\na = [["0"]]\nb = ["1"]\n')
    put("let-cycle.toml", 'let = { x = "y", y = "x" }\na = [["x"]]\nb = ["1"]\n')
    # Random mutations of catalogue tables.
    cat = os.path.join(ROOT, "tableau", "catalogue")
    sources = sorted(f for f in os.listdir(cat) if f.endswith(".toml"))
    junk = ["1e308", "-1e-308", "9" * 400, "sqrt(2)^999", "1/(1-1)", "(", "cbrt(-8)", "2^-99999", "x/0",
            "sqrt(" * 50 + "2" + ")" * 50, "0", "1/3"]
    for k in range(60):
        src = rng.choice(sources)
        text = open(os.path.join(cat, src)).read()
        quoted = list(re.finditer(r'"([^"\n]*)"', text))
        if quoted and rng.random() < 0.8:
            m = rng.choice(quoted)
            text = text[:m.start(1)] + rng.choice(junk) + text[m.end(1):]
        else:
            lines = text.splitlines()
            if lines:
                del lines[rng.randrange(len(lines))]
            text = "\n".join(lines)
        put(f"mut{k}-{src}", text)
    return files


def scene_files(tmp, rng):
    files = []
    scenes = os.path.join(ROOT, "scenes")
    sources = sorted(f for f in os.listdir(scenes) if f.endswith(".toml"))
    values = ["0", "-1", "1e308", "1e-300", "-1e308", "1e-12", "100000000", "3.5", "nan", "inf",
              '"text"', "true", "[]", "18446744073709551615"]
    for k in range(60):
        src = rng.choice(sources)
        text = open(os.path.join(scenes, src)).read()
        nums = list(re.finditer(r"(?<=[=\[,\s])-?\d[\d._eE+-]*", text))
        if nums and rng.random() < 0.85:
            m = rng.choice(nums)
            text = text[:m.start()] + rng.choice(values) + text[m.end():]
        else:
            lines = [l for l in text.splitlines()]
            if lines:
                del lines[rng.randrange(len(lines))]
            text = "\n".join(lines)
        path = os.path.join(tmp, f"scene{k}-{src}")
        with open(path, "w") as f:
            f.write(text)
        files.append(path)
    return files


def root_and_generated_files(tmp, rng):
    """Every collocation family with s <= 8 as root(...) files (c given or
    not, exact and perturbed by 1e-40; written by tableau's example
    write_root_files), generate = files, and random mutations of both."""
    d = os.path.join(tmp, "roots")
    subprocess.run(["cargo", "run", "--release", "-q", "-p", "tableau", "--example",
                    "write_root_files", "--", d], cwd=ROOT, check=True)
    colloc = sorted(os.path.join(d, f) for f in os.listdir(d))
    files = []

    def put(name, text):
        path = os.path.join(tmp, name)
        with open(path, "w") as f:
            f.write(text)
        files.append(path)

    for g in ["gauss(4)", "gauss(16)", "gauss(17)", "gauss(0)", "radau2a(-1)", "lobatto3a3b(8)",
              "lobatto3c(1)", "nope(3)", "gauss(99999999999999999999)", "gauss(4", ""]:
        put(f"gen-{len(files)}.toml", f'generate = "{g}"\n')
    put("gen-claims.toml", 'generate = "gauss(3)"\nclaims = ["order = 7", "symplectic", "bogus"]\n')
    put("gen-extra.toml", 'generate = "gauss(3)"\na = [["1"]]\n')
    put("root-nested-pow.toml", 'name = "p"\nlet = { r = "root(((x^2)^100)^100 - 2, 0, 2)" }\na = [["r"]]\nb = ["1"]\n')
    put("root-huge-bounds.toml", 'name = "p"\nlet = { r = "root(x^2 - 2, -10^999, 10^999)" }\na = [["r"]]\nb = ["1"]\n')
    put("root-close.toml", 'name = "p"\nlet = { r = "root(x^2 - 2, 1, 2)", s = "root(x^2 - 2 - 1/10^300, 1, 2)" }\na = [["r - s"]]\nb = ["1"]\n')
    put("root-ten.toml", 'name = "p"\nlet = { ' + ", ".join(f'r{k} = "root(x^2 - {p}, 0, {p})"' for k, p in enumerate([2, 3, 5, 7, 11, 13, 17, 19, 23, 29])) +
        ' }\na = [["' + " + ".join(f"r{k}" for k in range(10)) + '"]]\nb = ["1"]\n')
    put("root-expand.toml", 'name = "p"\nlet = { ' + ", ".join(f'r{k} = "root(x^3 - {k + 2}, 0, 3)"' for k in range(6)) +
        ' }\na = [["(' + " + ".join(f"r{k}" for k in range(6)) + ')^64"]]\nb = ["1"]\n')
    junk = ["10^999", "1/10^999", "x^64", "(x^64)^64", "0", "-1", "1/0", "c0^64", "(c0+c1)^64",
            "root(x^2 - 2, 0, 2)", "sqrt(2)", "9" * 900, ")", "c9", "x"]
    sources = [f for f in colloc if "perturbed" not in f]
    for k in range(80):
        text = open(rng.choice(sources)).read()
        quoted = list(re.finditer(r'"([^"\n]*)"', text))
        r = rng.random()
        if quoted and r < 0.6:
            m = rng.choice(quoted)
            text = text[:m.start(1)] + rng.choice(junk) + text[m.end(1):]
        elif quoted and r < 0.8:
            m = rng.choice(quoted)
            inner = m.group(1)
            if inner:
                i = rng.randrange(len(inner))
                inner = inner[:i] + rng.choice(["^64", "*10^999", "", "(", "-", "9" * 50]) + inner[i + 1:]
            text = text[:m.start(1)] + inner + text[m.end(1):]
        else:
            lines = text.splitlines()
            if lines:
                del lines[rng.randrange(len(lines))]
            text = "\n".join(lines)
        put(f"rootmut{k}.toml", text)
    return colloc, files


def problem_files(tmp, rng):
    """Hostile linear problem files for compare --problem-file."""
    base = {"m": "[[2.0, 0.0], [0.0, 1.0]]", "g": "[[0.0, 0.5], [-0.5, 0.0]]",
            "k": "[[3.0, -1.0], [-1.0, 2.0]]", "f": "[0.1, 0.0]", "q0": "[1.0, 0.0]",
            "p0": "[0.0, 0.0]", "t_end": "10.0", "h_min": "1e-3", "h_max": "0.5"}
    values = ["0", "-1", "1e308", "-1e308", "1e-300", "nan", "inf", '"x"', "[]", "[[]]", "[1.0]",
              "[[1.0, 2.0], [3.0]]", "[[1e308, 0.0], [0.0, 1e308]]", "[[0.0, 0.0], [0.0, 0.0]]",
              "[[-1.0, 0.0], [0.0, 1.0]]", "[[1.0, 2.0], [3.0, 4.0]]", "true", "1e-320"]
    files = []
    for k in range(70):
        fields = dict(base)
        r = rng.random()
        key = rng.choice(sorted(base))
        if r < 0.8:
            fields[key] = rng.choice(values)
        else:
            del fields[key]
        if rng.random() < 0.15:
            fields["h_min"], fields["h_max"] = "0.5", "1e-3"
        path = os.path.join(tmp, f"problem{k}.toml")
        with open(path, "w") as f:
            f.write("".join(f"{a} = {b}\n" for a, b in fields.items()))
        files.append(path)
    return files


def cases(tmp, rng):
    out = defaultdict(list)
    tables = table_files(tmp, rng)
    for t in tables + ["/dev/zero", "/nonexistent.toml", tmp]:
        out["check"].append(["check", t])
    out["check"] += [["check", "--builtin", "nope"], ["check", "--builtin", ""], ["check"]]
    o = os.path.join(tmp, "out")
    q = ["--quick", "--out", o]
    for flag in ["--t-end", "--h-min", "--h-max", "--target"]:
        for v in EXTREME_FLOATS:
            out["compare"].append(["compare", "--problem", rng.choice(["kepler", "oscillator", "gyroscopic", "fpu"]), flag, v] + q)
    for flag in ["--points", "--repeats"]:
        for v in EXTREME_INTS:
            out["compare"].append(["compare", "--problem", "pendulum", flag, v] + q)
    for v in EXTREME_INTS:
        out["compare"].append(["compare", "--long", "--problem", "oscillator", "--steps", v] + q)
    for p in ["oscillator", "gyroscopic", "kepler"]:
        out["compare"].append(["compare", "--problem", p, "--t-end", "1e15", "--h-min", "1e14", "--h-max", "1e15", "--out", o])
    out["compare"] += [
        ["compare"] + q, ["compare", "--problem", "kepler", "--methods", ",,"] + q,
        ["compare", "--problem", "kepler", "--methods", "nope"] + q,
        ["compare", "--from", "/dev/zero"], ["compare", "--from", "/nonexistent.csv"],
        ["compare", "--peer-study", "--quick", "--methods", "rk4"],
    ]
    for t in rng.sample(tables, 25):
        out["compare"].append(["compare", "--problem", "kepler", "--table", t] + q)
    for v in EXTREME_FLOATS:
        out["paper"].append(["paper", "--cloth-frames", "0", "--out", o, rng.choice(["--k", "--q0", "--p0"]), v])
        out["paper"].append(["paper", "--cloth-frames", "0", "--out", o, "--h", v])
    for v in EXTREME_INTS:
        out["paper"].append(["paper", "--cloth-frames", "0", "--out", o, "--steps", v])
    out["paper"] += [["paper", "--cloth-frames", "0", "--out", o, "--h", "10"],
                     ["paper", "--cloth-frames", "0", "--out", o, "--h", "1e-300"],
                     ["paper", "--cloth-frames", "0", "--out", "/dev/null"]]
    short = ["--frames", "2", "--render", "none", "--out", o]
    for s in scene_files(tmp, rng):
        out["cloth"].append(["cloth", s] + short)
    for flag, vals in [("--frames", EXTREME_INTS), ("--substeps", EXTREME_INTS), ("--dt", EXTREME_FLOATS),
                       ("--grid", ["0x0", "1x1", "2x2", "100000000x2", "2048x2048", "-3x3", "axb", "3", "3x3x3"]),
                       ("--obj-every", EXTREME_INTS), ("--render", ["0,99999", "-1", "a", ""])]:
        for v in vals:
            args = ["cloth", os.path.join(ROOT, "scenes", "paper.toml"), flag, v]
            args += [a for a in short if not (flag == "--frames" and a in ("--frames", "2"))] if flag != "--render" else ["--frames", "2", "--out", o]
            out["cloth"].append(args)
    for v in ["1e-300", "0", "-1", "nan", "1e300"]:
        out["cloth"].append(["cloth", os.path.join(ROOT, "scenes", "paper.toml"), "--stability", "--duration", v, "--methods", "leapfrog", "--out", o])
        out["cloth"].append(["cloth", os.path.join(ROOT, "scenes", "paper.toml"), "--stability", "--tolerance", v, "--methods", "leapfrog", "--duration", "0.05", "--out", o])
    out["cloth"].append(["cloth", os.path.join(ROOT, "scenes", "paper.toml"), "--method", "nope"] + short)
    out["cloth"].append(["cloth", "/dev/zero"] + short)

    # The newer surfaces.
    colloc, rootmuts = root_and_generated_files(tmp, rng)
    for t in colloc + rootmuts:
        out["check"].append(["check", t])
    for t in rng.sample(colloc, 30) + rootmuts:
        out["check"].append(["check", "--json", t])
    for t in rng.sample(colloc, 30) + rng.sample(rootmuts, 40):
        out["compare"].append(["compare", "--problem", rng.choice(["kepler", "oscillator"]), "--table", t] + q)
    for pf in problem_files(tmp, rng):
        out["compare"].append(["compare", "--problem-file", pf] + q)
    problems = ["oscillator", "pendulum", "kepler", "kepler-hard", "henon-heiles", "fpu", "outer-solar", "gyroscopic"]
    for p in problems:
        for m in ["logh:kahan-li8", "adaptive:kahan-li8", "logh:leapfrog", "adaptive:rk4", "logh:nope", "adaptive:"]:
            out["compare"].append(["compare", "--problem", p, "--methods", m] + q)
            flag = rng.choice(["--t-end", "--h-min", "--h-max", "--points"])
            v = rng.choice(EXTREME_FLOATS if flag != "--points" else EXTREME_INTS)
            out["compare"].append(["compare", "--problem", p, "--methods", m, flag, v] + q)
    scenes_dir = os.path.join(ROOT, "scenes")
    for sc in sorted(f for f in os.listdir(scenes_dir) if f.endswith(".toml") and "128" not in f):
        for m in ["avf", "discrete-gradient", "midpoint", "gauss2"]:
            for solver in ["newton", "local-global"]:
                args = ["cloth", os.path.join(scenes_dir, sc), "--method", m, "--solver", solver, "--grid", "6x6"] + short
                out["cloth"].append(args)
        for v in ["0", "1e-300", "1e-16", "2", "nan", "-1", "inf"]:
            out["cloth"].append(["cloth", os.path.join(scenes_dir, sc), "--method", "avf", "--grid", "6x6", "--tolerance", v] + short)
        out["cloth"].append(["cloth", os.path.join(scenes_dir, sc), "--stability", "--methods", "avf,midpoint",
                             "--solver", rng.choice(["newton", "local-global"]), "--grid", "5x5", "--duration", "0.05", "--out", o])
    for s in scene_files(tmp, rng)[:30]:
        out["cloth"].append(["cloth", s, "--method", rng.choice(["avf", "discrete-gradient", "midpoint"]), "--grid", "6x6"] + short)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default=os.path.join(ROOT, "target", "release", "symlab"))
    ap.add_argument("--timeout", type=float, default=20.0)
    ap.add_argument("--mem-gb", type=float, default=4.0)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--only", help="one subcommand")
    a = ap.parse_args()
    rng = random.Random(a.seed)
    tmp = tempfile.mkdtemp(prefix="symlab-hostile-")
    counts = defaultdict(Counter)
    bad = []
    try:
        all_cases = cases(tmp, rng)
        for sub, lst in all_cases.items():
            if a.only and sub != a.only:
                continue
            for args in lst:
                cls, out, err = run(a.bin, args, a.timeout, int(a.mem_gb * 2**30), ROOT)
                counts[sub][cls] += 1
                if cls not in ("ok", "error"):
                    last = (err.strip().splitlines() or [""])[-1][:200]
                    bad.append((sub, cls, " ".join(x if len(x) < 80 else x[:77] + "..." for x in args), last))
                print(f"{sub:8} {cls:7} {' '.join(x[:60] for x in args)[:150]}", flush=True)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print("\nclass counts per subcommand:")
    classes = ["ok", "error", "panic", "abort", "hang", "silent"]
    print(f"{'':10}" + "".join(f"{c:>8}" for c in classes) + f"{'total':>8}")
    for sub, c in counts.items():
        print(f"{sub:10}" + "".join(f"{c[k]:>8}" for k in classes) + f"{sum(c.values()):>8}")
    if bad:
        print("\nnot clean:")
        for sub, cls, cmd, last in bad:
            print(f"  [{cls}] {cmd}\n      {last}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
