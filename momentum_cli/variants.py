"""`momentum variants`: one problem, many students: `let` values drawn, answers as `expect`.

In: a key file, `--vary NAME=LO..HI [UNIT]` ranges, a count and a seed. Out: COUNT
files (the key with the drawn `let` values and its `expect` lines refreshed) and
`index.csv`. The draw is Python's Mersenne Twister from the seed, values rounded to
the digits asked: the same seed gives the same files on every machine.
"""
from __future__ import annotations

import csv
import io
import os
import random
import re

from .run import SourceTextError, decode_source, read_source, solve_source
from .snapshots import DEFAULT_DIGITS, number, refreshed

_RANGE = re.compile(r"^\s*([A-Za-z_]\w*)\s*=\s*([-+]?[\d.]+(?:[eE][-+]?\d+)?)\s*\.\.\s*"
                    r"([-+]?[\d.]+(?:[eE][-+]?\d+)?)\s*([^\s].*)?$")


class VariantError(ValueError):
    """A usage error: an unreadable key, a bad range, a name the key has no `let` for."""


def parse_vary(option: str) -> tuple[str, float, float, str | None]:
    m = _RANGE.match(option)
    if not m:
        raise VariantError(f"--vary {option!r}: write NAME=LO..HI, e.g. v0=4..6 or "
                           "'v0=4..6 m/s'")
    lo, hi = float(m.group(2)), float(m.group(3))
    if not lo <= hi:
        raise VariantError(f"--vary {option!r}: LO must not exceed HI")
    return m.group(1), lo, hi, (m.group(4) or "").strip() or None


def _let_line(name: str) -> re.Pattern:
    return re.compile(rf"^([ \t]*let[ \t]+{re.escape(name)}[ \t]*=[ \t]*)(.*?)([ \t]*(#.*)?)$",
                      re.M)


_VALUE_UNIT = re.compile(r"^[-+]?[\d.]+(?:[eE][-+]?\d+)?[ \t]*([A-Za-z_][\w*/^]*)?$")


def draw(rng: random.Random, lo: float, hi: float, digits: int) -> str:
    """A value uniform in [lo, hi], to `digits` significant figures (as written)."""
    x = rng.uniform(lo, hi)
    x = min(max(float(f"{x:.{digits}g}"), lo), hi)
    return number(x, digits)


def make_variants(key: str, vary: list[str], count: int, seed: int, out_dir: str,
                  digits: int = 3, expect_digits: int = DEFAULT_DIGITS):
    """Write the variants and index.csv; returns (index rows, messages for variants
    that did not solve)."""
    from .overrides import let_names

    try:
        text = read_source(key).text
    except (OSError, SourceTextError) as exc:
        raise VariantError(f"{key}: cannot read: {getattr(exc, 'strerror', None) or exc}") \
            from None
    ranges = [parse_vary(v) for v in vary]
    names = let_names(text)
    for name, *_ in ranges:
        if name not in names:
            from .diagnostics import did_you_mean

            raise VariantError(f"--vary {name}: {key} has no `let {name}`" +
                               did_you_mean(name, names))
    units = {}
    for name, _, _, unit in ranges:
        m = _let_line(name).search(text)
        written = _VALUE_UNIT.match(m.group(2).strip())
        units[name] = unit if unit else (written.group(1) if written and written.group(1)
                                         else None)
        if unit is None and not written:
            raise VariantError(f"--vary {name}: `let {name} = {m.group(2).strip()}` is not a "
                               "number with a unit; give the unit: "
                               f"--vary '{name}=LO..HI UNIT'")
    try:
        os.makedirs(out_dir, exist_ok=True)
    except OSError as exc:
        raise VariantError(f"--out {out_dir}: {exc.strerror or exc}") from None
    rng = random.Random(seed)
    stem = os.path.splitext(os.path.basename(key))[0]
    width = max(2, len(str(count)))
    rows, failed, answer_names = [], [], []
    for i in range(1, count + 1):
        values = {name: draw(rng, lo, hi, digits) for name, lo, hi, _ in ranges}
        body = text
        for name, value in values.items():
            unit = f" {units[name]}" if units[name] else ""
            body = _let_line(name).sub(lambda m: m.group(1) + value + unit + m.group(3), body,
                                       count=1)
        vname = f"{stem}-v{i:0{width}d}"
        path = os.path.join(out_dir, vname + ".mom")
        res = solve_source(decode_source(path, body), False, 6, "float")
        body = refreshed(body, res, expect_digits)
        with open(path, "w", encoding="utf-8", newline="") as fh:
            fh.write(body)
        row = {"variant": vname, "file": os.path.basename(path), "status": res.status}
        for name, value in values.items():
            row[name] = f"{value} {units[name]}".strip()
        if res.report is not None:
            for a in res.report.answers:
                col = f"{a['name']} ({a['unit']})" if a["unit"] else a["name"]
                if col not in answer_names:
                    answer_names.append(col)
                row[col] = number(a["value"], expect_digits) if a["value"] is not None else ""
        else:
            d = next((d for d in res.diagnostics if d.severity == "error"), None)
            failed.append(f"{path}: error: {d.message if d else 'does not solve'}")
        rows.append(row)
    header = ["variant", "file", "status"] + [r[0] for r in ranges] + answer_names
    buf = io.StringIO()
    w = csv.DictWriter(buf, header, lineterminator="\n", restval="")
    w.writeheader()
    w.writerows(rows)
    with open(os.path.join(out_dir, "index.csv"), "w", encoding="utf-8", newline="") as fh:
        fh.write(buf.getvalue())
    return rows, failed
