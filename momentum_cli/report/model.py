"""The report model: everything a renderer shows, as plain data (strings and floats).

Built once from a `Solution`; the plain, rich and JSON renderers only lay it out, so
the three outputs cannot disagree about a number.
"""
from __future__ import annotations

import math

from ..compile import System
from ..expr import Add, Const, Known, Mul, evaluate, variables
from ..numbers import fmt_num, fmt_tiny
from ..records import field, record
from ..expr import Var
from ..solve import CheckReport, Solution
from ..units import ACCELERATION, INERTIA, LENGTH, MASS, MOMENT, VELOCITY
from .abbrev import abbreviate, name_list
from . import printer as printer_module
from .printer import lines, lines_of, printers
from .statements import statements
from .treecode import caller as tcaller
from .treecode import evaluate as tval
from .treecode import value_and_magnitude as tv_and_m
from .reader import (
    STATE_DIMS,
    angle_names,
    direction,
    is_angle,
    lines_in,
    reader_for,
    si_lines,
)

PRINTERS_FROM = 64  # equations in a scene from which its rows go through printer.lines
# equations in a scene from which its checks' trees go through treecode (compiled per
# shape: a long sequence's like trees); a small file's few trees are walked (their shapes,
# met a few times, cost a compile each: 3x the walks over a batch of small files)
TREECODE_FROM = 64
# the checks' many like trees by `treecode.caller` (tests turn it off)
CHECK_CALLERS = True
PRINTER_LOOP = True  # a big scene's row texts by `row_texts`' loop (tests turn it off)


@record
class EquationRow:
    index: int
    principle: str
    group: str
    line: int | None
    symbolic: str
    numeric: str
    kind: str
    role: str  # solved | check | not needed | undetermined
    solves: list = field(default_factory=list)  # unknowns its block solves (named in numeric)

    def __init__(self, index, principle, group, line, symbolic, numeric, kind, role,
                 solves=None):
        """By hand: one row per equation (10^5 of them in a big scene), plain slots."""
        self.index, self.principle, self.group, self.line = index, principle, group, line
        self.symbolic, self.numeric, self.kind, self.role = symbolic, numeric, kind, role
        self.solves = [] if solves is None else solves


@record
class Report:
    file: str
    title: str
    bodies: list[dict]
    effects: list[str]
    knowns: list[dict]  # per state: id, label, items [(name, value, unit)]
    transitions: list[dict]  # kind, key, line, why, equations (EquationRow list)
    other_equations: dict[str, list[EquationRow]]
    blocks: list[dict]
    unknowns: list[dict]  # name, si_value, unit
    checks: list[CheckReport]
    answers: list[dict]
    regimes: list[dict]
    diagnostics: list = field(default_factory=list)
    counts: dict = field(default_factory=dict)
    flows: list = field(default_factory=list)  # control-volume flux rows (evaluated)
    expectations: list = field(default_factory=list)  # the `expect` lines, checked (dicts)
    # the reader's units: system "si"|"us", degrees, name ("SI" | "US customary") and the
    # labels of mass, inertia, length, velocity; knowns, bodies' shown_mass/shown_inertia,
    # unknowns' value/shown_unit, answers without `in UNIT` and numeric lines are in them
    units: dict = field(default_factory=dict)
    sensitivities: dict | None = None  # `--sensitivity`: report/sensitivity.section
    diagrams: list = field(default_factory=list)  # diagram.ImpulseDiagram per impact/interval


def _finite(x: float | None) -> float | None:
    if x is None or not isinstance(x, (int, float)) or not math.isfinite(x):
        return None
    return 0.0 if x == 0 else float(x)


def _finite_all(xs) -> list:
    """`[_finite(x) for x in xs]`, a finite float without a call (x - x is 0 only then)."""
    return [(0.0 if x == 0 else x) if type(x) is float and x - x == 0.0 else _finite(x)
            for x in xs]


_NONE: frozenset = frozenset()
_SI_UNIT = {"x": "m", "y": "m", "angle": "rad", "vx": "m/s", "vy": "m/s",
            "omega": "rad/s"}  # a state quantity's SI unit (the knowns')


def _lines(e, integrated: bool, values, keep, system, reader, sig: int,
           shown: tuple) -> tuple[str, str]:
    """(symbolic, numeric) line of one equation: an integration's as it integrated;
    in SI and radians by the printer compiled for the equation's shape (printer.py),
    where a scene is big enough to meet its shapes often (`shown[2]`); else, and in SI
    in degrees (`shown[3]`: the angles' test), by one walk printing both lines.
    `shown`: the numbers printed so far, to 6 and to `sig` figures (value -> text)."""
    if integrated:
        return e.text(), e.text(numeric=True)
    if reader.system != "us":
        if shown[2]:
            got = lines(e, values, keep, sig, shown[0], shown[1])
            if got is not None:
                return got
        return si_lines(e, values, keep, sig, shown[0], shown[1], shown[3])
    return lines_in(e, values, keep, system, reader, sig)


def equation_text(index: int, principle: str, line, role: str, sym: str, num: str) -> str:
    """One equation row as the plain report shows it: its number, principle, line (or
    scene) and role, then its symbolic line and (where it differs) its numeric line."""
    tail = f"\n      {sym}\n      {num}" if num != sym else f"\n      {sym}"
    if line:
        return f"  ({index + 1}) {principle} (line {line}){tail}" if role == "solved" \
            else f"  ({index + 1}) {principle} (line {line}) [{role}]{tail}"
    return f"  ({index + 1}) {principle} (scene){tail}" if role == "solved" else \
        f"  ({index + 1}) {principle} (scene) [{role}]{tail}"


class Lazy:
    """A list of the report made item by item each time it is read, never held whole: a
    big scene's report is streamed into its text while only the solution is alive (the
    rows, blocks and unknowns of 10^5 balls are half a gigabyte as objects). `make()`
    gives an iterator over the items; a copy (`list`, pickle) is a plain list."""

    __slots__ = ("_n", "_make", "texts", "part")

    def __init__(self, n: int, make, texts=None, part=None):
        """`texts`: None, or a function giving an iterator over the items' plain text
        (`equation_text` of each row), made without the items (plain text reads no more).
        `part`: None, or a function giving items i to j - 1 (`part(i, j)`) as a Lazy, the
        others not made (text.part_of: a range of the text made by another process)."""
        self._n, self._make, self.texts, self.part = n, make, texts, part

    def __iter__(self):
        return self._make()

    def __len__(self) -> int:
        return self._n

    def __bool__(self) -> bool:
        return self._n > 0

    def __getitem__(self, i):
        return list(self._make())[i]

    def __reduce__(self):
        return (list, (list(self._make()),))


def part_of(items, i: int, j: int):
    """Items `i` to `j - 1` of a report's list, or of a `Lazy` (made as read)."""
    part = getattr(items, "part", None)
    return part(i, j) if part is not None else items[i:j]


def rows_of(transitions, i: int):
    """The equation rows of transition `i`: a lazy report's without making the
    transition (its statements and diagram)."""
    rows = getattr(transitions, "rows", None)
    return rows(i) if rows is not None else transitions[i]["equations"]


class Deferred:
    """A list made when it is first read, then held (a lazy report's checks: a tenth of a
    second for 10^4 impacts, made by whoever reads them first). What is appended before
    it is made comes after the made items; a copy (`list`, pickle) is a plain list."""

    __slots__ = ("_make", "_items", "_later", "_release")

    def __init__(self, make, release=None):
        """`release()`: drop what only `make` reads (made again if it must be), for a
        process that leaves the making to another (forked_text's parent)."""
        self._make, self._items, self._later, self._release = make, None, [], release

    def release(self) -> None:
        if self._items is None and self._release is not None:
            self._release()

    def _made(self) -> list:
        if self._items is None:
            self._items = self._make() + self._later
            self._make = self._later = self._release = None
        return self._items

    def append(self, item) -> None:
        (self._later if self._items is None else self._items).append(item)

    def __iter__(self):
        return iter(self._made())

    def __len__(self) -> int:
        return len(self._made())

    def __bool__(self) -> bool:
        return bool(self._made())

    def __getitem__(self, i):
        return self._made()[i]

    def __eq__(self, other) -> bool:
        return self._made() == (list(other) if isinstance(other, Deferred) else other)

    __hash__ = None

    def __reduce__(self):
        return (list, (self._made(),))


class LazyTransitions(Lazy):
    """A lazy report's transitions, with what splitting its text needs without making
    them: a transition's rows alone (`rows(i)`), and each one's size (`sizes()`)."""

    __slots__ = ("rows", "sizes")

    def __init__(self, n: int, make, part, rows, sizes):
        """`rows(i)`: transition i's equation rows (its `equations`) without its
        statements and diagram; `sizes()`: (rows, bodies moved) of each transition."""
        super().__init__(n, make, None, part)
        self.rows, self.sizes = rows, sizes


def build_report(name: str, sol: Solution, sig: int = 6, units: str = "file",
                 lazy: bool = False) -> Report:
    """`units`: si | us | file (the units the file is written in), for what is shown;
    the SI values stay beside them (si_value) for JSON. `lazy`: the transitions (their
    equations, statements and diagrams), blocks and unknowns are `Lazy`, made from the
    solution as a renderer reads them (for a report rendered at once, then dropped)."""
    system: System = sol.system
    sc = system.scene
    st = sol.structure
    values = sol.values
    reader = reader_for(units, sc.file_units)
    # the block's list of unknowns (and a set of them) shared by its rows (a copy per
    # row is O(N^2)); lists by equation index, not dicts: a dict entry costs ~5x a list
    # slot (three of 3*10^5 at 10^5 balls, and a copied list a block: ~60 MB)
    n_eqs = len(system.equations)
    solves: list = [None] * n_eqs  # None: in no block
    keeps: list = [_NONE] * n_eqs
    for b in sol.blocks:
        unk = b.unknowns if type(b.unknowns) is list else list(b.unknowns)
        keep = set(unk) if len(unk) > 1 else unk  # only `in` reads it: 1 name, no set
        for k in b.equations:
            solves[k], keeps[k] = unk, keep
    checked = set(st.redundant).union(st.constant_eqs)  # lists: a set, not a scan per row
    under = st.under_eqs
    role = ["solved" if solves[k] is not None else "check" if k in checked else
            "undetermined" if k in under else "not needed" for k in range(n_eqs)]
    # an integration's rows print what it integrated and its result (integration.py)
    integrated = {k for integ in system.integrations for k in integ.equations}
    six: dict = {}
    eqs = system.equations
    # the printers compiled per shape pay off where shapes recur many times (a big scene);
    # a small file's rows are printed by the walk (its shapes, met a few times a file,
    # would not be compiled: printers() would only walk the tree to count them)
    shown = (six, six if sig == 6 else {}, len(eqs) >= PRINTERS_FROM and not reader.degrees,
             angle_names(system) if reader.degrees else None)

    def row(k: int) -> EquationRow:
        e = eqs[k]
        return EquationRow(k, e.principle, e.group, e.span.line if e.span else None,
                           *_lines(e, k in integrated, values, keeps[k], system,
                                   reader, sig, shown),
                           e.kind, role[k], [] if solves[k] is None else solves[k])

    def row_text(k: int) -> str:
        """`equation_text` of `row(k)`, without the row."""
        e = eqs[k]
        span = e.span
        return equation_text(k, e.principle, span.line if span else None, role[k],
                             *_lines(e, k in integrated, values, keeps[k], system,
                                     reader, sig, shown))

    # row_texts' (matcher, printers) met last, and which followed which: kept from one
    # group of rows (a transition) to the next
    last_read: list = [None]
    next_read: dict = {}

    def row_texts(ks):
        """`map(row_text, ks)`, the same strings: a big scene's rows (SI, radians, printers
        on) printed in one loop, each by its shape's printers where they are compiled (no
        call per row but the shape's matcher and printers); any other row by `row_text`."""
        if not (PRINTER_LOOP and shown[2]) or reader.system == "us":
            yield from map(row_text, ks)
            return
        six, sixes = shown[0], shown[1]
        # the rows repeat a few kinds in a period (a cradle's impact: restitution, then
        # momentum x and y of each body): the shape that followed the last row's shape
        # the time before is read by its matcher first, with no other lookup
        after, prev = next_read, last_read[0]
        for k in ks:
            e = eqs[k]
            if k in integrated:
                yield row_text(k)
                continue
            guess = after.get(prev)
            leaves = guess[0](e.lhs, e.rhs) if guess is not None else None
            if leaves is not None:
                got = leaves, guess[1]
                prev = guess
            else:
                got = printers(e)
                if got:
                    read = printer_module.READ_BY
                    if len(after) > 64:
                        after.clear()
                    after[prev] = prev = read
            last_read[0] = prev
            if not got:  # not compiled yet, or long: as `lines` prints it
                pair = lines_of(got, e, values, keeps[k], sig, six, sixes) \
                    if got is not None else None
                if pair is None:
                    pair = si_lines(e, values, keeps[k], sig, six, sixes, shown[3])
                sym, num = pair
            else:
                leaves, (psym, pnum) = got
                texts = getattr(e, "_texts", None)  # `Equation.text()` printed it already
                sym = texts[0] if texts is not None and texts[0] is not None else \
                    psym(leaves, None, None, 6, six)
                num = pnum(leaves, values, keeps[k], sig, sixes)
            span = e.span
            line = span.line if span else None
            r = role[k]
            tail = f"\n      {sym}\n      {num}" if num != sym else f"\n      {sym}"
            if line:
                yield f"  ({k + 1}) {e.principle} (line {line}){tail}" if r == "solved" \
                    else f"  ({k + 1}) {e.principle} (line {line}) [{r}]{tail}"
            else:
                yield f"  ({k + 1}) {e.principle} (scene){tail}" if r == "solved" else \
                    f"  ({k + 1}) {e.principle} (scene) [{r}]{tail}"

    by_group: dict[str, list[int]] = {}  # one pass over the equations, not one a transition
    for k, e in enumerate(eqs):
        by_group.setdefault(e.group, []).append(k)
    if not lazy:  # every row made once, in order (and shared by the transitions' lists)
        rows = [row(k) for k in range(len(eqs))]

    def group_rows(ks: list):
        if lazy:  # made as read: a transition of 10^5 bodies is not held as rows
            return Lazy(len(ks), lambda: map(row, ks), lambda: row_texts(ks),
                        lambda i, j: group_rows(ks[i:j]))
        return [rows[k] for k in ks]

    k_mass, k_inertia = reader.factor(MASS), reader.factor(INERTIA)  # once, not per body
    bodies = [dict(name=b.name, shape=b.kind, mass=b.mass, inertia=b.inertia,
                   formula=b.inertia_formula, particle=b.is_particle,
                   weight=b.weight_given, shown_mass=b.mass / k_mass,
                   shown_inertia=b.inertia / k_inertia)
              for b in sc.bodies.values()]
    effects = []
    acc = reader.label(ACCELERATION)
    if sc.gravity is not None:
        g = math.hypot(*sc.gravity)
        effects.append(f"gravity {fmt_num(g / reader.factor(ACCELERATION), sig)} {acc} along "
                       f"({fmt_num(sc.gravity[0] / g, 4)}, {fmt_num(sc.gravity[1] / g, 4)})")
    elif sc.g is not None:
        effects.append(f"g = {fmt_num(sc.g / reader.factor(ACCELERATION), sig)} {acc} (into "
                       "the plane: weights only, no planar force)")
    else:
        effects.append("no gravity (none declared)")
    for j in sc.joints:
        what = {"link": "link (two-force member)",
                "slider": "slider (free along the line)"}.get(j.kind, str(j.kind))
        other = j.b.name if j.b.body else "ground"
        effects.append(f"{what} {j.label}: {j.a.name} to {other}")
    knowns = []
    for sid, spec in sc.states.items():
        items = []
        for (body, q), (v, _) in spec.givens.items():
            items.append((f"{body}.{q}",
                          *reader.show(v, STATE_DIMS[q], _SI_UNIT[q], q == "angle")))
        units = [u for _n, _v, u in items]
        for (body, q), hs in spec.hints.items():
            for rel, v, _ in hs:
                shown_v = reader.show(v, STATE_DIMS[q], _SI_UNIT[q], q == "angle")
                items.append((f"{body}.{q} {rel}", shown_v[0], "hint"))
                units.append(shown_v[1])
        # items: (name, value, unit) in the reader's units, unit "hint" for a bound (its
        # unit in `units`, one per item)
        knowns.append(dict(id=sid, label=spec.label or "", items=items, units=units))
    used_groups = set(map(_group_of, system.transitions))

    def transition_items(trs):
        for t in trs:
            group = _group_of(t)
            # system: the principles stated for the system (sum of momenta, moments about
            # a pin with I_O = I_G + m d^2), shown before the body-by-body rows
            # (statements.py)
            yield dict(kind=t.kind, key=t.key, before=t.before, after=t.after,
                       line=t.span.line, why=list(t.why),
                       equations=group_rows(by_group.get(group, ())),
                       system=statements(t, values, system, reader, sig, shown))

    other: dict[str, list[EquationRow]] = {}
    for group, ks in by_group.items():
        if group not in used_groups:
            other[group] = group_rows(ks)

    def block_items():
        for i, b in enumerate(sol.blocks):
            ks = b.equations
            if len(ks) == 1:  # most blocks (one unknown, one equation): no set to sort
                span = eqs[ks[0]].span
                lines = [span.line] if span else []
            else:
                lines = sorted({eqs[k].span.line for k in ks if eqs[k].span})
            # `_finite(x)` without a call for a finite float (x - x is 0 only then)
            x, r = b.cond, b.residual
            d = dict(index=i + 1, unknowns=list(b.unknowns), method=b.method,
                     condition_number=(0.0 if x == 0 else x)
                     if type(x) is float and x - x == 0.0 else _finite(x),
                     iterations=b.iterations,
                     residual=(0.0 if r == 0 else r)
                     if type(r) is float and r - r == 0.0 else _finite(r), lines=lines)
            q = b.quality
            if q is not None:
                x, r, z = q.cond, q.backward, q.bound
                d["quality"] = dict(method=q.method, precision=q.precision,
                                    condition_number=(0.0 if x == 0 else x)
                                    if type(x) is float and x - x == 0.0 else _finite(x),
                                    backward_error=(0.0 if r == 0 else r)
                                    if type(r) is float and r - r == 0.0 else _finite(r),
                                    error_bound=(0.0 if z == 0 else z)
                                    if type(z) is float and z - z == 0.0 else _finite(z),
                                    iterations=q.iterations)
            if b.matrix is not None and len(b.unknowns) > 1:
                d["matrix"] = [_finite_all(row) for row in b.matrix]
                d["rhs"] = _finite_all(b.rhs)
            yield d

    def block_texts():
        """What plain text reads of each `block_items` dict, as a tuple (index, unknowns,
        method, condition number, iterations, residual, lines, matrix or None, rhs or
        None): no dict, no quality (JSON's)."""
        for i, b in enumerate(sol.blocks):
            ks = b.equations
            if len(ks) == 1:
                span = eqs[ks[0]].span
                lines = [span.line] if span else []
            else:
                lines = sorted({eqs[k].span.line for k in ks if eqs[k].span})
            x, r = b.cond, b.residual
            unk = b.unknowns
            if b.matrix is not None and len(unk) > 1:
                matrix, rhs = [_finite_all(row) for row in b.matrix], _finite_all(b.rhs)
            else:
                matrix = rhs = None
            yield (i + 1, unk if type(unk) is list else list(unk), b.method,
                   (0.0 if x == 0 else x) if type(x) is float and x - x == 0.0 else _finite(x),
                   b.iterations,
                   (0.0 if r == 0 else r) if type(r) is float and r - r == 0.0 else _finite(r),
                   lines, matrix, rhs)

    shows: dict = {}  # (dim, unit) -> (factor, label): `reader.show` without its calls
    degrees = reader.degrees

    def unknown_rows():
        """(name, SI value, SI unit, value and unit as the reader reads them) of each
        solved unknown: `unknown_items`' fields, and plain text's (`Lazy.texts`)."""
        for n, u in system.unknowns.items():
            if n in values:
                x = values[n]  # `_finite(x)` without a call for a finite float
                si = (0.0 if x == 0 else x) if type(x) is float and x - x == 0.0 else \
                    _finite(x)
                if si is not None and not (degrees and u.qty == "angle"):  # is_angle(Var(n))
                    fl = shows.get((u.dim, u.unit))
                    if fl is None:
                        fl = shows[u.dim, u.unit] = (reader.factor(u.dim),
                                                     reader.label(u.dim, u.unit))
                    yield n, si, u.unit, si / fl[0], fl[1]
                else:
                    yield (n, si, u.unit, *reader.show(si, u.dim, u.unit, u.qty == "angle"))

    def unknown_items():
        for n, si, unit, v, shown_unit in unknown_rows():
            yield dict(name=n, si_value=si, unit=unit, value=v, shown_unit=shown_unit)

    def unknown_texts():
        """What plain text reads of each unknown: (name, value, shown unit), no dict."""
        for n, _si, _unit, v, shown_unit in unknown_rows():
            yield n, v, shown_unit

    if lazy:
        from .diagram import lazy_diagrams

        trs = system.transitions

        def transitions_part(i: int, j: int) -> Lazy:
            some = trs[i:j]
            return Lazy(len(some), lambda: transition_items(some))

        transitions = LazyTransitions(
            len(trs), lambda: transition_items(trs), transitions_part,
            lambda i: group_rows(by_group.get(_group_of(trs[i]), ())),
            lambda: [(len(by_group.get(_group_of(t), ())), len(t.bodies)) for t in trs])
        blocks = Lazy(len(sol.blocks), block_items, block_texts)
        unknowns = Lazy(sum(1 for n in system.unknowns if n in values), unknown_items,
                        unknown_texts)
        diagrams = lazy_diagrams(sol, reader)
    else:
        from .diagram import build_diagrams

        transitions = list(transition_items(system.transitions))
        blocks = list(block_items())
        unknowns = list(unknown_items())
    flows = _flow_rows(system, values)

    def made_checks() -> list:
        return list(sol.checks) + _energy_checks(sol, sig, reader) + _residual_checks(sol) + \
            _flux_checks(flows) + _error_estimates(sol)

    # a lazy report's checks are made where they are first read: by the process that
    # writes the Checks section (forked_text: the child, beside the other's transitions)
    checks = Deferred(made_checks, lambda: _drop_residuals(system)) if lazy else made_checks()
    answers = []
    for f, (n, v, u, si) in zip(system.finds, sol.answers):
        if not f.explicit and f.factor == 1.0:  # no `in UNIT`: the reader's units
            v, u = reader.show(si, f.dim, u, u == "rad" and is_angle(Var(n), system))
        answers.append(dict(name=n, value=_finite(v), unit=u, si_value=_finite(si),
                            direction=direction(n, _finite(si), system)))
    regimes = [dict(contact=s.label, transition=s.transition,
                    regime="stick" if s.regime == "stick" else "slide")
               for s in system.friction if s.regime != "no slip"]  # static checks: in checks
    counts = dict(unknowns=len(system.unknowns), equations=len(system.equations),
                  blocks=len(st.blocks), solved_blocks=len(sol.blocks),
                  redundant=len(st.redundant) + len(st.constant_eqs),
                  undetermined=len(st.under))
    if not lazy:
        diagrams = build_diagrams(sol, reader)
    rep = Report(name, sc.title, bodies, effects, knowns, transitions, other, blocks, unknowns,
                 checks, answers, regimes, list(sol.diagnostics), counts, flows,
                 diagrams=diagrams)
    rep.units = dict(system=reader.system, degrees=reader.degrees,
                     name="US customary" if reader.system == "us" else "SI",
                     mass=reader.label(MASS), inertia=reader.label(INERTIA),
                     length=reader.label(LENGTH), velocity=reader.label(VELOCITY))
    return rep


def _group_of(t) -> str:
    """The group of a transition's equations (`Equation.group`)."""
    return f"{t.kind} {t.before} -> {t.after}"


_DIAGRAM_INDEX: list = [None, 0, {}]  # the diagrams list last indexed, its length, the index


def diagram_for(rep: Report, t: dict):
    """The impulse diagram of a transition of the report (None: an energy phase). The
    report's diagrams are indexed by (kind, key) once: a lookup per transition of a long
    sequence would otherwise scan them all (quadratic in the number of impacts)."""
    ds = rep.diagrams
    if type(ds) is not list and hasattr(ds, "of"):  # lazy: the transition's own, made now
        return ds.of(t["kind"], t["key"])
    cache = _DIAGRAM_INDEX
    if cache[0] is not ds or cache[1] != len(ds):
        index: dict = {}
        for d in ds:
            index.setdefault((d.kind, d.key), d)  # the first, as a scan finds it
        cache[:] = [ds, len(ds), index]
    return cache[2].get((t["kind"], t["key"]))


def diagram_lines(rep: Report, t: dict, indent: str = "") -> list | None:
    """`diagram_for(rep, t).lines(indent)` (None: no diagram); a lazy report's made
    straight from its transition (`LazyDiagrams.text`), without the diagram's objects."""
    ds = rep.diagrams
    if type(ds) is not list and hasattr(ds, "text"):
        return ds.text(t["kind"], t["key"], indent)
    d = diagram_for(rep, t)
    return None if d is None else d.lines(indent)


def forget_diagram_index() -> None:
    """Drop `diagram_for`'s index (it holds the last report's diagrams): once a report
    is rendered, so that its diagrams are freed with it."""
    _DIAGRAM_INDEX[:] = [None, 0, {}]


def expectation_dict(c) -> dict:
    """One checked `expect` line as plain data, values in the expectation's unit."""
    s = c.spec
    f = s.factor or 1.0
    d = dict(line=s.span.line, quantity=s.quantity, met=c.met, message=c.message,
             error=s.error, unit=s.unit or None, expected=None, tolerance=None, got=None,
             difference=None)
    if s.error is None and s.expected:
        d["expected"] = [_finite(v / f) for v in s.expected]
        d["tolerance"] = _finite(max(s.tolerance) / f) if s.tolerance else None
    if c.got:
        d["got"] = [_finite(g / f) if g is not None else None for g in c.got]
        diffs = [abs(g - v) / f for g, v in zip(c.got, s.expected) if g is not None]
        d["difference"] = _finite(max(diffs)) if diffs else None
    return d


def add_expectations(rep: Report, checks, sig: int = 6) -> None:
    """Each `expect` line becomes a check (ok: met; error: not met) and an entry of
    `rep.expectations`."""
    for c in checks:
        d = expectation_dict(c)
        rep.expectations.append(d)
        rep.checks.append(CheckReport(f"expect, line {d['line']}: {d['quantity']}",
                                      "ok" if c.met else "error", c.message, d["difference"]))


def _flux_checks(flows: list[dict]) -> list[CheckReport]:
    """Each control volume: every rate is a flow in the declared direction (>= 0)."""
    out = []
    for volume in dict.fromkeys(r["volume"] for r in flows):
        rows = [r for r in flows if r["volume"] == volume and r["rate"] is not None]
        bad = [f"{r['what']} at line {r['line']}" for r in rows if r["rate"] < 0]
        if bad:
            out.append(CheckReport(f"flux signs, {volume}", "warning",
                                   f"negative rate: {', '.join(bad)} flows the other way"))
        else:
            n_in = sum(r["what"] == "inflow" for r in rows)
            out.append(CheckReport(f"flux signs, {volume}", "ok",
                                   f"{n_in} inflow(s) bring momentum in (+), {len(rows) - n_in} "
                                   "outflow(s) take it out (-); every rate >= 0"))
    return out


def _flow_rows(system: System, values) -> list[dict]:
    """Each inflow, outflow and force of a control volume with its momentum flux
    (the sign already that of the balance: + in, - out) and its moment about O."""
    def ev(e):
        try:
            return _finite(evaluate(e, values))
        except (KeyError, ValueError, ZeroDivisionError, OverflowError):
            return None

    out = []
    for r in system.flow_rows:
        mdot = ev(r.rate) if r.rate is not None else None
        vx, vy = ev(r.velocity.x), ev(r.velocity.y)
        ax, ay = ev(r.at.x), ev(r.at.y)
        if mdot is not None and None not in (vx, vy):
            fx, fy = r.sign * mdot * vx, r.sign * mdot * vy
        else:
            fx, fy = vx, vy  # a force row: the force itself
        moment = ax * fy - ay * fx if None not in (ax, ay, fx, fy) else None
        out.append(dict(volume=r.volume, what=r.what, line=r.line, rate=mdot, vx=vx, vy=vy,
                        flux_x=fx, flux_y=fy, moment=moment))
    return out


def fmt_bound(x: float) -> str:
    t = fmt_tiny(x)
    return t if t.startswith("<") else f"<= {t}"


def _error_estimates(sol: Solution) -> list[CheckReport]:
    """Each linear block's conditioning and error bound.

    The warning (estimated relative error above 1e-6) is raised for the answers the
    file asks for: a component that is round-off around zero has no meaningful
    relative error, and only exact arithmetic can tell it from a tiny true value.
    """
    asked: set[str] | None = None  # the answers' unknowns: read once a block has a bound
    out = []
    texts: dict = {}
    snapped = sol.snapped or ()
    for b in sol.blocks:
        q = b.quality
        unknowns = b.unknowns
        if q is None or len(unknowns) < 2:
            continue
        if asked is None:
            asked = set()
            for f in sol.system.finds:
                variables(f.expr, asked)
        name = f"error estimate, block {', '.join(unknowns[:3])}" + \
            ("..." if len(unknowns) > 3 else "")
        # a value snapped to 0 (round-off, said in the checks) has no relative error; a
        # block of a long sequence mostly holds no answer at all (one set test, no loop)
        if asked.isdisjoint(unknowns):
            mine = {}
        else:
            comps = q.components or [q.bound] * len(unknowns)
            mine = {u: e for u, e in zip(unknowns, comps) if u in asked and u not in snapped}
        worst = max(mine.values(), default=0.0)
        shown = worst if mine else q.bound
        # the text is a function of these alone: a long sequence of like blocks repeats it
        key = (q.cond, q.backward, shown, bool(mine), q.precision, q.method, q.iterations)
        detail = texts.get(key)
        if detail is None:
            detail = texts[key] = (
                f"cond {fmt_num(q.cond, 3)} (1-norm, equilibrated), backward error "
                f"{fmt_tiny(q.backward)}, relative error {fmt_bound(shown)}"
                + (" for the answers" if mine else " (no answer here)") +
                f" ({q.precision}, {q.method}"
                + (f", {q.iterations} refinement steps" if q.iterations else "") + ")")
        status = "ok"
        if mine and worst > 1e-6:
            status = "warning"
            lossy = name_list([u for u, e in mine.items() if e > 1e-6], "unknowns")
            detail += (f"; digits may be lost in {lossy}: try --precision refine or "
                       "--precision exact")
        out.append(CheckReport(name, status, detail, _finite(shown)))
    return out


def _energy_checks(sol: Solution, sig: int, reader=None) -> list[CheckReport]:
    out = []
    k = reader.factor(MOMENT) if reader is not None else 1.0
    J = reader.label(MOMENT, "J") if reader is not None else "J"
    system, values = sol.system, sol.values
    nums: dict = {}  # (x, figures) -> fmt_num(x, figures), x != 0: a sequence repeats its Ts

    def num(x: float, sig: int) -> str:
        if x == 0:  # 0.0 and -0.0 are one key: printed each
            return fmt_num(x, sig)
        s = nums.get((x, sig))
        if s is None:
            if len(nums) > 4096:
                nums.clear()
            s = nums[x, sig] = fmt_num(x, sig)
        return s

    coded = len(system.equations) >= TREECODE_FROM
    # a long sequence's like energies, one after another: the shape's code tried first
    val = (tcaller("val") if CHECK_CALLERS else tval) if coded else None
    for t in system.transitions:
        if t.kind != "impact":
            continue
        T1, T2 = t.energy
        try:  # one walk each; a failure is "not solved" only where a name is missing
            a = val(T1, values) if coded else None  # by the shape's code (treecode.py)
            if a is None:
                a = evaluate(T1, values)
            b = val(T2, values) if coded else None
            if b is None:
                b = evaluate(T2, values)
        except (KeyError, ValueError, ZeroDivisionError, OverflowError):
            if variables(T1) <= values.keys() and variables(T2) <= values.keys():
                raise
            a = None
        if a is None:
            out.append(CheckReport(f"kinetic energy, impact {t.before} -> {t.after}", "info",
                                   "not all velocities were solved (use --all)"))
            continue
        lost = a - b
        frac = lost / a if a > 0 else 0.0
        tol = 1e-9 * max(a, b, 1e-300)
        if lost < -tol:
            status, what = "warning", "GAINED (not physical for an impact)"
        else:
            status, what = "ok", "lost"
        of = ""
        if t.bodies:  # a long list as its first and last bodies and their number
            names, n = abbreviate(t.bodies)
            of = f"T of {{{names}}}" + (f" ({n} bodies)" if n else "") + ": "
        out.append(CheckReport(f"kinetic energy, impact {t.before} -> {t.after}", status,
                               f"{of}T{t.before} = {num(a / k, sig)} {J}, T{t.after} = "
                               f"{num(b / k, sig)} {J}, {what} "
                               f"{num(abs(lost) / k if abs(lost) > tol else 0.0, sig)} {J} "
                               f"({num(abs(frac) * 100 if abs(lost) > tol else 0.0, 4)} %)",
                               _finite(frac)))
    return out


def value_and_magnitude(e, values) -> tuple[float, float]:
    """(`evaluate(e)`, `magnitude(e)`) in one walk, the same floats: a term that is not a
    sum, nor a product with one sum, has magnitude |value| (evaluated once, not twice)."""
    t = type(e)
    if t is Add:
        vals, mags = [], []
        for x in e.terms:
            tx = type(x)  # a leaf inline: its value, and its magnitude |value|
            if tx is Const or tx is Known:
                v = x.value
                m = abs(v)
            elif tx is Var:
                v = values[x.name]
                m = abs(v)
            else:
                v, m = value_and_magnitude(x, values)
            vals.append(v)
            mags.append(m)
        return math.fsum(vals), sum(mags)
    if t is Mul:
        fs = e.factors
        for f in fs:  # a zero known factor: both are 0 (as evaluate and magnitude say)
            if (type(f) is Const or type(f) is Known) and f.value == 0.0:
                return 0.0, 0.0
        sums = [f for f in fs if type(f) is Add]
        if len(sums) == 1:
            r = k = 1.0
            for f in fs:
                tf = type(f)
                if f is sums[0]:
                    v, m = value_and_magnitude(f, values)
                else:
                    v = f.value if tf is Const or tf is Known else \
                        values[f.name] if tf is Var else evaluate(f, values)
                    k *= v
                r *= v
            return r, abs(k) * m
    v = evaluate(e, values)
    return v, abs(v)


def _drop_residuals(system: System) -> None:
    """The residual trees `_residual_checks` reads and then drops, dropped unread (made
    again, the same trees, if it runs after all)."""
    for e in system.equations:
        if e.momentum_row:
            e._residual = None


def _residual_checks(sol: Solution) -> list[CheckReport]:
    """The largest relative residual of the momentum equations that were solved."""
    system, values = sol.system, sol.values
    worst = 0.0
    n = 0
    coded = len(system.equations) >= TREECODE_FROM
    # a long sequence's like residuals, one after another: the shape's code tried first
    vm = (tcaller("vm") if CHECK_CALLERS else tv_and_m) if coded else None
    eqs = system.equations
    for b in sol.blocks:
        for k in b.equations:
            e = eqs[k]
            if not e.momentum_row:
                continue
            try:
                res = e.residual
                e._residual = None  # its last reader (made again if asked): its memory
                # goes to the text (~130 bytes a row)
                # by the shape's code (treecode.py), or walked
                got = vm(res, values) if vm is not None else None
                r, s = got if got is not None else value_and_magnitude(res, values)
                r = abs(r)
            except KeyError:  # it also holds an unknown no equation determines
                continue
            worst = max(worst, r / s if s > 0 else r)
            n += 1
    if not n:
        return []
    status = "ok" if worst < 1e-9 else "warning"
    return [CheckReport("momentum residuals", status,
                        f"largest relative residual {fmt_tiny(worst)} over {n} impulse-momentum "
                        "equations", worst)]
