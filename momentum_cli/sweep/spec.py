"""Sweep designs: `--vary NAME=LO..HI:N` grids and `--sample 'NAME~dist(...)'` draws.

In: the options' text, a count and a seed. Out: a `Design` (parameter names, their
dimensions and units) whose `columns(seed)` are the variants' SI values as numpy
arrays: grids in product order (the last `--vary` fastest), then for every grid point
`count` Monte Carlo draws (numpy's PCG64 from the seed, one draw per sample in the
order given), so the same seed gives the same variants on every machine.
"""
from __future__ import annotations

import math
import re

import numpy as np

from ..records import record


class SpecError(ValueError):
    """A design option that cannot be used: the message is one line for the command line."""


DISTRIBUTIONS = {"uniform": 2, "normal": 2, "lognormal": 2, "triangular": 3}

_NAME = r"[A-Za-z_][A-Za-z_0-9]*(?:\[[A-Za-z_0-9]+\])?(?:\.[A-Za-z_]+)?(?:@[A-Za-z_0-9]+)?"
_VARY = re.compile(rf"^\s*({_NAME})\s*=\s*(.+?)\s*\.\.\s*(.+?)\s*:\s*([^\s]+)\s*(.*?)\s*$")
_SAMPLE = re.compile(rf"^\s*({_NAME})\s*~\s*([A-Za-z_]+)\s*\((.*)\)\s*$")


@record
class Param:
    """One varied input: a `let` name (or a given number, `rod.y@1`, `e[A]`)."""

    name: str
    kind: str  # grid | uniform | normal | lognormal | triangular
    args: tuple  # SI floats: (lo, hi, n) for a grid, the distribution's parameters
    dim: tuple
    unit: str  # the unit the option was written in ("" when dimensionless)
    option: str  # the option's text, for messages


@record
class Design:
    params: list
    count: int | None = None
    seed: int | None = None

    @property
    def names(self) -> list[str]:
        return [p.name for p in self.params]

    @property
    def size(self) -> int:
        n = 1
        for p in self.params:
            if p.kind == "grid":
                n *= p.args[2]
        return n * (self.count if self.sampled else 1)

    @property
    def sampled(self) -> bool:
        return any(p.kind != "grid" for p in self.params)

    def columns(self, seed: int | None = None) -> dict[str, np.ndarray]:
        """Every variant's SI value of every parameter (float64 arrays of `size`)."""
        seed = self.seed if seed is None else seed
        grids = [p for p in self.params if p.kind == "grid"]
        axes = [np.linspace(p.args[0], p.args[1], p.args[2]) for p in grids]
        reps = self.count if self.sampled else 1
        out: dict[str, np.ndarray] = {}
        if axes:
            mesh = np.meshgrid(*axes, indexing="ij")
            for p, m in zip(grids, mesh):
                out[p.name] = np.repeat(m.ravel(), reps)
        n = self.size
        if self.sampled:
            rng = np.random.Generator(np.random.PCG64(seed))
            for p in self.params:
                if p.kind != "grid":
                    out[p.name] = _draw(rng, p, n)
        return {p.name: np.ascontiguousarray(out[p.name], dtype=float) for p in self.params}


def _draw(rng, p: Param, n: int) -> np.ndarray:
    a = p.args
    if p.kind == "uniform":
        return rng.uniform(a[0], a[1], n)
    if p.kind == "normal":
        return rng.normal(a[0], a[1], n)
    if p.kind == "triangular":
        return rng.triangular(a[0], a[1], a[2], n)
    # lognormal(mean, sd) of the quantity itself: the underlying normal's mu and sigma
    s2 = math.log1p((a[1] / a[0]) ** 2)
    return rng.lognormal(math.log(a[0]) - s2 / 2, math.sqrt(s2), n)


def parse_design(vary: list[str], sample: list[str], count: int | None,
                 seed: int | None) -> Design:
    """The design of the options; SpecError (one line) for anything unusable."""
    vary, sample = list(vary or []), list(sample or [])
    if not vary and not sample:
        raise SpecError("give at least one --vary NAME=LO..HI:N or --sample 'NAME~normal(a, b)'")
    params = [_vary(v) for v in vary] + [_sample(s) for s in sample]
    seen: set[str] = set()
    for p in params:
        if p.name in seen:
            raise SpecError(f"{p.option}: {p.name} is varied twice")
        seen.add(p.name)
    if sample:
        if count is None:
            raise SpecError("--sample needs --count N (how many variants to draw)")
        if count < 1:
            raise SpecError(f"--count {count}: give at least 1")
        if seed is None:
            seed = 0
    elif count is not None:
        raise SpecError("--count draws --sample values; a --vary grid has its own count (:N)")
    d = Design(params, count if sample else None, seed)
    if d.size > 10**9:
        raise SpecError(f"the design has {d.size} variants; at most 10^9")
    return d


def _vary(option: str) -> Param:
    m = _VARY.match(option)
    if not m:
        raise SpecError(f"--vary {option!r}: write NAME=LO..HI:N, e.g. --vary e=0..1:101 or "
                        "--vary 'h=0.5..2:16 m'")
    name, lo_t, hi_t, n_t, unit = m.groups()
    try:
        n = int(n_t)
    except ValueError:
        raise SpecError(f"--vary {option!r}: the number of points {n_t!r} is not a whole "
                        "number (NAME=LO..HI:N)") from None
    if n < 1:
        raise SpecError(f"--vary {option!r}: give at least 1 point")
    where = f"--vary {option!r}"
    (lo, hi), dim, label = _values(where, [lo_t, hi_t], unit)
    if not lo <= hi:
        raise SpecError(f"{where}: LO must not exceed HI")
    if n == 1 and lo != hi:
        raise SpecError(f"{where}: one point cannot span {lo_t}..{hi_t}; give N >= 2")
    return Param(name, "grid", (lo, hi, n), dim, label, f"--vary {option}")


def _sample(option: str) -> Param:
    m = _SAMPLE.match(option)
    if not m:
        raise SpecError(f"--sample {option!r}: write NAME~DIST(ARGS), e.g. "
                        "--sample 'm~normal(2 kg, 0.05 kg)'")
    name, kind, inner = m.groups()
    if kind not in DISTRIBUTIONS:
        import difflib

        close = difflib.get_close_matches(kind, DISTRIBUTIONS, n=1)
        raise SpecError(f"--sample {option!r}: unknown distribution {kind!r}" +
                        (f"; did you mean '{close[0]}'?" if close else
                         f" (use {', '.join(DISTRIBUTIONS)})"))
    args = [a for a in inner.split(",")]
    want = DISTRIBUTIONS[kind]
    where = f"--sample {option!r}"
    if len(args) != want or not all(a.strip() for a in args):
        sig = {"uniform": "LO, HI", "normal": "MEAN, SD", "lognormal": "MEAN, SD",
               "triangular": "LO, MODE, HI"}[kind]
        raise SpecError(f"{where}: {kind} takes {want} values: {kind}({sig})")
    vals, dim, label = _values(where, args, "")
    if kind == "uniform" and not vals[0] <= vals[1]:
        raise SpecError(f"{where}: LO must not exceed HI")
    if kind in ("normal", "lognormal") and vals[1] < 0:
        raise SpecError(f"{where}: the standard deviation must not be negative")
    if kind == "lognormal" and vals[0] <= 0:
        raise SpecError(f"{where}: a lognormal mean must be positive")
    if kind == "triangular" and not (vals[0] <= vals[1] <= vals[2] and vals[0] < vals[2]):
        raise SpecError(f"{where}: triangular needs LO <= MODE <= HI with LO < HI")
    return Param(name, kind, tuple(vals), dim, label, f"--sample {option}")


def _values(where: str, texts: list[str], unit: str):
    """SI floats of numbers written with units (`2 kg`, or a trailing unit for all),
    one dimension for all; a bare number among dimensional ones takes their unit."""
    parsed = []
    for t in texts:
        t = t.strip()
        if unit and _plain_number(t):
            t = f"{t} {unit}"
        parsed.append(_quantity(where, t))
    dims = {d for _, d, u in parsed if u}
    if len(dims) > 1:
        raise SpecError(f"{where}: the values have different dimensions")
    dim = dims.pop() if dims else (0, 0, 0)
    label = next((u for _, _, u in parsed if u), "")
    out = []
    for (v, d, u), t in zip(parsed, texts):
        if d != dim:
            if u or dim == (0, 0, 0):
                raise SpecError(f"{where}: the values have different dimensions")
            # a bare number beside dimensional ones: in the unit written beside it
            v = _quantity(where, f"{t.strip()} {label}")[0]
        out.append(v)
    return out, dim, label


def _plain_number(t: str) -> bool:
    try:
        float(t)
        return True
    except ValueError:
        return False


def _quantity(where: str, text: str) -> tuple[float, tuple, str]:
    """(SI value, dimension, unit as written) of `2 kg`, `-0.5`, `30 deg`."""
    from ..diagnostics import ProblemError
    from ..overrides import OverrideError, value_node
    from ..quantity import Evaluator, Q, constant
    from ..expr import Const
    from .. import syntax as S

    def names(ref, expect):
        if ref.name == "pi" and ref.index is None and ref.member is None and not ref.at:
            return Q(Const(math.pi), (0, 0, 0))
        raise ProblemError(f"'{ref.text}' is not a number", ref.span, code="name")

    try:
        node = value_node("x", text)
        q = Evaluator(names)(node)
        v = constant(q, node)
    except OverrideError as exc:
        raise SpecError(f"{where}: {str(exc).split(': ', 1)[-1]}") from None
    except ProblemError as exc:
        raise SpecError(f"{where}: {text!r}: {exc.diagnostics[0].message}") from None
    if not math.isfinite(v):
        raise SpecError(f"{where}: {text!r} is not a finite number")
    unit = ""
    if q.dim != (0, 0, 0):
        from ..units import si_label

        unit = node.unit if isinstance(node, S.Num) and node.unit else si_label(q.dim)
    return float(v), q.dim, unit
