"""Generated-problem property test: random impact scenes, written as problem TEXT,
solved through the real parser and pipeline, against an independent dense solve.

The scenes (tests/scenegen.py) have bodies of every shape, several contacts at once
(smooth, rough, Coulomb friction; restitution given or `?`; with the ground, with declared
surfaces and between bodies), joints (pins to the ground and between bodies, welds,
links; a body on a lone ground pin struck by free bodies) and redundant true statements
(`conserve momentum ...` where it holds, `conserve angular momentum ... about` a lone
ground pin, `equation Q = true value`).
Every scene is well-posed by construction, so each must be answered (a contact that would
pull is answered with a warning), and

* every state-2 velocity, impulse and found e matches the dense solve (numpy, assembled
  here from the generated parameters: Newton-Euler per body, Newton's restitution, the
  tangential laws, joint constraints);
* momentum is conserved along every impulse-free direction, angular momentum about a
  ground pin that is the only external impulse, and frictionless contacts with e <= 1
  that push never gain energy (checked on the program's answers);
* a stated true principle is reported to hold; a pulling contact is warned about; the
  program's friction regimes obey Coulomb (stick inside the cone, sliding friction
  against the slip, never reversing it, with J_n >= 0).

CI runs a fixed budget (`--gen-count`, default 200 scenes); the large run is
`nice -n 10 python -m pytest -m generated --gen-count 10000 tests/test_generated.py`
(or `python tests/scenegen.py --count 10000 --shrink 3` with shrinking).

Gated features (scenegen.GATES) fail on the current main for reasons other branches fix;
they are kept out of the budget and run here as expected failures until their gate is
flipped in scenegen.py.
"""
from __future__ import annotations

import math

import pytest
import scenegen as g

pytestmark = pytest.mark.generated


def _fail_report(outs, limit: int = 3) -> str:
    bad = [o for o in outs if o.status not in ("ok", "pull-refused")]
    lines = [f"{len(bad)} of {len(outs)} generated scenes failed"]
    for o in bad[:limit]:
        lines.append(f"--- seed {o.seed} ({o.category}): {o.status}: {o.detail}\n{o.text}")
    return "\n".join(lines)


def test_generated_scenes(gen_count, gen_start, capsys):
    outs, secs = g.run_many(gen_count, gen_start)
    fig = g.figures(outs, secs)
    if gen_count > 200:  # the large run: say what it measured
        with capsys.disabled():
            print("\ngenerated scenes:", {k: v for k, v in fig.items() if k != "by category"})
            print("by category:", fig["by category"])
    # every category of the budget is drawn
    assert set(fig["by category"]) == set(g.categories()) or gen_count < len(g.categories())
    assert fig["ok"] + fig["pull-refused"] == fig["scenes"], _fail_report(outs)


@pytest.mark.parametrize("gate", sorted(g.GATES))
def test_gated_feature(gate, request):
    """Scenes of one gated feature: an expected failure until the gate is flipped."""
    if not g.GATES[gate]:
        request.applymarker(pytest.mark.xfail(
            reason=f"gate {gate}: fails on main until the fixing branch is merged "
                   "(see scenegen.py); strict: XPASS means flip the gate", strict=True))
    cats = [c for c, gt in g.GATED.items() if gt == gate] or \
        {"check_tolerance": ["redundant"], "structure_rank": ["unknown_e"]}[gate]
    outs, _ = g.run_many(40, 0, cats, gated=[gate])
    assert all(o.status in ("ok", "pull-refused") for o in outs), _fail_report(outs)


# ---- the dense solve itself, against closed forms (so that it is a reference) ------------------

def _particle(name, m, vx, vy=0.0, pos=(0.0, 0.0)):
    return g.Body(name, "particle", m, (), 0.0, pos, (vx, vy, 0.0))


def _solve(bodies, contacts, joints=()):
    return g.dense_solve(g.Scene(0, "hand", list(bodies), list(contacts), list(joints)))


@pytest.mark.parametrize("e", [0.0, 0.3, 1.0])
def test_dense_head_on_particles(e):
    m1, m2, u1, u2 = 2.0, 3.0, 5.0, -1.0
    c = g.Contact("k", g.Pt("a"), g.Pt("b"), (-1.0, 0.0), (-1, 0), e)
    d = _solve([_particle("a", m1, u1), _particle("b", m2, u2)], [c])
    v1 = (m1 * u1 + m2 * u2 - m2 * e * (u1 - u2)) / (m1 + m2)
    v2 = (m1 * u1 + m2 * u2 + m1 * e * (u1 - u2)) / (m1 + m2)
    assert d.v2[("a", "vx")] == pytest.approx(v1, abs=1e-12)
    assert d.v2[("b", "vx")] == pytest.approx(v2, abs=1e-12)
    assert d.impulses["J_n[k]@1->2"] == pytest.approx(m1 * (u1 - v1), abs=1e-12)


def test_dense_particle_strikes_pinned_rod():
    """Angular momentum about the pin and Newton's law: the textbook closed form."""
    M, L, m, v, e, dd = 4.0, 1.2, 0.5, 10.0, 0.5, 0.9  # struck dd from the pin
    rod = g.Body("rod", "rod", M, (L,), 0.0, (L / 2, 0.0), (0.0, 0.0, 0.0))
    pin = g.Joint("pin", "O", g.Pt("rod", (-L / 2, 0.0)), None)
    c = g.Contact("k", g.Pt("p"), g.Pt("rod", (dd - L / 2, 0.0)), (0.0, -1.0), (0, -1), e)
    d = _solve([rod, _particle("p", m, 0.0, -v, (dd - L / 2, 0.0))], [c], [pin])
    I_O = M * L * L / 3
    # m v dd = m v' dd + I_O w ;  w dd - v' = e v  (speeds downward positive for the ball)
    w = m * v * dd * (1 + e) / (I_O + m * dd * dd)
    vp = w * dd - e * v
    assert d.v2[("rod", "omega")] == pytest.approx(-w, rel=1e-12)
    assert d.v2[("p", "vy")] == pytest.approx(-vp, rel=1e-12)


def test_dense_forming_pin_joins_bodies():
    """Issue 9, reproduction 3: 1 kg at 4 m/s joins 3 kg at rest by a pin from state 2."""
    a, b = _particle("a", 1.0, 4.0), _particle("b", 3.0, 0.0)
    pin = g.Joint("pin", "j", g.Pt("a"), g.Pt("b"), forming=True)
    d = _solve([a, b], [], [pin])
    assert d.v2[("a", "vx")] == pytest.approx(1.0) and d.v2[("b", "vx")] == pytest.approx(1.0)
    assert d.impulses["Jx[j]@1->2"] == pytest.approx(-3.0)


@pytest.mark.parametrize("mu, slides", [(0.1, True), (2.0, False)])
def test_dense_friction_on_the_ground(mu, slides):
    """A particle hits the ground obliquely: slide with J_t = -mu J_n, or stick."""
    m, vx, vy, e = 2.0, 3.0, -4.0, 0.5
    c = g.Contact("k", g.Pt("p"), None, (0.0, 1.0), (0, 1), e, mode="friction", mu=mu)
    d = _solve([_particle("p", m, vx, vy)], [c])
    jn = m * (1 + e) * -vy
    assert d.impulses["J_n[k]@1->2"] == pytest.approx(jn)
    if slides:
        assert d.regimes["k"] == "slide"
        assert d.v2[("p", "vx")] == pytest.approx(vx - mu * jn / m)
    else:
        assert d.regimes["k"] == "stick" and d.v2[("p", "vx")] == pytest.approx(0.0, abs=1e-12)


def test_dense_rim_contact_of_a_disk():
    """A round body touches at its rim: friction at G - r n spins it (rough floor)."""
    m, r, vx, vy = 2.0, 0.5, 3.0, -2.0
    disk = g.Body("d", "disk", m, (r,), 0.0, (0.0, r), (vx, vy, 0.0))
    c = g.Contact("k", g.Pt("d", round=True), None, (0.0, 1.0), (0, 1), 0.0, mode="rough")
    dd = _solve([disk], [c])
    # no slip at the rim: vx' + w r = 0 ; angular momentum about the contact point
    I = m * r * r / 2
    w = -m * vx * r / (I + m * r * r)
    assert dd.v2[("d", "omega")] == pytest.approx(w)
    assert dd.v2[("d", "vx")] == pytest.approx(-w * r)


def test_generator_is_deterministic_and_well_posed():
    for seed in range(30):
        a, b = g.generate(seed), g.generate(seed)
        assert g.render(a) == g.render(b)
        d = g.dense_solve(a)
        assert d.rank_ok and math.isfinite(d.cond)
        for c in a.contacts:  # every contact is closing before the impact
            assert g._rel(a, c, None, c.normal) < 0


# ---- the failures found, shrunk by hand to their smallest files ----------------------------------
# Each is an expected failure while its gate (scenegen.GATES) is closed. Expected values are
# hand closed forms, or (slide_sign) the dense solve of the same scene.

REPRODUCTIONS = {
    "forming": ("""\
problem "A 1 kg block at 4 m/s latches onto a 3 kg block at rest"
body a: particle(mass = 1 kg)
body b: particle(mass = 3 kg)
state 1: a.v = (4 m/s, 0), b at rest
state 2
pin a to b from 2
impact 1 -> 2
find a.vx@2, b.vx@2
""", {"a.vx@2": 1.0, "b.vx@2": 1.0}),  # momentum: 1*4 = (1 + 3) v
    "regime_check": ("""\
problem "A ball hits a rough floor obliquely and slides; a true redundant statement"
body p: particle(mass = 2 kg)
state 1: p.v = (3 m/s, -4 m/s)
state 2
impact 1 -> 2:
    contact k: p with ground normal (0, 1): restitution 0.5, friction 0.1
equation p.vx@2 = 2.4 m/s
find p.vx@2, p.vy@2
""", {"p.vx@2": 2.4, "p.vy@2": 2.0}),  # J_n = 2*1.5*4 = 12, slide: vx = 3 - 0.1*12/2
    "check_tolerance": ("""\
problem "Equal balls, e = 1: the striker stops; its speed stated to round-off"
body a: particle(mass = 1 kg)
body b: particle(mass = 1 kg)
state 1: a.v = (5 m/s, 0), b at rest
state 2
impact 1 -> 2:
    contact k: a with b normal (-1, 0): restitution 1, smooth
equation a.vx@2 = 1e-17 m/s
find a.vx@2, b.vx@2
""", {"a.vx@2": 0.0, "b.vx@2": 5.0}),
    "structure_rank": ("""\
problem "Find e from a measured speed; momentum conservation also stated"
body a: particle(mass = 1 kg)
body b: particle(mass = 1 kg)
state 1: a.v = (5 m/s, 0), b at rest
state 2
impact 1 -> 2:
    contact k: a with b normal (-1, 0): restitution ?, smooth
equation b.vx@2 = 4 m/s
conserve momentum x of {a, b} over 1 -> 2
find a.vx@2, e[k]
""", {"a.vx@2": 1.0, "e[k]": 0.6}),  # a: 5 - 4; e = (4 - 1)/5
    "slide_sign": ("""\
problem "Two sliding contacts: a block on a rigid body that strikes a wall"
body quill: rigid(mass = 5.89 kg, inertia = 1.97 kg*m^2)
body jet: plate(mass = 9.73 kg, width = 0.15 m, height = 0.6 m)
point P1 = jet at (0.075 m, 0.3 m)
point P2 = quill at (0.19 m, 0.46 m)
point P3 = quill at (0.8 m, -0.67 m)
state 1:
    quill.angle = 0.0 rad
    quill.vx = -1.26 m/s
    quill.vy = 3.17 m/s
    quill.omega = -0.0775 rad/s
    jet.angle = -1.83 rad
    jet.vx = 0.427 m/s
    jet.vy = 2.91 m/s
    jet.omega = -2.41 rad/s
state 2
impact 1 -> 2:
    contact k1: P1 with P2 normal (0, 1): restitution 0, friction 0.41
    contact k2: P3 with ground normal (1, 0): restitution 0, friction 0.51
find quill.vx@2, jet.vx@2, J_t[k1]@1->2, J_t[k2]@1->2
""", {"quill.vx@2": -0.27385640888767937, "jet.vx@2": 0.3781099054296713,
      "J_t[k1]@1->2": 0.47570062016929765, "J_t[k2]@1->2": -2.719669417055958}),
}


@pytest.mark.parametrize("gate", sorted(REPRODUCTIONS))
def test_reproduction(gate, request):
    """The shrunk failure of each gated feature answers its hand value once fixed."""
    if not g.GATES[gate]:
        request.applymarker(pytest.mark.xfail(
            reason=f"gate {gate}: fails on main (see scenegen.py)", strict=True))
    text, want = REPRODUCTIONS[gate]
    got, _sol = g.program_answers(text)
    for name, value in want.items():
        assert got[name] == pytest.approx(value, rel=1e-9, abs=1e-12), name
