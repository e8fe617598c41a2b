"""The report's loops over many like items (a big scene's equation rows printed in one
loop, ...) against the general path they shortcut: the same plain text and JSON, byte for
byte, with each shortcut switched off, on every example and on chains and cradles of a
few sizes (above and below the sizes where the shortcuts switch on)."""
from __future__ import annotations

import pytest
from helpers import solved_scenes
from test_hard import cradle_text

from momentum_cli.bench import chain_text
from momentum_cli.report import json_out, model, text
from momentum_cli.report.model import build_report
from momentum_cli.scene import build
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse

# (module, name of the switch): each shortcut's switch, off for the general path
SWITCHES = [(model, "PRINTER_LOOP"), (model, "CHECK_CALLERS")]


def _scenes():
    yield from ((name, sol) for name, sol, _keeps in solved_scenes())
    for n in (3, 70, 250):
        for name, src in ((f"chain{n}.mom", chain_text(n)),
                          (f"cradle{n}.mom", cradle_text(n, "sequence"))):
            yield name, solve_scene(build(parse(Source(name, src))))


def _texts(name, sol) -> list:
    out = []
    for units in ("file", "si", "us"):
        for sig in (6, 4):
            out.append("\n".join(text.render_parts(
                build_report(name, sol, sig, units, lazy=True), sig)))
    out.append(text.render(build_report(name, sol, 6, "file", lazy=True), 6, detail="brief"))
    out.append(json_out.dumps(json_out.report_fields(build_report(name, sol, 6, "file",
                                                                  lazy=True))))
    return out


@pytest.mark.parametrize("switch", SWITCHES, ids=lambda s: s[1])
def test_each_shortcut_prints_what_the_general_path_prints(switch, monkeypatch):
    module, flag = switch
    checked = 0
    for name, sol in _scenes():
        fast = _texts(name, sol)
        monkeypatch.setattr(module, flag, False)
        slow = _texts(name, sol)
        monkeypatch.setattr(module, flag, True)
        assert fast == slow, name
        checked += 1
    assert checked > 60
