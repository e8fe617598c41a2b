"""`momentum test`: a folder of problem files run as tests of their `expect` lines.

In: paths (files, or folders searched for *.mom recursively), options. Out: one
`Outcome` per file (passed / failed / error / skipped, with `file:line` failure lines),
a summary line, and the JSON, JSON Lines and JUnit XML forms of the same outcomes.
A file without `expect` lines passes if it solves; an error that no `expect error`
line names fails it.
"""
from __future__ import annotations

import fnmatch
import os
import re

from .records import field, record

_SIMULATE = re.compile(r"^[ \t]*simulate[ \t]+from\b", re.M)
_FIND = re.compile(r"^[ \t]*find\b", re.M)


class CollectError(ValueError):
    """A path that does not exist or holds no problem file (a usage error)."""


def collect(paths, pattern: str | None = None) -> list[str]:
    """Every *.mom under the paths (folders recursively, hidden folders skipped), each
    once, folders in sorted order; `pattern` keeps the paths that contain it (or match
    it, with * ? [ ])."""
    out: list[str] = []
    for p in paths or ["."]:
        if os.path.isdir(p):
            found = []
            for root, dirs, files in os.walk(p):
                dirs[:] = sorted(d for d in dirs if not d.startswith(".") and d != "__pycache__")
                found += [os.path.join(root, f) for f in files if f.endswith(".mom")]
            out += sorted(found, key=lambda f: f.replace(os.sep, "\0"))
        elif os.path.exists(p):
            out.append(p)
        else:
            raise CollectError(f"{p}: no such file or folder")
    seen = set()
    out = [f for f in out if not (os.path.normpath(f) in seen or seen.add(os.path.normpath(f)))]
    if pattern:
        glob = any(c in pattern for c in "*?[")
        out = [f for f in out if ((fnmatch.fnmatch(f, pattern) or fnmatch.fnmatch(
            os.path.basename(f), pattern)) if glob else pattern in f)]
    return out


def is_simulation(text: str) -> bool:
    """A simulate scene: a `simulate` block and no `find` line."""
    return bool(_SIMULATE.search(text)) and not _FIND.search(text)


@record
class Outcome:
    file: str
    outcome: str  # passed | failed | error | skipped
    status: str  # the solve's: solved | error | unreadable | internal
    failures: list[str] = field(default_factory=list)  # `file:line: expected ... got ...`
    expectations: list[dict] = field(default_factory=list)
    diagnostics: list = field(default_factory=list)
    note: str = ""
    seconds: float = 0.0


def judge(res, seconds: float = 0.0) -> Outcome:
    """The outcome of one solved (or failed) file against its `expect` lines."""
    from .report.model import expectation_dict

    name = res.name
    exp = [expectation_dict(c) for c in res.expects]
    if res.status in ("unreadable", "internal"):
        msg = res.diagnostics[0].message if res.diagnostics else res.status
        return Outcome(name, "error", res.status, [f"{name}: {msg}"], exp, res.diagnostics,
                       seconds=seconds)
    failures = []
    if res.status == "error":
        errors = [c for c in res.expects if c.spec.error is not None]
        if errors:
            failures = [_where(name, c) + c.message.removeprefix("not met: ")
                        for c in errors if not c.met]
        else:
            d = next((d for d in res.diagnostics if d.severity == "error"), None)
            where = f"{name}:{d.span.line}:{d.span.column}" if d and d.span else name
            what = f"{d.message} [{d.code}]" if d else "error"
            failures = [f"{where}: unexpected error: {what} (add `expect error "
                        f"{d.code if d else 'CODE'}` if it is meant to fail)"]
    else:
        failures = [_where(name, c) + c.message.removeprefix("not met: ")
                    for c in res.expects if not c.met]
    n = len(res.expects)
    note = f"{n} expectation{'s' * (n != 1)}" if n else "no expect lines"
    return Outcome(name, "failed" if failures else "passed", res.status, failures, exp,
                   res.diagnostics, note, seconds)


def _where(name: str, c) -> str:
    return f"{name}:{c.spec.span.line}: "


def summary(outcomes) -> dict:
    counts = {k: sum(o.outcome == k for o in outcomes)
              for k in ("passed", "failed", "error", "skipped")}
    counts["total"] = len(outcomes)
    return counts


def summary_line(counts: dict) -> str:
    parts = [f"{counts['passed']} passed", f"{counts['failed']} failed"]
    if counts["error"]:
        parts.append(f"{counts['error']} error{'s' * (counts['error'] != 1)}")
    if counts["skipped"]:
        parts.append(f"{counts['skipped']} skipped")
    return ", ".join(parts)


def outcome_line(o: Outcome) -> str:
    """One line per file, then its failure lines indented."""
    tag = {"passed": "PASS ", "failed": "FAIL ", "error": "ERROR", "skipped": "SKIP "}[o.outcome]
    head = f"{tag} {o.file}" + (f" ({o.note})" if o.note and o.outcome != "failed" else "")
    return "\n".join([head] + [f"  {f}" for f in o.failures])


def outcome_dict(o: Outcome) -> dict:
    return dict(type="file", file=o.file, outcome=o.outcome, status=o.status,
                failures=list(o.failures), expectations=list(o.expectations),
                diagnostics=[d.to_json() for d in o.diagnostics], note=o.note)


def junit_xml(outcomes, counts: dict) -> str:
    """JUnit XML (testsuites / testsuite / testcase, with failure, error, skipped)."""
    import xml.etree.ElementTree as ET

    total = f"{sum(o.seconds for o in outcomes):.3f}"
    attrs = dict(tests=str(counts["total"]), failures=str(counts["failed"]),
                 errors=str(counts["error"]), skipped=str(counts["skipped"]), time=total)
    suites = ET.Element("testsuites", name="momentum test", **attrs)
    suite = ET.SubElement(suites, "testsuite", name="momentum", **attrs)
    for o in outcomes:
        folder, base = os.path.split(o.file)
        case = ET.SubElement(suite, "testcase",
                             classname=folder.replace(os.sep, ".").strip(".") or ".",
                             name=base, file=o.file, time=f"{o.seconds:.3f}")
        if o.outcome in ("failed", "error"):
            tag = "failure" if o.outcome == "failed" else "error"
            el = ET.SubElement(case, tag, message=o.failures[0] if o.failures else o.outcome,
                               type=tag)
            el.text = "\n".join(o.failures)
        elif o.outcome == "skipped":
            ET.SubElement(case, "skipped", message=o.note)
    ET.indent(suites)
    return '<?xml version="1.0" encoding="utf-8"?>\n' + ET.tostring(suites, encoding="unicode") \
        + "\n"


def simulate_outcome(source, seconds_start: float) -> Outcome:
    """A simulate scene run with `momentum simulate`: passes if it simulates."""
    import time

    from .run import simulate_source

    res, _ = simulate_source(source, 1e-9, None, None, True)
    seconds = time.perf_counter() - seconds_start
    if res.status == "error":
        d = next((d for d in res.diagnostics if d.severity == "error"), None)
        where = f"{source.name}:{d.span.line}" if d and d.span else source.name
        return Outcome(source.name, "failed", "error",
                       [f"{where}: simulate: {d.message if d else 'error'}"], [],
                       res.diagnostics, seconds=seconds)
    return Outcome(source.name, "passed", "solved", [], [], res.diagnostics,
                   "simulated", seconds)
