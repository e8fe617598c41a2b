"""The house rules of the package's layering, as tests.

syntax -> scene -> compile -> analyse -> solve -> report -> cli: the syntax stage imports
nothing downstream; the physics core imports no report, cli, run, typer or rich; no two
modules import each other (directly or around a loop); and the plain and JSON `solve`
of a small problem never pays for numpy, scipy or rich.
"""
from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PKG = ROOT / "momentum_cli"
CORE = ("scene", "compile", "analyse", "solve", "sim", "elements", "laws", "joints")
UPPER = ("report", "cli", "run", "__main__")
DOWNSTREAM_OF_SYNTAX = CORE + UPPER


def _modules() -> dict[str, Path]:
    mods = {}
    for path in PKG.rglob("*.py"):
        rel = path.relative_to(ROOT).with_suffix("")
        name = ".".join(rel.parts)
        mods[name.removesuffix(".__init__")] = path
    return mods


def _imports(name: str, path: Path) -> list[tuple[str, int]]:
    """Every module `path` imports, at any depth (lazy imports count), as absolute names."""
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(a.name, node.lineno) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - node.level + 1]
                if node.module:
                    out.append((".".join(base + [node.module]), node.lineno))
                else:
                    out += [(".".join(base + [a.name]), node.lineno) for a in node.names]
            else:
                out.append((node.module or "", node.lineno))
    return out


def _stage(mod: str) -> str:
    parts = mod.split(".")
    return parts[1] if len(parts) > 1 else parts[0]


def _graph() -> tuple[dict[str, set[str]], list[str]]:
    """Module -> the package modules it imports; and the layering crossings found."""
    mods = _modules()
    graph: dict[str, set[str]] = {m: set() for m in mods}
    crossings = []
    for mod, path in sorted(mods.items()):
        st = _stage(mod)
        for name, line in _imports(mod, path):
            where = f"{path.relative_to(ROOT)}:{line}"
            top = name.split(".")[0]
            if top == "momentum_cli":
                target = name
                while target not in mods and "." in target:
                    target = target.rsplit(".", 1)[0]
                if target in mods and target != mod:
                    graph[mod].add(target)
                tst = _stage(name)
                if st == "syntax" and tst in DOWNSTREAM_OF_SYNTAX:
                    crossings.append(f"{where}: syntax imports {name}")
                if st in CORE and tst in UPPER:
                    crossings.append(f"{where}: core module {mod} imports {name}")
            elif top == "typer" and st != "cli":
                crossings.append(f"{where}: {mod} imports typer (only cli should)")
            elif top == "rich" and st not in ("report", "cli"):
                crossings.append(f"{where}: {mod} imports rich (only report/ and cli should)")
    return graph, crossings


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan, iterative)."""
    index, low, on, stack, out, counter = {}, {}, set(), [], [], [0]
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter[0]
        counter[0] += 1
        stack.append(root)
        on.add(root)
        while work:
            v, it = work[-1]
            for w in it:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(graph.get(w, ())))))
                    break
                if w in on:
                    low[v] = min(low[v], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[v])
                if low[v] == index[v]:
                    comp = []
                    while True:
                        w = stack.pop()
                        on.discard(w)
                        comp.append(w)
                        if w == v:
                            break
                    if len(comp) > 1:
                        out.append(sorted(comp))
    return out


def test_no_module_crosses_the_layering():
    _, crossings = _graph()
    assert crossings == []


def test_no_import_cycles():
    graph, _ = _graph()
    assert _cycles(graph) == []


def test_the_cycle_finder_finds_a_cycle():
    """The check above could pass vacuously; a made-up loop must be found."""
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert _cycles(graph) == [["a", "b", "c"]]


SMALL_SOLVE = r"""
import io, sys, contextlib
from momentum_cli.cli import main
path = sys.argv[1]
for flag in ("--plain", "--json"):
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        try:
            sys.argv = ["momentum", "solve", flag, path]
            main()
        except SystemExit as e:
            assert e.code in (0, None), e.code
    assert out.getvalue().strip(), flag
heavy = sorted(m for m in ("numpy", "scipy", "rich") if m in sys.modules)
assert not heavy, heavy
print("light")
"""


def test_small_plain_and_json_solve_never_import_numpy_scipy_or_rich():
    path = ROOT / "examples" / "seed_rod_drop_smooth.mom"
    r = subprocess.run([sys.executable, "-c", SMALL_SOLVE, str(path)], capture_output=True,
                       text=True, cwd=ROOT)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip().endswith("light")
