"""A one-shot `solve` without typer: start-up is most of a small problem's time.

In: the command line (argv without the program name). Out: the same run as typer's
`solve` (solve_cmd.run_solve, same defaults) ending in SystemExit, or False when the
line is anything but `solve FILE... [simple options]` with plain or JSON output.
"""
from __future__ import annotations

import errno
import os
import sys

# flags: option -> run_solve keyword; valued options: option -> (keyword, allowed values)
_FLAGS = {"--plain": "plain", "--json": "json_flag", "--jsonl": "jsonl", "-q": "quiet",
          "--quiet": "quiet", "--all": "solve_all", "--no-pager": "no_pager",
          "--strict": "strict"}
_VALUED = {"--digits": "digits", "-p": "digits", "--precision": "precision",
           "--units": "units", "--steps": "steps", "--format": "fmt", "-f": "fmt",
           "--color": "color"}
_FORMATS = ("auto", "plain", "json")  # the rich and document formats go through typer


def parse(argv: list[str]):
    """(files, options) for a command line the fast path takes, else None (any doubt)."""
    from . import solve_cmd as sc

    if not argv or argv[0] != "solve" or os.environ.get("_MOMENTUM_COMPLETE"):
        return None
    choices = {"precision": sc.Precision, "units": sc.Units, "steps": sc.Steps,
               "color": sc.Color, "fmt": sc.SolveFormat}
    files: list[str] = []
    opts: dict = {}
    args = argv[1:]
    i = 0
    while i < len(args):
        a = args[i]
        i += 1
        if a == "-" or not a.startswith("-"):
            files.append(a)
            continue
        name, eq, value = a.partition("=")
        if not eq and a in _FLAGS:
            opts[_FLAGS[a]] = True
            continue
        if name not in _VALUED or (eq and not name.startswith("--")):
            return None  # unknown, -h, --, -p4, -qp 4 ...: typer's business
        key = _VALUED[name]
        if not eq:
            if i >= len(args):
                return None
            value, i = args[i], i + 1
        if key in opts:
            return None  # repeated: let click decide
        if key == "digits":
            if not (value.isascii() and value.isdigit() and 1 <= int(value) <= 17):
                return None
            opts[key] = int(value)
        elif key == "fmt" and value not in _FORMATS:
            return None
        else:
            try:
                opts[key] = choices[key](value)
            except ValueError:
                return None
    if not files or files.count("-") > 1 or any(f != "-" and os.path.isdir(f) for f in files):
        return None  # usage errors and directories: typer's messages
    if "-" in files and (sys.stdin is None or sys.stdin.isatty()):
        return None
    return files, opts


def try_solve(argv: list[str]):
    """Run `solve` as typer would for a command line `parse` takes (SystemExit with the
    exit code); False, having done nothing, for any other."""
    from . import solve_cmd as sc

    parsed = parse(argv)
    if parsed is None:
        return False
    files, opts = parsed
    kw = dict(sc.SOLVE_DEFAULTS, **opts)
    if not kw["jsonl"]:
        try:
            mode = sc._pick_format(kw["fmt"], kw["json_flag"], kw["plain"])
        except sc.BadParameter:
            return False  # conflicting formats: typer's usage error
        if mode == "rich":
            return False
    try:
        sc.run_solve(files, **kw)
    except sc.BadParameter:
        return False  # raised before anything is read or printed
    except sc.Exit as done:
        sys.exit(done.exit_code)
    except OSError as exc:  # as click: a broken standard error ends quietly with 1
        if exc.errno != errno.EPIPE:
            raise
        sys.stdout, sys.stderr = _Pacified(sys.stdout), _Pacified(sys.stderr)
        sys.exit(1)
    sys.exit(0)


class _Pacified:
    """A stream whose flush ignores a broken pipe (click's PacifyFlushWrapper)."""

    def __init__(self, stream):
        self._stream = stream

    def flush(self):
        try:
            self._stream.flush()
        except OSError as exc:
            if exc.errno != errno.EPIPE:
                raise

    def __getattr__(self, name):
        return getattr(self._stream, name)
