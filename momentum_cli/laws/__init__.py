"""Impact laws for one planar contact with Coulomb friction (pure math, no scene).

In: the contact's Delassus matrix W and pre-impact relative velocity v0 in (t, n).
Out: the contact impulse, the final relative velocity, the phases of the impulse
path and the kinetic energy change under Newton's, Poisson's or Stronge's law.
"""
from .impulse_path import (
    LAWS,
    ImpactResult,
    Phase,
    delassus,
    resolve,
)

__all__ = ["LAWS", "ImpactResult", "Phase", "delassus", "resolve"]
