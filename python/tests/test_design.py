"""symlab.design: the design library's pipeline from Python, the same as
`symlab design FILE` (tables, claims, proofs), and its refusals as
exceptions naming the field."""

import pytest

import symlab

YOSHIDA = """name = "Yoshida triple jump, order 4"
form = "composition"
stages = 3
order = 4
range = 2.0
seed = 1
starts = 20
"""


def test_yoshida_from_text_is_exact_and_checks():
    d = symlab.design(YOSHIDA)
    assert d["unknowns"] == ["g1"]
    assert d["starts_run"] == 20
    best = d["designs"][0]
    assert best["proof"] == "exact"
    assert best["exact"] == "2/3 + cbrt(2/27) + cbrt(1/54)"
    assert abs(best["x"]["g1"] - 1.3512071919596578) < 1e-12
    assert "order = 4" in best["claims"]
    # The emitted table is a table like any other: symlab.check proves its
    # claims exactly.
    v = symlab.check(symlab.Table.from_toml(best["toml"]))
    assert v["order_separable"] == 4 and v["symplectic_separable"] is True
    assert [c["holds"] for c in v["claims"]] == [True, True, True]
    assert d["written"] == []


def test_certified_design_from_a_file_writes_what_the_cli_writes(root, tmp_path, symlab_bin):
    import subprocess

    path = root / "designs" / "mclachlan-sb3a.toml"
    d = symlab.design(path, starts=50, out=tmp_path / "py")
    best = d["designs"][0]
    assert best["proof"] == "certified"
    assert best["radius"].startswith("1/1")
    assert "order = 4 (certified)" in best["claims"]
    # Ranked by the objective.
    errors = [x["effective_error"] for x in d["designs"]]
    assert errors == sorted(errors)
    assert abs(best["x"]["a1"] - 0.40518861839525227722) < 1e-12
    # McLachlan's SB3A: x* = 2.9218392 over 5 force evaluations (the Rust
    # tests check the exact threshold against a floating-point scan).
    assert abs(best["stability_per_stage"] - 2.921839239 / 5) < 1e-9
    # The same files, byte for byte, as `symlab design` with the same seed
    # and starts (the report's timing line aside).
    cli = tmp_path / "cli"
    subprocess.run(
        [symlab_bin, "design", str(path), "--out", str(cli), "--starts", "50"],
        check=True,
        capture_output=True,
    )
    for written in d["written"]:
        name = written.rsplit("/", 1)[-1]
        if name.endswith(".toml"):
            assert (tmp_path / "py" / name).read_text() == (cli / name).read_text(), name
    assert best["toml"] == (tmp_path / "py" / best["name"]).read_text()


def test_seed_gives_the_same_solutions():
    a = symlab.design(YOSHIDA, seed=7, starts=30)
    b = symlab.design(YOSHIDA, seed=7, starts=30)
    assert [x["x"] for x in a["designs"]] == [x["x"] for x in b["designs"]]
    assert [x["hits"] for x in a["designs"]] == [x["hits"] for x in b["designs"]]


@pytest.mark.parametrize(
    "text, field",
    [
        (YOSHIDA.replace("stages = 3", "stages = 0"), "field stages"),
        (YOSHIDA.replace("order = 4", "order = 3"), "field order"),
        (YOSHIDA.replace('form = "composition"', 'form = "RK"'), "field form"),
        (YOSHIDA + "colour = 1\n", "colour"),
    ],
)
def test_bad_family_names_the_field(text, field):
    with pytest.raises(symlab.DesignError) as e:
        symlab.design(text)
    assert field in str(e.value)
    assert isinstance(e.value, ValueError)


def test_bad_arguments_name_the_argument(tmp_path):
    with pytest.raises(symlab.DesignError, match="field starts"):
        symlab.design(YOSHIDA, starts=0)
    with pytest.raises(TypeError, match="seed"):
        symlab.design(YOSHIDA, seed="1")
    with pytest.raises(ValueError, match="seed"):
        symlab.design(YOSHIDA, seed=-1)
    with pytest.raises(TypeError, match="family"):
        symlab.design(3)
    with pytest.raises(symlab.DesignError, match="missing.toml: cannot read the file"):
        symlab.design(tmp_path / "missing.toml")


def test_second_corrector_family_is_solved_exactly(root, tmp_path):
    """`form = "second-corrector"` from Python, as `symlab design` runs it:
    c² exact, the emitted table's claims hold, and seed/starts refused."""
    path = root / "designs" / "whckl-c17-corrector2.toml"
    d = symlab.design(path, out=tmp_path / "c2")
    assert d["form"] == "second-corrector"
    assert d["kernel"] == "whckl-c17"
    assert d["c_squared"] == "11/5760"
    assert abs(d["c_value"] - (11 / 5760) ** 0.5) < 1e-15
    best = d["designs"][0]
    assert best["proof"] == "exact"
    assert (tmp_path / "c2" / best["name"]).read_text() == best["toml"]
    v = symlab.check(symlab.Table.from_toml(best["toml"]))
    assert all(c["holds"] for c in v["claims"]), v["claims"]
    with pytest.raises(symlab.DesignError, match="starts"):
        symlab.design(path, starts=5)
    with pytest.raises(symlab.DesignError, match="seed"):
        symlab.design(path, seed=1)


def test_processed_kernel_with_its_processor(root):
    d = symlab.design(str(root / "designs" / "bcm-processed6-s11.toml"), starts=50)
    assert d["unknowns"] == ["g1", "g5"]
    best = d["designs"][0]
    assert abs(best["x"]["g1"] - 0.1705768865009222157) < 1e-9
    assert best["proof"] == "certified"
    p = best["processor"]
    assert p["claims"] == ["order = 6 (residual < 1e-40)"], p
    assert len(p["z"]) == 6
    # The processed table is checked by symlab.check as any table is.
    v = symlab.check(symlab.Table.from_toml(best["toml"]))
    assert all(c["holds"] for c in v["claims"]), v["claims"]
    # Other families have no processor.
    assert symlab.design(YOSHIDA)["designs"][0]["processor"] is None


def test_processed_drift_kick_kernel_with_its_processor(root):
    """A processed ABA kernel (effective order 4, three kicks): its
    processor is a drift–kick sequence, named u1, u2, v1, v2, and the
    processed table's claim holds in symlab.check."""
    d = symlab.design(str(root / "designs" / "processed-aba3-order4.toml"))
    best = d["designs"][0]
    assert best["proof"] == "certified"
    p = best["processor"]
    assert p["names"] == ["u1", "u2", "v1", "v2"]
    assert len(p["z"]) == 4
    assert p["claims"] == ["order = 4 (residual < 1e-40)"], p
    v = symlab.check(symlab.Table.from_toml(best["toml"]))
    assert all(c["holds"] for c in v["claims"]), v["claims"]


def test_processed_near_integrable_kernel(root):
    """Effective generalised order (8, 4) of a three-kick ABA kernel: one
    kernel condition (ABB), a six-kick processor, the (8, 4) claim held."""
    d = symlab.design(str(root / "designs" / "processed-near-aba3-8-4.toml"))
    assert d["conditions"] == ["ABB"]
    best = d["designs"][0]
    p = best["processor"]
    assert p["names"] == [f"u{i}" for i in range(1, 6)] + [f"v{i}" for i in range(1, 6)]
    assert p["claims"] == ["order = (8, 4) (residual < 1e-40)"], p
    v = symlab.check(symlab.Table.from_toml(best["toml"]))
    assert all(c["holds"] for c in v["claims"]), v["claims"]
