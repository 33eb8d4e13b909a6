import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture
def root():
    return ROOT


@pytest.fixture
def tables(root):
    return root / "tests" / "tables"


@pytest.fixture(scope="session")
def symlab_bin():
    """The command-line binary, built by `cargo test --workspace` (the test
    script runs that first); $SYMLAB_BIN overrides."""
    path = pathlib.Path(os.environ.get("SYMLAB_BIN", ROOT / "target" / "debug" / "symlab"))
    if not path.exists():
        pytest.fail(f"{path} is missing: build it with `cargo build` (python/test.sh does) or set SYMLAB_BIN")
    return str(path)
