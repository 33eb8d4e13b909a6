"""symlab.cloth.run: positions per frame as NumPy arrays (the files it
writes beside them are compared with the command line's in
test_cloth_same_as_cli.py)."""

import numpy as np
import pytest

import symlab

SCENE = """
[cloth]
width = 1.0
height = 1.0
nx = 4
ny = 4
[material]
density = 0.1
stretch = 10.0
[pins]
edges = ["top"]
[simulation]
substeps = 20
frames = 3
method = "gauss2"
"""


def test_positions_per_frame(tmp_path):
    out = symlab.cloth.run(SCENE, "stormer-verlet", frames=2, out=tmp_path)
    pos = out["positions"]
    assert pos.dtype == np.float64 and pos.shape == (3, 16, 3)
    assert out["steps"] == 40
    assert len(out["energy"]) == 3
    # The top edge is pinned: those particles do not move.
    top = pos[:, -4:, :] if pos[0, -1, 1] > pos[0, 0, 1] else pos[:, :4, :]
    np.testing.assert_array_equal(top[0], top[-1])
    # The rest fall.
    assert not np.array_equal(pos[0], pos[-1])


def test_scene_file(root, tmp_path):
    out = symlab.cloth.run(root / "scenes" / "corners.toml", "stormer-verlet", frames=1,
                           out=tmp_path)
    assert (tmp_path / "energy.csv").exists() and "stormer-verlet" in out["summary"]
    assert out["positions"].shape[0] == 2


def test_a_blow_up_is_stopped_by_the_energy_guard(root, tmp_path):
    # 5 steps per frame is far beyond Störmer–Verlet's stable step on this
    # scene: the guard stops the run (as the command line's does), says
    # where, and keeps what was good.
    with pytest.raises(symlab.IntegrationError, match=r"blew up at step \d+ .*\|H − H₀\|/E_ref") as e:
        symlab.cloth.run(root / "scenes" / "corners.toml", "stormer-verlet", frames=1, substeps=5,
                         out=tmp_path)
    assert "output up to the last good frame, 0" in str(e.value)
    assert (tmp_path / "energy.csv").read_text().count("\n") == 2


def test_bad_method_and_scene(tmp_path):
    with pytest.raises(ValueError, match="method"):
        symlab.cloth.run(SCENE, "no-such-method", frames=1, out=tmp_path)
    with pytest.raises(symlab.ProblemError, match="scene"):
        symlab.cloth.run("/no/such/scene.toml", frames=1)
    with pytest.raises(ValueError, match="frames"):
        symlab.cloth.run(SCENE, frames=0)
