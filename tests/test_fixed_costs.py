"""A big file's process pays no fixed cost it does not need: syntax_lines compiles no
regex once its code is in the cache folder, and the banded solve loads LAPACK's
extension without running scipy's package set-up. Each runs in a fresh process, as the
`momentum` command does."""
from __future__ import annotations

import os
import subprocess
import sys

import pytest


def _python(code: str, cache) -> subprocess.CompletedProcess:
    env = dict(os.environ, MOMENTUM_CACHE_DIR=str(cache))
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=env, timeout=120)


NO_COMPILER = """
import re, momentum_cli.syntax as syntax
def refuse(*a, **k):
    raise AssertionError("re.compile called")
re.compile = refuse
import momentum_cli.syntax_lines as L
L.setup(syntax)
print(L._HEAD.match("impact 1 -> 2:").group())
"""


def test_syntax_lines_compiles_no_regex_once_its_code_is_kept(tmp_path):
    first = _python("import momentum_cli.syntax_lines", tmp_path)
    assert first.returncode == 0, first.stderr
    again = _python(NO_COMPILER, tmp_path)
    assert again.returncode == 0, again.stderr
    assert again.stdout.split() == ["impact"]


def test_the_banded_solve_loads_lapack_without_scipys_package(tmp_path):
    pytest.importorskip("scipy")
    got = _python("import sys\nfrom momentum_cli import banded\nm = banded._flapack()\n"
                  "print(m is not None and hasattr(m, 'dgbtrf'), 'scipy' in sys.modules)",
                  tmp_path)
    assert got.returncode == 0, got.stderr
    assert got.stdout.split() == ["True", "False"]
