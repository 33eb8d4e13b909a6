"""`symlab.cloth.run` is the job `symlab cloth` runs (`jobs::cloth`): the
same scene gives the same summary (its wall-clock lines set aside) and the
same files, byte for byte; a run the command line was stopped in can be
resumed from Python to the bytes of a run never stopped; a refused
argument is named by its keyword where the command line names its flag."""

import signal
import subprocess
import time

import pytest

import symlab

TIMED = ("wall time", "per frame", "real time", "time split")


def without_times(summary, out_dir):
    return "\n".join(line.replace(str(out_dir), "DIR") for line in summary.splitlines()
                     if not line.strip().startswith(TIMED))


def cli(symlab_bin, root, *args):
    return subprocess.run([symlab_bin, "cloth", *args], capture_output=True, text=True,
                          cwd=root)


def files(d):
    return {p.relative_to(d).as_posix(): p.read_bytes() for p in sorted(d.rglob("*"))
            if p.is_file()}


# A spring scene with an explicit scheme, one through the sparse stage
# solver, and an inextensible one stepped by RATTLE (with checkpoints).
CASES = [
    ("scenes/corners.toml", ["--method", "stormer-verlet", "--frames", "12"],
     dict(method="stormer-verlet", frames=12)),
    ("scenes/corners.toml", ["--method", "gauss2", "--frames", "3", "--grid", "6x6"],
     dict(method="gauss2", frames=3, grid="6x6")),
    ("scenes/hammock-inextensible.toml", ["--grid", "8x8", "--frames", "6", "--render", "0,6",
                                          "--obj-every", "3"],
     dict(grid="8x8", frames=6, render=[0, 6], obj_every=3)),
]


@pytest.mark.parametrize("scene,flags,kwargs", CASES, ids=["explicit", "stage", "rattle"])
def test_same_summary_and_files(symlab_bin, root, tmp_path, scene, flags, kwargs):
    a, b = tmp_path / "cli", tmp_path / "py"
    done = cli(symlab_bin, root, scene, *flags, "--out", str(a))
    assert done.returncode == 0, done.stderr
    out = symlab.cloth.run(root / scene, out=b, **kwargs)
    assert without_times(out["summary"], b) == without_times(done.stdout, a)
    fa, fb = files(a), files(b)
    assert sorted(fa) == sorted(fb)
    assert "energy.csv" in fa and any(n.endswith(".obj") for n in fa)
    for name in fa:
        assert fa[name] == fb[name], name
    # The arrays are the frames the files hold.
    energy = (a / "energy.csv").read_text().splitlines()
    assert len(out["time"]) == len(energy) - 1 == out["positions"].shape[0]


def test_resume_from_python_a_run_the_cli_was_stopped_in(symlab_bin, root, tmp_path):
    scene = "scenes/hammock-inextensible.toml"
    flags = ["--grid", "10x10", "--frames", "240", "--render", "none", "--obj-every", "0"]
    ref, stopped = tmp_path / "ref", tmp_path / "stopped"
    done = cli(symlab_bin, root, scene, *flags, "--checkpoint-every", "off", "--out", str(ref))
    assert done.returncode == 0, done.stderr
    child = subprocess.Popen([symlab_bin, "cloth", scene, *flags, "--checkpoint-every", "0",
                              "--out", str(stopped)], cwd=root, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    ckpt = stopped / "checkpoint.symlab"
    start = time.monotonic()
    while not ckpt.exists():
        assert child.poll() is None, "the run ended before its first checkpoint"
        assert time.monotonic() - start < 60, "no checkpoint after 60 s"
        time.sleep(0.005)
    child.send_signal(signal.SIGTERM)
    stdout, stderr = child.communicate(timeout=120)
    assert child.returncode == 143, stderr
    assert "stopped by SIGTERM" in stdout
    out = symlab.cloth.resume(stopped)
    assert not ckpt.exists(), "a finished run leaves no checkpoint"
    assert (stopped / "energy.csv").read_bytes() == (ref / "energy.csv").read_bytes()
    assert without_times(out["summary"], stopped) == without_times(done.stdout, ref)
    # The arrays hold the frames this call ran, up to the last.
    assert 0 < len(out["time"]) <= 241 and out["time"][-1] == pytest.approx(4.0, rel=1e-9)


def test_refusals_name_the_keyword(symlab_bin, root, tmp_path):
    scene = root / "scenes" / "corners.toml"
    cases = [
        (dict(frames=2_000_000), ["--frames", "2000000"], "frames: ", "--frames: "),
        (dict(grid="abc"), ["--grid", "abc"], "grid: ", "--grid: "),
        (dict(render="5,abc"), ["--render", "5,abc"], "render: ", "--render: "),
        (dict(solver="newton"), ["--solver", "newton"], "solver=newton: ", "--solver newton: "),
        (dict(method="nope"), ["--method", "nope"], "method: ", "--method: "),
    ]
    for kwargs, flags, py_prefix, cli_prefix in cases:
        done = cli(symlab_bin, root, str(scene), *flags, "--out", str(tmp_path / "x"))
        assert done.returncode == 2
        assert done.stderr.startswith("error: " + cli_prefix), done.stderr
        with pytest.raises(ValueError) as e:
            symlab.cloth.run(scene, out=tmp_path / "y", **kwargs)
        message = str(e.value)
        assert message.startswith(py_prefix), message
        # The rest of the message is the command line's, word for word.
        assert message[len(py_prefix):] == done.stderr[len("error: " + cli_prefix):].strip()
