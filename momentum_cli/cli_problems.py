"""The command line for problem sets: `test`, `expect`, `variants`, `grade`; `--set`.

Registered on `cli.app` (imported at the end of cli.py). Flags and output only: the
work is done by problemset, snapshots, variants and grading.
"""
from __future__ import annotations

import sys
from typing import List, Optional

import typer

from .cli import _internal, _is_utf8, _print_diagnostics, _read_all, _safe_streams, app
from .diagnostics import ExitCode

SET_HELP = "Override a `let` constant: NAME=VALUE with its unit, e.g. --set v0='5 m/s' " \
           "(repeatable)."


def overrides_for(sets: Optional[List[str]], sources) -> tuple:
    """The `--set` pairs, checked: each parses as a value and names a `let` of every
    file given (else a usage error, exit 2, with "did you mean")."""
    from .overrides import OverrideError, check_names, split

    if not sets:
        return ()
    try:
        pairs = tuple(split(s) for s in sets)
        for src in sources:
            if src is not None:
                check_names(pairs, src.text, src.name)
    except OverrideError as exc:
        raise typer.BadParameter(str(exc)) from None
    return pairs


class _Progress:
    """A transient rich progress bar on stderr, shown once a run passes half a second."""

    def __init__(self, total: int, what: str):
        import time

        self.total, self.what, self.began, self.bar = total, what, time.perf_counter(), None

    def __call__(self, done: int) -> None:
        import time

        if self.bar is None:
            if time.perf_counter() - self.began < 0.5:
                return
            from rich.console import Console
            from rich.progress import Progress

            self.bar = Progress(console=Console(file=sys.stderr), transient=True)
            self.bar.start()
            self.task = self.bar.add_task(self.what, total=self.total)
        self.bar.update(self.task, completed=done)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()


@app.command()
def test(
    paths: List[str] = typer.Argument(None, metavar="[PATH...]",
                                      help="Problem files or folders (searched for *.mom "
                                           "recursively); default: the current folder."),
    pattern: Optional[str] = typer.Option(None, "-k", metavar="PATTERN",
                                          help="Only files whose path contains PATTERN (or "
                                               "matches it, with * ? [ ])."),
    junit: Optional[str] = typer.Option(None, "--junit-xml", metavar="FILE",
                                        help="Also write JUnit XML for CI systems."),
    json_flag: bool = typer.Option(False, "--json", help="Print one JSON document."),
    jsonl: bool = typer.Option(False, "--jsonl", help="Print one JSON object per file as "
                                                      "soon as it is done, then a summary."),
    simulate: bool = typer.Option(False, "--simulate",
                                  help="Also run `simulate` on simulate scenes (a `simulate` "
                                       "block and no `find`): they pass if they simulate."),
    sets: Optional[List[str]] = typer.Option(None, "--set", metavar="NAME=VALUE",
                                             help=SET_HELP),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="Only failures and the summary."),
) -> None:
    """Run problem files as tests of their `expect` lines.

    One line per file, `file:line: expected ... got ...` for each expectation not met,
    and a last line `N passed, M failed`. A file without `expect` lines passes if it
    solves; a file that fails with an error no `expect error CODE` line names fails.
    Exit code: 0 all passed, 1 a failure or error, 2 usage.

    \b
    Examples:
      momentum test examples/
      momentum test -k rod --junit-xml report.xml problems/
      momentum test --jsonl problems/ | jq .
    """
    import json
    import time

    from .problemset import (
        CollectError,
        Outcome,
        collect,
        is_simulation,
        judge,
        outcome_dict,
        outcome_line,
        simulate_outcome,
        summary,
        summary_line,
    )
    from .run import solve_many

    if json_flag and jsonl:
        raise typer.BadParameter("--json and --jsonl: choose one")
    try:
        files = collect(paths, pattern)
    except CollectError as exc:
        raise typer.BadParameter(str(exc)) from None
    if not files:
        raise typer.BadParameter("no problem files (*.mom) found" +
                                 (f" matching -k {pattern}" if pattern else ""))
    _safe_streams()
    out = sys.stdout
    items = list(_read_all(files))
    overrides = overrides_for(sets, [s for _, s, _ in items])
    sim = {name for name, s, r in items if s is not None and simulate and is_simulation(s.text)}
    solved = solve_many([s for n, s, r in items if r is None and n not in sim], False, 6,
                        "float", overrides)
    progress = _Progress(len(items), "testing") if sys.stderr.isatty() and not \
        (json_flag or jsonl) and len(items) > 1 else None
    outcomes: list[Outcome] = []
    began = time.perf_counter()
    try:
        for i, (name, source, res) in enumerate(items):
            start = time.perf_counter()
            if name in sim:
                try:
                    o = simulate_outcome(source, start)
                except Exception as exc:  # a bug in momentum: reported, the run goes on
                    o = judge(_internal(name, exc, False))
            else:
                if res is None:
                    res = next(solved)
                o = judge(res, time.perf_counter() - start)
            outcomes.append(o)
            if progress is not None:
                progress(i + 1)
            if jsonl:
                out.write(json.dumps(outcome_dict(o), allow_nan=False) + "\n")
                out.flush()
            elif not json_flag and not (quiet and o.outcome in ("passed", "skipped")):
                if progress is not None and progress.bar is not None:
                    progress.bar.console.print(outcome_line(o), markup=False, highlight=False)
                else:
                    out.write(outcome_line(o) + "\n")
    finally:
        if progress is not None:
            progress.close()
    counts = summary(outcomes)
    seconds = time.perf_counter() - began
    if junit:
        from .problemset import junit_xml

        try:
            with open(junit, "w", encoding="utf-8") as fh:
                fh.write(junit_xml(outcomes, counts))
        except OSError as exc:
            raise typer.BadParameter(f"--junit-xml {junit}: {exc.strerror or exc}") from None
    if json_flag:
        from . import __version__
        from .report.json_out import SCHEMA_VERSION, clean

        doc = {"schema_version": SCHEMA_VERSION, "momentum_version": __version__,
               "files": clean([outcome_dict(o) for o in outcomes]), "summary": counts}
        out.write(json.dumps(doc, allow_nan=False, indent=2, ensure_ascii=not _is_utf8(out))
                  + "\n")
    elif jsonl:
        out.write(json.dumps(dict(type="summary", **counts)) + "\n")
    else:
        out.write(summary_line(counts) + (f" in {seconds:.2f} s" if sys.stdout.isatty() else "")
                  + "\n")
    out.flush()
    if any(o.status == "internal" for o in outcomes):
        raise typer.Exit(int(ExitCode.INTERNAL))
    raise typer.Exit(int(ExitCode.PROBLEM if counts["failed"] or counts["error"] else
                         ExitCode.OK))


@app.command()
def expect(
    files: List[str] = typer.Argument(..., metavar="FILE", help="Problem files (.mom)."),
    write: bool = typer.Option(False, "--write", "-w",
                               help="Insert or refresh the `expect` lines in each file, in "
                                    "place (atomically), and show the diff."),
    digits: int = typer.Option(4, "--digits", "-p", min=1, max=15,
                               help="Significant figures of the expected values (the "
                                    "tolerance is half a unit in the last one)."),
    sets: Optional[List[str]] = typer.Option(None, "--set", metavar="NAME=VALUE",
                                             help=SET_HELP),
) -> None:
    """Print `expect` lines for the current answers; with --write, put them in the file.

    Without --write nothing is written. With it, only `expect` lines change (refreshed
    in place, an explicit `± TOL` or `within P %` kept; new lines after the last
    `expect` or `find` line); the file is replaced through a temporary file.

    \b
    Examples:
      momentum expect examples/seed_rod_drop_smooth.mom
      momentum expect --write problems/*.mom
    """
    from .run import solve_source
    from .snapshots import WriteError, answer_lines, diff, refreshed, write_atomic

    _safe_streams()
    out, err = sys.stdout, sys.stderr
    items = list(_read_all(files))
    overrides = overrides_for(sets, [s for _, s, _ in items])
    worst = ExitCode.OK
    for name, source, res in items:
        if res is None:
            try:
                res = solve_source(source, False, 6, "float", overrides)
            except Exception as exc:
                res = _internal(name, exc, False)
        if res.status in ("unreadable", "internal"):
            _print_diagnostics(res, err)
            worst = max(worst, ExitCode.USAGE if res.status == "unreadable" else
                        ExitCode.INTERNAL)
            continue
        if not write:
            if len(items) > 1:
                out.write(f"==> {name} <==\n")
            out.writelines(f"expect {body}\n" for body in answer_lines(res, digits).values())
            continue
        new = refreshed(source.text, res, digits)
        if new == source.text:
            out.write(f"{name}: expect lines up to date\n")
            continue
        try:
            with open(name, "rb") as fh:
                raw = fh.read()
            old = raw.decode("utf-8")
            if old.startswith("\ufeff"):
                new = "\ufeff" + new
            write_atomic(name, new)
        except (WriteError, OSError, UnicodeDecodeError) as exc:
            err.write(f"{name}: error: {exc}\n" if not isinstance(exc, WriteError) else
                      f"{exc}\n")
            worst = max(worst, ExitCode.USAGE)
            continue
        out.write(diff(name, old, new))
    out.flush()
    raise typer.Exit(int(worst))


@app.command()
def variants(
    key: str = typer.Argument(..., metavar="KEY.mom", help="The problem file to vary."),
    vary: List[str] = typer.Option(..., "--vary", metavar="NAME=LO..HI",
                                   help="A `let` to draw uniformly from LO..HI, in the let's "
                                        "own unit or one given: v0=4..6 or 'v0=4..6 m/s'."),
    count: int = typer.Option(..., "--count", "-n", min=1, max=100000,
                              help="How many variants."),
    seed: int = typer.Option(..., "--seed", help="The random seed: the same seed gives the "
                                                  "same files on every machine."),
    out_dir: str = typer.Option(..., "--out", metavar="DIR", help="Folder for the variants."),
    digits: int = typer.Option(3, "--digits", "-p", min=1, max=12,
                               help="Significant figures of the drawn values."),
    expect_digits: int = typer.Option(4, "--expect-digits", min=1, max=15,
                                      help="Significant figures of the `expect` lines."),
) -> None:
    """Write COUNT variants of a problem with `let` values drawn, each with its `expect`
    lines, and an index CSV (variant, values, answers).

    \b
    Examples:
      momentum variants key.mom --vary v0=4..6 --vary m=1..3 --count 40 --seed 7 --out hw3
    """
    from .variants import VariantError, make_variants

    try:
        rows, failed = make_variants(key, vary, count, seed, out_dir, digits, expect_digits)
    except VariantError as exc:
        raise typer.BadParameter(str(exc)) from None
    for line in failed:
        sys.stderr.write(line + "\n")
    sys.stdout.write(f"{len(rows)} variants of {key} in {out_dir} (index: "
                     f"{out_dir.rstrip('/')}/index.csv)\n")
    raise typer.Exit(int(ExitCode.PROBLEM if failed else ExitCode.OK))


@app.command()
def grade(
    key: List[str] = typer.Argument(..., metavar="KEY_PATH",
                                    help="The key: problem files or folders (*.mom)."),
    answers: str = typer.Option(..., "--answers", metavar="CSV",
                                help="student, problem, quantity, value, unit (unit "
                                     "optional: the key's)."),
    rel: Optional[float] = typer.Option(None, "--rel", metavar="PERCENT",
                                        help="Relative tolerance in percent for every "
                                             "quantity (default: each `expect` line's own; "
                                             "1 % for quantities without one)."),
    csv_out: Optional[str] = typer.Option(None, "--csv", metavar="FILE",
                                          help="Write one row per student and quantity."),
    json_flag: bool = typer.Option(False, "--json", help="Print one JSON document."),
    fmt: str = typer.Option("auto", "--format", "-f", help="auto | rich | plain."),
) -> None:
    """Grade students' answers against a key: right, rounding, sign error, unit slip,
    wrong or missing; a table per student and per problem, and class statistics.

    \b
    Examples:
      momentum grade examples/problem-set --answers examples/problem-set/answers.csv
      momentum grade hw3/ --answers submitted.csv --csv grades.csv
    """
    import json

    from .grading import GradeError, grade_all, render_plain, to_csv, to_json
    from .problemset import CollectError, collect

    try:
        files = collect(key)
    except CollectError as exc:
        raise typer.BadParameter(str(exc)) from None
    if not files:
        raise typer.BadParameter("no key files (*.mom) found")
    _safe_streams()
    try:
        result = grade_all(files, answers, rel)
    except GradeError as exc:
        raise typer.BadParameter(str(exc)) from None
    for line in result.key_errors:
        sys.stderr.write(line + "\n")
    if csv_out:
        with open(csv_out, "w", encoding="utf-8", newline="") as fh:
            fh.write(to_csv(result))
    if json_flag:
        from . import __version__

        sys.stdout.write(json.dumps(dict(to_json(result), momentum_version=__version__),
                                    indent=2, allow_nan=False) + "\n")
    elif fmt == "rich" or (fmt == "auto" and sys.stdout.isatty()):
        from .grading import render_rich

        render_rich(result)
    else:
        sys.stdout.write(render_plain(result))
    raise typer.Exit(int(ExitCode.PROBLEM if result.key_errors else ExitCode.OK))
