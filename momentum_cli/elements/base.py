"""The Element interface: a contact law or a joint that writes its own equations.

An element is built from its scene statement and answers every question the stages ask
of it: its unknowns and rows for an impact, an interval or a state (`stamp`), its
regimes and inequalities (`regimes`, `check`), its rows for `simulate` (`constraint`),
its energy (`potential`) and what the report says of it (`describe`). Compile and
simulate iterate over elements; nothing else switches on their kind.
"""
from __future__ import annotations

from collections.abc import Callable

from ..expr import ZERO, E
from ..records import field, record
from ..source import Span
from .keys import Key
from .kinds import PhaseKind, Regime


@record
class ImpulseSource:
    """An impulse source acting during a transition, for 'why a principle holds'."""

    bodies: tuple[str | None, str | None]  # the two sides (None: ground)
    point: str  # the name of where it acts
    direction: tuple[float, float] | None  # None: any direction in the plane
    torque_only: bool = False
    what: str = ""


@record
class FrictionSite:
    """A contact whose tangential law depends on a regime chosen at solve time."""

    key: str
    label: str
    transition: str
    mu: float
    jn: str
    jt: str | None
    regime: Regime
    slip_expr: E | None  # tangential slip velocity whose sign the slide must oppose
    span: Span
    decided: bool = True  # False: the slip direction is re-checked after solving
    law: object = None  # its tangential law (contacts.Coulomb): `law.stick_holds(jt, jn)`
    slip_after: E | None = None  # an impact's slip after it: its regime is one of 3 to choose


@record
class Phase:
    """What an element stamps rows for: an impact or interval (before -> after, with the
    impulse bookkeeping of that transition) or one state (before == after)."""

    kind: PhaseKind
    before: str
    after: str
    group: str
    span: Span | None = None
    apply: Callable | None = None  # apply(point, J, torque=None, normal=None, sign=1.0)
    sources: list[ImpulseSource] = field(default_factory=list)
    contacts: list = field(default_factory=list)  # (label, v_n before, v_n after) for reports
    dur: Callable[[], E] | None = None  # the interval's duration (made unknown on demand)

    @property
    def key(self) -> str:
        return f"{self.before}->{self.after}"

    @staticmethod
    def state(sid: str) -> "Phase":
        return Phase(PhaseKind.STATE, sid, sid, f"state {sid}")


@record(frozen=True)
class SimRow:
    """One velocity constraint row for simulate: A u' = -beta, its force along `col` of B
    (None: along the row itself)."""

    name: str  # its constraint force: Fx[O], F[link], M[weld], N[A], F_t[A]
    row: object  # numpy row over the velocities u
    beta: float  # the acceleration term without u'
    angular: bool = False  # a rotation row (drift scales it by the length scale)
    col: object = None


@record
class Check:
    """One of an element's inequalities, judged on solved values."""

    what: str
    ok: bool
    detail: str


def registrar(table: dict):
    """A class decorator factory: `@by_kind(KIND)` sets the class's `kind` and files it
    in `table` under that kind (how a new law or joint joins its family)."""
    def by_kind(kind):
        def register(cls):
            cls.kind = kind
            table[kind] = cls
            return cls
        return register
    return by_kind


class Element:
    """Base of every contact law and joint: by default it adds nothing anywhere."""

    label: str
    span: Span

    def bodies(self) -> tuple[str | None, ...]:
        return ()

    def unknowns(self, phase: Phase) -> list[Key]:
        """The keys of the unknowns it adds in `phase`."""
        return []

    def stamp(self, phase: Phase, compiler) -> None:
        """Add its unknowns and rows for `phase` to the compiler's system."""

    def regimes(self) -> tuple[Regime, ...]:
        return ()

    def check(self, values: dict) -> list[Check]:
        return []

    def constraint(self, frame, *args) -> list[SimRow]:
        """Its velocity constraint rows for simulate at one frame (sim.dynamics.Frame)."""
        return []

    def potential(self, compiler, sid: str) -> E:
        """Its potential energy at state sid (a spring's); zero for most."""
        return ZERO

    def describe(self) -> str:
        return self.label
