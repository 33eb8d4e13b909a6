"""The examples in the extension's docstrings (written in Rust, so
--doctest-modules does not collect them) run as written."""

import doctest

import pytest

import symlab
from symlab import _symlab

OBJECTS = [_symlab.Table, _symlab.check, _symlab.Problem, _symlab.integrate]


@pytest.mark.parametrize("obj", OBJECTS, ids=lambda o: o.__name__)
def test_docstring_examples(obj):
    tests = doctest.DocTestFinder(recurse=False).find(obj, obj.__name__, globs={"symlab": symlab})
    examples = sum(len(t.examples) for t in tests)
    assert examples > 0, f"{obj.__name__} has no example"
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    for t in tests:
        runner.run(t)
    assert runner.summarize(verbose=False).failed == 0


def test_stubs_cover_the_api(root):
    stub = (root / "python" / "symlab" / "__init__.pyi").read_text()
    for name in symlab.__all__:
        if name not in ("cloth", "__version__"):
            assert name in stub, name
