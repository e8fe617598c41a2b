"""`momentum bench sweep` (issue 13): the table's rows and formats; no timed asserts."""
from __future__ import annotations

import numpy as np

from conftest import EXAMPLES, ROOT
from momentum_cli.sweep import bench

BOUNCE = str(EXAMPLES / "sweep" / "bounce_height.mom")


def test_rows_for_a_file_with_lets_and_one_without():
    files = [BOUNCE, str(EXAMPLES / "seed_plastic_collision.mom")]
    rows = bench.run(files, count=20, loop=2, processes=0)
    a, b = rows
    assert a.parameters == "e, h, r" and a.variants == 20 and a.failed == 0
    assert a.batched > 0 and a.numpy_limit > 0 and a.scalar_loop > 0
    assert a.process_per_file is None
    assert "1 nonlinear" in a.note  # the rebound's energy equation is not in numpy's limit
    assert b.batched is None and b.numpy_limit > 0 and "nothing to vary" in b.note
    md = bench.markdown(rows)
    assert md.splitlines()[0].startswith("| problem | unknowns |")
    assert len(md.splitlines()) == 4


def test_inputs_are_lets_given_scalars_and_coefficients():
    path = EXAMPLES / "seed_rod_drop_smooth.mom"
    found = bench.inputs(path.read_text(encoding="utf-8"), str(path))
    assert sorted(found) == ["e[A]", "rod.angle@1", "rod.angle@2", "rod.y@1"]
    assert found["rod.y@1"] == (1.0, (0, 1, 0))
    assert abs(found["rod.angle@1"][0] - np.radians(30)) < 1e-15  # SI: radians
    assert found["e[A]"][0] == 1.0


def test_let_design_draws_within_five_percent_in_si():
    with open(BOUNCE, encoding="utf-8") as fh:
        cols = bench.let_design(fh.read(), BOUNCE, 1000)
    assert sorted(cols) == ["e", "h", "r"]
    assert np.all(np.abs(cols["r"] / 0.033 - 1) <= 0.05)  # 33 mm, in metres
    assert np.all(np.abs(cols["h"] / 1.5 - 1) <= 0.05)


def test_numpy_limit_solves_the_files_own_linear_blocks():
    """The stacked blocks are the solved file's: their solution is its values."""
    from momentum_cli.scene import build
    from momentum_cli.solve import solve_scene
    from momentum_cli.source import Source
    from momentum_cli.syntax import parse

    path = EXAMPLES / "seed_plastic_collision.mom"
    sol = solve_scene(build(parse(Source(str(path), path.read_text(encoding="utf-8")))))
    for b in sol.blocks:
        if b.method == "linear" and b.matrix is not None:
            x = np.linalg.solve(np.array(b.matrix), np.array(b.rhs))
            assert np.allclose(x, [sol.values[u] for u in b.unknowns], rtol=1e-9, atol=1e-12)
    rate, unknowns, _ = bench.numpy_limit(path.read_text(encoding="utf-8"), str(path), 100, 1)
    assert rate > 0 and unknowns == len(sol.system.unknowns)


def test_cli_markdown_names_the_versions():
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-m", "momentum_cli", "bench", "sweep", "--count", "5",
                          "--loop", "1", "--processes", "0", "--markdown", BOUNCE],
                         capture_output=True, text=True, cwd=ROOT, check=True).stdout
    assert "| problem |" in out and "numpy" in out and "lark" in out and "python" in out
