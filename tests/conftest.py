"""Shared test fixtures: the golden-file update flag and helpers to run the CLI."""
from __future__ import annotations

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"


def pytest_addoption(parser):
    parser.addoption("--update-golden", action="store_true", default=False,
                     help="rewrite examples/*.out and *.json from the current output")
    _fuzz_options(parser)
    parser.addoption("--gen-count", type=int, default=200,
                     help="scenes in the generated-problem test (tests/test_generated.py); "
                          "the large run: -m generated --gen-count 10000")
    parser.addoption("--gen-start", type=int, default=0,
                     help="first seed of the generated-problem test")


def pytest_configure(config):
    config.addinivalue_line("markers", "generated: the generated-problem property test "
                            "(random scenes against an independent dense solve)")
    config.addinivalue_line("markers", "fuzz: the large hostile-corpus run; selected only "
                                       "with -m fuzz (see tests/test_fuzz_corpus.py)")


@pytest.fixture
def gen_count(request) -> int:
    return request.config.getoption("--gen-count")


@pytest.fixture
def gen_start(request) -> int:
    return request.config.getoption("--gen-start")



# ---- the hostile corpus (tests/fuzz_corpus.py): a large run only with `-m fuzz` ----------
def _fuzz_options(parser):
    parser.addoption("--fuzz-count", type=int, default=100000,
                     help="files in the large fuzz corpus run (`-m fuzz`)")
    parser.addoption("--fuzz-seed", type=int, default=2026,
                     help="seed of the large fuzz corpus run")


def pytest_collection_modifyitems(config, items):
    if "fuzz" in (config.getoption("-m") or ""):
        return
    skip = pytest.mark.skip(reason="the large fuzz run needs -m fuzz")
    for item in items:
        if "fuzz" in item.keywords and item.get_closest_marker("fuzz") is not None:
            item.add_marker(skip)
# ---- end of the fuzz corpus options ------------------------------------------------------


@pytest.fixture
def update_golden(request) -> bool:
    return request.config.getoption("--update-golden")


@pytest.fixture(autouse=True)
def _fixed_env(monkeypatch, tmp_path_factory):
    """Goldens must not depend on the terminal: no colour, fixed width, UTF-8."""
    monkeypatch.setenv("NO_COLOR", "1")
    monkeypatch.setenv("COLUMNS", "100")
    monkeypatch.setenv("PYTHONIOENCODING", "utf-8")
    if "MOMENTUM_CACHE_DIR" not in os.environ:
        monkeypatch.setenv("MOMENTUM_CACHE_DIR", str(tmp_path_factory.getbasetemp() / "cache"))
