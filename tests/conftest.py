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
    parser.addoption("--gen-count", type=int, default=200,
                     help="scenes in the generated-problem test (tests/test_generated.py); "
                          "the large run: -m generated --gen-count 10000")
    parser.addoption("--gen-start", type=int, default=0,
                     help="first seed of the generated-problem test")


def pytest_configure(config):
    config.addinivalue_line("markers", "generated: the generated-problem property test "
                            "(random scenes against an independent dense solve)")


@pytest.fixture
def gen_count(request) -> int:
    return request.config.getoption("--gen-count")


@pytest.fixture
def gen_start(request) -> int:
    return request.config.getoption("--gen-start")


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
