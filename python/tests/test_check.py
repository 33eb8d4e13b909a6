"""symlab.Table and symlab.check: exact verdicts, and the refusals of
`symlab check` as Python exceptions naming the field."""

import json
import subprocess

import pytest

import symlab


def test_builtin_gauss2_exact_verdicts():
    v = symlab.check(symlab.Table.builtin("gauss2"))
    assert v["symplectic"] is True
    assert v["order"] == 4
    assert v["symmetric"] is True
    assert v["w_nonzero"] == []
    assert "W = BA + AᵀB − bbᵀ = 0" in v["report"]


def test_generated_table():
    t = symlab.Table.generate("gauss(8)")
    assert t.entries == "generated"
    v = symlab.check(t)
    assert v["symplectic"] is True
    assert v["order"] == 16
    assert v["generator"]


def test_fields_and_claims_hold():
    t = symlab.Table(name="implicit midpoint", a=[["1/2"]], b=["1"], claims=["symplectic", "order = 2"])
    v = symlab.check(t)
    assert [c["holds"] for c in v["claims"]] == [True, True]
    assert v["order"] == 2


def test_perturbed_gauss_refused_exactly():
    # a[0][1] off by 1e-17: every W entry is ~1e-17, below the 1e-14 a float
    # check tolerates, so a floating-point verifier calls it symplectic.
    t = symlab.Table(
        name="Gauss 2, perturbed by 1e-17",
        a=[["1/4", "1/4 - sqrt(3)/6 + 1/100000000000000000"], ["1/4 + sqrt(3)/6", "1/4"]],
        b=["1/2", "1/2"],
        claims=["symplectic"],
    )
    with pytest.raises(symlab.ClaimError, match=r"claim `symplectic` does not hold"):
        symlab.check(t)
    v = symlab.check(t, claims="report")
    assert v["symplectic"] is False
    w = v["w_nonzero"]
    assert w and all(abs(e["value_f64"]) < 1e-14 for e in w)
    assert all(e["value"] != "0" for e in w)  # exact strings
    assert v["claims"][0]["holds"] is False


def test_false_claim_names_claim_from_file(tables):
    text = (tables / "rk4.toml").read_text()
    t = symlab.Table.from_toml(text + '\nclaims = ["symplectic"]\n' if "claims" not in text else text.replace("claims = [", 'claims = ["symplectic", '), origin="rk4-claims.toml")
    with pytest.raises(symlab.ClaimError, match=r"rk4-claims.toml: claim `symplectic` does not hold"):
        symlab.check(t)


@pytest.mark.parametrize(
    "name, field",
    [("nonsquare.toml", "a"), ("short-b.toml", "b"), ("float.toml", None), ("unknown-function.toml", None)],
)
def test_malformed_tables_name_the_field_like_the_cli(tables, name, field):
    path = tables / name
    with pytest.raises(symlab.TableError) as e:
        symlab.check(symlab.Table.from_file(path))
    msg = str(e.value)
    assert msg.startswith(str(path))
    assert "field " in msg
    if field:
        assert f"field {field}" in msg


def test_message_equals_cli(tables, symlab_bin):
    path = tables / "nonsquare.toml"
    cli = subprocess.run([symlab_bin, "check", str(path)], capture_output=True, text=True)
    assert cli.returncode == 2
    with pytest.raises(symlab.TableError) as e:
        symlab.check(symlab.Table.from_file(path))
    assert cli.stderr.strip() == f"error: {e.value}"


def test_budget_exceeded_names_field():
    big = "1" * 20000
    with pytest.raises(symlab.BudgetError, match=r"field b\[0\].*tableau::budget::MAX_LITERAL_DIGITS"):
        symlab.Table(name="huge", a=[["0"]], b=[big])


def test_float_entry_refused():
    with pytest.raises(symlab.TableError, match=r"field b\[0\]"):
        symlab.Table(name="floaty", a=[["0"]], b=[1.0])


def test_bad_field_type():
    with pytest.raises(TypeError, match=r"field a\[0\]\[0\]"):
        symlab.Table(name="x", a=[[object()]], b=["1"])


def test_unknown_builtin_lists_alternatives():
    with pytest.raises(symlab.TableError, match="gauss8"):
        symlab.Table.builtin("no-such-table")


def test_report_equals_cli_output(symlab_bin):
    cli = subprocess.run([symlab_bin, "check", "--builtin", "forest-ruth"], capture_output=True, text=True, check=True)
    v = symlab.check(symlab.Table.builtin("forest-ruth"))
    assert v["report"] == cli.stdout
    js = json.loads(subprocess.run([symlab_bin, "check", "--builtin", "forest-ruth", "--json"],
                                   capture_output=True, text=True, check=True).stdout)
    for k, val in js.items():
        if k != "w_nonzero":
            assert v[k] == val, k


def test_list_tables():
    ids = {t["id"] for t in symlab.list_tables()}
    assert {"gauss2", "rk4", "leapfrog"} <= ids
