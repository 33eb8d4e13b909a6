"""`symlab.check` returns the JSON object of `symlab check --json`, field
for field, for every kind of table: both are `tableau::verdict`'s. Only the
timings differ between two runs (`verify_ms`, `round_ms`, `ms`, and the
`time` row of a generated table's `report`); they are compared as present
and non-negative, then set aside."""

import json
import re
import subprocess

import pytest

import symlab

TIMINGS = {"verify_ms", "round_ms", "ms"}

# Generated tables of every family, with and without the generator syntax
# (`gauss(3)` always generates; `gauss5` has no catalogue file).
GENERATED = ["gauss(3)", "gauss5", "radau1a3", "radau2a4", "lobatto3a4", "lobatto3b3",
             "lobatto3c3", "lobatto3a3b3", "lobatto3a3b4"]


def without_timings(v, where="$"):
    if isinstance(v, dict):
        out = {}
        for k, x in v.items():
            if k in TIMINGS:
                assert isinstance(x, (int, float)) and x >= 0, f"{where}.{k} = {x!r}"
                continue
            out[k] = without_timings(x, f"{where}.{k}")
            if k == "report":
                out[k] = re.sub(r"(?m)^(  time {9}.*?)\d+ ms(.*?)\d+ ms$", r"\1# ms\2# ms", x)
        return out
    if isinstance(v, list):
        return [without_timings(x, f"{where}[{i}]") for i, x in enumerate(v)]
    return v


def cli_json(symlab_bin, *args):
    out = subprocess.run([symlab_bin, "check", "--json", *args], capture_output=True, text=True,
                         check=True).stdout
    return json.loads(out)


def assert_same(py, cli):
    py, cli = without_timings(py), without_timings(cli)
    assert sorted(py) == sorted(cli)
    for k in cli:
        assert py[k] == cli[k], k


def catalogue_ids():
    return [t["id"] for t in symlab.list_tables()]


def test_every_kind_is_covered(tables):
    ids = catalogue_ids()
    assert len(ids) >= 40 and any(t["processed"] for t in symlab.list_tables())
    assert len(list((tables / "roots").glob("*.toml"))) >= 4


@pytest.mark.parametrize("table_id", catalogue_ids())
def test_catalogue_table(symlab_bin, table_id):
    py = symlab.check(symlab.Table.builtin(table_id), claims="report")
    assert_same(py, cli_json(symlab_bin, "--builtin", table_id))


@pytest.mark.parametrize("generator", GENERATED)
def test_generated_table(symlab_bin, generator):
    py = symlab.check(symlab.Table.builtin(generator), claims="report")
    assert py["generator"]
    assert_same(py, cli_json(symlab_bin, "--builtin", generator))


def test_root_files(symlab_bin, tables):
    for path in sorted((tables / "roots").glob("*.toml")):
        py = symlab.check(symlab.Table.from_file(path), claims="report")
        assert py["entries"] == "algebraic"
        assert_same(py, cli_json(symlab_bin, str(path)))


def test_table_files_and_near_integrable(symlab_bin, tables):
    checked = 0
    for path in sorted(tables.glob("*.toml")):
        try:
            t = symlab.Table.from_file(path)
        except symlab.TableError:
            continue  # malformed on purpose: the refusal's parity is tested in test_check.py
        for flag in ([], ["--near-integrable"]):
            py = symlab.check(t, claims="report", near_integrable=bool(flag))
            assert_same(py, cli_json(symlab_bin, *flag, str(path)))
            checked += 1
    assert checked >= 18  # 9 well-formed files today, each with and without the flag
