"""Elements: contact laws and joints that write their own rows, structured keys, enums.

Expected numbers come from closed forms written here (momentum and angular momentum
conservation of the joined bodies, Newton's law for two particles), not from the program.
"""
from __future__ import annotations

import math
import pickle
import pytest
from helpers import answers, solve_text

from momentum_cli.diagnostics import ProblemError
from momentum_cli.elements.contacts import (
    Coulomb,
    ContactElement,
    RestitutionLaw,
    restitution_law,
    RESTITUTION_LAWS,
)
from momentum_cli.elements.joints import Damper, Spring
from momentum_cli.elements.keys import Key, duration_key, impulse_key, state_key
from momentum_cli.elements.kinds import (
    Component,
    JointKind,
    KeyKind,
    Regime,
    Restitution,
    Tangential,
)
from momentum_cli.expr import Const, mul, neg
from momentum_cli.scene import build
from momentum_cli.sim.integrate import simulate
from momentum_cli.solve import solve_scene
from momentum_cli.source import Source
from momentum_cli.syntax import parse


def scene_of(text: str):
    return build(parse(Source("t.mom", text)))


def replace(rec, **changes):
    """A copy of a record with some fields changed."""
    fields = {f: getattr(rec, f) for f in type(rec).__annotations__}
    return type(rec)(**(fields | changes))


# a 2 kg particle at 5 m/s strikes a 3 kg one at rest, e = 1
TWO_PARTICLES = """
body a: particle(mass = 2 kg)
body b: particle(mass = 3 kg)
state 1: a.v = (5 m/s, 0), b at rest
state 2
impact 1 -> 2:
    contact a with b normal (-1, 0): restitution 1, smooth
"""


# ---- keys and kinds -------------------------------------------------------------------------
def test_a_key_is_its_name_and_carries_its_fields():
    k = state_key("rod", "omega", "3")
    assert k == "rod.omega@3" and {"rod.omega@3": 1}[k] == 1
    assert (k.kind, k.body, k.qty, k.state) == (KeyKind.STATE, "rod", "omega", "3")
    j = impulse_key(Component.JN, "A", "2->3")
    assert j == "J_n[A]@2->3" and j.local == "J_n[A]" and j.transition == "2->3"
    assert j.kind is KeyKind.IMPULSE and j.comp is Component.JN and j.label == "A"
    assert impulse_key(Component.M, "O", "1->2").kind is KeyKind.ANGULAR_IMPULSE
    t = pickle.loads(pickle.dumps(duration_key("1->2")))
    assert t == "t@1->2" and t.transition == "1->2" and t.kind is KeyKind.DURATION


def test_kinds_print_as_the_file_writes_them():
    assert JointKind("weld") is JointKind.WELD and f"{JointKind.WELD} w" == "weld w"
    assert str(Tangential.FRICTION) == "friction" and Regime.SLIDE_NEG.sign == -1.0
    assert Regime.sliding(0.3) is Regime.SLIDE_POS and Regime.STICK == "stick"


def test_the_solved_unknowns_are_keys():
    sol = solve_text(TWO_PARTICLES + "find b.vx@2\n")
    keys = {k: k for k in sol.system.unknowns}
    jn = keys["J_n[a-b]@1->2"]
    assert isinstance(jn, Key) and jn.comp is Component.JN and jn.transition == "1->2"
    v = keys["b.vx@2"]
    assert (v.body, v.qty, v.state) == ("b", "vx", "2")


# ---- contact laws -------------------------------------------------------------------------------
def _contact(text_props: str):
    sc = scene_of(f"""
body a: particle(mass = 1 kg)
state 1: a.v = (0, -1 m/s)
state 2
impact 1 -> 2:
    contact a with ground normal (0, 1): {text_props}
""")
    return ContactElement(sc.transitions[0].contacts[0])


def test_a_contact_element_names_its_impulses_by_its_tangential_law():
    from momentum_cli.elements.base import Phase
    from momentum_cli.elements.kinds import PhaseKind

    phase = Phase(PhaseKind.IMPACT, "1", "2", "impact 1 -> 2")
    smooth, rough = _contact("restitution 0.5, smooth"), _contact("restitution 0.5, rough")
    assert smooth.unknowns(phase) == ["J_n[a]@1->2"]
    assert rough.unknowns(phase) == ["J_n[a]@1->2", "J_t[a]@1->2"]
    assert smooth.describe() == "contact a: restitution 0.5, smooth"
    assert _contact("separation 2 m/s").restitution.kind is Restitution.SEPARATION


def test_coulomb_owns_its_cone_and_its_regimes():
    law = _contact("restitution 0, friction 0.5").tangential
    assert isinstance(law, Coulomb)
    assert law.regimes() == (Regime.STICK, Regime.SLIDE_POS, Regime.SLIDE_NEG)
    assert law.stick_holds(0.5, 1.0) and law.stick_holds(-0.5, 1.0)
    assert not law.stick_holds(0.51, 1.0)
    assert law.sim_regime(1e-12, 1e-9) == "stick"
    assert law.sim_regime(-0.2, 1e-9) == -1.0 and law.sim_regime(0.2, 1e-9) == 1.0
    assert _contact("restitution 0, friction 0").tangential.sim_regime(0.2, 1e-9) == "rest"


def test_contact_checks_are_its_inequalities():
    el = _contact("restitution 0, friction 0.5")
    jn, jt = impulse_key(Component.JN, "a", "1->2"), impulse_key(Component.JT, "a", "1->2")
    ok = el.check({jn: 2.0, jt: 0.9})
    assert all(c.ok for c in ok)
    bad = el.check({jn: -1.0, jt: 0.9})
    assert [c.ok for c in bad] == [False, False]


def test_a_new_restitution_law_is_one_subclass():
    """A toy law (the separation speed is a third of the approach speed, whatever the
    file says) plugs in by registering; two particles then follow Newton's e = 1/3."""

    @restitution_law("third")
    class Third(RestitutionLaw):
        def stamp_impact(self, rows, compiler):
            compiler.eq(rows.vn2, mul(neg(Const(1 / 3)), rows.vn1), "a third", rows.phase.group,
                        self.c.span)

    try:
        sc = scene_of(TWO_PARTICLES + "find a.vx@2, b.vx@2\n")
        t = sc.transitions[0]
        t.contacts = [replace(c, law="third") for c in t.contacts]
        got = {n: si for n, _v, _u, si in solve_scene(sc).answers}
    finally:
        del RESTITUTION_LAWS["third"]
    m1, m2, v1, e = 2.0, 3.0, 5.0, 1 / 3
    assert math.isclose(got["a.vx@2"], (m1 - e * m2) * v1 / (m1 + m2), rel_tol=1e-12)
    assert math.isclose(got["b.vx@2"], (1 + e) * m1 * v1 / (m1 + m2), rel_tol=1e-12)


# ---- joints ----------------------------------------------------------------------------------
def test_springs_and_dampers_pull_by_their_own_laws():
    sc = scene_of("""
body a: particle(mass = 1 kg)
point P = ground at (0, 0)
spring s: a to P stiffness 200 N/m length 0.5 m
state 1: a.pos = (1 m, 0), a at rest
""")
    jt = sc.joints[0]
    spring = Spring(jt, sc)
    assert spring.kind is JointKind.SPRING and not spring.impulsive
    assert spring.tension(0.8, 0.0) == pytest.approx(200 * 0.3)
    damper = Damper(replace(jt, kind=JointKind.DAMPER, stiffness=4.0), sc)
    assert damper.tension(0.8, 2.0) == 8.0 and damper.power(8.0, 2.0) == -16.0


# ---- reproduction 3: a joint that forms in an impact ---------------------------------------------
def latched(m1: float, m2: float, v1: float) -> str:
    """Particle a (m1 at v1) and b (m2 at rest) at one place, pinned together from state 2."""
    return f"""
body a: particle(mass = {m1} kg)
body b: particle(mass = {m2} kg)
pin latch: a to b from 2
state 1: a.pos = (0, 0), a.v = ({v1} m/s, 0), b.pos = (0, 0), b at rest
state 2
"""


def test_a_pin_that_forms_in_an_impact_joins_the_bodies_plastically():
    m1, m2, v1 = 1.0, 3.0, 4.0
    got = answers(latched(m1, m2, v1) + """impact 1 -> 2
find a.vx@2, b.vx@2, Jx[latch]@1->2
""")
    v = m1 * v1 / (m1 + m2)  # momentum of the pair is conserved
    assert math.isclose(got["a.vx@2"], v, rel_tol=1e-12)
    assert math.isclose(got["b.vx@2"], v, rel_tol=1e-12)
    assert math.isclose(got["Jx[latch]@1->2"], m1 * (v - v1), rel_tol=1e-12)


def test_a_weld_that_forms_in_an_impact_conserves_angular_momentum():
    """A 1 kg disk moving at 4 m/s across the end of a 3 kg, 1 m rod at rest welds to
    it: the pair moves as one body, with the momentum and the angular momentum about its
    centre of mass that the disk brought."""
    M, L, m, r, v0 = 3.0, 1.0, 1.0, 0.1, 4.0
    got = answers(f"""
body rod: rod(mass = {M} kg, length = {L} m)
body d: disk(mass = {m} kg, radius = {r} m)
point E = rod at ({L / 2} m, 0)
weld d to E from 2
state 1: rod.pos = (0, 0), rod.angle = 0, rod at rest, \\
    d.pos = ({L / 2} m, 0), d.angle = 0, d.v = (0, {v0} m/s), d.omega = 0
state 2
impact 1 -> 2
find rod.omega@2, d.omega@2, rod.vy@2, d.vy@2, rod.vx@2
""")
    xc = m * (L / 2) / (M + m)  # the pair's centre of mass, on the rod's axis
    vc = m * v0 / (M + m)
    H = m * (L / 2 - xc) * v0  # the disk's angular momentum about it (the rod is at rest)
    I = M * L * L / 12 + M * xc ** 2 + m * r * r / 2 + m * (L / 2 - xc) ** 2
    w = H / I
    assert math.isclose(got["rod.omega@2"], w, rel_tol=1e-12)
    assert math.isclose(got["d.omega@2"], w, rel_tol=1e-12)
    assert math.isclose(got["rod.vy@2"], vc - w * xc, rel_tol=1e-12)
    assert math.isclose(got["d.vy@2"], vc + w * (L / 2 - xc), rel_tol=1e-12)
    assert abs(got["rod.vx@2"]) < 1e-12


# ---- reproduction 8: simulate refuses a law it cannot apply --------------------------------
@pytest.mark.parametrize("law", ["restitution ?", "separation 2 m/s"])
def test_simulate_refuses_a_contact_without_a_restitution(law):
    text = f"""problem "ball"
gravity 9.81 m/s^2 down
body ball: sphere(mass = 0.1 kg, radius = 20 mm)
surface floor normal (0, 1) at (0, 0)
state 1: ball.pos = (0, 1.02 m), ball at rest
state 2
state 3
impact 2 -> 3:
    contact ball with floor: {law}, smooth
simulate from 1:
    until 2 impacts
"""
    with pytest.raises(ProblemError) as err:
        simulate(scene_of(text), rtol=1e-6)
    d = err.value.diagnostics[0]
    line = text.splitlines()[d.span.line - 1]
    assert d.span.line == 9 and line[d.span.column - 1:].startswith(law.split()[0])
    assert "restitution" in d.message


def test_coulomb_chooses_its_next_regime_from_the_solved_impulses():
    from momentum_cli.elements.base import FrictionSite

    law = _contact("restitution 0, friction 0.5").tangential
    site = FrictionSite("1->2:a", "a", "1->2", 0.5, "jn", "jt", Regime.STICK, None, None)
    assert law.next_regime(site, {"jn": 2.0, "jt": 0.9}) is None  # inside the cone
    assert law.next_regime(site, {"jn": 2.0, "jt": -1.5}) is Regime.SLIDE_POS  # J_t < 0
    assert law.next_regime(site, {"jn": 2.0, "jt": 1.5}) is Regime.SLIDE_NEG


def test_a_joint_formed_in_one_impact_acts_in_the_next():
    """The latched pair (1 kg at 4 m/s onto 3 kg) then strikes a wall with e = 1/2 at b:
    the pin carries b's rebound to a, so the pair leaves at -e times its common speed."""
    m1, m2, v1, e = 1.0, 3.0, 4.0, 0.5
    got = answers(latched(m1, m2, v1) + f"""state 3
impact 1 -> 2
impact 2 -> 3:
    contact b with ground normal (-1, 0): restitution {e}, smooth
find a.vx@3, b.vx@3, Jx[latch]@2->3
""")
    v = m1 * v1 / (m1 + m2)
    assert math.isclose(got["a.vx@3"], -e * v, rel_tol=1e-12)
    assert math.isclose(got["b.vx@3"], -e * v, rel_tol=1e-12)
    assert math.isclose(got["Jx[latch]@2->3"], m1 * (-e * v - v), rel_tol=1e-12)
