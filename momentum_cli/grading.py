"""`momentum grade`: students' answers against a key, each classified.

In: key files (solved; their `expect` lines say what is asked and to what tolerance)
and a CSV `student, problem, quantity, value, unit`. Out: one `Grade` per student and
asked quantity: right, rounding (right to fewer digits than asked), sign error, unit
slip (the right number in another unit), wrong or missing; per-student and
per-problem tables and class statistics as text, rich, CSV and JSON.
"""
from __future__ import annotations

import csv
import io
import math
import os
import re
from collections import Counter

from .records import field, record
from .units import UnitError, parse_unit

CLASSES = ("right", "rounding", "sign error", "unit slip", "wrong", "missing")
DEFAULT_REL = 0.01  # a quantity the key has no `expect` line for: within 1 %
DEFAULT_ASKED_DIGITS = 3
# Units a student may have used instead of the key's (a unit slip), by dimension.
COMMON_UNITS = ("m/s", "km/h", "mph", "ft/s", "in/s", "cm/s", "rad/s", "rpm", "deg/s", "rev/s",
                "deg", "rad", "rev", "m", "cm", "mm", "km", "ft", "in", "kg", "gram", "lbm",
                "slug", "N", "kN", "lbf", "N*s", "kN*s", "lbf*s", "N*m*s", "lbf*ft*s", "J", "kJ",
                "lbf*ft", "N*m", "s", "ms", "min", "h", "m/s^2", "ft/s^2", "rad/s^2")
_FAMILY = re.compile(r"-v\d+$")


class GradeError(ValueError):
    """The answers file cannot be read (a usage error)."""


@record
class KeyItem:
    problem: str
    quantity: str
    value: float  # SI, the solved value
    tolerance: float  # SI
    unit: str  # the key's display unit
    factor: float  # SI per unit
    dim: tuple
    asked_digits: int


@record
class Grade:
    student: str
    problem: str
    quantity: str
    key: str  # the key's value in its unit, as text
    answer: str  # the student's value and unit, as text ("" if missing)
    verdict: str  # one of CLASSES


@record
class GradeResult:
    grades: list[Grade]
    keys: list[KeyItem]
    students: list[str]
    key_errors: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)  # answers the key does not ask for


def sig_digits(text: str) -> tuple[int, int]:
    """(significant digits, exponent of the last digit) of a number as written."""
    m = re.match(r"^\s*[-+]?(\d*)(?:\.(\d*))?(?:[eE]([-+]?\d+))?\s*$", text)
    if not m or not (m.group(1) or m.group(2)):
        return 0, 0
    whole, frac, exp = m.group(1) or "", m.group(2) or "", int(m.group(3) or 0)
    digits = (whole + frac).lstrip("0")
    return max(len(digits), 1), -len(frac) + exp


def _first_number(text: str) -> str:
    m = re.search(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?", text)
    return m.group(0) if m else ""


def load_key(files: list[str], rel: float | None) -> tuple[list[KeyItem], list[str]]:
    """The asked quantities of each key file: its `expect` lines (their tolerance), or
    every answer within 1 % when it has none; `rel` overrides every tolerance."""
    from .run import SourceTextError, read_source, solve_source

    from .expectations import component_names

    keys, errors, seen = [], [], set()
    for path in files:
        problem = os.path.splitext(os.path.basename(path))[0]
        try:
            res = solve_source(read_source(path))
        except (OSError, SourceTextError) as exc:
            errors.append(f"{path}: error: cannot read: {getattr(exc, 'strerror', exc)}")
            continue
        if res.report is None:
            d = next((d for d in res.diagnostics if d.severity == "error"), None)
            if any(c.spec.error for c in res.expects):
                continue  # a problem meant to fail asks for nothing
            errors.append(f"{path}: error: the key does not solve: {d.message if d else ''}")
            continue
        answers = {a["name"]: a for a in res.report.answers}
        if res.expects:
            for c in res.expects:
                s = c.spec
                if s.error or not c.got:
                    continue
                names = component_names(s.quantity, answers) or [s.quantity]
                numbers = re.findall(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?", s.written)
                for i, name in enumerate(names):
                    if (problem, name) in seen or i >= len(c.got):
                        continue
                    seen.add((problem, name))
                    tol = s.tolerance[i] if rel is None else rel * abs(c.got[i])
                    asked = sig_digits(numbers[i])[0] if s.how == "digits" and \
                        i < len(numbers) else DEFAULT_ASKED_DIGITS
                    keys.append(KeyItem(problem, name, c.got[i], tol, s.unit or
                                        answers.get(name, {}).get("unit", ""), s.factor,
                                        s.dim, asked or DEFAULT_ASKED_DIGITS))
        else:
            for a in res.report.answers:
                if a["si_value"] is None:
                    continue
                factor = a["si_value"] / a["value"] if a["value"] else 1.0
                r = DEFAULT_REL if rel is None else rel
                keys.append(KeyItem(problem, a["name"], a["si_value"], r * abs(a["si_value"]),
                                    a["unit"], factor, _dim_of(a["unit"]),
                                    DEFAULT_ASKED_DIGITS))
    return keys, errors


def _dim_of(unit: str):
    try:
        return parse_unit(unit)[0][1] if unit else (0, 0, 0)
    except (UnitError, OverflowError):
        return None


def _factor(unit: str, dim) -> float | None:
    """SI per `unit` read with dimension `dim`, or None if it has another dimension."""
    try:
        readings = parse_unit(unit)
    except (UnitError, OverflowError):
        return None
    return next((f for f, d in readings if d == dim), None)


def classify(k: KeyItem, value: str, unit: str) -> str:
    """right, rounding, sign error, unit slip, wrong or missing."""
    value, unit = (value or "").strip(), (unit or "").strip()
    if not value:
        return "missing"
    try:
        x = float(value)
    except ValueError:
        return "wrong"
    if not math.isfinite(x):
        return "wrong"
    tol = k.tolerance * (1 + 1e-9) + 1e-12 * abs(k.value)
    factor = k.factor if not unit else _factor(unit, k.dim)
    if factor is not None:
        si = x * factor
        if abs(si - k.value) <= tol:
            return "right"
        if abs(k.value) > tol and abs(-si - k.value) <= tol:
            return "sign error"
        n, last = sig_digits(value)
        if 0 < n < k.asked_digits and abs(si - k.value) <= 0.5 * 10.0 ** last * factor * \
                (1 + 1e-9):
            return "rounding"
    for other in COMMON_UNITS + ((k.unit,) if k.unit else ()):
        f = _factor(other, k.dim)
        if f is None or (factor is not None and math.isclose(f, factor, rel_tol=1e-12)):
            continue
        if abs(x * f - k.value) <= max(tol, 0.005 * abs(k.value)):
            return "unit slip"
    return "wrong"


def read_answers(path: str) -> list[dict]:
    """Rows of the answers CSV (header: student, problem, quantity, value[, unit])."""
    try:
        with open(path, encoding="utf-8-sig", newline="") as fh:
            text = fh.read()
    except OSError as exc:
        raise GradeError(f"--answers {path}: {exc.strerror or exc}") from None
    rows = list(csv.DictReader(io.StringIO(text), skipinitialspace=True))
    need = {"student", "problem", "quantity", "value"}
    have = {(h or "").strip().lower() for h in (rows[0].keys() if rows else
                                                 csv.reader(io.StringIO(text)).__next__()
                                                 if text.strip() else [])}
    if not need <= have:
        raise GradeError(f"--answers {path}: the header must name student, problem, "
                         f"quantity, value (and optionally unit); missing: "
                         f"{', '.join(sorted(need - have))}")
    out = []
    for r in rows:
        r = {(k or "").strip().lower(): (v or "").strip() for k, v in r.items()}
        out.append(r)
    return out


def grade_all(files: list[str], answers_csv: str, rel_percent: float | None = None) \
        -> GradeResult:
    rows = read_answers(answers_csv)
    keys, errors = load_key(files, None if rel_percent is None else rel_percent / 100.0)
    students = list(dict.fromkeys(r["student"] for r in rows if r.get("student")))
    given: dict[tuple[str, str, str], dict] = {}
    answered: dict[str, set[str]] = {}
    for r in rows:
        given.setdefault((r["student"], r["problem"], r["quantity"]), r)
        answered.setdefault(r["student"], set()).add(r["problem"])
    families = Counter(_FAMILY.sub("", p) for p in dict.fromkeys(k.problem for k in keys))
    grades = []
    for s in students:
        mine = answered.get(s, set())
        for k in keys:
            fam = _FAMILY.sub("", k.problem)
            if families[fam] > 1 and k.problem not in mine:
                continue  # a variant: each student is graded on the one they answered
            r = given.get((s, k.problem, k.quantity))
            verdict = classify(k, r.get("value", ""), r.get("unit", "")) if r else "missing"
            answer = f"{r.get('value', '')} {r.get('unit', '')}".strip() if r else ""
            grades.append(Grade(s, k.problem, k.quantity, _key_text(k), answer, verdict))
    return GradeResult(grades, keys, students, errors, _unmatched(rows, keys, answers_csv))


def _unmatched(rows, keys, path: str) -> list[str]:
    """One warning per answered (problem, quantity) that the key does not ask for."""
    from .diagnostics import did_you_mean

    asked = {(k.problem, k.quantity) for k in keys}
    problems = sorted({k.problem for k in keys})
    out = []
    for p, q in dict.fromkeys((r["problem"], r["quantity"]) for r in rows):
        if (p, q) in asked:
            continue
        if p not in problems:
            out.append(f"{path}: warning: problem '{p}' is not in the key" +
                       did_you_mean(p, problems) + " (its answers are not graded)")
        else:
            qs = [k.quantity for k in keys if k.problem == p]
            out.append(f"{path}: warning: the key of {p} does not ask for '{q}'" +
                       did_you_mean(q, qs) + " (not graded)")
    return out


def _key_text(k: KeyItem) -> str:
    from .numbers import fmt_num

    return f"{fmt_num(k.value / k.factor, 6)} {k.unit}".strip()


def per_student(result: GradeResult) -> list[dict]:
    out = []
    for s in result.students:
        mine = [g for g in result.grades if g.student == s]
        c = Counter(g.verdict for g in mine)
        out.append(dict(student=s, total=len(mine), score=c["right"] / len(mine) if mine else
                        0.0, **{k: c[k] for k in CLASSES}))
    return out


def per_problem(result: GradeResult) -> list[dict]:
    """Per asked quantity: how many got it right, and the most common mistake."""
    out = []
    for k in result.keys:
        mine = [g for g in result.grades if g.problem == k.problem and g.quantity == k.quantity]
        c = Counter(g.verdict for g in mine)
        mistakes = [(n, v) for v, n in c.items() if v != "right"]
        common = max(mistakes, key=lambda t: (t[0], -CLASSES.index(t[1])))[1] if mistakes \
            else None
        out.append(dict(problem=k.problem, quantity=k.quantity, key=_key_text(k),
                        students=len(mine), right=c["right"], most_common_mistake=common,
                        **{v: c[v] for v in CLASSES if v != "right"}))
    return out


def statistics(result: GradeResult) -> dict:
    c = Counter(g.verdict for g in result.grades)
    scores = [r["score"] for r in per_student(result)]
    return dict(students=len(result.students), answers=len(result.grades),
                mean_score=sum(scores) / len(scores) if scores else 0.0,
                **{k: c[k] for k in CLASSES})


def to_json(result: GradeResult) -> dict:
    return {"schema_version": "1",
            "grades": [dict(student=g.student, problem=g.problem, quantity=g.quantity,
                            key=g.key, answer=g.answer, verdict=g.verdict)
                       for g in result.grades],
            "students": per_student(result), "problems": per_problem(result),
            "statistics": statistics(result), "key_errors": list(result.key_errors),
            "warnings": list(result.warnings)}


def to_csv(result: GradeResult) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["student", "problem", "quantity", "key", "answer", "verdict"])
    for g in result.grades:
        w.writerow([g.student, g.problem, g.quantity, g.key, g.answer, g.verdict])
    return buf.getvalue()
