"""Compile: Scene -> equation system (unknowns, equations with provenance).

Each declared transition adds the principles that hold for it, derived from the
scene rather than from a template: linear impulse-momentum per body in x and y,
angular impulse-momentum about each body's centre of mass, Newton's restitution and
the tangential law at each contact, the reactions of pins, welds and links as
unknown impulses, and the kinematic constraints of every state. Energy phases add
T1 + V1 + U12 = T2 + V2. Positions do not change in an impact; an interval keeps its
start configuration for the moment arms (constant forces, constant geometry).
Helpers in their own modules: principles.py (stated principles), references.py (names
in `find` lines and equations), flows.py (control volumes and burning bodies).
"""
from __future__ import annotations

import math
from collections import defaultdict

from . import syntax as S
from .aliases import StateChains, last_break
from .diagnostics import Collector, ProblemError
from .elements.base import FrictionSite, ImpulseSource, Phase
from .elements.contacts import contact_element
from .elements.joints import BearingFriction, joint_element
from .elements.keys import Key, duration_key, state_key
from .elements.kinds import EquationKind, KeyKind, PhaseKind, TransitionKind
from .energy_groups import energy_groups, split_joints
from . import impact_contacts, impact_phase
from .expr import (
    NEG_ONE,
    V2,
    ZERO,
    Add,
    Const,
    E,
    Known,
    Mul,
    Var,
    add,
    add_all,
    mul,
    neg,
    omega_cross,
    rotate,
    rotate_v2,
    to_text,
)
from .principles import PrinciplesMixin, external
from .records import EMPTY_LIST, field, record
from .references import FindSpec, ReferencesMixin
from .scene import (
    STATE_QTYS,
    PointOn,
    Scene,
    Symbolic,
    TransitionSpec,
)
from .source import Span
from .system_laws import system_laws
from .tracks import Track, tracks_of
from .units import (
    TIME,
    Dim,
    describe,
    si_label,
)


@record
class Unknown:
    name: str
    dim: Dim
    unit: str
    kind: KeyKind  # state | impulse | angular-impulse | restitution | duration | user | derived
    hints: list[tuple[str, float, Span]] = field(default_factory=list)
    state: str | None = None
    body: str | None = None
    qty: str | None = None


@record
class Equation:
    lhs: E
    rhs: E
    principle: str
    group: str
    span: Span | None
    kind: EquationKind = EquationKind.AUTO
    index: int = 0
    _residual: E | None = None
    _texts: dict | None = None

    @property
    def residual(self) -> E:
        if self._residual is None:
            self._residual = add(self.lhs, neg(self.rhs))
        return self._residual

    @property
    def momentum_row(self) -> bool:
        """An impulse-momentum equation (linear or angular): the rows the report's
        momentum-residual check reads again, so the only residuals kept past the solve."""
        return "impulse-momentum" in self.principle

    def text(self, numeric: bool = False) -> str:
        """`lhs = rhs`, symbolically or with numbers (printed once, then remembered in a
        pair indexed by `numeric`: a dict per equation cost a big scene 230 bytes each)."""
        if self._texts is None:
            self._texts = [None, None]
        t = self._texts[numeric]
        if t is None:
            lhs = rhs = None
            if not numeric:
                lhs, rhs = _short_text(self.lhs), _short_text(self.rhs)
            t = self._texts[numeric] = \
                f"{to_text(self.lhs, numeric) if lhs is None else lhs} = " \
                f"{to_text(self.rhs, numeric) if rhs is None else rhs}"
        return t


@record
class TransitionInfo:
    kind: str
    key: str
    before: str
    after: str
    span: Span
    why: list[str]
    contacts: list[tuple[str, E, E]]  # label, approach normal velocity, separation velocity
    energy: tuple[E, E] | None = None  # kinetic energy of the bodies it moves, before/after
    bodies: tuple[str, ...] = ()  # the bodies it moves (whose T its energy and T_lost cover)
    laws: list = field(default_factory=list)  # system_laws.SystemLaw: shown, not solved
    impulses: list = field(default_factory=list)  # Applied: each impulse on a body (diagrams)
    # impact_phase: its whole-impact plan's number (one per kind in a process: the same
    # trees, texts and contact geometry up to names and numbers); None: made otherwise
    kind_id: int | None = None


@record
class Applied:
    """One impulse (and angular impulse) applied to a body in an impact or interval, with
    the world arm from its G at the start: what the impulse diagram draws."""

    body: str
    point: PointOn
    J: V2
    torque: E | None
    arm: V2
    what: str = ""  # the impulse source it belongs to (`contact A`, `pin O`, `weight of rod`)


@record
class System:
    scene: Scene
    unknowns: dict[str, Unknown]
    equations: list[Equation]
    finds: list[FindSpec]
    transitions: list[TransitionInfo]
    friction: list[FrictionSite]
    notes: Collector
    invalid_stated: list[tuple[Span, str]]
    flow_rows: list = field(default_factory=list)  # flows.FlowRow, for the report
    integrations: list = field(default_factory=list)  # integration.Integration: solve runs them
    path_laws: list = field(default_factory=list)  # contact_laws.PathLawSite


def compile_scene(scene: Scene, regimes: dict[str, str] | None = None,
                  impulses: dict | None = None) -> System:
    """Build the equation system for `scene` with the given friction regimes (and the
    contact impulses that Poisson's or Stronge's law found, by site; see contact_laws)."""
    c = _Compiler(scene, regimes or {})
    c.impulses = impulses or {}
    return c.run()


def _chronological(phases: list) -> list:
    """Phases ordered so that one starting at state S comes after every phase ending at
    S (a burn's start mass is what they left; the unknowns of a state are made by the
    phase that ends there, so the structure never depends on the order of the file's
    statements); else file order. Kahn's topological sort, O(N log N); file order itself
    when no phase starts where it or a later one ends (the common file: one pass)."""
    ends: set = set()
    for p in reversed(phases):
        ends.add(p.after)
        if p.before in ends:
            return _kahn(phases)
    return list(phases)


def _kahn(phases: list) -> list:
    """_chronological by Kahn's sort: the ready phase of least file index first."""
    import heapq

    pending: dict = defaultdict(int)  # state -> phases ending there, not yet placed
    starting: dict = defaultdict(list)  # state -> phases starting there (file indices)
    for k, p in enumerate(phases):
        pending[p.after] += 1
        starting[p.before].append(k)
    ready = [k for k, p in enumerate(phases) if pending[p.before] == 0]
    heapq.heapify(ready)
    placed = [False] * len(phases)
    out: list = []
    rest = 0  # the first index not yet placed, for a cycle of states (file order)
    while len(out) < len(phases):
        if ready:
            k = heapq.heappop(ready)
            if placed[k]:
                continue
        else:
            while placed[rest]:
                rest += 1
            k = rest
        placed[k] = True
        out.append(phases[k])
        after = phases[k].after
        pending[after] -= 1
        if pending[after] == 0:
            for q in starting[after]:
                if not placed[q]:
                    heapq.heappush(ready, q)
    return out


class _Compiler(ReferencesMixin, PrinciplesMixin):
    Applied = Applied  # for impact_contacts and impact_phase (which compile imports)
    TransitionInfo = TransitionInfo
    Equation = Equation
    Unknown = Unknown
    Fresh = None  # compile.Fresh, set below (impact_phase's rows)

    def __init__(self, scene: Scene, regimes: dict[str, str]):
        self.scene = scene
        self.regimes = regimes
        self.unknowns: dict[str, Unknown] = {}
        self.equations: list[Equation] = []
        self._seen: set[str] = set()  # principle|text of each equation (see `eq`)
        self._by_principle: dict | None = {}  # principle -> its equation, or their texts
        self.notes = Collector(list(scene.notes.items))
        self.friction: list[FrictionSite] = []
        self.invalid: list[tuple[Span, str]] = []
        self.transitions: list[TransitionInfo] = []
        self.sources: dict[str, list[ImpulseSource]] = {}
        self.losses: dict[str, list[E]] = {}  # impact -> each contact's energy loss (impulses)
        self._alias: dict[tuple[str, str, str], tuple[str, str, str]] = {}
        self._into: dict[str, list[TransitionSpec]] = {}
        self._out: dict[str, list[TransitionSpec]] = {}
        self._busy: dict[str, set] = {}
        self._reach: dict[str, set] | None = None
        self._chains = None  # aliases.StateChains, when the states form simple chains
        self._order: dict[str, int] | None = None  # body -> its index in the scene
        # each body's record: its chain breaks, sv's and vel's answers, terms of T, mass
        self._tracks: dict[str, Track] = tracks_of(scene.bodies)
        self._T: dict[tuple, E] = {}  # _kinetic's answers, by state and bodies in order
        self._hints: bool | None = None  # whether any state has hints (_key_value)
        self._next: dict[str, list[str]] | None = None  # for holds_at
        self._prev: dict[str, str] | None = None  # for mass
        self.flows = None  # flows.FlowCompiler, for `steady` and `burn` statements
        self.tspecs = {t.key: t for t in scene.transitions}
        self.joints = [joint_element(jt, scene) for jt in scene.joints]
        self._by_label = {j.label: j for j in self.joints}
        self.impulses: dict = {}  # site -> (P_t, P_n) from the impulse path
        self.path_laws: list = []  # contact_laws.PathLawSite

    # ---- unknowns and state variables ------------------------------------------------------
    def unknown(self, name: str, dim: Dim, kind: KeyKind, unit: str | None = None, **kw) -> Var:
        if name not in self.unknowns:
            self.unknowns[name] = Unknown(name, dim, unit or si_label(dim), kind, **kw)
        return Var(name)

    def _find(self, key):
        """The variable a state quantity really is: quantities that a transition cannot
        change are the same variable on both sides (resolved backwards, memoized, and
        only for what is referenced, so a sequence of N impacts costs O(N))."""
        hit = self._alias.get(key)
        if hit is not None:
            return hit
        if self._chains is not None:
            hit = self._chains.head(*key, self._given, self._linked)
            if hit is not None:
                self._alias[key] = hit
                return hit
        path = []
        on_path = {key}
        cur = key
        while True:
            if self._given(cur) is not None:
                break
            body, qty, sid = cur
            prev = None
            for t in self._into.get(sid, ()):
                if self._linked(body, qty, t):
                    prev = (body, qty, t.before)
                    break
            if prev is None or prev in on_path:
                break
            path.append(cur)
            on_path.add(prev)
            cur = prev
            hit = self._alias.get(cur)
            if hit is not None:
                cur = hit
                break
        if self._given(cur) is None:
            # the head of the chain: a later state may give it (e.g. only the end velocity)
            cur = self._forward_given(cur) or cur
        for k in path:
            self._alias[k] = cur
        self._alias[key] = cur
        return cur

    def _forward_given(self, key):
        body, qty, sid = key
        seen = {sid}
        while True:
            nxt = None
            for t in self._out.get(sid, ()):
                if self._linked(body, qty, t):
                    nxt = t.after
                    break
            if nxt is None or nxt in seen:
                return None
            seen.add(nxt)
            if self._given((body, qty, nxt)) is not None:
                return (body, qty, nxt)
            sid = nxt

    def _linked(self, body: str, qty: str, t: TransitionSpec) -> bool:
        """Whether transition t leaves this quantity of this body unchanged."""
        if t.kind == TransitionKind.ENERGY:
            return False
        if qty in ("x", "y", "angle"):
            return not (t.kind == TransitionKind.INTERVAL and
                        self._given((body, qty, t.after)) is not None)
        return body not in self._busy[t.key]

    def _given(self, key):
        body, qty, sid = key
        st = self.scene.states.get(sid)
        if st is None:
            return None
        return st.givens.get((body, qty))

    def sv(self, body: str, qty: str, sid: str) -> E:
        """A body's state quantity: a Known if given, else an unknown `rod.omega@3`
        (made once per body, quantity and state: the elements ask for it many times)."""
        svs = self._tracks[body].sv
        hit = svs.get((qty, sid))
        if hit is None:
            hit = svs[(qty, sid)] = self._state_value(body, qty, sid)
        return hit

    def _state_value(self, body: str, qty: str, sid: str) -> E:
        b = self.scene.bodies[body]
        if b.is_particle and qty in ("angle", "omega"):
            return ZERO
        chains = self._chains
        key = None
        if chains is not None:
            # sv remembers its answers: ask the chains directly (no second memo by key);
            # a head is its own head, so sv's memo at the head state holds the shared node
            key, given = chains.head_given(body, qty, sid, self.scene.states, self._linked)
            if key is not None:
                if key[2] == sid:
                    return self._key_value(key, body, qty, given)
                svs = self._tracks[body].sv
                hit = svs.get((qty, key[2]))
                if hit is None:
                    hit = svs[(qty, key[2])] = self._key_value(key, body, qty, given)
                return hit
        if key is None:
            key = self._find((body, qty, sid))
            given = self._given(key)
        # states that share the variable share its node, the head's in the body's memo
        svs = self._tracks[body].sv
        at = (qty, key[2])
        hit = svs.get(at)
        if hit is None:
            hit = svs[at] = self._key_value(key, body, qty, given)
        return hit

    def _key_value(self, key: tuple, body: str, qty: str, given) -> E:
        sid = key[2]
        name = _state_name(body, qty, sid)
        if given is not None:
            return Known(name, given[0])
        hints = self._hints
        if hints is None:  # whether any state has hints (most scenes: none)
            hints = self._hints = any(st.hints for st in self.scene.states.values())
        unknowns = self.unknowns
        u = unknowns.get(name)
        if u is None:
            dim, unit = STATE_QTYS[qty]
            # no hints in the scene: the shared empty list (records.EMPTY_LIST)
            u = unknowns[name] = Unknown(name, dim, unit, _STATE, [] if hints else EMPTY_LIST,
                                         sid, body, qty)
        if hints:
            hints = self.scene.states[sid].hints
        if hints:
            hints = hints.get((body, qty))
            if hints:
                for h in list(hints):
                    if h not in u.hints:
                        u.hints.append(h)
        return Var(name)

    def mass(self, body: str, sid: str) -> E:
        """A body's mass at a state: as declared, or what the last burn before it left."""
        if self.flows is None:
            m = self._tracks[body].mass
            if m is not None:
                return m
        b = self.scene.bodies[body]
        if self.flows is None or not self.flows.masses:
            tr = self._tracks[body]
            m = tr.mass
            if m is None:
                m = tr.mass = Known(f"m_{body}", b.mass)
            return m
        seen = {sid}
        cur = sid
        while True:
            m = self.flows.masses.get((body, cur))
            if m is not None:
                return m
            prev = self._first_into().get(cur)
            if prev is None or prev in seen:
                return Known(f"m_{body}", b.mass)
            seen.add(prev)
            cur = prev

    def _first_into(self) -> dict[str, str]:
        """state -> the state before it, by the first transition (file order) into it."""
        if self._prev is None:
            self._prev = {}
            for t in self.scene.transitions:
                self._prev.setdefault(t.after, t.before)
        return self._prev

    def vel(self, body: str, sid: str) -> V2:
        vels = self._tracks[body].vel
        hit = vels.get(sid)
        if hit is None:
            hit = vels[sid] = self.vel_miss(body, sid)
        return hit

    def moved_vel(self, body: str, sid: str) -> V2:
        """vel at the state after a transition that moves the body (the transition being
        compiled: the body's velocity breaks there). On the chains, with no velocity of
        it given past its chain's first state and no hints, that is two new unknowns at
        sid: made without searching the chain."""
        tr = self._tracks[body]
        vels = tr.vel
        hit = vels.get(sid)
        if hit is not None:
            return hit
        if tr.late or self._chains is None or self._hints is not False:
            return self.vel(body, sid)
        svs = tr.sv
        ax, ay = ("vx", sid), ("vy", sid)
        if ax in svs or ay in svs:
            return self.vel(body, sid)
        hit = vels[sid] = V2(self._new_unknown(body, "vx", sid, svs, ax),
                             self._new_unknown(body, "vy", sid, svs, ay))
        return hit

    def vel_miss(self, body: str, sid: str) -> V2:
        """vel for a velocity not asked for before (not remembered: the caller does)."""
        chains = self._chains
        w = chains.where.get(sid) if chains is not None else None
        if w is None:
            return V2(self.sv(body, "vx", sid), self.sv(body, "vy", sid))
        return self._on_chain_v(body, sid, w)

    def _on_chain_v(self, body: str, sid: str, w) -> V2:
        """_on_chain of vx, then of vy, in one call (the commonest miss of vel: a body's
        velocity at a state asked for the first time). When vx and vy break at the same
        states (a body moved by impacts, its velocity given whole), one search finds
        both heads, and the commonest heads (both already made; both given there; both
        unknowns of a scene without hints, met for the first time) are made inline;
        anything else goes component by component (_on_chain_q)."""
        c, p = w
        chain = self._chains.chains[c]
        tr = self._tracks[body]
        breaks = tr.breaks
        svs = tr.sv
        pts = breaks.get(("vx", c))
        if pts == breaks.get(("vy", c)):
            k, start = last_break(chain, pts, p)
            ax, ay = ("vx", start), ("vy", start)
            x, y = svs.get(ax), svs.get(ay)
            if x is not None and y is not None:
                return V2(x, y)
            if x is None and y is None:
                states = self.scene.states
                givens = states[start].givens
                bx, by = (body, "vx"), (body, "vy")
                gx, gy = givens.get(bx), givens.get(by)
                later = False  # a later state may give what start does not
                if (gx is None or gy is None) and pts is not None and k + 1 < len(pts):
                    nxt = states[chain[pts[k + 1]]].givens
                    later = bx in nxt or by in nxt
                if not later:
                    if gx is not None and gy is not None:  # _key_value of given ones
                        x = svs[ax] = Known(_state_name(body, "vx", start), gx[0])
                        y = svs[ay] = Known(_state_name(body, "vy", start), gy[0])
                        return V2(x, y)
                    if gx is None and gy is None and self._hints is False:
                        return V2(self._new_unknown(body, "vx", start, svs, ax),
                                  self._new_unknown(body, "vy", start, svs, ay))
        x = self._on_chain_q(body, "vx", c, p, chain, breaks.get(("vx", c)), svs)
        return V2(x, self._on_chain_q(body, "vy", c, p, chain, breaks.get(("vy", c)), svs))

    def _new_unknown(self, body: str, qty: str, sid: str, svs: dict, at: tuple) -> Var:
        """_key_value for an unknown of a scene without hints, remembered in the body's sv
        memo at `at`: its Unknown made if new, and a Var of it."""
        name = _state_name(body, qty, sid)
        unknowns = self.unknowns
        if name not in unknowns:
            dim, unit = STATE_QTYS[qty]
            unknowns[name] = Unknown(name, dim, unit, _STATE, EMPTY_LIST, sid, body, qty)
        hit = svs[at] = _new(Var)
        hit.name = name
        return hit

    def _on_chain_q(self, body: str, qty: str, c, p, chain, pts, svs) -> E:
        """A velocity component's node at chain position p (see _on_chain_v)."""
        k, start = last_break(chain, pts, p)
        # sv's memo holds the node of each head (made once, found again through it;
        # sv may have made it): no break lies between start and sid, so sid's node is
        # start's; vel's memo, the velocity at sid
        at = (qty, start)  # the head's key in the body's sv memo
        hit = svs.get(at)
        if hit is not None:
            return hit
        states = self.scene.states
        bq = (body, qty)
        given = states[start].givens.get(bq)
        if given is None and pts is not None and k + 1 < len(pts):
            nxt = chain[pts[k + 1]]  # a later state may give it (the end velocity)
            g = states[nxt].givens.get(bq)
            if g is not None and self._linked(body, qty, self._chains.into[nxt]):
                at, given = (qty, nxt), g
                hit = svs.get(at)
                if hit is not None:
                    return hit
        if given is not None or self._hints is not False:
            hit = svs[at] = self._key_value((body, qty, at[1]), body, qty, given)
            return hit
        return self._new_unknown(body, qty, at[1], svs, at)

    def pos(self, body: str, sid: str) -> V2:
        return V2(self.sv(body, "x", sid), self.sv(body, "y", sid))

    def arm(self, p: PointOn, sid: str, normal: tuple[float, float] | None = None,
            sign: float = 1.0) -> V2:
        """The world vector from a body's G to point p at state sid."""
        b = self.scene.bodies[p.body]
        if p.round_contact and normal is not None and b.radius:
            r = b.radius
            return V2(Const(-sign * r * normal[0]), Const(-sign * r * normal[1]))
        if p.located_by is not None:
            return rotate_v2(self.symbolic(p.located_by), self.sv(p.body, "angle", sid))
        if p.offset == (0.0, 0.0) or b.is_particle:
            return ZERO_V2
        return rotate(p.offset, self.sv(p.body, "angle", sid))

    def symbolic(self, s: Symbolic) -> E | V2:
        """A force, moment, duration or offset that names unknowns, dimension checked."""
        q = self._evaluator()(s.node, s.dim)
        if q.is_vector != s.vector:
            raise ProblemError(f"{s.what} needs " + ("a vector such as (1, 0); got a scalar"
                                                     if s.vector else "a scalar; got a vector"),
                               s.node.span, code="type")
        if q.dim != s.dim:
            raise ProblemError(f"{s.what} needs {describe(s.dim)}; got {describe(q.dim)}",
                               s.node.span, code="units")
        if s.vector and s.shift != (0.0, 0.0):
            return q.value + V2(Const(s.shift[0]), Const(s.shift[1]))
        return q.value

    def point_velocity(self, p: PointOn | None, sid: str, normal=None, sign=1.0) -> V2:
        if p is None or p.body is None:
            return V2(ZERO, ZERO)
        b = self.scene.bodies[p.body]
        if p.located_by is None and b.is_particle and (
                not (p.round_contact and normal is not None and b.radius) or
                (type(b.radius) in _PLAIN and type(normal[0]) in _PLAIN and
                 type(normal[1]) in _PLAIN and type(sign) in _PLAIN)):
            # a particle's arm is plain numbers (or none) and its w is 0: v itself
            return self.vel(p.body, sid)
        r = self.arm(p, sid, normal, sign)
        v = self.vel(p.body, sid)  # first: the order unknowns are made in is the columns'
        w = self.sv(p.body, "omega", sid)
        if w is ZERO and _plain_const(r.x) and _plain_const(r.y):
            return v  # a particle: w x r folds to zeros, and v + 0 is v
        return v + omega_cross(w, r)

    def point_position(self, p: PointOn | None, sid: str) -> V2:
        if p is None:
            return V2(ZERO, ZERO)
        if p.body is None:
            return V2(Const(p.offset[0]), Const(p.offset[1]))
        return self.pos(p.body, sid) + self.arm(p, sid)

    # ---- equations ------------------------------------------------------------------------------
    def eq(self, lhs: E, rhs: E, principle: str, group: str, span: Span | None,
           kind: EquationKind = EquationKind.AUTO) -> Equation | None:
        e = Equation(lhs, rhs, principle, group, span, kind)
        if self._by_principle is not None and "|" in principle:
            self._seen_by_key()
        if self._by_principle is not None:
            # a repeat has the same principle and prints the same: print an equation
            # only when its principle is seen again (most are unique: it names a body)
            same = self._by_principle.get(principle)
            if same is None:
                self._by_principle[principle] = e
            else:
                if type(same) is not set:
                    same = self._by_principle[principle] = _texts_of(same)
                t = e.text()
                if t in same:
                    return None
                same.add(t)
        else:
            key = principle + "|" + e.text()
            if key in self._seen:
                return None
            self._seen.add(key)
        e.index = len(self.equations)
        self.equations.append(e)
        return e

    def _seen_by_key(self) -> None:
        """From now on, repeats by `principle|text` (a principle with a `|` in it could
        meet another's text there: the keys decide, as they always did)."""
        for principle, same in self._by_principle.items():
            for t in _texts_of(same):
                self._seen.add(principle + "|" + t)
        self._by_principle = None

    # ---- the compile ------------------------------------------------------------------------------
    def run(self) -> System:
        sc = self.scene
        self._positions()
        if sc.steady or sc.burns or sc.gains:
            from .flows import FlowCompiler

            self.flows = FlowCompiler(self)
            # first, in the order of their states: later phases use the mass one leaves
            for b in _chronological(sc.burns + sc.gains):
                if isinstance(b, S.GainDecl):
                    self.flows.gain(b)
                else:
                    self.flows.burn(b)
            for cv in sc.steady:
                self.flows.steady(cv)
        for t in _chronological(sc.transitions):
            if t.kind == TransitionKind.ENERGY:
                self._energy(t)
            else:
                self._impulse_phase(t)
        for sid, st in sc.states.items():
            if self.joints:
                phase = Phase.state(sid)
                for jt in self.joints:
                    jt.stamp(phase, self)
            for body, surface, span in st.rolls:
                self._rolling(body, surface, sid, f"state {sid}", span, None)
        for s in sc.stated:
            self._stated(s)
        for ue in sc.equations:
            self._user_equation(ue)
        finds = self._finds()
        return System(sc, self.unknowns, self.equations, finds, self.transitions, self.friction,
                      self.notes, self.invalid, self.flows.rows if self.flows else [],
                      self.flows.integrations if self.flows else [], self.path_laws)

    def _positions(self) -> None:
        """Which quantities each transition leaves unchanged, and checks of the givens.

        Positions are unchanged by impacts; intervals keep their start configuration.
        A body that nothing acts on in an impact (or, in an interval, no force) keeps
        its velocity. Such quantities share one variable across the transition (see
        `_find`); where the file gives both sides, they must agree.
        """
        sc = self.scene
        for t in sc.transitions:
            if t.kind == TransitionKind.ENERGY:
                continue
            self._busy[t.key] = self._busy_bodies(t)
            self._into.setdefault(t.after, []).append(t)
            self._out.setdefault(t.before, []).append(t)
        self._chains = StateChains.build(sc.states, self._into, self._out, self._busy,
                                         self._tracks)
        states = sc.states
        for sid, st in states.items():
            outs = self._out.get(sid)
            if not outs or not st.givens:
                continue
            # the givens of each state after (a state no transition's: none)
            ends = [(t, states[t.after].givens if t.after in states else {}) for t in outs]
            if not any(g for _, g in ends):
                continue
            for (b, q), (value, span) in st.givens.items():
                for t, after in ends:
                    gc = after.get((b, q))
                    if gc is None or gc[0] == value or not self._linked(b, q, t):
                        continue
                    why = ("positions unchanged during an impact" if q in ("x", "y", "angle")
                           else f"no impulse acts on {b}: its velocity is unchanged")
                    self.eq(Known(state_key(b, q, t.after), gc[0]),
                            Known(state_key(b, q, sid), value),
                            why, f"{t.kind} {t.before} -> {t.after}", gc[1],
                            EquationKind.CONSISTENCY)

    def _moved(self, key: str) -> list[str]:
        """The bodies transition `key` moves, in the scene's order (sorting the few
        busy ones, not scanning every body: N two-body impacts cost O(N))."""
        if self._order is None:
            self._order = {b: k for k, b in enumerate(self.scene.bodies)}
        return sorted(self._busy[key], key=self._order.__getitem__)

    def _busy_bodies(self, t: TransitionSpec) -> set[str]:
        """Bodies that something acts on during an impact or interval."""
        sc = self.scene
        if t.kind == TransitionKind.INTERVAL and sc.gravity is not None:
            return set(sc.bodies)
        busy: set = set()
        for c in t.contacts:
            busy.update((c.a.body, c.b.body if c.b else None))
        for jt in self.joints:
            if jt.acts_in(self, t):
                busy.update(jt.bodies())
        for _, p, _ in t.forces:
            busy.add(p.body)
        for _, b, _ in t.moments:
            busy.add(b)
        for body, _, _ in t.rolls:
            busy.add(body)
        for a, b, _ in t.stops_relative:
            busy.update((a, b))
        for a, _ in t.stops:
            busy.add(a)
        busy.discard(None)
        return busy

    # ---- impacts and intervals ----------------------------------------------------------------
    def _impulse_phase(self, t: TransitionSpec) -> None:
        key = t.key
        if impact_phase.fits(self, t):
            return impact_phase.stamp(self, t, key)
        sc = self.scene
        i, j = t.before, t.after
        group = f"{t.kind} {i} -> {j}"
        is_interval = t.kind == TransitionKind.INTERVAL
        # impulses acting on each body: (arm from G, impulse vector, torque)
        lin: dict[str, list[V2]] = defaultdict(list)
        ang: dict[str, list[E]] = defaultdict(list)
        sources: list[ImpulseSource] = []
        hits: dict[str, list] = defaultdict(list)  # per body: (point, arm, J, torque)
        pins = bool(self.joints)  # hits are read only about a pin (system_laws._pins)
        applied: list[tuple[int, Applied]] = []  # (index of the source it precedes, impulse)
        contacts_info = []
        duration: E | None = None
        if is_interval:
            duration = Const(t.duration) if t.duration is not None else None
            if duration is not None:
                duration = Known(duration_key(key), t.duration)

        def dur() -> E:
            nonlocal duration
            if duration is None:
                duration = self.unknown(duration_key(key), TIME, KeyKind.DURATION, "s")
                u = self.unknowns[duration_key(key)]
                u.hints.append((">", 0.0, t.span))
            return duration

        def apply(p: PointOn | None, J: V2, torque: E | None = None, normal=None, sign=1.0):
            if p is None or p.body is None:
                return
            r = self.arm(p, i, normal, sign)
            if pins:
                hits[p.body].append((p, r, J, torque))
            applied.append((len(sources), Applied(p.body, p, J, torque, r)))
            lin[p.body].append(J)
            if sc.bodies[p.body].is_particle:
                return  # no angular row: its moment is never used
            m = r.cross(J)
            if torque is not None:
                m = add(m, torque)
            ang[p.body].append(m)

        phase = Phase(PhaseKind(t.kind), i, j, group, t.span, apply, sources, contacts_info,
                      dur)
        fast = not is_interval
        bodies = sc.bodies
        for c in t.contacts:
            if fast and impact_contacts.fits(c, bodies):
                impact_contacts.stamp(self, c, i, j, key, group, pins, hits, applied, lin,
                                      sources, contacts_info)
            else:
                contact_element(c).stamp(phase, self)
        for jt in self.joints:
            if jt.acts_in(self, t):
                jt.stamp(phase, self)
        for name, span in t.bearing_friction:
            BearingFriction(self._by_label[name], span).stamp(phase, self)
        if is_interval:
            if sc.gravity is not None:
                for b, body in sc.bodies.items():
                    mg = mul(self.mass(b, i), Known("g", sc.g))  # the weight, m g
                    W = V2(mul(Const(sc.gravity[0] / sc.g), mg),
                           mul(Const(sc.gravity[1] / sc.g), mg))
                    lin[b].append(W.scale(dur()))
                    applied.append((len(sources), Applied(b, PointOn(b, (0.0, 0.0), b, t.span),
                                                          W.scale(dur()), None,
                                                          V2(ZERO, ZERO))))
                    sources.append(ImpulseSource((b, None), b, _unit(sc.gravity), False,
                                           f"weight of {b}"))
            for F, p, span in t.forces:
                Fv = self.symbolic(F) if isinstance(F, Symbolic) else V2(Const(F[0]),
                                                                           Const(F[1]))
                apply(p, Fv.scale(dur()))
                direction = None if isinstance(F, Symbolic) else _unit(F)
                sources.append(ImpulseSource((p.body, None), p.name, direction, False,
                                       f"force at {p.name}"))
            for M, b, span in t.moments:
                Mv = self.symbolic(M) if isinstance(M, Symbolic) else Const(M)
                ang[b].append(mul(Mv, dur()))
                applied.append((len(sources), Applied(b, PointOn(b, (0.0, 0.0), b, span),
                                                      V2(ZERO, ZERO), mul(Mv, dur()),
                                                      V2(ZERO, ZERO))))
                sources.append(ImpulseSource((b, None), b, None, True, f"moment on {b}"))
        if t.duration_expr is not None:
            self.eq(dur(), self.symbolic(t.duration_expr), "the duration as stated", group,
                    t.duration_expr.node.span)
        # impulse-momentum for each body that something acts on
        moved = self._moved(key)
        for b in moved:
            body = sc.bodies[b]
            v1, v2 = self.vel(b, i), self.vel(b, j)
            m = self.mass(b, i)
            for comp, a1, a2, jsum in (("x", v1.x, v2.x, [J.x for J in lin[b]]),
                                       ("y", v1.y, v2.y, [J.y for J in lin[b]])):
                rhs = add_all(jsum)
                if type(a1) in _NAMED and type(a2) in _NAMED and type(m) in _NAMED:
                    lhs = Mul((m, Add((a2, Mul((NEG_ONE, a1))))))  # mul(m, a2 - a1)
                else:
                    lhs = mul(m, add(a2, neg(a1)))
                self.eq(lhs, rhs, f"linear impulse-momentum {comp}: {b}", group, t.span)
            if not body.is_particle:
                I = Known(f"I_{b}", body.inertia)
                w1, w2 = self.sv(b, "omega", i), self.sv(b, "omega", j)
                rhs = add_all(ang[b])
                self.eq(mul(I, add(w2, neg(w1))), rhs,
                        f"angular impulse-momentum about G: {b}", group, t.span)
        # end conditions
        for a, b, span in t.stops_relative:
            ba, bb = sc.bodies[a], sc.bodies[b]
            if ba.is_particle or bb.is_particle:
                raise ProblemError("`stops relative to` compares rotations; a particle has none",
                                   span, code="name")
            self.eq(self.sv(a, "omega", j), self.sv(b, "omega", j),
                    f"{a} stops turning relative to {b}", group, span)
        for a, span in t.stops:
            for q in ("vx", "vy") + (() if sc.bodies[a].is_particle else ("omega",)):
                self.eq(self.sv(a, q, j), ZERO, f"{a} stops", group, span)
        for body, surface, span in t.rolls:
            normal = None
            for c in t.contacts:
                if c.a.body == body and c.b is None and (c.surface in (surface, None) or
                                                         surface == "ground"):
                    normal = c.normal
            self._rolling(body, surface, j, group, span, normal)
        self.sources[key] = sources
        why = self._why(sources, t, moved)
        energy = (self._kinetic(i, moved), self._kinetic(j, moved))
        laws = system_laws(self, t, sources, moved, hits) if not is_interval else []
        for k, a in applied:  # each element applies its impulses, then names its source
            a.what = sources[k].what if k < len(sources) else ""
        self.transitions.append(TransitionInfo(t.kind, key, i, j, t.span, why, contacts_info,
                                               energy, tuple(moved), laws,
                                               [a for _, a in applied]))

    def holds_at(self, from_state: str | None, sid: str) -> bool:
        """Whether something that holds from state `from_state` on (None: always) holds
        in state sid: sid is reachable from it through the transitions."""
        if from_state is None:
            return True
        if self._reach is None:
            self._reach = {}
        seen = self._reach.get(from_state)
        if seen is None:
            if self._next is None:  # state -> the states its transitions lead to, in order
                self._next = {}
                for t in self.scene.transitions:
                    self._next.setdefault(t.before, []).append(t.after)
            seen, todo = {from_state}, [from_state]
            while todo:
                s = todo.pop()
                for after in self._next.get(s, ()):
                    if after not in seen:
                        seen.add(after)
                        todo.append(after)
            self._reach[from_state] = seen
        return sid in seen

    def _rolling(self, body: str, surface: str, sid: str, group: str, span: Span,
                 normal) -> None:
        sc = self.scene
        b = sc.bodies[body]
        if normal is None:
            sf = sc.surfaces.get(surface)
            normal = sf.normal if sf is not None and sf.normal is not None else None
        if normal is None:
            raise ProblemError(f"rolling on '{surface}' needs its normal: declare `surface "
                               f"{surface} normal (0, 1)`", span, code="name")
        if b.radius is None or b.is_particle:
            raise ProblemError(f"'{body}' cannot roll: only disks, rings, spheres and bodies with "
                               "a radius roll", span, code="name")
        p = PointOn(body, (0.0, 0.0), f"{body}'s contact point", span, True)
        v = self.point_velocity(p, sid, normal, 1.0)
        n = V2(Const(normal[0]), Const(normal[1]))
        tg = V2(Const(-normal[1]), Const(normal[0]))
        self.eq(v.dot(tg), ZERO, f"{body} rolls on {surface}: contact point has no slip", group,
                span)
        self.eq(v.dot(n), ZERO, f"{body} rolls on {surface}: stays on the surface", group, span)

    # ---- energy phases ---------------------------------------------------------------------------
    def _kinetic(self, sid: str, bodies=None) -> E:
        names = tuple(self.scene.bodies if bodies is None else bodies)
        hit = self._T.get((sid, names))  # an impact's energy and its T_lost: one tree
        if hit is None:
            hit = self._T[(sid, names)] = self._kinetic_of(sid, names)
        return hit

    def _kinetic_of(self, sid: str, names) -> E:
        terms = []
        tracks = self._tracks
        bodies = self.scene.bodies
        declared = self.flows is None  # a mass remembered is the declared one
        for b in names:
            tr = tracks[b]
            hit = tr.T.get(sid)
            if hit is None:
                m = tr.mass if declared else None
                if m is not None and bodies[b].is_particle:
                    # _body_kinetic of a particle with its declared mass, inline
                    v = tr.vel.get(sid)
                    if v is None:
                        v = tr.vel[sid] = self.vel_miss(b, sid)
                    vx, vy = v.x, v.y
                    if type(vx) in _NAMED and type(vy) in _NAMED and type(m) in _NAMED:
                        hit = (_half_mv2(m, vx, vy),)
                        tr.T[sid] = hit
                        terms.append(hit[0])
                        continue
                hit = tr.T[sid] = self._body_kinetic(b, sid)
            terms.extend(hit)
        return add_all(terms)

    def _body_kinetic(self, b: str, sid: str) -> tuple:
        """A body's terms of T at a state (shared by every sum of T that names it: an
        impact's energy before and after, `T@1`, `T_lost`)."""
        body = self.scene.bodies[b]
        v = self.vel(b, sid)
        m = self.mass(b, sid)
        vx, vy = v.x, v.y
        if type(vx) in _NAMED and type(vy) in _NAMED and type(m) in _NAMED:
            # what mul and add fold 1/2 m (vx vx + vy vy) to, written directly
            t = _half_mv2(m, vx, vy)
        else:
            t = mul(Const(0.5), mul(m, v.dot(v)))
        if body.is_particle:
            return (t,)
        w = self.sv(b, "omega", sid)
        if type(w) in _NAMED:
            return (t, Mul((Const(0.5), Known(f"I_{b}", body.inertia), w, w)))
        return (t, mul(Const(0.5), mul(Known(f"I_{b}", body.inertia), mul(w, w))))

    def _potential(self, sid: str, bodies=None) -> E:
        sc = self.scene
        V: E = ZERO
        if sc.gravity is not None:
            gx, gy = sc.gravity
            g = Known("g", sc.g)
            for b in sc.bodies if bodies is None else bodies:
                r = self.pos(b, sid)
                m = self.mass(b, sid)
                # V = -m g_vec . r: with gravity `down` this is m*g*y
                h = add(mul(Const(-gx / sc.g), r.x), mul(Const(-gy / sc.g), r.y))
                V = add(V, mul(mul(m, g), h))
        for jt in self.joints:
            if bodies is not None and not all(b is None or b in bodies for b in jt.bodies()):
                continue
            e = jt.potential(self, sid)
            if e is not ZERO:
                V = add(V, e)
        return V

    def _energy(self, t: TransitionSpec) -> None:
        # beside an impact (or interval) between the same states the balance is a statement
        # the student makes: the impact's rows decide, and it is checked (true for e = 1),
        # or it finds what they leave open (an unknown e)
        kind = EquationKind.STATED if any(
            tr.kind != TransitionKind.ENERGY and (tr.before, tr.after) == (t.before, t.after)
            for tr in self.scene.transitions) else EquationKind.AUTO
        i, j = t.before, t.after
        u = f"U{i}{j}" if len(i) == len(j) == 1 else f"U{i}-{j}"  # the work from i to j
        group = f"energy {i} -> {j}"
        groups = energy_groups(self.scene, self.joints, self.holds_at, t)
        for msg in split_joints(groups, self.joints, self.holds_at, t):
            self.notes.warn(msg, t.span, code="energy")
        whole = len(groups) == 1 and len(groups[0]) == len(self.scene.bodies)
        for bodies in groups:
            U: E = ZERO
            for F, p, span in t.forces:
                if p.body in bodies:
                    d = self.point_position(p, j) - self.point_position(p, i)
                    U = add(U, d.dot(V2(Const(F[0]), Const(F[1]))))
            for M, b, span in t.moments:
                if b in bodies:
                    U = add(U, mul(Const(M), add(self.sv(b, "angle", j),
                                                 neg(self.sv(b, "angle", i)))))
            lhs = add(add(self._kinetic(i, bodies), self._potential(i, bodies)), U)
            rhs = add(self._kinetic(j, bodies), self._potential(j, bodies))
            of = "" if whole else f" of {{{', '.join(bodies)}}}"
            self.eq(lhs, rhs, f"work-energy{of}: T{i} + V{i} + {u} = T{j} + V{j}", group, t.span,
                    kind)
        for body, surface, span in t.rolls:
            self._rolling(body, surface, j, group, span, None)
        why = [f"energy is conserved except for the work {u} of the declared forces and "
               "moments"]
        if self.scene.gravity is not None:
            why.append("gravity and springs enter as potential energy V")
        self.transitions.append(TransitionInfo("energy", t.key, i, j, t.span, why, [], None,
                                               tuple(b for g in groups for b in g)))

    # ---- why a principle holds --------------------------------------------------------------------
    def _why(self, sources: list[ImpulseSource], t: TransitionSpec,
             bodies: list[str] | None = None) -> list[str]:
        """For the bodies the transition moves (`bodies`, when the caller has them),
        together and one by one (up to six)."""
        out = []
        if bodies is None:
            bodies = self._moved(t.key)
        if not bodies:
            return ["nothing acts: every body keeps its velocity"]
        system = set(bodies)
        shown = bodies if len(bodies) <= 6 else bodies[:3] + ["..."] + bodies[-2:]
        label = f"{{{', '.join(shown)}}}" + (f" ({len(bodies)} bodies)" if len(bodies) > 6
                                               else "")
        ext = [s for s in sources if external(s, system)]
        out.append(self._linear_why(label, ext) + "; " + self._angular_why(label, ext))
        if 1 < len(bodies) <= 6:
            for body in bodies:
                ext = [s for s in sources if external(s, {body})]
                out.append(self._linear_why(body, ext) + "; " + self._angular_why(body, ext))
        return out

    @staticmethod
    def _linear_why(label: str, ext: list[ImpulseSource]) -> str:
        lines = [s for s in ext if not s.torque_only]
        if not lines:
            return f"{label}: no external impulse, so linear momentum is conserved in every " \
                   "direction"
        dirs = [s.direction for s in lines]
        if all(d is not None for d in dirs):
            d0 = dirs[0]
            if all(abs(d0[0] * d[1] - d0[1] * d[0]) < 1e-12 for d in dirs):
                return f"{label}: {_along(d0)}"
        names = ", ".join(sorted({s.what for s in lines}))
        return f"{label}: external impulses ({names}) leave no direction free"

    @staticmethod
    def _angular_why(label: str, ext: list[ImpulseSource]) -> str:
        if not ext:
            return "angular momentum is conserved about every point"
        if any(s.torque_only for s in ext):
            return "an external moment acts, so angular momentum is not conserved"
        points = {s.point for s in ext}
        if len(points) == 1:
            return f"angular momentum is conserved about {points.pop()} (all external impulses " \
                   "act there)"
        return "no point is free of external angular impulse"

_PLAIN = (float, int)  # numbers that are not a sweep's traced ones
_str_new = str.__new__
_STATE = KeyKind.STATE


def _state_name(body: str, qty: str, sid: str) -> Key:
    """state_key(body, qty, sid), with one call instead of its two (a big scene makes
    ~4 a body)."""
    name = _str_new(Key, f"{body}.{qty}@{sid}")
    name.kind = _STATE
    name.body = body
    name.qty = qty
    name.state = sid
    name.transition = name.label = name.comp = None
    return name
_NAMED = (Var, Known)  # leaves that mul and add never fold (a 0 Known is kept)
ZERO_V2 = impact_contacts.ZERO_V2  # the arm of a point at G (a V2 is frozen: one for all)


class Fresh(list):
    """Equations of one principle not yet printed: each holds an unknown made after every
    equation before it, so no two can print the same (see impact_phase's rows). Items:
    an Equation, or the set of texts of those before."""

    __slots__ = ()


_Compiler.Fresh = Fresh


def _texts_of(same) -> set:
    """The texts of what `eq` remembers for a principle: an Equation, a Fresh list, or
    already a set of texts."""
    t = type(same)
    if t is set:
        return same
    if t is Fresh:
        out: set = set()
        for x in same:
            if type(x) is set:
                out |= x
            else:
                out.add(x.text())
        return out
    return {same.text()}


_new = object.__new__


def _half_mv2(m, vx, vy) -> Mul:
    """`Mul((Const(0.5), m, Add((Mul((vx, vx)), Mul((vy, vy))))))`, what mul and add fold
    1/2 m (vx vx + vy vy) to for named leaves, its nodes made by object.__new__ and
    their slots (as their __init__ would; a big scene makes one a body and state)."""
    h = _new(Const)
    h.value = 0.5
    xx = _new(Mul)
    xx.factors = (vx, vx)
    yy = _new(Mul)
    yy.factors = (vy, vy)
    s = _new(Add)
    s.terms = (xx, yy)
    t = _new(Mul)
    t.factors = (h, m, s)
    return t


def _minus(e) -> str | None:
    """The name of x in -x, `Mul((Const(-1.0), x))` with x named; else None."""
    if type(e) is Mul:
        fs = e.factors
        if len(fs) == 2:
            c, x = fs
            if type(c) is Const and type(c.value) is float and c.value == -1.0 and \
                    type(x) in _NAMED:
                return x.name
    return None


def _short_text(e: E) -> str | None:
    """What to_text prints symbolically for the commonest small trees of impulse-momentum
    rows (x, -x, m*(b - a), with named leaves), without its walk; None for any other."""
    t = type(e)
    if t in _NAMED:
        return e.name
    if t is Mul:
        fs = e.factors
        if len(fs) != 2:
            return None
        m, d = fs
        if type(m) in _NAMED and type(d) is Add and len(d.terms) == 2:
            b, a = d.terms
            a = _minus(a)
            if a is not None and type(b) in _NAMED:
                return f"{m.name}*({b.name} - {a})"
            return None
        a = _minus(e)
        return None if a is None else "-" + a
    return None


def _plain_const(e: E) -> bool:
    """A float constant (not a sweep's traced number, whose zero products are kept)."""
    return type(e) is Const and type(e.value) is float


def _unit(v) -> tuple[float, float]:
    n = math.hypot(v[0], v[1])
    return (v[0] / n, v[1] / n)


_ALONG: dict = {}  # direction -> its words (a few directions: bounded below)


def _along(d0) -> str:
    """`external impulses act only along (1, 0), so ...` for direction d0 (remembered:
    an impact's why repeats the words of its normal for each body)."""
    key = (d0[0], d0[1], math.copysign(1.0, d0[0]), math.copysign(1.0, d0[1]))
    hit = _ALONG.get(key)
    if hit is None:
        perp = (-d0[1], d0[0])
        hit = (f"external impulses act only along ({_f(d0[0])}, {_f(d0[1])}), so "
               f"linear momentum is conserved along ({_f(perp[0])}, {_f(perp[1])})")
        if len(_ALONG) < 256 and type(d0[0]) is float and type(d0[1]) is float:
            _ALONG[key] = hit
    return hit


def _f(x: float) -> str:
    s = f"{x:.4g}"
    return "0" if s in ("-0", "0") else s

