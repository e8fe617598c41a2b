"""The impulse diagram of each impact and interval, as plain data (report stage).

In: a solved `Solution` (the compiled transitions record every impulse they apply to a
body, `compile.Applied`). Out: one `ImpulseDiagram` per impact or interval: per body the
impulses on it (where, which way, how large), what is dropped and why, and the scene's
configuration at the start of the transition, for the terminal list and the SVG drawing.
"""
from __future__ import annotations

import math
from functools import cached_property

from ..elements.keys import Key
from ..elements.kinds import Component, JointKind, KeyKind, Tangential
from ..expr import Const, Known, Mul, Var, evaluate, variables
from ..numbers import fmt_num
from ..records import field, record
from ..units import ANGULAR_IMPULSE, FORCE, IMPULSE, LENGTH
from .abbrev import name_list
from .reader import Reader

POSITION = ("x", "y", "angle")  # unchanged by an impact
PLAIN = True  # tests turn it off: every application by `_impulses`' general steps
KINDS = True  # tests turn it off: every transition's bodies placed (no per-kind places)
SIG = 4  # significant figures in the diagram (short lines, stable drawings)
UNIT = {False: "N*s", True: "N*m*s"}


@record
class DiagramBody:
    """A body in its configuration at the start of the transition."""

    name: str
    shape: str  # rod, disk, ring, sphere, plate, particle, rigid, composite, ...
    x: float
    y: float
    angle: float
    placed: bool  # its position is known (else it is drawn where its contacts put it)
    parts: list  # (kind, centre from G in the body frame, {dim: m}, rotation)
    v_before: tuple | None = None
    v_after: tuple | None = None
    omega_before: float | None = None
    omega_after: float | None = None
    particle: bool = False


@record
class DiagramImpulse:
    """One impulse (or angular impulse) on one body."""

    body: str
    name: str  # J_n[A], Jx[O], m g t, M[bearing]
    what: str  # the element it comes from: contact A, pin O, weight of rod
    point: str  # where it acts
    at: tuple  # world position (m)
    direction: tuple | None  # its assumed positive direction (unit); None: a moment
    words: str  # up, to the left, along n = (0.866, 0.5), counter-clockwise
    value: float | None  # along `direction` (N*s) or counter-clockwise (N*m*s); None: unsolved
    moment: bool = False

    @property
    def unit(self) -> str:
        return UNIT[self.moment]


@record
class Dropped:
    """A force that is not impulsive here (or not in this phase's balance), and why."""

    body: str | None
    what: str
    why: str


@record
class DiagramSurface:
    name: str
    at: tuple
    normal: tuple


@record
class ImpulseDiagram:
    """The impulse diagram of one impact or interval."""

    title: str
    kind: str  # impact | interval
    key: str  # 2->3
    before: str
    after: str
    bodies: list[DiagramBody]
    impulses: list[DiagramImpulse]
    dropped: list[Dropped]
    surfaces: list[DiagramSurface] = field(default_factory=list)
    pins: list = field(default_factory=list)  # (name, (x, y)): pins to the ground
    links: list = field(default_factory=list)  # (label, kind, a, b): joints between bodies
    notes: list = field(default_factory=list)
    reader: Reader = field(default_factory=Reader)  # the reader's units (values stay SI)

    def show(self, si_value, dim, si_unit: str) -> tuple:
        """(value, unit) as the reader reads it: US customary for a US problem."""
        return self.reader.show(si_value, dim, si_unit)

    def lines(self, indent: str = "") -> list[str]:
        """The terminal list: per body its impulses, then what is dropped (plain ASCII);
        every line after `indent` (the plain report's two spaces, without a second list)."""
        out = [indent + self.title]
        by_body: dict = {}  # one pass, not one scan of every impulse per body
        for i in self.impulses:
            by_body.setdefault(i.body, []).append(i)
        # the reader's factors and labels once (as `show` gives them), numbers through
        # one cache: the same few values recur along a chain
        r = self.reader
        got = _SHOWN.get((r.system, r.degrees)) or _shown(r)
        shown, f = got
        cache = _NUMS
        if len(cache) > 4096:
            cache.clear()
        num = _num

        add = out.append
        for b in self.bodies:
            mine = by_body.get(b.name)
            if not mine:
                add(f"{indent}  {b.name}: no impulse")
                continue
            add(f"{indent}  {b.name}:")
            for i in mine:
                k, unit = shown[i.moment]
                v = "?" if i.value is None else num(i.value / k)
                if i.moment:
                    where = f" on {b.name}"
                elif i.at is None:
                    where = f" at {i.point} {_xy(None)}"
                else:
                    where = f" at {i.point} ({num(i.at[0] / f)}, {num(i.at[1] / f)})"
                add(f"{indent}    {i.name} = {v} {unit}{where}, {i.words}")
        for d in self.dropped:
            on = f" ({d.body})" if d.body and d.body not in d.what else ""
            out.append(f"{indent}  dropped: {d.what}{on}: {d.why}")
        return out  # the notes (what is drawn schematically) belong to the drawing

    def svg(self) -> str:
        """One self-contained <svg> element: the scene, the impulses, the velocities."""
        from .diagram_svg import render_svg

        return render_svg(self)

    def to_dict(self) -> dict:
        return dict(
            title=self.title, kind=self.kind, before=self.before, after=self.after,
            bodies=[dict(name=b.name, shape=b.shape, x=b.x, y=b.y, angle=b.angle,
                         placed=b.placed, v_before=_list(b.v_before), v_after=_list(b.v_after),
                         omega_before=b.omega_before, omega_after=b.omega_after)
                    for b in self.bodies],
            impulses=[dict(body=i.body, name=i.name, what=i.what, point=i.point,
                           at=_list(i.at), direction=_list(i.direction), words=i.words,
                           value=i.value, unit=i.unit, moment=i.moment)
                      for i in self.impulses],
            dropped=[dict(body=d.body, what=d.what, why=d.why) for d in self.dropped],
            lines=self.lines())


# a reader's (system, degrees) -> the impulses' (factor, label) by moment, the length factor
_SHOWN: dict = {}


def _shown(r: Reader) -> tuple:
    """`_SHOWN` of reader `r`, made (keyed by its fields: a record's hash is slow)."""
    got = _SHOWN[r.system, r.degrees] = (
        {m: (r.factor(d), r.label(d, UNIT[m])) for m, d in
         ((False, IMPULSE), (True, ANGULAR_IMPULSE))}, r.factor(LENGTH))
    return got
# (coefficients, component, contact normal) -> (size, words) of an impulse in a diagram's
# text (`_Builder.plain_lines`): a pure function of the key, shared by all
_DIRS: dict = {}
_NUMS: dict = {}  # x -> its text in a diagram (a pure function of x: shared by all)


def _num(x: float) -> str:
    """x as a diagram prints it, from `_NUMS` (bounded by its users, who clear it)."""
    s = _NUMS.get(x)
    if s is None:
        s = _NUMS[x] = fmt_num(_clean(x), SIG)
    return s


def _list(v):
    return None if v is None else [float(x) for x in v]


def _clean(x: float) -> float:
    return 0.0 if abs(x) < 1e-12 else x


def _xy(p) -> str:
    return f"({fmt_num(_clean(p[0]), SIG)}, {fmt_num(_clean(p[1]), SIG)})"


_WORDS: dict = {}  # (d, symbol) -> words: a long sequence repeats a few directions


def direction_words(d: tuple, symbol: str | None = None) -> str:
    """`up`, `to the left`, or `along n = (0.866, 0.5)` for a unit vector."""
    key = (d, symbol)
    w = _WORDS.get(key)
    if w is None:
        if len(_WORDS) > 4096:
            _WORDS.clear()
        w = _WORDS[key] = _direction_words(d, symbol)
    return w


def _direction_words(d: tuple, symbol: str | None = None) -> str:
    x, y = (_clean(round(c, 12)) for c in d)
    axis = {(0.0, 1.0): "up", (0.0, -1.0): "down", (1.0, 0.0): "to the right",
            (-1.0, 0.0): "to the left"}.get((x, y))
    along = f"along {symbol + ' = ' if symbol else ''}{_xy((x, y))}"
    if axis and symbol:
        return f"{axis} ({along})"
    return axis or along


# ---- building ----------------------------------------------------------------------------------
def build_diagrams(sol, reader: Reader | None = None) -> list[ImpulseDiagram]:
    """One diagram per impact and interval of the solved system, in its order."""
    system = sol.system
    shared = _Shared(sol)
    out = [_Builder(shared, t, reader or Reader()).build() for t in system.transitions
           if t.kind in ("impact", "interval")]
    for d in out:
        d.reader = reader or Reader()
    return out


class LazyDiagrams:
    """`build_diagrams`, each diagram made when it is read (iterated, or `of` the
    transition being rendered) and not kept: a report streamed into its text holds one
    transition's diagram at a time. A copy (`list`, pickle) is a plain list."""

    __slots__ = ("sol", "reader", "shared", "ts")

    def __init__(self, sol, reader: Reader | None):
        self.sol, self.reader, self.shared = sol, reader or Reader(), None
        self.ts = {}  # (kind, key) -> the first transition of it, as an index finds it
        for t in sol.system.transitions:
            if t.kind in ("impact", "interval"):
                self.ts.setdefault((t.kind, t.key), t)

    def _build(self, t) -> ImpulseDiagram:
        if self.shared is None:
            self.shared = _Shared(self.sol)
        d = _Builder(self.shared, t, self.reader).build()
        d.reader = self.reader
        return d

    def of(self, kind: str, key: str):
        """The diagram of a transition for its text (`lines`): the bodies' velocities,
        the surfaces, pins and links, which only a drawing reads, are left out."""
        t = self.ts.get((kind, key))
        if t is None:
            return None
        if self.shared is None:
            self.shared = _Shared(self.sol)
        d = _Builder(self.shared, t, self.reader).build(lines_only=True)
        d.reader = self.reader
        return d

    def text(self, kind: str, key: str, indent: str = "") -> list | None:
        """`of(kind, key).lines(indent)`, the same lines, made straight from the transition
        where every application is the commonest (`_Builder.plain_lines`): no impulse or
        diagram objects; None: no diagram."""
        t = self.ts.get((kind, key))
        if t is None:
            return None
        if self.shared is None:
            self.shared = _Shared(self.sol)
        b = _Builder(self.shared, t, self.reader)
        got = b.plain_lines(indent) if PLAIN else None
        if got is None:
            d = b.build(lines_only=True)
            d.reader = self.reader
            got = d.lines(indent)
        return got

    def prepare(self) -> None:
        """The lookups every diagram shares, made now (before a fork: both processes
        inherit them instead of each making them, forked_text)."""
        if self.shared is None and self.ts:
            self.shared = _Shared(self.sol)

    def __iter__(self):
        for t in self.sol.system.transitions:
            if t.kind in ("impact", "interval"):
                yield self._build(t)

    def __len__(self) -> int:
        return sum(1 for t in self.sol.system.transitions if t.kind in ("impact", "interval"))

    def __bool__(self) -> bool:
        return bool(self.ts)

    def __getitem__(self, i):
        return list(self)[i]

    def __reduce__(self):
        return (list, (list(self),))


def lazy_diagrams(sol, reader: Reader | None = None) -> LazyDiagrams:
    return LazyDiagrams(sol, reader)


class _Shared:
    """What every diagram of one solution looks up: transitions by key, the states an
    impact ties (positions unchanged), a schematic length; computed once."""

    def __init__(self, sol):
        self.sol = sol
        sc = sol.system.scene
        self.specs = {(str(s.kind), s.key): s for s in sc.transitions}
        parent: dict = {}

        def root(x):
            while parent.get(x, x) != x:
                parent[x] = parent.get(parent[x], parent[x])
                x = parent[x]
            return x

        for tr in sc.transitions:
            if str(tr.kind) == "impact":
                a, b = root(tr.before), root(tr.after)
                if a != b:
                    parent[a] = b
        self.root = root
        # a position or angle known anywhere among the states an impact ties
        self.placed: dict = {}
        for sid, st in sc.states.items():
            r = root(sid)
            for (b, q), (v, _) in st.givens.items():
                if q in POSITION:
                    self.placed.setdefault((b, q, r), v)
        odd = False  # a value a lookup by "body.q@state" might find but `placed` lacks
        for k, v in sol.values.items():
            if isinstance(k, Key):
                if k.kind is KeyKind.STATE and k.qty in POSITION:
                    if k.state is not None:
                        self.placed.setdefault((k.body, k.qty, root(k.state)), v)
                    else:
                        odd = True
            else:
                odd = True
        # no position or angle known at any state (given or solved): every body's lookups
        # in `_known_at` find nothing (its diagram places it by its ties)
        self.unplaced = not self.placed and not odd
        self.parts: dict = {}  # body -> its parts as a diagram draws them (made once)
        # (impact kind, its contacts' points) -> where each application acts, when no
        # position is known (`_Builder.plain_lines`): a kind's bodies are placed alike
        self.kinds: dict = {}
        self.own = len(self.specs) == len(sc.transitions)  # no two transitions of one key

    @cached_property
    def still_points(self) -> bool:
        """Every contact point at its body's G or a round body's rim, none located by an
        unknown: a kind's contacts place its bodies alike whatever their points (read
        where a kind's places are looked up, not for every solution)."""
        return all(
            p is None or (p.located_by is None and (p.round_contact or not any(p.offset)))
            for tr in self.sol.system.scene.transitions for c in tr.contacts
            for p in (c.a, c.b))

    @cached_property
    def size(self) -> float:
        """A length for schematic spacing (read only where a body is placed by a tie)."""
        sizes = [_extent(b) for b in self.sol.system.scene.bodies.values()]
        return max([x for x in sizes if x > 0] or [1.0])


def _where(a, body: DiagramBody, arm) -> tuple:
    """Where an application's impulses act (the body's centre plus the arm) and how the
    diagram names that point."""
    p = a.point
    at = (body.x + arm[0], body.y + arm[1])
    if p.round_contact and p.name == a.body:
        point = f"{a.body}'s contact point" if arm != (0.0, 0.0) else f"{a.body}'s centre"
    else:
        point = "G" if p.name == a.body else p.name
    return at, point

class _Builder:
    def __init__(self, shared: _Shared, t, reader: Reader):
        self.reader = reader
        self.shared, self.sol, self.t = shared, shared.sol, t
        self.sc = self.sol.system.scene
        self.values = self.sol.values
        self.spec = shared.specs.get((t.kind, t.key))
        self.notes: list[str] = []
        self._by_what: dict | None = None

    def _contacts(self) -> dict:
        """The transition's contacts by the name an application gives (`contact LABEL`;
        the first of a repeated label), built once: a lookup per impulse, not a scan."""
        if self._by_what is None:
            self._by_what = {}
            for c in (self.spec.contacts if self.spec else ()):
                self._by_what.setdefault(f"contact {c.label}", c)
        return self._by_what

    def _value(self, body: str, q: str, s: str):
        v = self.values.get(f"{body}.{q}@{s}")  # a Key is the str it prints: no Key made
        if v is None:
            st = self.sc.states.get(s)
            g = st.givens.get((body, q)) if st is not None else None
            v = g[0] if g is not None else None
        return v

    # -- state values: solved, given, or shared across the impacts that keep positions
    def known(self, body: str, q: str, sid: str):
        v = self._value(body, q, sid)
        if v is not None or q not in POSITION:
            return v
        sh = self.shared
        return sh.placed.get((body, q, sh.root(sid)))

    def build(self, lines_only: bool = False) -> ImpulseDiagram:
        """`lines_only`: what `ImpulseDiagram.lines` reads (no velocities, surfaces, pins
        or links: a drawing's)."""
        t = self.t
        kind_word = "impact" if t.kind == "impact" else "interval"
        title = f"Impulse diagram, {kind_word} {t.before} -> {t.after}"
        bodies = self._bodies(lines_only)
        self._place(bodies)
        where = {b.name: b for b in bodies}
        impulses = []
        for a in t.impulses:
            impulses.extend(self._impulses(a, where[a.body]))
        order = {b.name: k for k, b in enumerate(bodies)}
        impulses.sort(key=lambda i: order[i.body])  # stable: grouped by body
        if lines_only:
            return ImpulseDiagram(title, t.kind, t.key, t.before, t.after, bodies, impulses,
                                  self._dropped(), [], [], [], self.notes)
        return ImpulseDiagram(title, t.kind, t.key, t.before, t.after, bodies, impulses,
                              self._dropped(), self._surfaces(bodies), self._pins(),
                              self._links(where), self.notes)

    def plain_lines(self, indent: str = "") -> list | None:
        """`ImpulseDiagram.lines(indent)` of `build(lines_only=True)`, the same strings: each
        impulse's line formatted where it is found (no diagram, no sort: grouped by body
        as found); an application that takes `_plain_impulses` (impulses alone, no torque)
        without `DiagramImpulse`s, any other by `_impulses`."""
        t = self.t
        apps = t.impulses
        monos = []
        known_arms = True  # every arm a number (else read as `_impulses` evaluates it)
        for a in apps:
            # None: an application with a torque, or whose J is not `_monomials`' (a
            # weight's m*g*t): its impulses by `_impulses`' general steps, laid out here
            mono = _monomials(a.J) if a.torque is None else None
            if mono is None:
                known_arms = False
            else:
                tx, ty = type(a.arm.x), type(a.arm.y)
                if not ((tx is Const or tx is Known) and (ty is Const or ty is Known)):
                    known_arms = False
            monos.append(mono)
        # an impact of one compiled kind (`TransitionInfo.kind_id`: the same contacts'
        # normals, radii and bodies by index) with no position known anywhere and no
        # joint: its bodies are placed by its contacts alone, as every impact of its kind
        # (and the same points' offsets) places them: where each application acts is
        # read from the first one's (its places are the same floats)
        sh = self.shared
        kid = getattr(t, "kind_id", None)
        gkey = ats = None
        if kid is not None and KINDS and sh.unplaced and not self.sc.joints and \
                self.spec is not None and sh.own and known_arms:
            gkey = kid if sh.still_points else \
                (kid, tuple([(c.a.offset, c.a.round_contact, c.a.located_by is None,
                              None if c.b is None else
                              (c.b.body is None, c.b.offset, c.b.round_contact))
                             for c in self.spec.contacts]))
            ats = sh.kinds.get(gkey)
        if ats is None:
            bodies = self._bodies(True)
            self._place(bodies, notes=False)
            where = {b.name: b for b in bodies}
            names = [b.name for b in bodies]
            made: list | None = [] if gkey is not None else None
        else:
            names = t.bodies
            made = None
        r = self.reader
        got = _SHOWN.get((r.system, r.degrees)) or _shown(r)
        (k, unit), f = got[0][False], got[1]
        cache = _NUMS
        if len(cache) > 4096:
            cache.clear()
        vals = self.values
        contacts = self._contacts()
        dirs = _DIRS
        by_body: dict = {}
        for k_app, (a, mono) in enumerate(zip(apps, monos)):
            if mono is None:  # as `ImpulseDiagram.lines` lays out `_impulses`' own
                self._general_lines(a, where[a.body], by_body, indent, got)
                continue
            p = a.point
            if ats is None:
                body = where[a.body]
                if p.round_contact or p.located_by is not None:
                    arm = (a.arm.x.value, a.arm.y.value) if known_arms else \
                        _arm(a.arm, vals)
                else:
                    arm = (0.0, 0.0) if body.particle else _rot(p.offset, body.angle)
                at, point = _where(a, body, arm)
                if made is not None:
                    made.append(at)
            else:  # `_where`'s name of the point, its place the kind's
                at = ats[k_app]
                if p.round_contact and p.name == a.body:  # its arm: the known one
                    point = f"{a.body}'s contact point" if \
                        (a.arm.x.value, a.arm.y.value) != (0.0, 0.0) else f"{a.body}'s centre"
                else:
                    point = "G" if p.name == a.body else p.name
            head = None
            contact = contacts.get(a.what)
            normal = contact.normal if contact is not None else None
            for n in (mono if len(mono) == 1 else sorted(mono, key=str)):
                d = mono[n]
                # its size and words: a function of the coefficients, the component and
                # the contact's normal (`_symbol`), met again and again along a sequence
                dk = (d, getattr(n, "comp", None), normal)
                sw = dirs.get(dk)
                if sw is None:
                    size = math.hypot(*d)
                    if size == 0:
                        sw = (size, None)
                    else:
                        d = (d[0] / size, d[1] / size)
                        sw = (size, direction_words(d, _symbol(n, d, contact)))
                    if len(dirs) > 4096:
                        dirs.clear()
                    dirs[dk] = sw
                size, words = sw
                if size == 0:
                    continue
                val = vals.get(n)
                if head is None:  # where it acts: the same for each impulse of `a`
                    x, y = at[0] / f, at[1] / f
                    sx, sy = _num(x), _num(y)
                    head = f" {unit} at {point} ({sx}, {sy}), "
                    mine = by_body.get(a.body)
                    if mine is None:
                        mine = by_body[a.body] = []
                if val is None:
                    v = "?"
                else:
                    v = _num(val * size / k)
                mine.append(f"{indent}    {_local(n)} = {v}{head}{words}")
        bodies = where = None  # 10^5 bodies' records: not held beside their lines
        out = [f"{indent}Impulse diagram, {'impact' if t.kind == 'impact' else 'interval'} "
               f"{t.before} -> {t.after}"]
        add = out.append
        take = by_body.pop  # each body's list freed as its lines are moved to `out`
        for name in names:
            mine = take(name, None)
            if not mine:
                add(f"{indent}  {name}: no impulse")
                continue
            add(f"{indent}  {name}:")
            out += mine
        if made is not None and len(sh.kinds) < 4096:
            sh.kinds[gkey] = made
        for d in self._dropped():
            on = f" ({d.body})" if d.body and d.body not in d.what else ""
            add(f"{indent}  dropped: {d.what}{on}: {d.why}")
        return out

    def _general_lines(self, a, body: DiagramBody, by_body: dict, indent: str,
                       shown: tuple) -> None:
        """The lines of application `a`'s impulses by `_impulses`, added to `by_body`,
        each as `ImpulseDiagram.lines` writes it (`shown`: `_SHOWN` of the reader)."""
        units, f = shown
        for i in self._impulses(a, body):
            k, unit = units[i.moment]
            if i.value is None:
                v = "?"
            else:
                v = _num(i.value / k)
            if i.moment:
                where = f" on {i.body}"
            elif i.at is None:
                where = f" at {i.point} {_xy(None)}"
            else:
                x, y = i.at[0] / f, i.at[1] / f
                sx, sy = _num(x), _num(y)
                where = f" at {i.point} ({sx}, {sy})"
            mine = by_body.get(i.body)
            if mine is None:
                mine = by_body[i.body] = []
            mine.append(f"{indent}    {i.name} = {v} {unit}{where}, {i.words}")

    def _known_at(self, sid: str):
        """`known(body, q, sid)` for one state, its givens and its root looked up once
        (a transition of 10^4 bodies asks for seven quantities of each)."""
        values, sh = self.values, self.shared
        st = self.sc.states.get(sid)
        givens = st.givens if st is not None else {}
        placed = sh.placed
        root: list = []

        def known(body: str, q: str):
            v = values.get(f"{body}.{q}@{sid}")
            if v is None:
                g = givens.get((body, q))
                v = g[0] if g is not None else None
            if v is not None or q not in POSITION:
                return v
            if not root:
                root.append(sh.root(sid))
            return placed.get((body, q, root[0]))
        return known

    def _bodies(self, lines_only: bool = False) -> list[DiagramBody]:
        i, j = self.t.before, self.t.after
        ki = self._known_at(i)
        values, states = self.values, self.sc.states
        st_i, st_j = states.get(i), states.get(j)
        gi = st_i.givens if st_i is not None else {}
        gj = st_j.givens if st_j is not None else {}
        at_i, at_j = "@" + i, "@" + j

        def vel(body: str, q: str, at: str, givens: dict):
            """`known(body, q, state)` of a velocity (no shared position to fall back on)."""
            v = values.get(body + q + at)
            if v is None:
                g = givens.get((body, q[1:]))
                v = g[0] if g is not None else None
            return v

        out = []
        bodies = self.sc.bodies
        if lines_only and self.shared.unplaced:  # nothing to look up: `ki` finds None
            nan = math.nan
            return [DiagramBody(name, b.kind, nan, nan, 0.0, False, (), None, None, None,
                                None, b.is_particle)
                    for name in self.t.bodies for b in (bodies[name],)]
        shapes = self.shared.parts
        for name in self.t.bodies:
            b = bodies[name]
            x, y, ang = ki(name, "x"), ki(name, "y"), ki(name, "angle")
            particle = b.is_particle
            if lines_only:  # the name and the position its impulses are placed by
                out.append(DiagramBody(
                    name, b.kind, x if x is not None else math.nan,
                    y if y is not None else math.nan, ang or 0.0,
                    x is not None and y is not None, (), None, None, None, None, particle))
                continue
            vi = (vel(name, ".vx", at_i, gi), vel(name, ".vy", at_i, gi))
            vj = (vel(name, ".vx", at_j, gj), vel(name, ".vy", at_j, gj))
            parts = shapes.get(name)
            if parts is None:  # one list per body, shared by its diagrams (read only)
                parts = shapes[name] = [(k, c, dict(dims), rot) for k, c, dims, rot in b.outline]
            out.append(DiagramBody(
                name, b.kind, x if x is not None else math.nan, y if y is not None else math.nan,
                ang or 0.0, x is not None and y is not None, parts,
                None if None in vi else vi, None if None in vj else vj,
                None if particle else vel(name, ".omega", at_i, gi),
                None if particle else vel(name, ".omega", at_j, gj), particle))
            if ang is None and not particle and _turns(b):
                self.notes.append(f"{name}'s angle is not known at state {i}: drawn at 0")
        return out

    # -- positions: known, or from the pins, joints and contacts that tie a body to another
    def _place(self, bodies: list[DiagramBody], notes: bool = True) -> None:
        """Known positions first; then what pins, welds and contacts tie to a placed body;
        a group that nothing places starts at a schematic spot, in a row beside the rest.
        `notes`: say what is drawn schematically (a drawing's; the text lines never read
        them)."""
        if all(b.placed for b in bodies):  # every position known: nothing to tie
            return
        where = {b.name: b for b in bodies}
        ties = self._ties()
        size = self._size()
        row = 0.0
        guessed = []
        while True:
            self._propagate(bodies, where, ties)
            loose = [b for b in bodies if not b.placed]
            if not loose:
                break
            b = loose[0]
            missing = [q for q, v in (("x", b.x), ("y", b.y)) if math.isnan(v)]
            if len(missing) == 1:  # one coordinate given: the other one does not matter here
                if notes:
                    self.notes.append(f"{b.name}.{missing[0]} at state {self.t.before} is not "
                                      "known: drawn at 0")
            else:
                guessed.append(b.name)
            b.x = row if math.isnan(b.x) else b.x
            b.y = 0.0 if math.isnan(b.y) else b.y
            row = max(row, b.x) + 2.5 * size
            b.placed = True
        if guessed and notes:
            self.notes.append(f"positions at state {self.t.before} are not known: "
                              f"{name_list(guessed, 'bodies')} drawn schematically"
                              + (" (the rest where contacts and joints put them)"
                                 if len(guessed) < len(bodies) else ""))

    def _propagate(self, bodies, where, ties) -> None:
        moved = True
        while moved:
            moved = False
            for b in bodies:
                if b.placed:
                    continue
                for other, mine, theirs, normal, gap in ties.get(b.name, ()):
                    anchor = self._world(theirs, where, other) if other else theirs.offset
                    if anchor is None:
                        continue
                    r = _rot(mine.offset, b.angle) if not mine.round_contact else (0.0, 0.0)
                    sep = (normal[0] * gap, normal[1] * gap) if normal else (0.0, 0.0)
                    b.x, b.y = anchor[0] - r[0] + sep[0], anchor[1] - r[1] + sep[1]
                    b.placed = moved = True
                    break

    def _size(self) -> float:
        """A length for schematic spacing: the largest body, or 1 m."""
        return self.shared.size

    def _ties(self) -> dict:
        """body -> [(other body or None, its point, the other's point, normal, gap)]."""
        ties: dict = {}
        size = self._size()
        for jt in self.sc.joints:
            if jt.kind not in (JointKind.PIN, JointKind.WELD):
                continue
            ties.setdefault(jt.a.body, []).append((jt.b.body, jt.a, jt.b, None, 0.0))
            if jt.b.body:
                ties.setdefault(jt.b.body, []).append((jt.a.body, jt.b, jt.a, None, 0.0))
        for c in (self.spec.contacts if self.spec else ()):
            if c.b is None or c.b.body is None or c.normal is None:
                continue
            ra = self.sc.bodies[c.a.body].radius if c.a.round_contact else None
            rb = self.sc.bodies[c.b.body].radius if c.b.round_contact else None
            gap = (ra or 0.0) + (rb or 0.0) if (ra or rb) else 0.6 * size
            n = c.normal  # a is on the +n side of b
            ties.setdefault(c.a.body, []).append((c.b.body, c.a, c.b, n, gap))
            ties.setdefault(c.b.body, []).append((c.a.body, c.b, c.a, (-n[0], -n[1]), gap))
        return ties

    def _world(self, p, where: dict, body: str | None):
        b = where.get(body)
        if b is None or not b.placed:
            return None
        r = (0.0, 0.0) if p.round_contact else _rot(p.offset, b.angle)
        return (b.x + r[0], b.y + r[1])

    # -- the impulses of one application, split into their unknowns
    def _impulses(self, a, body: DiagramBody) -> list[DiagramImpulse]:
        t, vals = self.t, self.values
        # J linear in impulses, one per component (a contact's J_n along its normal): the
        # direction of each is read off its coefficients, as the two evaluations give it
        mono = _monomials(a.J) if a.torque is None else None
        if mono is not None:
            ax, ay = a.arm.x, a.arm.y
            tx, ty = type(ax), type(ay)
            if PLAIN and (tx is Const or tx is Known) and (ty is Const or ty is Known):
                return self._plain_impulses(a, body, mono)
            names = set(mono)
            torque = _NO_NAMES
        else:
            names = variables(a.J.x)
            variables(a.J.y, names)
            torque = variables(a.torque) if a.torque is not None else _NO_NAMES
        # an unknown nothing solved (an angle not needed) reads 0: the values themselves
        # where every name is solved or an impulse (no layer over them for most impulses)
        ax, ay = a.arm.x, a.arm.y
        tx, ty = type(ax), type(ay)
        p = a.point
        if mono is not None and (tx is Const or tx is Known) and (ty is Const or ty is Known):
            # the commonest: impulses alone (never read through a layer) and a known arm,
            # as `evaluate` reads its leaves
            base = vals
            arm = (ax.value, ay.value) if p.round_contact or p.located_by is not None else \
                (0.0, 0.0) if body.particle else _rot(p.offset, body.angle)
        else:
            arm_names = variables(ax)
            variables(ay, arm_names)
            over = {}
            for group in (names, arm_names, torque):
                for n in group:
                    if n not in vals and n not in over and not _impulse(n):
                        over[n] = 0.0
            base = _Over(vals, over) if over or a.torque is not None else vals
            if p.round_contact or p.located_by is not None:
                try:
                    arm = (evaluate(ax, base), evaluate(ay, base))
                except (KeyError, ValueError, ZeroDivisionError):
                    arm = (0.0, 0.0)
            else:
                arm = (0.0, 0.0) if body.particle else _rot(p.offset, body.angle)
        at, point = _where(a, body, arm)
        out = []
        imp = sorted((n for n in names if _impulse(n)), key=str)
        imp_set = set(imp)
        contact = self._contacts().get(a.what)
        if imp:
            # what J and the torque read, as `base` over the impulses at 0 reads it, in one
            # plain dict (a lookup through no layers; a name `base` lacks stays missing)
            zero = {}
            for n in (names | torque) if mono is None else ():
                if n in imp_set:
                    zero[n] = 0.0
                else:
                    try:
                        zero[n] = base[n]
                    except KeyError:
                        pass
            for n in imp:
                if mono is not None:
                    d = mono[n]
                else:
                    one = dict(zero)
                    one[n] = 1.0
                    try:
                        d = (evaluate(a.J.x, one) - evaluate(a.J.x, zero),
                             evaluate(a.J.y, one) - evaluate(a.J.y, zero))
                    except (KeyError, ValueError, ZeroDivisionError):
                        continue
                size = math.hypot(*d)
                if size == 0:
                    continue
                d = (d[0] / size, d[1] / size)
                symbol = _symbol(n, d, contact)
                val = vals.get(n)
                where, pos = point, at
                c = self._moment_of(a, n, zero, torque)
                if c:  # applied at G with its moment: drawn on its line of action
                    pos = (at[0] + c / size * d[1], at[1] - c / size * d[0])
                    where = "its line of action"
                out.append(DiagramImpulse(a.body, _local(n), a.what, where, pos, d,
                                          direction_words(d, symbol),
                                          None if val is None else val * size))
        elif not _zero_vec(a.J):
            try:
                J = (evaluate(a.J.x, vals), evaluate(a.J.y, vals))
            except (KeyError, ValueError, ZeroDivisionError):
                J = None
            name = _applied_name(a.what, t.kind)
            if J is None or math.hypot(*J) == 0:
                out.append(DiagramImpulse(a.body, name, a.what, point, at, None, "unknown",
                                          None))
            else:
                m = math.hypot(*J)
                d = (J[0] / m, J[1] / m)
                out.append(DiagramImpulse(a.body, name, a.what, point, at, d,
                                          direction_words(d), m))
        if a.torque is not None:
            out.extend(self._moments(a, body, at, point, base))
        return out

    def _plain_impulses(self, a, body: DiagramBody, mono: dict) -> list[DiagramImpulse]:
        """`_impulses` of the commonest application, without its general steps: impulses
        alone (each name of `mono` an impulse, no torque: no moment of its own) and a
        known arm, its values read as `evaluate` reads its leaves."""
        vals, p = self.values, a.point
        if p.round_contact or p.located_by is not None:
            arm = (a.arm.x.value, a.arm.y.value)
        else:
            arm = (0.0, 0.0) if body.particle else _rot(p.offset, body.angle)
        at, point = _where(a, body, arm)
        contact = self._contacts().get(a.what)
        out = []
        for n in (mono if len(mono) == 1 else sorted(mono, key=str)):
            d = mono[n]
            size = math.hypot(*d)
            if size == 0:
                continue
            d = (d[0] / size, d[1] / size)
            val = vals.get(n)
            out.append(DiagramImpulse(a.body, _local(n), a.what, point, at, d,
                                      direction_words(d, _symbol(n, d, contact)),
                                      None if val is None else val * size))
        return out

    @staticmethod
    def _moment_of(a, n, zero: dict, torque: set) -> float:
        """The moment about G per unit of impulse n that an element adds to its
        application (a slider's reaction acts where the collar is, not at G); `torque`:
        the unknowns of its torque."""
        if a.torque is None or n not in torque:
            return 0.0
        try:
            return evaluate(a.torque, {**zero, n: 1.0}) - evaluate(a.torque, zero)
        except (KeyError, ValueError, ZeroDivisionError):
            return 0.0

    def _moments(self, a, body, at, point, base) -> list[DiagramImpulse]:
        names = sorted((n for n in variables(a.torque)
                        if getattr(n, "kind", None) is KeyKind.ANGULAR_IMPULSE), key=str)
        out = []
        for n in names:
            val = self.values.get(n)
            zero = base.over({k: 0.0 for k in names})
            try:
                s = evaluate(a.torque, zero.over({n: 1.0})) - evaluate(a.torque, zero)
            except (KeyError, ValueError, ZeroDivisionError):
                continue
            if s == 0:
                continue
            words = "counter-clockwise" if s > 0 else "clockwise"
            out.append(DiagramImpulse(a.body, _local(n), a.what, point, at, None, words,
                                      None if val is None else val * abs(s), True))
        if not names and not any(_impulse(n) for n in variables(a.torque)):
            # a known moment integrated over the interval
            try:
                m = evaluate(a.torque, self.values)
            except (KeyError, ValueError, ZeroDivisionError):
                m = None
            out.append(DiagramImpulse(a.body, _applied_name(a.what, self.t.kind), a.what,
                                      point, at, None, "counter-clockwise", m, True))
        return out

    # -- what is not impulsive
    def _dropped(self) -> list[Dropped]:
        t, sc = self.t, self.sc
        moved = set(t.bodies)
        out = []
        impact = t.kind == "impact"
        zero = "finite force x zero duration = no impulse"
        if impact:
            if sc.gravity is not None:
                for b in t.bodies:
                    W, unit = self.reader.show(sc.bodies[b].mass * math.hypot(*sc.gravity),
                                               FORCE, "N")
                    out.append(Dropped(b, f"weight of {b} ({fmt_num(W, SIG)} {unit}, "
                                          f"{direction_words(_unit(sc.gravity))})", zero))
            for _, p, _ in (self.spec.forces if self.spec else ()):
                out.append(Dropped(p.body, f"force at {p.name}", zero))
        if sc.gravity is None and sc.g is not None:
            out.append(Dropped(None, "weights", "act into the plane: no impulse in it"))
        for jt in sc.joints:
            if jt.kind in (JointKind.SPRING, JointKind.DAMPER) and \
                    ({jt.a.body, jt.b.body} & moved):
                why = zero if impact else ("not a constant force: its work enters the energy "
                                           "phases")
                out.append(Dropped(None, f"{jt.kind} {jt.label}", why))
        for c in (self.spec.contacts if self.spec else ()):
            if c.normal is not None and _smooth(c.mode):
                out.append(Dropped(c.a.body, f"friction at {c.label}",
                                   "smooth contact: no tangential impulse"))
        return out

    def _surfaces(self, bodies) -> list[DiagramSurface]:
        """The ground or surface each contact of the transition pushes from, through the
        point it touches."""
        out = []
        where = {b.name: b for b in bodies}
        for c in (self.spec.contacts if self.spec else ()):
            if c.b is not None and c.b.body is not None or c.normal is None:
                continue
            b = where.get(c.a.body)
            if b is None:
                continue
            if c.a.round_contact and self.sc.bodies[c.a.body].radius:
                r = self.sc.bodies[c.a.body].radius
                p = (b.x - r * c.normal[0], b.y - r * c.normal[1])
            else:
                r = (0.0, 0.0) if b.particle else _rot(c.a.offset, b.angle)
                p = (b.x + r[0], b.y + r[1])
                rim = _rim(b, p)  # the centre of a round part: it touches at its rim
                p = (p[0] - rim * c.normal[0], p[1] - rim * c.normal[1])
            out.append(DiagramSurface(c.surface or "ground", p, c.normal))
        return out

    def _links(self, where: dict) -> list:
        """Joints and springs between two drawn bodies whose points lie apart: a light
        pole, a link, a spring, drawn from one point to the other."""
        out = []
        for jt in self.sc.joints:
            if jt.b.body is None or jt.a.body not in where or jt.b.body not in where:
                continue
            pa, pb = self._world(jt.a, where, jt.a.body), self._world(jt.b, where, jt.b.body)
            if pa and pb and math.hypot(pa[0] - pb[0], pa[1] - pb[1]) > 1e-9:
                out.append((jt.label, str(jt.kind), pa, pb))
        return out

    def _pins(self) -> list:
        return [(jt.label, jt.b.offset) for jt in self.sc.joints
                if jt.kind in (JointKind.PIN, JointKind.WELD) and jt.b.body is None
                and jt.a.body in self.t.bodies]


_NO_NAMES: frozenset = frozenset()


def _monomial(e):
    """(impulse name or None, coefficient) of a component that is a finite constant, an
    impulse, or a nonzero finite constant times an impulse; None for anything else."""
    t = type(e)
    if t is Const or t is Known:
        v = e.value
        return (None, 0.0) if type(v) is float and v - v == 0.0 else None
    if t is Var:
        return (e.name, 1.0) if _impulse(e.name) else None
    if t is Mul and len(e.factors) == 2:
        f, g = e.factors
        if type(f) is Var:
            f, g = g, f
        if (type(f) is Const or type(f) is Known) and type(g) is Var and _impulse(g.name):
            c = f.value
            if type(c) is float and c - c == 0.0 and c != 0.0:
                return g.name, c
    return None


def _monomials(J) -> dict | None:
    """impulse name -> (d J.x, d J.y) per unit of it, for a J each of whose components
    is a `_monomial` (the differences `evaluate(J, one) - evaluate(J, zero)` give: the
    coefficient where the impulse is, 0.0 elsewhere); None otherwise, or with no impulse."""
    mx, my = _monomial(J.x), _monomial(J.y)
    if mx is None or my is None or (mx[0] is None and my[0] is None):
        return None
    out = {}
    if mx[0] is not None:
        out[mx[0]] = (mx[1], my[1] if my[0] == mx[0] else 0.0)
    if my[0] is not None and my[0] != mx[0]:
        out[my[0]] = (0.0, my[1])
    return out


def _arm(arm, vals) -> tuple:
    """The arm of an application whose arm is a tree and whose J is `_monomials`' (its
    names impulses), as `_Builder._impulses` evaluates it: an unknown nothing solved (an
    angle not needed) reads 0; (0, 0) where it cannot be evaluated."""
    ax, ay = arm.x, arm.y
    names = variables(ax)
    variables(ay, names)
    over = {}
    for n in names:
        if n not in vals and n not in over and not _impulse(n):
            over[n] = 0.0
    base = _Over(vals, over) if over else vals
    try:
        return (evaluate(ax, base), evaluate(ay, base))
    except (KeyError, ValueError, ZeroDivisionError):
        return (0.0, 0.0)


class _Over(dict):
    """Values with a few overridden (a dict over another, without copying it)."""

    def __init__(self, under, over=None):
        super().__init__(over or {})
        self.under = under

    def __missing__(self, k):
        return self.under[k]

    def setdefault(self, k, v):
        if k not in self and k not in self.under:
            self[k] = v
        return self[k]

    def over(self, more: dict) -> "_Over":
        return _Over(self, more)


def _symbol(n, d: tuple, contact) -> str | None:
    """`n` or `t` (or `-n`, `-t` on the contact's second body) for a contact's impulse."""
    comp = getattr(n, "comp", None)
    if contact is None or comp not in (Component.JN, Component.JT):
        return None
    nx, ny = contact.normal
    ref = (nx, ny) if comp is Component.JN else (-ny, nx)
    sym = "n" if comp is Component.JN else "t"
    return sym if ref[0] * d[0] + ref[1] * d[1] > 0 else "-" + sym


def _rim(b: DiagramBody, p: tuple) -> float:
    """The radius of the round part of b centred at p (0 if none)."""
    for kind, c, dims, _ in b.parts:
        w = _rot(c, b.angle)
        if dims.get("radius") and math.hypot(b.x + w[0] - p[0], b.y + w[1] - p[1]) < \
                1e-9 * max(1.0, dims["radius"]):
            return dims["radius"]
    return 0.0


_SMOOTH: dict = {}  # a contact's mode -> whether it is smooth (the enum's lookup once)


def _smooth(mode) -> bool:
    """`Tangential(mode) is Tangential.SMOOTH`, each mode looked up once."""
    got = _SMOOTH.get(mode)
    if got is None:
        got = Tangential(mode) is Tangential.SMOOTH
        if len(_SMOOTH) < 64:
            _SMOOTH[mode] = got
    return got


def _impulse(n) -> bool:
    return isinstance(n, Key) and n.kind is KeyKind.IMPULSE


def _local(n) -> str:
    return n.local if isinstance(n, Key) else str(n)


def _zero_vec(J) -> bool:
    return J.is_zero()


def _applied_name(what: str, kind: str) -> str:
    """The impulse of a finite force over an interval: `weight of rod x t`."""
    return f"{what} x t" if kind == "interval" else what


def _unit(v) -> tuple:
    n = math.hypot(*v)
    return (v[0] / n, v[1] / n)


def _rot(r, angle: float) -> tuple:
    c, s = math.cos(angle), math.sin(angle)
    return (r[0] * c - r[1] * s, r[0] * s + r[1] * c)


def _turns(b) -> bool:
    return b.kind != "particle"


def _extent(b) -> float:
    """The largest size of a body's shapes (m)."""
    out = 0.0
    for _, (cx, cy), dims, _ in b.outline:
        d = dict(dims)
        half = max(d.get("radius", 0.0), d.get("length", 0.0) / 2,
                   math.hypot(d.get("width", 0.0), d.get("height", 0.0)) / 2)
        out = max(out, 2 * (half + math.hypot(cx, cy)))
    return out
