"""Compile helper: one record per body, for what compile asks about that body again and again.

In: nothing (compile makes one per body; aliases.StateChains fills in its break positions).
Out: the body's break positions on the state chains and the nodes compile made for it.

Why one record: a body's velocity at a state asked for the first time cost ~13 lookups in
five tables keyed by tuples (body, qty, state) of 10^4-10^5 entries, each key a new tuple.
Reached by one lookup of the body's name, the record's own small dicts stay hot while the
impacts that move the body are compiled (the 10^4-impact cradle: a quarter fewer lookups).
What a new velocity still costs is mostly making its names, Unknowns and nodes.
"""
from __future__ import annotations

VELOCITIES = ("vx", "vy", "omega")
_LINEAR = ("vx", "vy")  # a particle's omega is 0, never a state quantity of its own


class Track:
    """A body's records for compile (the same nodes as before, found in fewer lookups).

    breaks: (qty, chain) -> sorted positions on that chain where the quantity breaks from
            the state before (given there, or moved by the transition into it);
            StateChains.build fills it.
    sv:     (qty, state) -> the node of the quantity at that state (sv's memo; a chain's
            head state holds the node every state up to the next break shares).
    vel:    state -> the velocity V2 at that state (vel's memo).
    T:      state -> the body's terms of kinetic energy there (shared by every sum of T).
    mass:   the Known of its declared mass, once made (None before).
    late:   whether a state after the first of its chain gives its vx or vy (else, on the
            chains, its velocity after a transition that moves it is new unknowns there).
    moves:  the quantities that break where a transition moves the body (a particle's
            omega is always 0: no positions kept for it).
    """

    __slots__ = ("breaks", "sv", "vel", "T", "mass", "late", "moves")

    def __init__(self, moves: tuple = VELOCITIES) -> None:
        self.moves = moves
        self.breaks: dict = {}
        self.sv: dict = {}
        self.vel: dict = {}
        self.T: dict = {}
        self.mass = None
        self.late = False


def tracks_of(bodies: dict) -> dict:
    """A new record for each body (name -> scene.Body)."""
    return {name: Track(_LINEAR if b.is_particle else VELOCITIES) for name, b in bodies.items()}
