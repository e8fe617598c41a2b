"""`momentum expect`: `expect` lines for a file's current answers, and writing them in place.

In: a solved (or failed) `FileResult` and the file's text. Out: the `expect` lines, and
the file's new text where only `expect` lines differ (refreshed in place, new ones
after the last `expect` or `find` line); `write_atomic` replaces the file through a
temporary file in the same folder.
"""
from __future__ import annotations

import math
import os
import re

from .expectations import component_names, scan_expects
from .units import UnitError, parse_unit

DEFAULT_DIGITS = 4
_REF = re.compile(r"^[A-Za-z_]\w*(\[[\w-]+\])?(\.\w+)?(@\d+(->\d+)?)?$")
_LINE = re.compile(r"^([ \t]*)expect[ \t]+(.*?)[ \t]*(#.*)?$")
_TOL = re.compile(r"[ \t]*(±|\+-|within\b).*$")
_FIND = re.compile(r"^[ \t]*find\b")


class WriteError(OSError):
    """A file that cannot be rewritten (read-only, or its folder is)."""


ZERO = 1e-12  # an answer this small against the largest in its unit is round-off: zero


def number(v: float, digits: int = DEFAULT_DIGITS, zero: float = 0.0) -> str:
    """`v` to `digits` significant figures, trailing zeros kept (they set the tolerance):
    2.5 -> 2.500; a value not above `zero` is 0 to digits-1 decimals."""
    if not math.isfinite(v):
        return "nan"
    if abs(v) <= zero or v == 0:
        return "0." + "0" * (digits - 1) if digits > 1 else "0"
    s = f"{v:#.{digits}g}"
    if "e" in s:
        mant, exp = s.split("e")
        s = f"{mant.rstrip('.')}e{int(exp)}"
    return s.rstrip(".")


def _unit_ok(unit: str) -> bool:
    if not unit:
        return True
    try:
        parse_unit(unit)
        return True
    except (UnitError, OverflowError):
        return False


def answer_lines(res, digits: int = DEFAULT_DIGITS) -> dict[str, str]:
    """{quantity: `QUANTITY = VALUE UNIT`} for every answer that an `expect` can name;
    `{"error": "error CODE"}` for a file that does not solve."""
    if res.report is None:
        code = next((d.code for d in res.diagnostics if d.severity == "error"), "error")
        return {"error": f"error {code}"}
    out = {}
    zero = zero_limits(res.report.answers)
    for a in res.report.answers:
        if a["value"] is None or not _REF.match(a["name"]) or not _unit_ok(a["unit"]):
            continue
        unit = f" {a['unit']}" if a["unit"] else ""
        v, limit = a["value"], zero.get(a["unit"], 0.0)
        if v != 0 and abs(v) <= limit:  # round-off around zero: a tolerance that ignores it
            text = f"0{unit} +- {number(limit * 1e3, 1)}{unit}"
        else:
            text = number(v, digits) + unit
        out.setdefault(a["name"], f"{a['name']} = {text}")
    return out


def zero_limits(answers) -> dict[str, float]:
    """Per unit, the size below which an answer is round-off (ZERO times the largest)."""
    out: dict[str, float] = {}
    for a in answers:
        if a["value"] is not None and math.isfinite(a["value"]):
            out[a["unit"]] = max(out.get(a["unit"], 0.0), ZERO * abs(a["value"]))
    return out


def refreshed(text: str, res, digits: int = DEFAULT_DIGITS) -> str:
    """The file's text with its `expect` lines set to the current answers: each existing
    line refreshed in place (its explicit tolerance and comment kept), an `expect error`
    for a file that fails, new lines after the last `expect` (or `find`) line. Every
    other line is kept byte for byte."""
    nl = "\r\n" if "\r\n" in text else "\n"
    lines = text.splitlines(keepends=True)
    want = answer_lines(res, digits)
    answers = {a["name"]: a for a in res.report.answers} if res.report else {}
    existing = scan_expects(text)
    checked = {c.spec.span.line: c for c in res.expects if c.spec.error is None} \
        if res.report is not None else {}
    drop, done = set(), set()
    for spec in existing:
        i = spec.span.line - 1
        m = _LINE.match(lines[i].rstrip("\r\n"))
        if not m:
            continue
        indent, comment = m.group(1), m.group(3)
        end = lines[i][len(lines[i].rstrip("\r\n")):]
        new_body = None
        if spec.error is not None:
            if "error" in want and "error" not in done:
                new_body = want["error"]
        elif "error" not in want:
            names = component_names(spec.quantity, answers)
            tol = _TOL.search(spec.written)
            suffix = " " + tol.group(0).strip() if tol else ""
            check = checked.get(spec.span.line)
            if check is not None and check.got and None not in check.got:
                s = check.spec  # refreshed in the unit the line is written in
                u = f" {s.unit}" if s.unit else ""
                f = s.factor or 1.0
                unit_of = answers[names[0]]["unit"] if names else None
                limit = max([ZERO * abs(a["si_value"]) for a in answers.values()
                             if a["unit"] == unit_of and a["si_value"] is not None] +
                            [0.0]) / f
                vals = ["0" if suffix and g != 0 and abs(g / f) <= limit else
                        number(g / f, digits, limit) for g in check.got]
                value = vals[0] + u if len(vals) == 1 else \
                    "(" + ", ".join(v + u for v in vals) + ")"
                new_body = f"{spec.quantity} = {value}{suffix}"
            if names:
                done.update(names)
        if new_body is None:
            drop.add(i)
            continue
        done.add(spec.name or "error")
        lines[i] = f"{indent}expect {new_body}" + (f"  {comment}" if comment else "") + \
            (end or "")
    new = [f"expect {body}" for key, body in want.items() if key not in done]
    at = max((s.span.line - 1 for s in existing if s.span.line - 1 not in drop), default=None)
    if at is None:
        finds = [i for i, ln in enumerate(lines) if _FIND.match(ln)]
        at = _statement_end(lines, finds[-1]) if finds else len(lines) - 1
    anchor = lines[at] if 0 <= at < len(lines) else ""
    if anchor.endswith(("\n", "\r")):
        nl = anchor[len(anchor.rstrip("\r\n")):]  # the line ending of the line above
    out = [ln for i, ln in enumerate(lines[:at + 1]) if i not in drop]
    if new:
        if out and not out[-1].endswith(("\n", "\r")):
            out[-1] += nl
        out += [ln + nl for ln in new]
    out += [ln for i, ln in enumerate(lines[at + 1:], at + 1) if i not in drop]
    return "".join(out)


def _statement_end(lines: list[str], i: int) -> int:
    """The last line of a statement continued with a trailing backslash."""
    while i + 1 < len(lines) and lines[i].rstrip("\r\n").rstrip().endswith("\\"):
        i += 1
    return i


def is_read_only(path: str) -> bool:
    """No write permission for us (also for root: a file without any write bit)."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return True
    return not os.access(path, os.W_OK) or not mode & 0o222


def write_atomic(path: str, text: str) -> None:
    """Replace `path` with `text`: a temporary file in the same folder, then os.replace
    (a reader sees the old file or the new one, never half of one); mode kept."""
    import tempfile

    if is_read_only(path):
        raise WriteError(f"{path}: cannot write: the file is read-only (nothing changed)")
    folder = os.path.dirname(os.path.abspath(path))
    try:
        fd, tmp = tempfile.mkstemp(dir=folder, prefix="." + os.path.basename(path) + ".",
                                   suffix=".tmp")
    except OSError as exc:
        raise WriteError(f"{path}: cannot write: {exc.strerror or exc} (nothing changed)") \
            from None
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as fh:
            fh.write(text)
        os.chmod(tmp, os.stat(path).st_mode & 0o7777)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def diff(path: str, old: str, new: str) -> str:
    import difflib

    return "".join(difflib.unified_diff(old.splitlines(keepends=True),
                                        new.splitlines(keepends=True), path, path))
