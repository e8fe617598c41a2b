"""The kinds the core switches on, as enums: joints, tangential laws, restitution laws,
friction regimes, transitions and unknowns.

They are `str` enums, so a kind prints and serialises as the word the file uses and a
record built before this module existed still compares equal to its member.
"""
from __future__ import annotations

from enum import Enum


class _Word(str, Enum):
    def __str__(self) -> str:  # as the file writes it, in every message and golden
        return self.value

    __format__ = str.__format__


class JointKind(_Word):
    PIN = "pin"
    WELD = "weld"
    LINK = "link"
    SPRING = "spring"
    DAMPER = "damper"  # a simulation's dashpot: a force along its line, no impulse
    SLIDER = "slider"  # a collar free along a body's line, held across it


class Tangential(_Word):
    """What a contact does along its surface."""

    SMOOTH = "smooth"  # no tangential impulse
    ROUGH = "rough"  # no slip after the impact (an impact only)
    FRICTION = "friction"  # Coulomb: |J_t| <= mu J_n, stick or slide


class Restitution(_Word):
    """How a contact's normal impulse ends an impact."""

    NEWTON = "newton"  # v_n+ = -e v_n-
    SEPARATION = "separation"  # v_n+ given
    POISSON = "poisson"  # P_n = (1 + e) P_c along the impulse path
    ENERGETIC = "energetic"  # restitution work = e^2 x compression work (Stronge)


class Regime(_Word):
    """A Coulomb contact's state for one transition."""

    STICK = "stick"
    REST = "rest"  # simulate: a persistent contact with no tangential force (smooth)
    SLIDE_POS = "slide+"  # slipping along +t: friction along -t
    SLIDE_NEG = "slide-"
    NO_SLIP = "no slip"  # a rough contact: no regime to choose; its friction is only checked

    @property
    def sign(self) -> float:
        """The slip direction along t (0 when sticking)."""
        return {Regime.SLIDE_POS: 1.0, Regime.SLIDE_NEG: -1.0}.get(self, 0.0)

    @staticmethod
    def sliding(slip: float) -> "Regime":
        return Regime.SLIDE_POS if slip > 0 else Regime.SLIDE_NEG


class TransitionKind(_Word):
    IMPACT = "impact"
    INTERVAL = "interval"
    ENERGY = "energy"


class PhaseKind(_Word):
    """What an element is asked to stamp rows for."""

    IMPACT = "impact"
    INTERVAL = "interval"
    STATE = "state"


class KeyKind(_Word):
    """What an unknown (or a named known) is: the Unknown record's `kind` words."""

    STATE = "state"
    IMPULSE = "impulse"
    ANGULAR_IMPULSE = "angular-impulse"
    RESTITUTION = "restitution"
    DURATION = "duration"
    USER = "user"
    DERIVED = "derived"
    PARAMETER = "parameter"  # a named known: e[A], v_sep[A], I_rod, m_rod


class Component(_Word):
    """The symbol of an impulse or parameter key: J_n[A]@2->3 has Component.JN."""

    JN = "J_n"
    JT = "J_t"
    JX = "Jx"
    JY = "Jy"
    J = "J"  # along a link
    M = "M"  # a moment impulse (weld, bearing friction)
    J_HOLD = "J_hold"  # the friction impulse that would hold a stopped body (a static check)
    E = "e"
    V_SEP = "v_sep"


class Clause(_Word):
    """A clause of a transition or a simulate block (syntax.Clause.kind)."""

    BEARING_FRICTION = "bearing-friction"
    BEARING_TORQUE = "bearing-torque"
    STOPS_RELATIVE = "stops-relative"
    STOPS = "stops"
    ROLLS = "rolls"
    FORCE = "force"
    MOMENT = "moment"
    DURATION = "duration"
    FREE = "free"


class Prop(_Word):
    """A property of a contact clause (syntax.Prop.kind)."""

    RESTITUTION = "restitution"
    RESTITUTION_UNKNOWN = "restitution?"
    SMOOTH = "smooth"
    ROUGH = "rough"
    FRICTION = "friction"
    SLIP = "slip"
    SEPARATION = "separation"
    STATIC = "static"  # the static coefficient a no-slip contact is checked against


class EquationKind(_Word):
    """Where an equation comes from: the scene's physics, or a statement to check."""

    AUTO = "auto"  # written by the compiler from the scene
    STATED = "stated"  # a principle the file states (checked when redundant)
    USER = "user"  # an `equation` line
    CONSISTENCY = "consistency"  # two givens that must agree
