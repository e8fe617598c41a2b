"""Build: syntax nodes -> Scene (names resolved, SI floats, inertias, unit vectors).

Every quantity is converted to SI here, once, and its dimension checked at its
line:column. Inertias come from the shape formulas and, for composite bodies, the
parallel-axis theorem. Weights become masses with the file's own g.
"""
from __future__ import annotations

import math
import sys

from . import syntax as S
from .diagnostics import Collector, ProblemError, did_you_mean
from .elements.kinds import Clause, JointKind, Prop, Restitution, Tangential, TransitionKind
from .elements.geometry import centre, line_of_centres
from .expr import Const, hypot
from .quantity import Evaluator, Q, constant, constant_vector, unit_readings
from .records import field, record
from .source import Span
from .unit_system import FileUnits
from .unit_system import detect as detect_units
from .units import (
    ACCELERATION,
    FORCE,
    INERTIA,
    LENGTH,
    MASS,
    MOMENT,
    NONE,
    RATE,
    STIFFNESS,
    TIME,
    VELOCITY,
    Dim,
    describe,
    reading_for,
    si_label,
)

# quantity name in a state -> (dimension, SI unit label)
STATE_QTYS: dict[str, tuple[Dim, str]] = {
    "x": (LENGTH, "m"), "y": (LENGTH, "m"), "angle": (NONE, "rad"),
    "vx": (VELOCITY, "m/s"), "vy": (VELOCITY, "m/s"), "omega": (RATE, "rad/s"),
}
VECTOR_QTYS = {"v": ("vx", "vy"), "pos": ("x", "y")}
_AT_REST_PARTICLE, _AT_REST = ("vx", "vy"), ("vx", "vy", "omega")  # what `B at rest` gives
ROTATION_QTYS = ("angle", "omega")


@record(frozen=True)
class Body:
    name: str
    span: Span
    kind: str
    mass: float
    inertia: float  # about G, kg*m^2
    inertia_formula: str
    radius: float | None = None  # round bodies: contact point is at G - r n
    length: float | None = None  # rods: ends at +-length/2 along body x
    is_particle: bool = False  # no rotation unknowns
    origin: tuple[float, float] = (0.0, 0.0)  # the user's body-frame origin, from G
    weight_given: bool = False
    # its shapes, for drawing: (kind, centre from G in the body frame, ((dim, value), ...),
    # rotation in rad); one for a simple body, each part of a composite
    outline: tuple = ()


@record(frozen=True)
class Symbolic:
    """A value the file writes with unknowns (`force (P, 0)`, `duration 2 s - t@1->2`,
    `point Q = rod at (d, 0)`): compile evaluates it among the other unknowns and checks
    its dimension there. `shift` is added to a vector (a point's offset from G)."""

    node: object
    dim: Dim
    what: str
    vector: bool
    shift: tuple[float, float] = (0.0, 0.0)


@record(frozen=True)
class PointOn:
    """A point of a body (offset from G in the body frame) or of the ground (world)."""

    body: str | None  # None: the ground
    offset: tuple[float, float]
    name: str
    span: Span
    round_contact: bool = False  # a round body's contact point: G - r n, in the world frame
    located_by: Symbolic | None = None  # the offset, when an unknown locates the point


@record(frozen=True)
class Joint:
    kind: JointKind  # pin | weld | link | spring (| damper: simulate)
    label: str
    a: PointOn
    b: PointOn
    span: Span
    along: tuple[float, float] | None = None
    stiffness: float | None = None
    length: float | None = None
    from_state: str | None = None  # holds only from this state on


@record(frozen=True)
class Contact:
    label: str
    span: Span
    a: PointOn
    b: PointOn | None  # None: the ground or a fixed surface
    normal: tuple[float, float] | None  # unit, the impulse on `a`; None: plan-view friction
    restitution: float | None
    restitution_unknown: bool
    mode: Tangential  # smooth | rough | friction
    mu: float | None
    slip: tuple[float, float] | None
    surface: str | None = None
    restitution_name: str | None = None  # a declared `unknown` used as this contact's e
    separation: float | None = None  # the relative normal speed after an impact, if given
    law: Restitution = Restitution.NEWTON  # how the normal impulse ends (elements/contacts.py)
    law_span: Span | None = None  # where the file states the normal law (`restitution ...`)
    mu_static: float | None = None  # `static 0.4`: checked against the friction a no-slip needs


@record
class StateSpec:
    id: str
    label: str | None
    span: Span
    givens: dict[tuple[str, str], tuple[float, Span]] = field(default_factory=dict)
    hints: dict[tuple[str, str], list[tuple[str, float, Span]]] = field(default_factory=dict)
    rolls: list[tuple[str, str, Span]] = field(default_factory=list)


@record
class TransitionSpec:
    kind: TransitionKind
    before: str
    after: str
    span: Span
    contacts: list[Contact] = field(default_factory=list)
    bearing_friction: list[tuple[str, Span]] = field(default_factory=list)
    stops_relative: list[tuple[str, str, Span]] = field(default_factory=list)
    stops: list[tuple[str, Span]] = field(default_factory=list)
    rolls: list[tuple[str, str, Span]] = field(default_factory=list)
    # a force or moment is a constant, or a Symbolic when it names unknowns
    forces: list[tuple[tuple[float, float] | Symbolic, PointOn, Span]] = \
        field(default_factory=list)
    moments: list[tuple[float | Symbolic, str, Span]] = field(default_factory=list)
    duration: float | None = None
    groups: list[tuple[str, ...]] = field(default_factory=list)  # energy `of {rod}, {ball}`
    free: list[str] = field(default_factory=list)  # energy `free ball`: a balance of its own
    duration_expr: Symbolic | None = None  # a duration that names unknowns

    @property
    def key(self) -> str:
        return f"{self.before}->{self.after}"


@record(frozen=True)
class Surface:
    name: str
    normal: tuple[float, float] | None
    at: tuple[float, float]
    span: Span
    located: bool = False  # `at` was given (a simulation needs to know where it is)


@record(frozen=True)
class StatedMomentum:
    span: Span
    direction: tuple[float, float]
    axis_text: str
    bodies: tuple[str, ...]
    before: str
    after: str


@record(frozen=True)
class StatedAngular:
    span: Span
    bodies: tuple[str, ...]
    about: PointOn
    before: str
    after: str


@record(frozen=True)
class StatedRestitution:
    span: Span
    value: float
    a: PointOn
    b: PointOn | None
    along: tuple[float, float]
    before: str
    after: str


@record
class Scene:
    title: str
    gravity: tuple[float, float] | None  # the planar gravity vector (None: no planar effect)
    g: float | None  # the file's g (for weights and `g` in expressions)
    constants: dict[str, Q]
    user_unknowns: dict[str, tuple[Dim, str, Span]]
    bodies: dict[str, Body]
    points: dict[str, PointOn]
    surfaces: dict[str, Surface]
    joints: list[Joint]
    states: dict[str, StateSpec]
    transitions: list[TransitionSpec]
    stated: list  # StatedMomentum | StatedAngular | StatedRestitution
    equations: list[S.UserEquation]
    finds: list[S.FindItem]
    notes: Collector
    gravity_span: Span | None = None
    steady: list = field(default_factory=list)  # syntax.SteadyDecl: compiled by flows.py
    burns: list = field(default_factory=list)  # syntax.BurnDecl: compiled by flows.py
    gains: list = field(default_factory=list)  # syntax.GainDecl: compiled by accretion.py
    simulations: list = field(default_factory=list)  # sim.spec.SimSpec: `momentum simulate`
    expects: list = field(default_factory=list)  # expectations.ExpectSpec: `expect` lines
    file_units: FileUnits = field(default_factory=FileUnits)  # the units the file is written in


SHAPES = {
    "particle": ({"mass", "weight", "radius"}, "0 (a particle)"),
    "rod": ({"mass", "weight", "length"}, "m*L^2/12"),
    "disk": ({"mass", "weight", "radius"}, "m*r^2/2"),
    "cylinder": ({"mass", "weight", "radius"}, "m*r^2/2"),
    "ring": ({"mass", "weight", "radius"}, "m*r^2"),
    "hoop": ({"mass", "weight", "radius"}, "m*r^2"),
    "sphere": ({"mass", "weight", "radius"}, "2*m*r^2/5"),
    "shell": ({"mass", "weight", "radius"}, "2*m*r^2/3"),
    "plate": ({"mass", "weight", "width", "height"}, "m*(w^2 + h^2)/12"),
    "rigid": ({"mass", "weight", "inertia", "gyration", "radius"}, "given"),
}
ROUND = {"disk", "cylinder", "ring", "hoop", "sphere", "shell"}
ARG_DIMS = {"mass": MASS, "weight": FORCE, "radius": LENGTH, "length": LENGTH, "width": LENGTH,
            "height": LENGTH, "inertia": INERTIA, "gyration": LENGTH}


MASS_RATE: Dim = (1, 0, -1)  # kg/s
# Magnitudes past these (in SI units) are refused: a subnormal float (below TINY) has
# lost its digits already; above 1e150 the squares and products the laws form overflow
# float64's 1.8e308.
TINY = sys.float_info.min
HUGE = 1e150


def _in_range(v: float, node, what: str, small: float = TINY) -> float:
    """`v`, or a located error when it is subnormal (below `small`) or too large to
    square."""
    if v != 0 and abs(v) < small:
        lost = f"below the smallest normal float ({TINY:.3g}): its digits are lost"
        raise ProblemError(f"{what} is {v:g}, {lost}", node.span, code="number",
                           notes=["use a larger unit, or a value that is not zero in effect"])
    if abs(v) > HUGE:
        raise ProblemError(f"{what} is {v:g}: too large for the products and squares the "
                           f"laws form (at most {HUGE:g} in SI units)", node.span, code="number",
                           notes=["use a unit that brings the value nearer 1"])
    return v


def unit_direction(x: float, y: float, node, what: str) -> tuple[float, float]:
    """(x, y) normalised, scaled first so that neither overflow nor subnormal
    components spoil it; a located error for a zero or non-finite direction."""
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ProblemError(f"{what} is not finite", node.span, code="number")
    scale = max(abs(x), abs(y))
    if 0 < scale < TINY:
        raise ProblemError(f"{what} has a length of {math.hypot(x, y):g}, below the smallest "
                           f"normal float ({TINY:.3g}): its direction cannot be trusted",
                           node.span, code="number",
                           notes=["write the direction with components near 1"])
    if scale == 0:
        raise ProblemError(f"{what} must be a non-zero direction", node.span, code="number")
    n = hypot(x, y)  # math.hypot, also for a sweep's traced numbers
    if not (TINY < n < math.inf):  # scaled first only where the length itself would not be
        x, y = x / scale, y / scale  # a normal float (as x / hypot rounds best elsewhere)
        n = hypot(x, y)
    return (x / n, y / n)


def build(doc: S.Document) -> Scene:
    """Resolve names, convert to SI and compute inertias; raise ProblemError on misuse."""
    b = _Builder(doc)
    try:
        return b.run()
    finally:  # the builder <-> evaluator cycle would keep the document alive until a
        b.ev = None  # cyclic collection (paused during a solve): break it here


_LEAF: dict = {}  # statement class -> whether no class derives from it
# the value of a literal number or vector in SI (its number, sign, unit and dimension: a
# batch of variants repeats most of them), and of a literal direction; an error is not kept
_LITERALS: dict = {}
_TRANSITION_KINDS = {k.value: k for k in TransitionKind}  # a kind's word -> the kind
_FACTORS: dict = {}  # (unit, dimension) -> the factor of its reading (_literal)

CONTACT_MEMO = True  # the memos of bodies and contacts; tests switch them off to compare
CONTACT_MEMO_FROM = 64  # bodies (transitions' clauses) in a file: fewer, no memo (a small
# file pays nothing); a memo of more distinct keys than MEMO_KINDS is dropped (no repeats)
MEMO_KINDS = 512


def _shape_key(shape):
    """What a one-shape body's mass, inertia and sizes depend on, when its arguments are
    literal numbers or named constants (`particle(mass = m, radius = 15 mm)`); None for
    anything else (the full walk)."""
    key = [shape.kind]
    for a in shape.args:
        v = a.value
        t = type(v)
        if t is S.Num and type(v.value) is float:
            key.append((a.name, v.value, math.copysign(1.0, v.value), v.unit))
        elif t is S.Ref and v.member is None and v.index is None and not v.at and \
                v.about is None:
            key.append((a.name, v.name))
        else:
            return None
    return tuple(key)


def _contact_key(c, kind):
    """What a contact clause's normal, law and friction depend on, when that is only
    literal numbers (a direction, `restitution 0.5`, `friction 0.3`) and the
    transition's kind: a big file repeats one such clause between other bodies. None
    for anything else (a named constant or unknown, an expression: the full walk)."""
    n = c.normal
    if type(n) is not S.VecLit:
        return None
    x, y = n.x, n.y
    if type(x) is not S.Num or type(y) is not S.Num or type(x.value) is not float or \
            type(y.value) is not float:
        return None
    key = [kind, x.value, math.copysign(1.0, x.value), x.unit, y.value,
           math.copysign(1.0, y.value), y.unit]
    for p in c.props:
        v = p.value
        if v is None:
            key.append((p.kind, p.law))
        elif type(v) is S.Num and type(v.value) is float:
            key.append((p.kind, p.law, v.value, math.copysign(1.0, v.value), v.unit))
        else:
            return None
    return tuple(key)
LITERALS_LIMIT = 4096


class _Kinds:
    """The document's statements by kind: `of(A, B)` are those that are an A or a B, in
    file order; grouped by type once, so each of the builder's passes walks only its own
    kinds (a 10^4-impact file has 3 x 10^4 statements and 25 passes)."""

    __slots__ = ("_st", "_by")

    def __init__(self, st):
        by: dict = {}
        for s in st:
            k = type(s)
            if k is tuple:  # a line kept as its text (scene_deferred): its node's class
                k = s[0]
            got = by.get(k)
            if got is None:
                by[k] = [s]
            else:
                got.append(s)
        self._st, self._by = st, by

    def __call__(self, *kinds) -> list:
        if len(kinds) == 1:  # most passes ask for one kind, which no statement type extends
            leaf = _LEAF.get(kinds[0])
            if leaf is None:
                leaf = _LEAF[kinds[0]] = not kinds[0].__subclasses__()
            if leaf:
                return self._by.get(kinds[0], [])
        types = [t for t in self._by if issubclass(t, kinds)]
        if not types:
            return []
        if len(types) == 1:
            return self._by[types[0]]
        return [s for s in self._st if isinstance(s, kinds) or
                (type(s) is tuple and issubclass(s[0], kinds))]


class _Builder:
    def __init__(self, doc: S.Document):
        self.doc = doc
        self.notes = Collector()
        self.constants: dict[str, Q] = {}
        self.g: float | None = None
        self.gravity: tuple[float, float] | None = None
        self.gravity_span = None
        self.ev = Evaluator(self._resolve_constant)
        self._contacts_seen: dict | None = None  # _contact's memo (a big file's)
        self._deferred = None  # the reader of lines kept as text (a big file's)
        self._bodies_seen: dict | None = None  # _body's memo (a big file's)
        self._outlines: dict | None = None  # _body's drawings, one tuple each (a big file's)
        self.bodies: dict[str, Body] = {}
        self.points: dict[str, PointOn] = {}
        self.surfaces: dict[str, Surface] = {}
        self.user_unknowns: dict[str, tuple[Dim, str, Span]] = {}

    # ---- names in constant expressions
    def _resolve_constant(self, ref: S.Ref, expect) -> Q:
        if ref.index is None and ref.member is None and not ref.at:
            if ref.name in self.constants:
                return self.constants[ref.name]
            if ref.name == "pi":
                return Q(Const(math.pi), NONE)
            if ref.name == "g":
                if self.g is None:
                    raise ProblemError("'g' is used but no gravity is declared", ref.span,
                                       code="name", notes=["add a line such as "
                                                           "`gravity 9.81 m/s^2 down`"])
                return Q(Const(self.g), ACCELERATION)
        names = list(self.constants) + ["pi", "g"]
        if ref.member or ref.at or ref.index:
            raise ProblemError(f"'{ref.text}' is not a constant; only constants can be used here",
                               ref.span, code="name")
        raise ProblemError(f"unknown name '{ref.name}'" + did_you_mean(ref.name, names),
                           ref.span, code="name")

    def value(self, node, dim: Dim, what: str) -> float:
        if type(node) is S.Num and type(node.value) is float:
            # a literal: its value depends on its number, unit and dimension only (a big
            # file repeats a few: `restitution 0.5`, `mass = 2 kg`); errors are not kept
            x = node.value
            key = (x, math.copysign(1.0, x), node.unit, dim)
            hit = _LITERALS.get(key)
            if hit is None:
                hit = self._literal(node, dim, what)
                if len(_LITERALS) >= LITERALS_LIMIT:
                    _LITERALS.clear()
                _LITERALS[key] = hit
            return hit
        return self._value(node, dim, what)

    def _literal(self, node, dim: Dim, what: str) -> float:
        """`_value` of a float literal. With a unit read before for this dimension, its
        number times the unit's factor (the product `Evaluator.ev` makes): a big file's
        distinct numbers in one unit (`mass = 0.0213 kg`) skip the unit's parse."""
        unit = node.unit
        if unit is None:
            return self._value(node, dim, what)
        factor = _FACTORS.get((unit, dim))
        if factor is not None:
            v = node.value * factor
            if math.isfinite(v):
                return _in_range(v, node, what)
            return self._value(node, dim, what)  # its error
        v = self._value(node, dim, what)
        factor, got = reading_for(unit_readings(unit, node.unit_span, dim), dim)
        if got == dim:
            if len(_FACTORS) >= LITERALS_LIMIT:
                _FACTORS.clear()
            _FACTORS[(unit, dim)] = factor
        return v

    def _value(self, node, dim: Dim, what: str) -> float:
        q = self.ev(node, dim)
        if q.is_vector:
            raise ProblemError(f"{what} needs a scalar; got a vector", node.span, code="type")
        self._check_dim(q, dim, node, what)
        v = constant(q, node)
        if not math.isfinite(v):
            raise ProblemError(f"{what} is not a finite number", node.span, code="number")
        _in_range(v, node, what)
        return v

    def vector(self, node, dim: Dim, what: str, ranged: bool = True) -> tuple[float, float]:
        if type(node) is S.VecLit and type(node.x) is S.Num and type(node.y) is S.Num and \
                type(node.x.value) is float and type(node.y.value) is float:
            # a literal vector such as (0, 3 m/s): once per numbers, units and dimension
            a, b = node.x, node.y
            key = (a.value, math.copysign(1.0, a.value), a.unit, b.value,
                   math.copysign(1.0, b.value), b.unit, dim, ranged)
            hit = _LITERALS.get(key)
            if hit is None:
                hit = self._vector(node, dim, what, ranged)
                if len(_LITERALS) >= LITERALS_LIMIT:
                    _LITERALS.clear()
                _LITERALS[key] = hit
            return hit
        return self._vector(node, dim, what, ranged)

    def _vector(self, node, dim: Dim, what: str, ranged: bool) -> tuple[float, float]:
        q = self.ev(node, dim)
        if not q.is_vector:
            raise ProblemError(f"{what} needs a vector such as (1, 0); got a scalar", node.span,
                               code="type")
        self._check_dim(q, dim, node, what)
        v = constant_vector(q, node)
        if not all(math.isfinite(c) for c in v):
            raise ProblemError(f"{what} is not finite", node.span, code="number")
        if ranged:  # the vector's size; a component tiny beside the other is harmless
            _in_range(max(v, key=abs), node, f"the largest component of {what}")
        return v

    def unit_vector(self, node, what: str) -> tuple[float, float]:
        if type(node) is S.VecLit and type(node.x) is S.Num and type(node.y) is S.Num and \
                type(node.x.value) is float and type(node.y.value) is float:
            # a literal direction such as (1, 0): once per numbers and units
            a, b = node.x, node.y
            key = (a.value, math.copysign(1.0, a.value), a.unit, b.value,
                   math.copysign(1.0, b.value), b.unit)
            key = ("direction",) + key
            hit = _LITERALS.get(key)
            if hit is None:
                hit = self._unit_vector(node, what)
                if len(_LITERALS) >= LITERALS_LIMIT:
                    _LITERALS.clear()
                _LITERALS[key] = hit
            return hit
        return self._unit_vector(node, what)

    def _unit_vector(self, node, what: str) -> tuple[float, float]:
        x, y = self.vector(node, NONE, what, ranged=False)  # only the direction counts
        return unit_direction(x, y, node, what)

    def _names_unknowns(self, node) -> bool:
        """Whether an expression names something other than a constant (an `unknown`, a
        state's quantity, `t@1->2`): then compile evaluates it."""
        if isinstance(node, S.Ref):
            plain = node.index is None and node.member is None and not node.at
            return not (plain and (node.name in self.constants or node.name in ("pi", "g")))
        kids = {S.BinOp: ("left", "right"), S.Neg: ("arg",), S.Mag: ("arg",),
                S.VecLit: ("x", "y")}.get(type(node), ())
        if isinstance(node, S.Call):
            return any(self._names_unknowns(a) for a in node.args)
        return any(self._names_unknowns(getattr(node, k)) for k in kids)

    def effect(self, node, dim: Dim, what: str, vector: bool):
        """A force, moment or duration: a constant, or a Symbolic that names unknowns."""
        if self._names_unknowns(node):
            return Symbolic(node, dim, what, vector)
        return self.vector(node, dim, what) if vector else self.value(node, dim, what)

    def _check_dim(self, q: Q, dim: Dim, node, what: str) -> None:
        if q.dim != dim:
            got = describe(q.dim)
            if isinstance(node, S.Num) and node.unit is None and dim != NONE:
                msg = f"{what} needs {describe(dim)} with a unit (e.g. {si_label(dim)})"
            else:
                msg = f"{what} needs {describe(dim)}; got {got}"
            raise ProblemError(msg, node.span, code="units")

    # ---- the passes
    def run(self) -> Scene:
        st = getattr(self.doc, "parts", None)  # a big file's, some lines kept as text
        if st is None:
            st = self.doc.statements
        else:
            from .scene_deferred import Deferred

            self._deferred = Deferred(self, sys.modules[__name__])
        of = _Kinds(st)  # the statements of some kinds, in file order (one pass, not 25)
        title = ""
        for s in of(S.Problem):
            title = s.title
        for s in of(S.Gravity):
            self._gravity(s)
        for s in of(S.Let, S.UnknownDecl):
            if isinstance(s, S.Let):
                self._let(s)
            elif isinstance(s, S.UnknownDecl):
                self._unknown(s)
        if CONTACT_MEMO and len(of(S.BodyDecl)) >= CONTACT_MEMO_FROM:
            self._bodies_seen = {}
            self._outlines = {}
        for s in of(S.BodyDecl):
            if type(s) is tuple:
                self._deferred.body(s)
            else:
                self._body(s)
        for s in of(S.Let):
            if s.name in self.bodies:
                raise ProblemError(f"'{s.name}' is a body; a `let` constant needs another name",
                                   s.span, code="name",
                                   notes=[f"the body is declared at line "
                                          f"{self.bodies[s.name].span.line}"])
        for s in of(S.SurfaceDecl):
            self._surface(s)
        for s in of(S.PointDecl):
            self._point(s)
        joints = [self._joint(s) for s in of(S.Joint)]
        labels: dict[str, Span] = {}
        for j in joints:
            if j.label in labels:
                raise ProblemError(f"two joints are called '{j.label}'", j.span, code="name",
                                   notes=["name them: `pin NAME: A to B`"])
            labels[j.label] = j.span
        self.joints = joints
        states: dict[str, StateSpec] = {}
        declared = {s.id for s in of(S.StateDecl)}
        for s in of(S.Joint):
            if s.from_state is not None and \
                    s.from_state not in declared:
                raise ProblemError(f"state {s.from_state} is not declared" +
                                   did_you_mean(s.from_state, declared), s.from_span,
                                   code="name")
        for s in of(S.StateDecl):
            if s.id in states:
                raise ProblemError(f"state {s.id} is declared twice", s.span, code="name")
            states[s.id] = self._state(s)
        transitions = []
        by_key: dict[str, list] = {}  # the transitions on each pair of states, in file order
        if CONTACT_MEMO and sum(len(s.clauses) if type(s) is not tuple else
                                self._deferred.clause_count(s)
                                for s in of(S.Transition)) >= CONTACT_MEMO_FROM:
            self._contacts_seen = {}  # many clauses (contacts): a memo
        for s in of(S.Transition):
            if type(s) is tuple:
                t = self._deferred.transition(s, states)
            else:
                t = self._transition(s, states)
            for other in by_key.get(t.key, ()):
                # an energy statement beside an impact is a redundant statement to
                # check (true for e = 1); two impacts or intervals contradict
                if other.key == t.key and TransitionKind.ENERGY not in (t.kind, other.kind):
                    raise ProblemError(
                        f"states {t.before} -> {t.after} have two transitions: this "
                        f"{t.kind} (line {t.span.line}) and the {other.kind} at line "
                        f"{other.span.line}", t.span, code="name",
                        notes=["one transition joins two states; give the second its own "
                               "states"])
            transitions.append(t)
            by_key.setdefault(t.key, []).append(t)
        stated = []
        for s in of(S.ConserveMomentum, S.ConserveAngular, S.RestitutionLaw):
            if isinstance(s, S.ConserveMomentum):
                stated.append(self._stated_momentum(s, states))
            elif isinstance(s, S.ConserveAngular):
                self._states_exist(states, s.before, s.after, s.span)
                self._body_names(s.bodies, s.span)
                stated.append(StatedAngular(s.span, s.bodies, self.fixed_point(s.about), s.before,
                                            s.after))
            elif isinstance(s, S.RestitutionLaw):
                self._states_exist(states, s.before, s.after, s.span)
                e = self.value(s.value, NONE, "a coefficient of restitution")
                self._check_restitution(e, s.value.span)
                b = self.fixed_point(s.b) if s.b is not None else None
                stated.append(StatedRestitution(s.span, e, self.fixed_point(s.a), b,
                                                self.unit_vector(s.along, "the line of impact"),
                                                s.before, s.after))
        equations = list(of(S.UserEquation))
        finds = [i for s in of(S.Find) for i in s.items]
        expects = []
        if of(S.Expect):
            from .expectations import build_expects

            expects, extra = build_expects(list(of(S.Expect)), self.ev,
                                           self.doc.source.text, finds)
            finds += extra
        if not self.bodies and not of(S.SteadyDecl):
            raise ProblemError("no bodies: declare one with `body NAME: rod(mass = ..., length = "
                               "...)`", Span(1, 1), code="empty", caret=False)
        if not finds:
            if of(S.SimulateDecl):
                self.notes.note("no `find` line: every determined unknown is solved (the "
                                "`simulate` block runs with `momentum simulate`)", None)
            else:
                self.notes.note("no `find` line: every determined unknown is solved", None)
        steady = list(of(S.SteadyDecl))
        names = set(self.bodies) | set(self.points) | set(self.surfaces)
        for s in steady:
            if s.name in names:
                raise ProblemError(f"'{s.name}' is already defined", s.span, code="name")
            names.add(s.name)
        burns = list(of(S.BurnDecl))
        for s in burns:
            self._burn(s, states, transitions)
        gains = list(of(S.GainDecl))
        taken = {f"{b.before}->{b.after}": b.span for b in burns}
        for s in gains:
            self._gain(s, states, transitions, taken)
        simulations = []
        for s in of(S.SimulateDecl):
            from .sim.spec import build_simulation

            if simulations:
                raise ProblemError("a file has one `simulate` block (this one is the "
                                   f"second; the first is at line {simulations[0].span.line})",
                                   s.span, code="name")
            simulations.append(build_simulation(self, s, states))
        return Scene(title=title, gravity=self.gravity, g=self.g, constants=self.constants,
                     user_unknowns=self.user_unknowns, bodies=self.bodies, points=self.points,
                     surfaces=self.surfaces, joints=joints, states=states,
                     transitions=transitions, stated=stated, equations=equations, finds=finds,
                     notes=self.notes, gravity_span=self.gravity_span, steady=steady,
                     burns=burns, gains=gains, simulations=simulations,
                     expects=expects, file_units=detect_units(self.doc))

    def _gain(self, s: S.GainDecl, states, transitions, taken: dict) -> None:
        """A gain or loss of mass: a particle between two declared states, with a rate,
        and no other phase between the same two states."""
        verb = "losing" if s.is_loss else "gaining"
        body = self._body_named(s.body, s.span)
        if not body.is_particle:
            raise ProblemError(f"a body {verb} mass is a particle (the mass joins at G)",
                               s.span, code="name")
        self._states_exist(states, s.before, s.after, s.span)
        if s.rate is None:
            raise ProblemError(f"a {'loss' if s.is_loss else 'gain'} needs `rate MASS_RATE` "
                               "(e.g. `rate 5 kg/s` or `rate 2 kg/m * chain.vy`)", s.span,
                               code="name")
        self._rate_in_range(s.rate, "the rate")
        key = f"{s.before}->{s.after}"
        for t in transitions:
            if t.key == key:
                raise ProblemError(f"states {s.before} -> {s.after} already have a transition",
                                   t.span, code="name")
        if key in taken:
            raise ProblemError(f"states {s.before} -> {s.after} already have a phase (line "
                               f"{taken[key].line})", s.span, code="name")
        taken[key] = s.span

    def _burn(self, s: S.BurnDecl, states, transitions) -> None:
        body = self._body_named(s.body, s.span)
        if not body.is_particle:
            raise ProblemError("a burning body is a particle (its thrust acts through G)",
                               s.span, code="name")
        self._states_exist(states, s.before, s.after, s.span)
        if s.exhaust is None:
            raise ProblemError("a burn needs `exhaust SPEED along (x, y)`", s.span, code="name")
        if s.rate is None and s.burned is None:
            raise ProblemError("a burn needs `burns MASS` (and `rate MASS_RATE` or `duration "
                               "TIME` for its time)", s.span, code="name")
        if s.rate is not None and (s.burned is None) == (s.duration is None):
            raise ProblemError("a burn needs either `burns MASS` or `duration TIME`", s.span,
                               code="name")
        for t in transitions:
            if t.key == f"{s.before}->{s.after}":
                raise ProblemError(f"states {s.before} -> {s.after} already have a transition",
                                   t.span, code="name")
        self._burn_values(s)

    def _known(self, node, dim: Dim, what: str) -> float | None:
        """The value of a constant expression, or None where it depends on unknowns (the
        later stages check those)."""
        try:
            q = self.ev(node, dim)
            if q.is_vector or q.dim != dim:
                return None
            return constant(q, node)
        except ProblemError:
            return None

    def _rate_in_range(self, node, what: str) -> None:
        """A constant mass rate (kg/s) that is subnormal or too large to square (the closed
        forms use ln(1 + x)/x and its series in x = rate t / m, massratio.py, so a tiny
        normal rate is exact, not an underflow)."""
        v = self._known(node, MASS_RATE, what)
        if v is not None:
            _in_range(v, node, what)

    def _burn_values(self, s: S.BurnDecl) -> None:
        """Constant burn data that no rocket has: a negative exhaust speed or burnt mass, a
        duration that is not positive, a direction that cannot be normalised."""
        self._rate_in_range(s.rate, "the burn rate")
        speed = self._known(s.exhaust, VELOCITY, "the exhaust speed")
        if speed is not None and _in_range(speed, s.exhaust, "the exhaust speed") < 0:
            raise ProblemError(f"the exhaust speed cannot be negative; got {speed:g} m/s",
                               s.exhaust.span, code="number",
                               notes=["give the direction the exhaust leaves in with `along`"])
        if s.direction is not None:
            try:
                q = self.ev(s.direction, NONE)
                xy = constant_vector(q, s.direction) if q.is_vector else None
            except ProblemError:
                xy = None
            if xy is not None:
                unit_direction(xy[0], xy[1], s.direction, "the exhaust direction")
        if s.burned is not None:
            m = self._known(s.burned, MASS, "the mass burned")
            if m is not None and _in_range(m, s.burned, "the mass burned") <= 0:
                raise ProblemError(f"the mass burned must be positive; got {m:g} kg",
                                   s.burned.span, code="number",
                                   notes=["a body that gains mass is written `gain`"])
        if s.duration is not None:
            d = self._known(s.duration, TIME, "the burn's duration")
            if d is not None and _in_range(d, s.duration, "the burn's duration") <= 0:
                raise ProblemError(f"a burn's duration must be positive; got {d:g} s",
                                   s.duration.span, code="number")

    def _gravity(self, s: S.Gravity) -> None:
        if self.g is not None:
            raise ProblemError("gravity is declared twice", s.span, code="name")
        g = self.value(s.magnitude, ACCELERATION, "gravity")
        if g <= 0:
            raise ProblemError("gravity must be positive (give its direction with down/up/...)",
                               s.magnitude.span, code="number")
        self.g = g
        self.gravity_span = s.span
        dirs = {"down": (0.0, -1.0), "up": (0.0, 1.0), "left": (-1.0, 0.0), "right": (1.0, 0.0)}
        if s.direction == "plane":
            self.gravity = None
        elif s.direction == "vector":
            n = self.unit_vector(s.vector, "the direction of gravity")
            self.gravity = (g * n[0], g * n[1])
        else:
            d = dirs[s.direction]
            self.gravity = (g * d[0], g * d[1])

    def _let(self, s: S.Let) -> None:
        if s.name in ("g", "pi"):
            raise ProblemError(f"'{s.name}' is built in and cannot be redefined", s.span,
                               code="name")
        if s.name in self.constants:
            raise ProblemError(f"'{s.name}' is defined twice", s.span, code="name")
        q = self.ev(s.value)
        if q.is_vector:
            constant_vector(q, s.value)
        else:
            constant(q, s.value)
        self.constants[s.name] = q

    def _unknown(self, s: S.UnknownDecl) -> None:
        dim, label = NONE, ""
        if s.unit:
            readings = unit_readings(s.unit, s.unit_span)
            dim, label = readings[0][1], s.unit
        self.user_unknowns[s.name] = (dim, label, s.span)

    # ---- bodies
    def _shape_args(self, shape: S.Shape) -> dict[str, tuple[float, Span]]:
        if shape.kind not in SHAPES:
            raise ProblemError(f"unknown shape '{shape.kind}'" + did_you_mean(shape.kind, SHAPES),
                               shape.span, code="name",
                               notes=["shapes: " + ", ".join(sorted(SHAPES))])
        allowed = SHAPES[shape.kind][0]
        out: dict[str, tuple[float, Span]] = {}
        for a in shape.args:
            if a.name not in allowed:
                raise ProblemError(f"{shape.kind}() has no argument '{a.name}'" +
                                   did_you_mean(a.name, allowed), a.span, code="name",
                                   notes=[f"{shape.kind}() takes " + ", ".join(sorted(allowed))])
            if a.name in out:
                raise ProblemError(f"'{a.name}' is given twice", a.span, code="name")
            v = self.value(a.value, ARG_DIMS[a.name], f"'{a.name}'")
            zero_ok = (a.name == "radius" and shape.kind in ("particle", "rigid")) or \
                (a.name == "inertia" and shape.kind == "rigid")  # rigid(inertia = 0): a point
            if v <= 0 and not (zero_ok and v == 0):
                raise ProblemError(f"'{a.name}' must be positive; got {v:g}", a.value.span,
                                   code="number")
            out[a.name] = (v, a.value.span)
        return out

    def _mass(self, shape: S.Shape, args) -> tuple[float, bool]:
        if "mass" in args and "weight" in args:
            raise ProblemError("give either mass or weight, not both", shape.span, code="name")
        if "mass" in args:
            return args["mass"][0], False
        if "weight" in args:
            if self.g is None:
                raise ProblemError("a weight needs the file's g to become a mass; declare "
                                   "gravity", args["weight"][1], code="name",
                                   notes=["e.g. `gravity 32.2 ft/s^2 down`, or `gravity 32.2 "
                                          "ft/s^2 into plane` for a horizontal-plane problem"])
            return args["weight"][0] / self.g, True
        raise ProblemError(f"{shape.kind}() needs a mass (or a weight)", shape.span, code="name")

    def _need(self, shape: S.Shape, args, name: str) -> float:
        if name not in args:
            raise ProblemError(f"{shape.kind}() needs '{name}'", shape.span, code="name")
        return args[name][0]

    def _simple(self, shape: S.Shape, args=None):
        """(mass, inertia, formula, radius, length, weight_given) of one shape (`args`: its
        `_shape_args`, when the caller has them)."""
        if args is None:
            args = self._shape_args(shape)
        m, w = self._mass(shape, args)
        k = shape.kind
        r = args.get("radius", (None,))[0]
        if k == "particle":
            return m, 0.0, "0 (particle)", r, None, w
        if k == "rod":
            L = self._need(shape, args, "length")
            return m, m * L * L / 12, "m*L^2/12", None, L, w
        if k == "plate":
            wd, h = self._need(shape, args, "width"), self._need(shape, args, "height")
            return m, m * (wd * wd + h * h) / 12, "m*(w^2 + h^2)/12", None, None, w
        if k == "rigid":
            if "inertia" in args and "gyration" in args:
                raise ProblemError("give either inertia or gyration, not both", shape.span,
                                   code="name")
            if "inertia" in args:
                return m, args["inertia"][0], "I_G given", r, None, w
            kk = self._need(shape, args, "gyration")
            return m, m * kk * kk, "m*k^2", r, None, w
        r = self._need(shape, args, "radius")
        factor = {"disk": 0.5, "cylinder": 0.5, "ring": 1.0, "hoop": 1.0, "sphere": 0.4,
                  "shell": 2 / 3}[k]
        return m, factor * m * r * r, SHAPES[k][1], r, None, w

    def _body(self, s: S.BodyDecl) -> None:
        if s.name in self.bodies or s.name in ("ground",):
            raise ProblemError(f"'{s.name}' is already a body name" if s.name != "ground" else
                               "'ground' is the fixed world; choose another name", s.span,
                               code="name")
        if not s.composite:
            shape = s.shapes[0]
            seen = self._bodies_seen
            key = _shape_key(shape) if seen is not None else None
            got = seen.get(key) if key is not None else None
            if got is None:
                n_notes = len(self.notes.items)
                args = self._shape_args(shape)  # evaluated once, for the body and its drawing
                m, inertia, formula, r, L, w = self._simple(shape, args)
                kind = shape.kind
                point_mass = kind == "particle" or (kind == "rigid" and inertia == 0)
                outline = ((kind, (0.0, 0.0), self._dims(shape, args), 0.0),)
                like = self._outlines
                if like is not None:  # one tuple for bodies drawn alike (10^5 balls: 12 MB)
                    outline = like.setdefault(outline, outline)
                got = (kind, m, inertia, formula,
                       r if kind in ROUND or kind in ("particle", "rigid") else None, L,
                       point_mass, w, outline)
                if key is not None and len(self.notes.items) == n_notes:
                    seen[key] = got  # the same literals and constants: the same numbers
                    if len(seen) >= MEMO_KINDS:
                        self._bodies_seen = None
            kind, m, inertia, formula, r, L, point_mass, w, outline = got
            self.bodies[s.name] = Body(s.name, s.span, kind, m, inertia, formula, r, L,
                                       point_mass, (0.0, 0.0), w, outline)
            return
        parts = []
        turns = []
        for shape in s.shapes:
            m, inertia, formula, r, L, w = self._simple(shape)
            at = self.vector(shape.at, LENGTH, "a part's position") if shape.at is not None \
                else (0.0, 0.0)
            turns.append(self.value(shape.rotated, NONE, "a part's rotation")
                         if shape.rotated is not None else 0.0)
            parts.append((shape.kind, m, inertia, at, w))
        M = sum(p[1] for p in parts)
        gx = sum(p[1] * p[3][0] for p in parts) / M
        gy = sum(p[1] * p[3][1] for p in parts) / M
        inertia = sum(p[2] + p[1] * ((p[3][0] - gx) ** 2 + (p[3][1] - gy) ** 2) for p in parts)
        formula = "sum(I_i + m_i*d_i^2)  (parallel axes: " + " + ".join(p[0] for p in parts) + ")"
        outline = tuple((p[0], (p[3][0] - gx, p[3][1] - gy), self._dims(shape), turn)
                        for p, shape, turn in zip(parts, s.shapes, turns))
        self.bodies[s.name] = Body(s.name, s.span, "composite", M, inertia, formula, None, None,
                                   False, (-gx, -gy), any(p[4] for p in parts), outline)

    def _dims(self, shape: S.Shape, args=None) -> tuple:
        """A shape's sizes (radius, length, width, height) in m, for drawing it."""
        if args is None:
            args = self._shape_args(shape)
        return tuple((k, args[k][0]) for k in ("radius", "length", "width", "height")
                     if k in args)

    def _surface(self, s: S.SurfaceDecl) -> None:
        if s.name in self.bodies or s.name in self.surfaces:
            raise ProblemError(f"'{s.name}' is already defined", s.span, code="name")
        n = self.unit_vector(s.normal, "a surface normal") if s.normal is not None else None
        at = self.vector(s.at, LENGTH, "a surface position") if s.at is not None else (0.0, 0.0)
        self.surfaces[s.name] = Surface(s.name, n, at, s.span, s.at is not None)

    def _point(self, s: S.PointDecl) -> None:
        if s.name in self.points or s.name in self.bodies:
            raise ProblemError(f"'{s.name}' is already defined", s.span, code="name")
        if s.alias is not None:
            p = self.point(s.alias)
            self.points[s.name] = PointOn(p.body, p.offset, s.name, s.span,
                                          located_by=p.located_by)
            return
        xy = self.effect(s.offset, LENGTH, "a point's position", True)
        if isinstance(xy, Symbolic):
            body = self._body_named(s.body, s.span)
            if body.is_particle:
                raise ProblemError(f"'{body.name}' is a particle: its only point is its centre",
                                   s.offset.span, code="name")
            self.points[s.name] = PointOn(body.name, body.origin, s.name, s.span,
                                          located_by=Symbolic(xy.node, LENGTH, xy.what, True,
                                                              body.origin))
            return
        if s.body == "ground" or s.body in self.surfaces:
            self.points[s.name] = PointOn(None, xy, s.name, s.span)
            return
        body = self._body_named(s.body, s.span)
        if body.is_particle and xy != (0.0, 0.0):
            raise ProblemError(f"'{body.name}' is a particle: its only point is its centre",
                               s.offset.span, code="name")
        ox, oy = body.origin
        self.points[s.name] = PointOn(body.name, (xy[0] + ox, xy[1] + oy), s.name, s.span)

    def _body_named(self, name: str, span: Span) -> Body:
        if name not in self.bodies:
            raise ProblemError(f"unknown body '{name}'" + did_you_mean(name, self.bodies), span,
                               code="name")
        return self.bodies[name]

    def fixed_point(self, ref: S.PointRef) -> PointOn:
        """A point at a known place: joints, contacts and stated principles need one."""
        p = self.point(ref)
        if p.located_by is not None:
            raise ProblemError(f"'{ref.text}' is located by an unknown: only a force may act "
                               "there", ref.span, code="name",
                               notes=["locate it with constants, or apply a `force` at it"])
        return p

    def point(self, ref: S.PointRef) -> PointOn:
        """Resolve a point reference: named point, body centre, `rod.end(+)`, `rod.A`."""
        if ref.end:
            body = self._body_named(ref.name, ref.span)
            if body.length is None:
                raise ProblemError(f"'{body.name}' is not a rod: it has no ends", ref.span,
                                   code="name", notes=["name a point: `point A = "
                                                       f"{body.name} at (x, y)`"])
            half = body.length / 2 * (1 if ref.end == "+" else -1)
            return PointOn(body.name, (half, 0.0), ref.text, ref.span)
        if ref.member:
            body = self._body_named(ref.name, ref.span)
            if ref.member in ("center", "centre", "G"):
                return PointOn(body.name, (0.0, 0.0), ref.text, ref.span,
                               round_contact=body.radius is not None)
            p = self.points.get(ref.member)
            if p is None or p.body != body.name:
                mine = [n for n, q in self.points.items() if q.body == body.name]
                raise ProblemError(f"'{body.name}' has no point '{ref.member}'" +
                                   did_you_mean(ref.member, mine + ["center"]), ref.span,
                                   code="name")
            return PointOn(p.body, p.offset, ref.text, ref.span, located_by=p.located_by)
        if ref.name in self.points:
            p = self.points[ref.name]
            return PointOn(p.body, p.offset, p.name, ref.span, located_by=p.located_by)
        if ref.name in self.bodies:
            b = self.bodies[ref.name]
            return PointOn(b.name, (0.0, 0.0), b.name, ref.span, round_contact=True)
        if ref.name == "ground":
            return PointOn(None, (0.0, 0.0), "ground", ref.span)
        if ref.name in self.surfaces:
            sf = self.surfaces[ref.name]
            return PointOn(None, sf.at, sf.name, ref.span)
        names = list(self.points) + list(self.bodies) + list(self.surfaces) + ["ground"]
        raise ProblemError(f"unknown point or body '{ref.name}'" + did_you_mean(ref.name, names),
                           ref.span, code="name")

    # ---- joints
    def _joint(self, s: S.Joint) -> Joint:
        a, b = self.fixed_point(s.a), self.fixed_point(s.b)
        if a.body is None and b.body is not None:
            a, b = b, a
        if a.body is None:
            raise ProblemError(f"a {s.kind} needs a body on at least one side", s.span,
                               code="name")
        if a.body == b.body:
            raise ProblemError(f"a {s.kind} joins two different bodies (or a body and the "
                               "ground)", s.span, code="name")
        label = s.label or (a.name if b.body is None else f"{a.name}-{b.name}")
        if s.kind == "pin" and s.at is not None:
            if b.body is not None:
                raise ProblemError("`at` places a pin to the ground; a pin between bodies is "
                                   "where its two points meet", s.at.span, code="name")
            b = PointOn(None, self.vector(s.at, LENGTH, "a pin's position"), b.name, b.span)
        if s.kind == "slider" and (b.offset != (0.0, 0.0) or a.body is None):
            raise ProblemError("a slider puts a body on another body's line: `slider collar on "
                               "rod along (1, 0)` (the line through the rod's centre)", s.span,
                               code="name")
        along = self.unit_vector(s.along, f"a {s.kind}'s direction") \
            if s.along is not None else None
        k = length = None
        if s.kind == "spring":
            k = self.value(s.stiffness, STIFFNESS, "a spring stiffness")
            if k < 0:
                raise ProblemError("a spring stiffness cannot be negative", s.stiffness.span,
                                   code="number")
            length = self.value(s.length, LENGTH, "a spring's free length") if s.length \
                is not None else 0.0
        return Joint(kind=JointKind(s.kind), label=label, a=a, b=b, span=s.span, along=along,
                     stiffness=k, length=length, from_state=s.from_state)

    # ---- states
    def _state(self, s: S.StateDecl) -> StateSpec:
        spec = StateSpec(s.id, s.label, s.span)
        givens, bodies = spec.givens, self.bodies
        for it in s.items:
            if isinstance(it, S.AtRest):  # (a big file's state lists 10^4 of them)
                body = bodies.get(it.body) or self._body_named(it.body, it.span)
                name, span = body.name, it.span
                for q in _AT_REST_PARTICLE if body.is_particle else _AT_REST:
                    k = (name, q)
                    if k in givens:
                        self._give(spec, name, q, 0.0, span)  # its error
                    givens[k] = (0.0, span)
            elif isinstance(it, S.RollsIn):
                self._body_named(it.body, it.span)
                spec.rolls.append((it.body, it.surface, it.span))
            else:
                self._given(spec, it)
        return spec

    def _qty(self, body: Body, qty: str, span: Span) -> None:
        if qty not in STATE_QTYS and qty not in VECTOR_QTYS:
            names = list(STATE_QTYS) + list(VECTOR_QTYS)
            raise ProblemError(f"'{qty}' is not a state quantity" + did_you_mean(qty, names),
                               span, code="name", notes=["a state gives x, y, pos, angle, v, vx, "
                                                         "vy or omega of a body"])
        if body.is_particle and qty in ROTATION_QTYS:
            raise ProblemError(f"'{body.name}' is a particle: it has no {qty}", span,
                               code="name", notes=["use a sphere or disk for a body that turns"])

    def _give(self, spec: StateSpec, body: str, qty: str, value: float, span: Span) -> None:
        if (body, qty) in spec.givens:
            raise ProblemError(f"{body}.{qty} is given twice in state {spec.id}", span,
                               code="name")
        spec.givens[(body, qty)] = (value, span)

    def _given(self, spec: StateSpec, it: S.Given) -> None:
        body = self._body_named(it.body, it.span)
        self._qty(body, it.qty, it.qty_span)
        if it.qty in VECTOR_QTYS:
            comps = VECTOR_QTYS[it.qty]
            dim = STATE_QTYS[comps[0]][0]
            if it.relation != "=":
                raise ProblemError("a hint needs a scalar quantity (vx, vy, omega, angle...)",
                                   it.span, code="type")
            v = self.vector(it.value, dim, f"{it.body}.{it.qty}")
            for c, x in zip(comps, v):
                self._give(spec, body.name, c, x, it.span)
            return
        dim = STATE_QTYS[it.qty][0]
        v = self.value(it.value, dim, f"{it.body}.{it.qty}")
        if it.relation == "=":
            self._give(spec, body.name, it.qty, v, it.span)
        else:
            spec.hints.setdefault((body.name, it.qty), []).append((it.relation, v, it.span))

    # ---- transitions
    def _states_exist(self, states, a: str, b: str, span: Span, spans=None) -> None:
        for k, sid in enumerate((a, b)):
            if sid not in states:
                where = spans[k] if spans else span
                raise ProblemError(f"state {sid} is not declared" + did_you_mean(sid, states),
                                   where, code="name", notes=[f"add a line `state {sid}`"])
        if a == b:
            raise ProblemError("a transition goes from one state to another", span, code="name")

    def _check_restitution(self, e: float, span: Span) -> None:
        if e < 0 or e > 1:
            raise ProblemError(f"a coefficient of restitution must be between 0 and 1; got {e:g}",
                               span, code="number")

    def _transition(self, s: S.Transition, states) -> TransitionSpec:
        self._states_exist(states, s.before, s.after, s.span, (s.before_span, s.after_span))
        tk = _TRANSITION_KINDS.get(s.kind) if type(s.kind) is str else None
        t = TransitionSpec(tk or TransitionKind(s.kind), s.before, s.after, s.span)
        labels = set()
        done = 0  # clauses before this one read by scene_deferred
        for i, c in enumerate(s.clauses):
            if type(c) is tuple:  # a contact line kept as its text (scene_deferred)
                if i < done:
                    continue
                if s.kind != TransitionKind.ENERGY:
                    done = self._deferred.contacts(s.clauses, i, s.kind, labels, t.contacts)
                    if done > i:
                        continue
                    con = self._deferred.contact(c, s.kind, states[s.before])
                    if con is not None and con.label not in labels:
                        labels.add(con.label)
                        t.contacts.append(con)
                        continue
                c = c[1](c[2], c[3])  # its node, read below
            if isinstance(c, S.Contact):
                if s.kind == TransitionKind.ENERGY:
                    raise ProblemError("contacts belong to impacts and intervals; an energy phase "
                                       "takes gravity, springs, forces and moments", c.span,
                                       code="name")
                con = self._contact(c, s.kind, states[s.before])
                if con.label in labels:
                    raise ProblemError(f"two contacts are called '{con.label}' in this transition",
                                       c.span, code="name",
                                       notes=["name them: `contact NAME: A with B`"])
                labels.add(con.label)
                t.contacts.append(con)
            elif c.kind == Clause.BEARING_FRICTION:
                if c.names[0] not in {j.label for j in self.joints if j.kind == JointKind.PIN}:
                    pins = [j.label for j in self.joints if j.kind == JointKind.PIN]
                    raise ProblemError(f"no pin called '{c.names[0]}'" +
                                       did_you_mean(c.names[0], pins), c.span, code="name",
                                       notes=["name a pin: `pin bearing: disk to rod.A`"])
                t.bearing_friction.append((c.names[0], c.span))
            elif c.kind == Clause.STOPS_RELATIVE:
                for n in c.names:
                    self._body_named(n, c.span)
                t.stops_relative.append((c.names[0], c.names[1], c.span))
            elif c.kind == Clause.STOPS:
                self._body_named(c.names[0], c.span)
                t.stops.append((c.names[0], c.span))
            elif c.kind == Clause.ROLLS:
                self._body_named(c.names[0], c.span)
                self._surface_named(c.names[1], c.span)
                t.rolls.append((c.names[0], c.names[1], c.span))
            elif c.kind == Clause.FORCE:
                f = self.effect(c.value, FORCE, "a force", True)
                point = self.point(c.point)
                if f == (0.0, 0.0):  # it has no direction, and adds nothing
                    self.notes.warn("a zero force has no effect; it is left out", c.span,
                                    code="zero-force")
                    continue
                t.forces.append((f, point, c.span))
            elif c.kind == Clause.MOMENT:
                body = self._body_named(c.names[0], c.span)
                t.moments.append((self.effect(c.value, MOMENT, "a moment", False), body.name,
                                  c.span))
            elif c.kind == Clause.DURATION:
                if s.kind != TransitionKind.INTERVAL:
                    raise ProblemError("only an interval has a duration", c.span, code="name")
                d = self.effect(c.value, TIME, "a duration", False)
                if isinstance(d, Symbolic):
                    t.duration_expr = d
                    continue
                if d <= 0:
                    raise ProblemError("a duration must be positive", c.value.span,
                                       code="number")
                t.duration = d
            elif c.kind == Clause.FREE:
                self._body_named(c.names[0], c.span)
                if s.kind == TransitionKind.ENERGY:  # its own energy balance
                    t.free.append(c.names[0])
        self._energy_groups(s, t)
        if s.kind == TransitionKind.INTERVAL:
            t.rolls = self._rolling_throughout(t)
        if s.kind == TransitionKind.IMPACT and (t.forces or t.moments):
            raise ProblemError("an impact is instantaneous: finite forces and moments give no "
                               "impulse; put them in an interval", (t.forces or t.moments)[0][2],
                               code="name")
        return t

    def _energy_groups(self, s: S.Transition, t: TransitionSpec) -> None:
        """`of {rod}, {ball}`: the groups of bodies an energy phase balances one by one."""
        if not s.groups:
            return
        if s.kind != TransitionKind.ENERGY:
            raise ProblemError("`of {...}` belongs to an energy phase", s.span, code="name")
        seen: set[str] = set()
        for group in s.groups:
            for name in group:
                self._body_named(name, s.span)
                if name in seen:
                    raise ProblemError(f"'{name}' is in two groups of this energy phase",
                                       s.span, code="name")
                seen.add(name)
            t.groups.append(tuple(group))
    def _plan_friction(self, c: S.Contact, kind: str, a: PointOn, b, surface) -> bool:
        """`contact wreck with ground: friction 0.6` under `gravity ... into plane`: kinetic
        friction in the plane, against the velocity, the normal force the weight."""
        if b is not None or surface not in (None, "ground") or self.gravity is not None \
                or self.g is None or kind != TransitionKind.INTERVAL:
            return False
        props = {p.kind for p in c.props}
        if props != {Prop.FRICTION}:
            raise ProblemError("with gravity into the plane, a contact with the ground is "
                               "friction in the plane: write only `friction MU`", c.span,
                               code="name")
        if a.offset != (0.0, 0.0):
            raise ProblemError("plan-view friction acts on a body as a whole: write the body's "
                               "name", c.a.span, code="name")
        return True

    def _rolling_throughout(self, t: TransitionSpec) -> list:
        """`BODY rolls on SURFACE` in an interval with no contact of its own: the body rolls
        throughout, held by a rough contact (normal and friction forces unknown). With a
        `friction MU` contact it is the end of a slide (kept as an end condition)."""
        kept = []
        for body, surface, span in t.rolls:
            if any(c.a.body == body and c.b is None and c.surface in (surface, None)
                   for c in t.contacts):
                kept.append((body, surface, span))
                continue
            sf = self._surface_named(surface, span)
            b = self.bodies[body]
            if sf.normal is None:
                raise ProblemError(f"rolling on '{surface}' needs its normal: declare `surface "
                                   f"{surface} normal (0, 1)`", span, code="name")
            if b.radius is None or b.is_particle:
                raise ProblemError(f"'{body}' cannot roll: only disks, rings, spheres and "
                                   "bodies with a radius roll", span, code="name")
            if any(c.label == body for c in t.contacts):
                raise ProblemError(f"a contact is already called '{body}' in this transition",
                                   span, code="name")
            t.contacts.append(Contact(label=body, span=span,
                                      a=PointOn(body, (0.0, 0.0), body, span, True), b=None,
                                      normal=sf.normal, restitution=None,
                                      restitution_unknown=False, mode=Tangential.ROUGH,
                                      mu=None, slip=None,
                                      surface=None if surface == "ground" else surface))
        return kept

    def _geometric_normal(self, c: S.Contact, a: PointOn, b: PointOn,
                          before: StateSpec) -> tuple[float, float]:
        """The normal the shapes fix, from the positions given in the state before: the
        line of centres of two round bodies, or from a round body's centre to the point
        it touches (a rod's end)."""
        round_ = [p.round_contact and bool(self.bodies[p.body].radius) for p in (a, b)]
        if not any(round_):
            raise ProblemError("a contact needs a normal: between two points the geometry "
                               "fixes none; write `normal (x, y)` (the direction of the impulse "
                               "on the first body), or give a body a radius", c.span,
                               code="name")
        pose, missing = {}, []
        for p in (a, b):
            g = before.givens
            qtys = ("x", "y") + (("angle",) if p.offset != (0.0, 0.0) else ())
            lack = [q for q in qtys if (p.body, q) not in g]
            missing += [f"{p.body}.{q}" for q in lack]
            if not lack:
                pose[p.body] = (g[(p.body, "x")][0], g[(p.body, "y")][0],
                                g[(p.body, "angle")][0] if "angle" in qtys else 0.0)
        if missing:
            raise ProblemError(f"the normal from the geometry needs {', '.join(missing)} in "
                               f"state {before.id}; give them, or write `normal (x, y)`",
                               c.span, code="name")
        n, d = line_of_centres(centre(pose, a), centre(pose, b))
        if n is None:
            raise ProblemError("the two contact points coincide in state "
                               f"{before.id}: the geometry fixes no normal; write "
                               "`normal (x, y)`", c.span, code="name")
        reach = sum(self.bodies[p.body].radius for p, r in zip((a, b), round_) if r)
        if abs(d - reach) > 1e-6 * max(d, reach):
            self.notes.warn(f"contact {a.name} with {b.name}: the bodies are {d:.6g} m apart in "
                           f"state {before.id} but their radii reach {reach:.6g} m; the normal "
                           "is along the line of centres", c.span)
        else:
            self.notes.note(f"contact {a.name} with {b.name}: normal ({n[0]:.4g}, {n[1]:.4g}) "
                            f"on {a.name}, from the geometry in state {before.id}", c.span)
        return n

    def _surface_named(self, name: str, span: Span) -> Surface:
        if name == "ground":
            return Surface("ground", None, (0.0, 0.0), span)
        if name not in self.surfaces:
            raise ProblemError(f"unknown surface '{name}'" + did_you_mean(name, self.surfaces),
                               span, code="name", notes=[f"declare it: `surface {name} normal "
                                                         "(0, 1)`"])
        return self.surfaces[name]

    def _contact(self, c: S.Contact, kind: str, before: StateSpec | None = None) -> Contact:
        a = self.fixed_point(c.a)
        b = self.fixed_point(c.b) if c.b is not None else None
        surface = None
        if b is not None and b.body is None:
            surface = b.name
            sf = self.surfaces.get(b.name)
            b = None
        else:
            sf = None
        if a.body is None:
            raise ProblemError("a contact's first point must be on a body", c.a.span,
                               code="name")
        if b is not None and b.body == a.body:
            raise ProblemError("a body cannot be in contact with itself", c.span, code="name")
        seen = self._contacts_seen
        key = None
        if seen is not None and c.normal is not None:
            key = _contact_key(c, kind)
            hit = seen.get(key) if key is not None else None
            if hit is not None:  # the same literals as a contact before: its results
                normal, e, e_unknown, mode, mu, slip, separation, law, law_at, mu_static = hit
                return self._contact_record(c, a, b, surface, normal, e, e_unknown, mode, mu,
                                            slip, None, separation, law,
                                            c.props[law_at].span if law_at >= 0 else None,
                                            mu_static)
            n_notes = len(self.notes.items)
        if c.normal is not None:
            normal = self.unit_vector(c.normal, "a contact normal")
        elif sf is not None and sf.normal is not None:
            normal = sf.normal
        elif kind == "simulate" and b is not None:
            normal = None  # two bodies: the simulation takes the normal from their shapes
        elif b is not None and before is not None:
            normal = self._geometric_normal(c, a, b, before)
        elif self._plan_friction(c, kind, a, b, surface):
            normal = None  # friction with the ground in plan view (elements.PlanFriction)
        else:
            where = f"declare `surface {surface} normal (0, 1)` or write " \
                if surface not in (None, "ground") else "write "
            raise ProblemError("a contact needs a normal: " + where + "`normal (0, 1)` (the "
                               "direction of the impulse on the first body)", c.span,
                               code="name")
        e = None
        e_unknown = False
        e_name = None
        separation = None
        mode = Tangential.SMOOTH
        mu = None
        slip = None
        mu_static = None
        modes = []
        law, law_span, law_at = Restitution.NEWTON, None, -1
        for i, p in enumerate(c.props):
            if p.kind in (Prop.RESTITUTION, Prop.RESTITUTION_UNKNOWN, Prop.SEPARATION):
                law_span, law_at = p.span, i
            if p.kind == Prop.RESTITUTION and p.law not in (None, "newton"):
                law = Restitution(p.law)
            if p.kind == Prop.RESTITUTION and isinstance(p.value, S.Ref) and \
                    p.value.name in self.user_unknowns and not p.value.member:
                e_name = p.value.name
                e_unknown = True
            elif p.kind == Prop.RESTITUTION:
                e = self.value(p.value, NONE, "a coefficient of restitution")
                self._check_restitution(e, p.value.span)
            elif p.kind == Prop.RESTITUTION_UNKNOWN:
                e_unknown = True
            elif p.kind in (Prop.SMOOTH, Prop.ROUGH):
                mode = Tangential(p.kind)
                modes.append(p)
            elif p.kind == Prop.FRICTION:
                mu = self.value(p.value, NONE, "a friction coefficient")
                if mu < 0:
                    raise ProblemError(f"a friction coefficient cannot be negative; got {mu:g}",
                                       p.value.span, code="number")
                mode = Tangential.FRICTION
                modes.append(p)
            elif p.kind == Prop.STATIC:
                mu_static = self.value(p.value, NONE, "a static friction coefficient")
                if mu_static < 0:
                    raise ProblemError("a friction coefficient cannot be negative; got "
                                       f"{mu_static:g}", p.value.span, code="number")
            elif p.kind == Prop.SLIP:
                slip = self.unit_vector(p.value, "a slip direction")
            elif p.kind == Prop.SEPARATION:
                separation = self.value(p.value, VELOCITY, "a separation speed")
                if separation < 0:
                    raise ProblemError("a separation speed cannot be negative (the bodies would "
                                       "pass through each other)", p.value.span, code="number")
        if len(modes) > 1:
            raise ProblemError("a contact is smooth, rough or has friction: choose one",
                               modes[1].span, code="name")
        if kind == "simulate" and (e_unknown or separation is not None or slip is not None):
            raise ProblemError("a simulated contact takes a restitution and smooth, rough or "
                               "`friction MU`", c.span, code="name")
        if kind in ("impact", "simulate") and e is None and not e_unknown and separation is None:
            raise ProblemError("an impact contact needs a restitution: `restitution 0.5` (or "
                               "`restitution ?` to find it, or `separation 2 m/s`)", c.span,
                               code="name")
        if separation is not None and (e is not None or e_unknown):
            raise ProblemError("give either a restitution or a separation speed, not both",
                               c.span, code="name")
        if mu_static is not None and mode not in (Tangential.ROUGH, Tangential.FRICTION):
            raise ProblemError("`static MU` checks the friction a contact needs to hold: write "
                               "`rough, static 0.4` or `friction 0.3 static 0.4`", c.span,
                               code="name")
        if law is not Restitution.NEWTON:
            if kind != "impact":
                raise ProblemError(f"the {law} restitution law resolves an impact; here write "
                                   "`restitution E` (Newton's law)", law_span, code="name")
            if e_unknown:
                raise ProblemError(f"the {law} law needs a known coefficient of restitution "
                                   "(to find e, use Newton's law: `restitution ?`)", law_span,
                                   code="name")
        mode = Tangential(mode)
        law = Restitution.SEPARATION if separation is not None else law
        if key is not None and e_name is None and len(self.notes.items) == n_notes:
            seen[key] = (normal, e, e_unknown, mode, mu, slip, separation, law, law_at,
                         mu_static)
            if len(seen) >= MEMO_KINDS:
                self._contacts_seen = None
        return self._contact_record(c, a, b, surface, normal, e, e_unknown, mode, mu, slip,
                                    e_name, separation, law, law_span, mu_static)

    @staticmethod
    def _contact_record(c, a, b, surface, normal, e, e_unknown, mode, mu, slip, e_name,
                        separation, law, law_span, mu_static) -> Contact:
        if b is None:
            label = c.label or a.name
        else:
            label = c.label or f"{a.name}-{b.name}"
        return Contact(label=label, span=c.span, a=a, b=b, normal=normal, restitution=e,
                       restitution_unknown=e_unknown, mode=mode, mu=mu, slip=slip,
                       surface=surface, restitution_name=e_name, separation=separation,
                       law=law, law_span=law_span, mu_static=mu_static)

    def _stated_momentum(self, s: S.ConserveMomentum, states) -> StatedMomentum:
        self._states_exist(states, s.before, s.after, s.span)
        self._body_names(s.bodies, s.span)
        if s.axis == "x":
            d, text = (1.0, 0.0), "x"
        elif s.axis == "y":
            d, text = (0.0, 1.0), "y"
        else:
            d = self.unit_vector(s.axis, "a direction")
            text = f"({d[0]:.4g}, {d[1]:.4g})"
        return StatedMomentum(s.span, d, text, s.bodies, s.before, s.after)

    def _body_names(self, names, span) -> None:
        for n in names:
            self._body_named(n, span)

    # ---- the public interface `simulate`'s block (sim/spec.py) is resolved through
    def body_named(self, name: str, span: Span) -> Body:
        """The body called `name`, or a located error naming the closest one."""
        return self._body_named(name, span)

    def contact(self, c: S.Contact, kind: str) -> Contact:
        """A contact clause resolved for `kind` (impact, interval, simulate)."""
        return self._contact(c, kind)

    def state_qty_dim(self, body: Body, qty: str, span: Span) -> Dim:
        """The dimension of a scalar state quantity of `body` (x, y, angle, vx, vy,
        omega), or a located error if it is not one or the body has no such quantity."""
        if qty not in STATE_QTYS:
            raise ProblemError(f"'{qty}' is not a state quantity" +
                               did_you_mean(qty, STATE_QTYS), span, code="name")
        self._qty(body, qty, span)
        return STATE_QTYS[qty][0]

    def damper(self, label: str, a: PointOn, b: PointOn, span: Span, damping: float) -> Joint:
        """A damper as a joint record whose `stiffness` holds the damping coefficient."""
        return Joint(kind=JointKind.DAMPER, label=label, a=a, b=b, span=span, stiffness=damping)
