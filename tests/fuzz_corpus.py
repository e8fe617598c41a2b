"""A corpus of hostile problem files, made from the examples by grammar-aware mutations.

Values are swapped for the ones that break programs (0, -1, 1e308, 1e-320, nan, inf,
1e999, a flipped sign), units for other units, lines deleted, duplicated, swapped or
cut short; whole files get CRLF line ends, a byte order mark, or bytes that are not
UTF-8. `corpus(count, seed)` is deterministic: the same count and seed give the same
files. `run(text)` runs one file through `solve` (and `simulate` when it has a block)
and classifies what came out; `tests/test_fuzz_corpus.py` drives both.
"""
from __future__ import annotations

import math
import random
import re
import signal
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent / "examples"
# the 1000-ball cradles are left out: each takes seconds, and they add no new syntax
BASES = sorted(p for p in list(ROOT.glob("*.mom")) + list(ROOT.glob("simulate/*.mom")) +
               list(ROOT.glob("hard/*.mom")) if "cradle_1000" not in p.name)

NUMBER = re.compile(r"(?<![\w.])\d+(?:\.\d*)?(?:[eE][-+]?\d+)?(?![\w.])")
ODD_VALUES = ["0", "-1", "1e308", "1e-320", "nan", "inf", "-0", "1e999", "1e-999", "-1e-320",
              "1e150", "1e306", "0.0", "-1e308", "(0/0)", "(1/0)"]
UNITS = ["kg", "g", "m", "mm", "km", "s", "m/s", "km/h", "N", "N*s", "J", "deg", "rad",
         "rad/s", "kg/s", "m/s^2", "N*m", "kg*m^2", "N/m", "lb", "ft", "ft/s"]
UNIT = re.compile(r"(?<=[\d)] )(" + "|".join(re.escape(u) for u in
                                            sorted(UNITS, key=len, reverse=True)) + r")\b")


def _value(text: str, rng: random.Random) -> str:
    spots = list(NUMBER.finditer(text))
    if not spots:
        return text
    m = rng.choice(spots)
    return text[:m.start()] + rng.choice(ODD_VALUES) + text[m.end():]


def _sign(text: str, rng: random.Random) -> str:
    spots = list(NUMBER.finditer(text))
    if not spots:
        return text
    m = rng.choice(spots)
    return text[:m.start()] + "-" + text[m.start():]


def _unit(text: str, rng: random.Random) -> str:
    spots = list(UNIT.finditer(text))
    if not spots:
        return text
    m = rng.choice(spots)
    return text[:m.start()] + rng.choice(UNITS) + text[m.end():]


def _lines(text: str, rng: random.Random) -> str:
    lines = text.split("\n")
    if len(lines) < 2:
        return text
    i = rng.randrange(len(lines))
    how = rng.choice(["delete", "duplicate", "truncate", "swap"])
    if how == "delete":
        del lines[i]
    elif how == "duplicate":
        lines.insert(i, lines[i])
    elif how == "truncate":
        lines[i] = lines[i][:rng.randrange(len(lines[i]) + 1)]
    else:
        j = rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
    return "\n".join(lines)


TEXT_MUTATIONS = [(_value, 5), (_sign, 1), (_unit, 2), (_lines, 3)]


def _encoding(data: bytes, rng: random.Random) -> bytes:
    how = rng.choice(["crlf", "bom", "latin1", "byte", "cut"])
    if how == "crlf":
        return data.replace(b"\n", b"\r\n")
    if how == "bom":
        return b"\xef\xbb\xbf" + data
    if how == "latin1":
        return data.decode("utf-8").encode("latin-1", errors="replace")
    if how == "byte":
        i = rng.randrange(len(data) + 1)
        return data[:i] + bytes([rng.choice([0x80, 0xff, 0xc3, 0x00, 0xfe])]) + data[i:]
    return data[:rng.randrange(len(data) + 1)]


def corpus(count: int, seed: int = 14):
    """(name, bytes) of `count` mutated files, the same for the same arguments."""
    rng = random.Random(seed)
    texts = [(p.relative_to(ROOT).as_posix(), p.read_text(encoding="utf-8")) for p in BASES]
    muts, weights = zip(*TEXT_MUTATIONS)
    for k in range(count):
        base, text = texts[rng.randrange(len(texts))]
        kinds = []
        for _ in range(rng.choice([1, 1, 1, 2, 3])):
            fn = rng.choices(muts, weights)[0]
            text = fn(text, rng)
            kinds.append(fn.__name__.strip("_"))
        data = text.encode("utf-8")
        if rng.random() < 0.08:
            data = _encoding(data, rng)
            kinds.append("encoding")
        yield f"{k:06d}-{base.replace('/', '-')}[{'+'.join(kinds)}]", data


# ---- running one file ----------------------------------------------------------------
class Hang(Exception):
    """A file that took longer than its time limit."""


@dataclass
class Tally:
    inputs: int = 0
    solved: int = 0
    errors: int = 0
    simulated: int = 0
    tracebacks: list = field(default_factory=list)
    hangs: list = field(default_factory=list)
    nonsense: list = field(default_factory=list)
    non_finite: list = field(default_factory=list)
    unlocated: list = field(default_factory=list)

    def line(self) -> str:
        return (f"inputs {self.inputs}: solved {self.solved}, located errors {self.errors}, "
                f"simulated {self.simulated}; tracebacks {len(self.tracebacks)}, hangs "
                f"{len(self.hangs)}, silent nonsense {len(self.nonsense)}, non-finite answers "
                f"{len(self.non_finite)}, errors without a location {len(self.unlocated)}")


def _alarm(_signum, _frame):
    raise Hang()


# errors about the whole file, which have no line to point at
WHOLE_FILE = {"unreadable", "encoding", "too-large", "too-deep", "empty", "binary"}


def _nonsense(report, diagnostics) -> str | None:
    """A solved report that says something no physics allows, without a word: a negative
    duration (a zero one only with a warning that names it), a mass that is not
    positive, a negative kinetic energy."""
    warned = " ".join(d.message for d in diagnostics if d.severity == "warning")
    for u in list(report.unknowns) + list(report.answers):
        name, v = u["name"], u["si_value"]
        if v is None or not math.isfinite(v):
            continue
        if re.fullmatch(r"t@\S+->\S+", name) and (v < 0 or v == 0 and name not in warned):
            return f"{name} = {v}"
        if (".mass@" in name or name.startswith("m_")) and v <= 0:
            return f"{name} = {v}"
        if re.fullmatch(r"T@\S+", name) and v < 0:
            return f"{name} = {v}"
    return None


def _non_finite(report) -> str | None:
    for u in list(report.unknowns) + list(report.answers):
        v = u["si_value"]
        if v is None or not math.isfinite(v):
            return f"{u['name']} = {v}"
    return None


def run(name: str, data: bytes, tally: Tally, limit: int = 20) -> None:
    """Solve (and simulate) one file within `limit` seconds, and count what came out."""
    from momentum_cli.run import SourceTextError, decode_source, simulate_source, solve_source

    tally.inputs += 1
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(limit)
    try:
        try:
            source = decode_source(name, data)
        except SourceTextError:
            tally.errors += 1
            return
        res = solve_source(source)
        _classify(name, res, tally, solved=True)
        if "simulate" in source.text:
            sim_res, _ = simulate_source(source, max_events=2000, max_time=limit / 2)
            tally.simulated += 1
            _classify(name, sim_res, tally, solved=False)
    except Hang:
        tally.hangs.append(name)
    except Exception as exc:  # a traceback: what this corpus is here to find
        tally.tracebacks.append(f"{name}: {type(exc).__name__}: {exc}")
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


def _classify(name: str, res, tally: Tally, solved: bool) -> None:
    if res.status == "error":
        if solved:
            tally.errors += 1
        for d in res.diagnostics:
            if d.severity == "error" and d.span is None and d.code not in WHOLE_FILE:
                tally.unlocated.append(f"{name}: {d.code}: {d.message}")
                break
        return
    if not solved:
        return
    tally.solved += 1
    bad = _non_finite(res.report)
    if bad:
        tally.non_finite.append(f"{name}: {bad}")
        return
    bad = _nonsense(res.report, res.diagnostics)
    if bad:
        tally.nonsense.append(f"{name}: {bad}")
