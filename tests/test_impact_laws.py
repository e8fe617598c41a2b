"""Impact laws at one planar contact (momentum_cli.laws): closed forms derived by hand.

Notation: W = [[a, b], [b, c]] in (t, n), v(P) = v0 + W P, v0 = (u, -V) with V > 0.
References: W. J. Stronge, "Rigid body collisions with friction", Proc. R. Soc. Lond.
A 431 (1990) 169-181, and "Impact Mechanics" (CUP), ch. 5 (the inclined slender rod
striking a rough half-space); T. R. Kane and D. A. Levinson, "Dynamics: Theory and
Applications" (McGraw-Hill, 1985), whose double pendulum striking a rough surface
gains kinetic energy under Newton's law with friction.
"""
from __future__ import annotations

import math

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from momentum_cli.laws import delassus, resolve

LAWS = ("newton", "poisson", "energetic")


def rod_w(m: float, l: float, theta: float):
    """The slender rod's W at its lower end A, floor normal n = (0, 1), t = (-1, 0).

    A - G = -(l/2)(cos th, sin th), so r_n = -(l/2) sin th and r_t = (l/2) cos th.
    With I = m l^2 / 12, (l/2)^2 / I = 3/m, and W = (1/m) 1 + (1/I)(r_n, -r_t)(r_n, -r_t)^T:
        a = W_tt = (1 + 3 sin^2 th)/m,  b = W_tn = 3 sin th cos th / m,
        c = W_nn = (1 + 3 cos^2 th)/m,  det W = 4/m^2 (independent of th).
    """
    s, c = math.sin(theta), math.cos(theta)
    return ((1 + 3 * s * s) / m, 3 * s * c / m), ((3 * s * c) / m, (1 + 3 * c * c) / m)


def close(x, y, rel=1e-12):
    return abs(x - y) <= rel * max(1.0, abs(x), abs(y))


def kinetic_change(W, v0, P):
    """T_after - T_before = P . v0 + P . W P / 2 (exact; independent of the path)."""
    (a, b), (_, c) = W
    pt, pn = P
    return pt * v0[0] + pn * v0[1] + 0.5 * (a * pt * pt + 2 * b * pt * pn + c * pn * pn)


# ---- W for free bodies -----------------------------------------------------------------------
def test_delassus_rod_matches_closed_form():
    m, l = 2.0, 1.5
    for deg in (10, 30, 45, 60, 80):
        th = math.radians(deg)
        W = delassus([(m, m * l * l / 12, (-l / 2 * math.cos(th), -l / 2 * math.sin(th)))],
                     (0.0, 1.0))
        Wc = rod_w(m, l, th)
        for i in range(2):
            for j in range(2):
                assert close(W[i][j], Wc[i][j])
        assert close(W[0][0] * W[1][1] - W[0][1] ** 2, 4 / m**2)


def test_delassus_two_particles_is_reduced_mass():
    """Two particles: v_rel changes by P (1/m1 + 1/m2) in every direction."""
    W = delassus([(2.0, None, None), (3.0, None, None)], (0.6, 0.8))
    assert close(W[0][0], 1 / 2 + 1 / 3) and close(W[1][1], 1 / 2 + 1 / 3)
    assert W[0][1] == 0.0


# ---- where the three laws coincide -------------------------------------------------------------
@pytest.mark.parametrize("e", [0.0, 0.4, 1.0])
def test_frictionless_all_laws_coincide(e):
    """Smooth: P_t = 0, v_n = v_n0 + c P_n; compression ends at P_c = V/c and every law
    ends at (1 + e) P_c (on one linear piece the energetic ratio e^2 of the works
    W_r/W_c = (x/P_c)^2 gives x = e P_c too), so v_n = e V."""
    W = ((1.3, 0.4), (0.4, 0.9))
    v0 = (0.7, -2.0)
    pc = 2.0 / 0.9
    for law in LAWS:
        r = resolve(W, v0, e, None, law)
        assert r.impulse[0] == 0.0
        assert close(r.impulse[1], (1 + e) * pc)
        assert close(r.velocity[1], 2.0 * e)
        assert close(r.velocity[0], 0.7 + 0.4 * (1 + e) * pc)


def test_single_regime_stick_all_laws_coincide():
    """No initial slip (u = 0) and |b/a| <= mu: the contact sticks from the start with
    dP_t/dP_n = -b/a and dv_n/dP_n = det/a, so P_c = V a/det, P_n = (1+e) P_c,
    P_t = -(b/a) P_n for every law."""
    W = ((2.0, 0.5), (0.5, 1.0))
    a, b, c = 2.0, 0.5, 1.0
    det = a * c - b * b
    for e in (0.0, 0.5, 1.0):
        pn = (1 + e) * 3.0 * a / det
        for law in LAWS:
            r = resolve(W, (0.0, -3.0), e, 0.3, law)
            assert close(r.impulse[1], pn), law
            assert close(r.impulse[0], -b / a * pn), law
            assert close(r.velocity[0], 0.0, 1e-12) and close(r.velocity[1], 3.0 * e)
            assert r.regimes() == ["stick"]


def test_single_regime_persistent_slide_all_laws_coincide():
    """Slip in +t (s = +1) that friction cannot stop: dv_t/dP_n = b - mu a >= 0. Then
    P_t = -mu P_n throughout, dv_n/dP_n = c - mu b, P_n = (1+e) V/(c - mu b)."""
    W = ((1.0, 0.8), (0.8, 1.0))
    mu, e, V = 0.3, 0.6, 2.0
    pn = (1 + e) * V / (1.0 - mu * 0.8)
    for law in LAWS:
        r = resolve(W, (1.0, -V), e, mu, law)
        assert close(r.impulse[1], pn) and close(r.impulse[0], -mu * pn), law
        assert r.regimes() == ["slide"]


# ---- Stronge's inclined rod: slip halts, then reverses or sticks -----------------------------------
def rod_path(theta, m, u, V, mu):
    """By hand, for the rod of `rod_w` with u < 0 (slip in -t, friction dP_t = +mu dP_n):
    phase 1 (slide):  dv_t/dP_n = b + mu a > 0, so the slip halts at p1 = -u/(b + mu a);
                      dv_n/dP_n = g1 = c + mu b, v_n(p1) = -V + g1 p1.
    phase 2:          stick if b/a <= mu with g2 = det/a, k2 = -b/a; else the slip
                      reverses to +t with dP_t = -mu dP_n, g2 = c - mu b, k2 = -mu.
    Compression ends in phase 2 when v_n(p1) < 0: P_c = p1 - v_n(p1)/g2.
    The normal work in compression is the area under the piecewise-linear v_n:
        W_c = p1 (-V + v1)/2 + (P_c - p1) v1/2,  v1 = v_n(p1).
    """
    (a, b), (_, c) = rod_w(m, 1.0, theta)
    p1 = -u / (b + mu * a)
    g1 = c + mu * b
    v1 = -V + g1 * p1
    if b / a <= mu:
        g2, k2, second = (a * c - b * b) / a, -b / a, "stick"
    else:
        g2, k2, second = c - mu * b, -mu, "reverse"
    assert v1 < 0
    pc = p1 - v1 / g2
    wc = p1 * (-V + v1) / 2 + (pc - p1) * v1 / 2
    return dict(a=a, b=b, c=c, p1=p1, v1=v1, g2=g2, k2=k2, pc=pc, wc=wc, second=second,
                mu=mu)


def pt_at(path, pn):
    """P_t after P_n in phase 2: mu p1 from phase 1, then k2 per unit P_n."""
    return path["mu"] * path["p1"] + path["k2"] * (pn - path["p1"])


@pytest.mark.parametrize("mu,second", [(0.5, "reverse"), (0.8, "stick")])
def test_stronge_rod_poisson_and_energetic(mu, second):
    """45 deg rod, m = 1 kg: a = c = 5/2, b = 3/2 (stick ratio 3/5); u = -0.6, V = 1.
    Poisson: P_f = (1 + e) P_c. Energetic: restitution lies in phase 2 where v_n rises
    from 0 with slope g2, so W_r = g2 x^2 / 2 = e^2 |W_c| gives x = e sqrt(2|W_c|/g2)."""
    th, e, u, V = math.radians(45), 0.9, -0.6, 1.0
    W = rod_w(1.0, 1.0, th)
    path = rod_path(th, 1.0, u, V, mu)
    assert path["second"] == second
    # the rational numbers at 45 deg: p1 = 0.6/(1.5 + 2.5 mu)
    assert close(path["p1"], 0.6 / (1.5 + 2.5 * mu))
    r = resolve(W, (u, -V), e, mu, "poisson")
    pf = (1 + e) * path["pc"]
    assert close(r.compression_end, path["pc"])
    assert close(r.impulse[1], pf) and close(r.impulse[0], pt_at(path, pf))
    assert r.regimes() == ["slide", second]
    assert close(r.work_compression, path["wc"])
    r = resolve(W, (u, -V), e, mu, "energetic")
    pf = path["pc"] + e * math.sqrt(2 * abs(path["wc"]) / path["g2"])
    assert close(r.impulse[1], pf) and close(r.impulse[0], pt_at(path, pf))
    assert close(r.work_restitution, e * e * abs(path["wc"]))
    # the final velocity, from (1)
    a, b, c = path["a"], path["b"], path["c"]
    pt = pt_at(path, pf)
    assert close(r.velocity[0], u + a * pt + b * pf) and close(r.velocity[1], -V + b * pt + c * pf)
    if second == "stick":
        assert abs(r.velocity[0]) < 1e-12
    # the three laws differ here
    n = resolve(W, (u, -V), e, mu, "newton").impulse[1]
    p = resolve(W, (u, -V), e, mu, "poisson").impulse[1]
    assert len({round(n, 9), round(p, 9), round(pf, 9)}) == 3


def test_stronge_rod_numbers_at_45_degrees_mu_0_8():
    """mu = 0.8, e = 0.9 in fractions: p1 = 0.6/(1.5 + 2) = 6/35; g1 = 2.5 + 1.2 = 3.7;
    v1 = -1 + 3.7*6/35 = -64/175; stick (3/5 <= 0.8), g2 = det/a = 4/2.5 = 8/5;
    P_c = 6/35 + (64/175)/(8/5) = 6/35 + 8/35 = 2/5. Poisson: P_n = 1.9*2/5 = 0.76,
    P_t = 0.8*6/35 - (3/5)(0.76 - 6/35) = 24/175 - 0.456 + 18/175 = -0.216."""
    W = rod_w(1.0, 1.0, math.radians(45))
    r = resolve(W, (-0.6, -1.0), 0.9, 0.8, "poisson")
    assert close(r.compression_end, 0.4)
    assert close(r.impulse[1], 0.76) and close(r.impulse[0], -0.216)
    assert abs(r.velocity[0]) < 1e-12 and close(r.velocity[1], -1 + 1.5 * -0.216 + 2.5 * 0.76)


# ---- Kane and Levinson: Newton's law with friction can create energy ---------------------------
def test_newton_with_friction_gains_energy_where_the_path_laws_do_not():
    """45 deg rod, m = 1 kg, u = -0.6, V = 1, e = 0.9, mu = 0.5. Newton with stick:
    W P = (0, eV) - v0 = (0.6, 1.9), det = 4, so P_t = (2.5*0.6 - 1.5*1.9)/4 = -0.3375,
    P_n = (2.5*1.9 - 1.5*0.6)/4 = 0.9625; |P_t|/P_n = 0.35 <= mu, so stick "holds".
    dT = P . (v0 + v_final)/2 = (-0.3375*(-0.6) + 0.9625*(-1 + 0.9))/2 = +0.053125:
    the friction impulse points along the initial slip (both -t), so it does positive
    work: the energy gain Kane and Levinson found for their double pendulum."""
    W = rod_w(1.0, 1.0, math.radians(45))
    r = resolve(W, (-0.6, -1.0), 0.9, 0.5, "newton")
    assert close(r.impulse[0], -0.3375) and close(r.impulse[1], 0.9625)
    assert r.regimes() == ["stick"]
    assert close(r.energy_change, 0.053125)
    assert r.gains_energy
    for law in ("poisson", "energetic"):
        q = resolve(W, (-0.6, -1.0), 0.9, 0.5, law)
        assert q.energy_change < 0 and not q.gains_energy


def test_rough_stops_the_slip_at_once():
    """mu = inf: P_t jumps by -u/a at P_n = 0 (v_n changes by -b u/a), then sticks with
    slope det/a: P_c = (V + b u/a) a/det for V > -b u/a."""
    W = ((2.0, 0.5), (0.5, 1.0))
    u, V = 1.0, 2.0
    a, b, c = 2.0, 0.5, 1.0
    det = a * c - b * b
    pc = (V + b * u / a) * a / det
    r = resolve(W, (u, -V), 0.5, math.inf, "poisson")
    assert r.regimes() == ["stop", "stick"]
    assert close(r.compression_end, pc)
    assert close(r.impulse[1], 1.5 * pc)
    assert close(r.impulse[0], -u / a - b / a * 1.5 * pc)
    assert abs(r.velocity[0]) < 1e-12


# ---- properties -------------------------------------------------------------------------------------
@st.composite
def impacts(draw):
    a = draw(st.floats(0.05, 20))
    c = draw(st.floats(0.05, 20))
    rho = draw(st.one_of(st.floats(-0.99, 0.99), st.sampled_from([-1.0, 1.0])))  # 1: rank 1
    b = rho * math.sqrt(a * c)
    u = draw(st.floats(-5, 5))
    V = draw(st.floats(0.01, 5))
    if abs(rho) == 1.0:  # one degree of freedom: every velocity is along q, W = q q^T
        q = (math.sqrt(a), rho * math.sqrt(c))
        u = -V * q[0] / q[1]
    e = draw(st.floats(0, 1))
    mu = draw(st.one_of(st.none(), st.floats(0, 3), st.just(math.inf)))
    return ((a, b), (b, c)), (u, -V), e, mu


@settings(max_examples=300, deadline=None)
@given(impacts())
@example((((1.0, 0.0), (0.0, 5.0)), (0.0, -3.472941895780789), 1e-30, None))  # v_n(P_c) ~ -0
def test_path_laws_properties(case):
    """Energetic never gains energy; compression ends at v_n = 0; |P_t| <= mu P_n on every
    piece (Coulomb); the energy summed over the pieces equals P.v0 + P.W.P/2."""
    W, v0, e, mu = case
    for law in ("poisson", "energetic"):
        r = resolve(W, v0, e, mu, law)
        scale = abs(v0[0]) + abs(v0[1])
        pc = r.compression_end
        comp = [p for p in r.phases if p.stage == "compression"]
        assert abs(comp[-1].v_end[1]) <= 1e-9 * scale or pc == 0.0
        for p in r.phases:
            dpt, dpn = p.pt[1] - p.pt[0], p.pn[1] - p.pn[0]
            assert dpn >= 0
            if mu is None:
                assert dpt == 0
            elif math.isfinite(mu):
                assert abs(dpt) <= mu * dpn * (1 + 1e-9) + 1e-12
        dT = kinetic_change(W, v0, r.impulse)
        T_scale = abs(r.impulse[0] * v0[0]) + abs(r.impulse[1] * v0[1]) + 1e-300
        assert abs(r.energy_change - dT) <= 1e-9 * T_scale
        if law == "energetic":
            assert r.energy_change <= 1e-9 * T_scale and not r.gains_energy
            assert r.velocity[1] >= -1e-9 * scale


# ---- the language: the three example files against the closed forms -------------------------------
EXAMPLES = __import__("pathlib").Path(__file__).resolve().parent.parent / "examples"


def solved(path_or_text: str):
    from helpers import solve_text

    text = (EXAMPLES / path_or_text).read_text() if path_or_text.endswith(".mom") \
        else path_or_text
    sol = solve_text(text)
    return sol, {name: si for name, _v, _u, si in sol.answers}


def rod_floor_expected(law: str) -> dict[str, float]:
    """examples/rod_rough_floor_*.mom: m = 2 kg, 45 deg, v_G = (1.2, -2) m/s, omega = 0,
    e = 0.9, mu = 0.5. With t = (-1, 0): u = -1.2, V = 2; W = rod_w(2, 1, 45 deg).
    Newton: P = W^-1 (-u, (1 + e) V) (stick holds: |P_t| <= mu P_n). Poisson and
    energetic: `rod_path` (the slip halts at p1, then reverses: b/a = 3/5 > mu).
    After: v_G = v_G0 + (-P_t, P_n)/m; omega = (r x P)/I with r = A - G;
    T_lost = -(P . v0 + P . W P / 2)."""
    m, th, u, V, e, mu = 2.0, math.radians(45), -1.2, 2.0, 0.9, 0.5
    (a, b), (_, c) = rod_w(m, 1.0, th)
    if law == "newton":
        det = a * c - b * b
        rt, rn = -u, (1 + e) * V
        pt, pn = (c * rt - b * rn) / det, (a * rn - b * rt) / det
        assert abs(pt) <= mu * pn
    else:
        path = rod_path(th, m, u, V, mu)
        assert path["second"] == "reverse"
        pn = (1 + e) * path["pc"] if law == "poisson" else \
            path["pc"] + e * math.sqrt(2 * abs(path["wc"]) / path["g2"])
        pt = pt_at(path, pn)
    I = m / 12
    r = (-0.5 * math.cos(th), -0.5 * math.sin(th))
    Px, Py = -pt, pn
    dT = pt * u + pn * -V + 0.5 * (a * pt * pt + 2 * b * pt * pn + c * pn * pn)
    return {"J_n[A]@1->2": pn, "J_t[A]@1->2": pt, "rod.vx@2": 1.2 + Px / m,
            "rod.vy@2": -2.0 + Py / m, "rod.omega@2": (r[0] * Py - r[1] * Px) / I,
            "T_lost@1->2": -dT}


def test_examples_rod_rough_floor_three_laws_match_closed_forms():
    """The three example files against `rod_floor_expected`; Newton gains
    dT = (P_t u + P_n (e - 1) V)/2 = 0.425 J and is warned about, the others lose."""
    for law in LAWS:
        sol, ans = solved(f"rod_rough_floor_{law}.mom")
        want = rod_floor_expected(law)
        for k, v in want.items():
            assert close(ans[k], v, 1e-9), (law, k)
        gain = [ch for ch in sol.checks if ch.name.startswith("impact law")]
        assert len(gain) == 1
        if law == "newton":
            assert close(-want["T_lost@1->2"], 0.425, 1e-9)
            assert gain[0].status == "warning" and "energetic" in gain[0].detail
        else:
            assert want["T_lost@1->2"] > 0 and gain[0].status == "ok"
            assert "slide" in gain[0].detail and "reverse" in gain[0].detail


DOUBLE = """problem "double pendulum strikes a rough floor"
body r1: rod(mass = 1 kg, length = 1 m)
body r2: rod(mass = 1 kg, length = 1 m)
point O = r1.end(-)
point A = r1.end(+)
point B = r2.end(-)
point C = r2.end(+)
pin O to ground at (0, 0)
pin A to B
state 1: r1.angle = {t1} deg, r2.angle = {t2} deg, r1.x = {x1} m, r1.y = {y1} m, r2.x = {x2} m, \\
    r2.y = {y2} m, r1.omega = {w1} rad/s, r2.omega = {w2} rad/s
state 2
impact 1 -> 2:
    contact C with ground normal (0, 1): restitution {e} {law}, friction {mu}
find J_n[C]@1->2, J_t[C]@1->2, r1.omega@2, r2.omega@2
"""


def double_pendulum(t1, t2, w1, w2, e, mu, law):
    """Two uniform rods (m, l = 1) pinned at O and to each other, the lower end C striking
    a rough floor. Independently, in generalized speeds (w1, w2) (absolute angles):
    T = q'^T M q'/2 with M11 = m l^2/4 + I + m l^2 = 4/3, M22 = m l^2/4 + I = 1/3,
    M12 = (m l^2/2) cos(t1 - t2); v_C = w1 l e1' + w2 l e2' with e' = (-sin, cos), so in
    (t, n) = ((-1, 0), (0, 1)) the Jacobian's columns are (sin t_k, cos t_k). An impulse
    P at C changes q' by M^-1 J^T P, so W = J M^-1 J^T and v0 = J q'0 (Stronge, ch. 5;
    Kane and Levinson's double pendulum is this system)."""
    a1, a2 = math.radians(t1), math.radians(t2)
    M = [[4 / 3, 0.5 * math.cos(a1 - a2)], [0.5 * math.cos(a1 - a2), 1 / 3]]
    dm = M[0][0] * M[1][1] - M[0][1] ** 2
    Mi = [[M[1][1] / dm, -M[0][1] / dm], [-M[1][0] / dm, M[0][0] / dm]]
    J = [[math.sin(a1), math.sin(a2)], [math.cos(a1), math.cos(a2)]]
    W = [[sum(J[i][k] * Mi[k][l] * J[j][l] for k in range(2) for l in range(2))
          for j in range(2)] for i in range(2)]
    v0 = (J[0][0] * w1 + J[0][1] * w2, J[1][0] * w1 + J[1][1] * w2)
    r = resolve(W, v0, e, mu, law)
    Jt = [[J[0][0], J[1][0]], [J[0][1], J[1][1]]]
    dq = [sum(Mi[i][k] * (Jt[k][0] * r.impulse[0] + Jt[k][1] * r.impulse[1])
              for k in range(2)) for i in range(2)]
    return r, (w1 + dq[0], w2 + dq[1])


@pytest.mark.parametrize("law", LAWS)
def test_double_pendulum_w_from_the_joints(law):
    """The solver's W at C comes from momentum and pin rows; it must equal J M^-1 J^T."""
    t1, t2, w1, w2, e, mu = -60.0, -20.0, 1.0, -2.0, 0.7, 0.3
    a1, a2 = math.radians(t1), math.radians(t2)
    g1 = (0.5 * math.cos(a1), 0.5 * math.sin(a1))
    A = (math.cos(a1), math.sin(a1))
    g2 = (A[0] + 0.5 * math.cos(a2), A[1] + 0.5 * math.sin(a2))
    text = DOUBLE.format(t1=t1, t2=t2, x1=g1[0], y1=g1[1], x2=g2[0], y2=g2[1], w1=w1, w2=w2,
                         e=e, mu=mu, law=law)
    r, (w1f, w2f) = double_pendulum(t1, t2, w1, w2, e, mu, law)
    _, ans = solved(text)
    assert close(ans["J_n[C]@1->2"], r.impulse[1], 1e-8)
    assert close(ans["J_t[C]@1->2"], r.impulse[0], 1e-8)
    assert close(ans["r1.omega@2"], w1f, 1e-8) and close(ans["r2.omega@2"], w2f, 1e-8)


# ---- errors ------------------------------------------------------------------------------------
ROD = """problem "p"
body rod: rod(mass = 1 kg, length = 1 m)
body ball: particle(mass = 1 kg)
point A = rod.end(-)
point B = rod.end(+)
state 1: rod.angle = 45 deg, rod.v = (0.6 m/s, -1 m/s), rod.omega = 0, ball.v = (0, 0)
state 2
{stmt}
find rod.omega@2
"""


@pytest.mark.parametrize("stmt,words", [
    ("impact 1 -> 2:\n    contact A with ground normal (0, 1): restitution 0.5 poisson, "
     "friction 0.3\n    contact B with ball normal (0, 1): restitution 0.5 energetic, smooth",
     "two contacts"),
    ("unknown e0\nimpact 1 -> 2:\n    contact A with ground normal (0, 1): restitution e0 "
     "energetic, smooth", "known coefficient"),
    ("impact 1 -> 2:\n    contact A with ground normal (0, -1): restitution 0.5 poisson, "
     "smooth", "not approaching"),
    ("interval 1 -> 2:\n    contact A with ground normal (0, 1): restitution 0.5 poisson, "
     "friction 0.3\n    duration 1 s", "resolves an impact"),
])
def test_path_law_errors_are_located(stmt, words):
    from helpers import error_of

    d = error_of(ROD.format(stmt=stmt))
    assert words in d.message and d.span is not None


def test_law_word_after_a_name_and_default_is_newton():
    """`restitution e0 poisson` (a `let` value) parses; no word means Newton's law."""
    base = ROD.format(stmt="let e0 = 0.5\nimpact 1 -> 2:\n    contact A with ground normal "
                      "(0, 1): restitution e0 {law}, friction 0.3")
    _, a = solved(base.format(law="poisson"))
    _, b = solved(base.format(law=""))
    _, c = solved(base.format(law="newton"))
    assert b == c and a != b


def test_a_stated_answer_is_checked_in_the_second_pass():
    """Appending `equation rod.vx@2 = <closed form>` changes nothing; 1e-3 off is an error
    naming the appended line (the first pass solves only the state before the impact)."""
    from helpers import error_of

    text = (EXAMPLES / "rod_rough_floor_poisson.mom").read_text()
    want = rod_floor_expected("poisson")
    ok = text + f"equation rod.vx@2 = {want['rod.vx@2']!r} m/s\n"
    _, ans = solved(ok)
    assert close(ans["J_n[A]@1->2"], want["J_n[A]@1->2"], 1e-9)
    bad = text + f"equation rod.vx@2 = {want['rod.vx@2'] * 1.001!r} m/s\n"
    d = error_of(bad)
    assert "inconsistent" in d.message and d.span.line == len(text.splitlines()) + 1


def test_the_state_before_must_not_come_through_the_impact():
    """The impulse path needs v0: a state before that only the impact's far side fixes
    (here rod.vx@1 from a given rod.vx@2) is refused at the contact."""
    from helpers import error_of

    text = ROD.format(stmt="impact 1 -> 2:\n    contact A with ground normal (0, 1): "
                      "restitution 0.5 poisson, friction 0.3").replace(
        "rod.v = (0.6 m/s, -1 m/s)", "rod.vy = -1 m/s").replace(
        "state 2\n", "state 2: rod.vx = 0.2 m/s\n")
    d = error_of(text)
    assert "rod.vx@1 (before the impact) is found only through" in d.message
    assert d.span.line == 9


def test_kane_levinson_double_pendulum_newton_gains_the_solver_warns():
    """The double pendulum (rods at -50 and -60 deg, both turning at -2 rad/s, e = 0.5,
    mu = 0.5): Newton's stick solution "holds" (|P_t| <= mu P_n) yet the impact more than
    doubles T; T before = q'^T M q'/2 from `double_pendulum`'s M. The solver's T_lost
    is minus that gain and a warning names C and the energetic law; Stronge's law loses."""
    t1, t2, w1, w2, e, mu = -50.0, -60.0, -2.0, -2.0, 0.5, 0.5
    a1, a2 = math.radians(t1), math.radians(t2)
    T0 = 0.5 * (4 / 3 * w1 * w1 + 1 / 3 * w2 * w2 + math.cos(a1 - a2) * w1 * w2)
    g1 = (0.5 * math.cos(a1), 0.5 * math.sin(a1))
    A = (math.cos(a1), math.sin(a1))
    g2 = (A[0] + 0.5 * math.cos(a2), A[1] + 0.5 * math.sin(a2))
    for law in ("newton", "energetic"):
        r, _ = double_pendulum(t1, t2, w1, w2, e, mu, law)
        text = DOUBLE.format(t1=t1, t2=t2, x1=g1[0], y1=g1[1], x2=g2[0], y2=g2[1], w1=w1,
                             w2=w2, e=e, mu=mu, law=law).replace(
            "find J_n[C]@1->2", "find T_lost@1->2, J_n[C]@1->2")
        sol, ans = solved(text)
        assert close(ans["T_lost@1->2"], -r.energy_change, 1e-8)
        warn = [c for c in sol.checks if c.name.startswith("impact law at C")]
        if law == "newton":
            assert r.energy_change > T0  # more than doubled
            assert warn and warn[0].status == "warning" and "energetic" in warn[0].detail
        else:
            assert r.energy_change < 0 and warn[0].status == "ok"


def test_a_given_velocity_after_a_path_law_impact_is_refused():
    """The path law decides the velocities after the impact; one given there would
    over-determine them (a located error, not a silent choice)."""
    from helpers import error_of

    text = ROD.format(stmt="impact 1 -> 2:\n    contact A with ground normal (0, 1): "
                      "restitution 0.5 energetic, friction 0.3").replace(
        "state 2\n", "state 2: rod.omega = -1 rad/s\n")
    d = error_of(text)
    assert "must follow from momentum" in d.message and d.span.line == 9


PINNED = """problem "pinned rod strikes a rough floor"
body rod: rod(mass = 1 kg, length = 1 m)
point O = rod.end(+)
point A = rod.end(-)
pin O to ground at (0, 0)
state 1: rod.angle = 60 deg, rod.x = -0.25 m, rod.y = {y} m, rod.omega = 2 rad/s
state 2
impact 1 -> 2:
    contact A with ground normal (0, 1): restitution 0.5 {law}, friction {mu}
find rod.omega@2, J_n[A]@1->2
"""


@pytest.mark.parametrize("mu", [0.3, 0.8])
def test_pendulum_one_degree_of_freedom(mu):
    """A rod (m = 1, l = 1) pinned at its upper end O strikes a rough floor with its lower
    end A (Stronge's compound pendulum). With rho = A - O = -(cos 60, sin 60) and
    q = k x rho in (t, n): q_t = -sin 60, q_n = -cos 60; I_O = m l^2/3. The contact's
    velocity is omega q, so W = q q^T / I_O (singular) and, sliding, omega changes at
    (q_n - mu s q_t)/I_O per unit P_n: it reaches 0 (v = 0, slip halted and compression
    over together) at P_c = |omega0| I_O/(|q_n| + mu |q_t|). Then, if |q_n/q_t| > mu, the
    slip reverses and omega grows at (|q_n| - mu |q_t|)/I_O the other way:
        Poisson:   omega_f = -e omega0 (|q_n| - mu|q_t|)/(|q_n| + mu|q_t|),
        energetic: omega_f = -e omega0 sqrt((|q_n| - mu|q_t|)/(|q_n| + mu|q_t|))
    (the normal work is v_n^2/(2 slope) on each side). If |q_n/q_t| <= mu it sticks with
    no velocity change at all: the contact locks, omega_f = 0; the energetic law ends at
    P_c, Poisson's at (1 + e) P_c (the pin takes the rest)."""
    qt, qn, I, w0, e = -math.sin(math.radians(60)), -0.5, 1 / 3, 2.0, 0.5
    pc = w0 * I / (abs(qn) + mu * abs(qt))
    ratio = (abs(qn) - mu * abs(qt)) / (abs(qn) + mu * abs(qt))
    W = ((qt * qt / I, qt * qn / I), (qt * qn / I, qn * qn / I))
    for law in ("poisson", "energetic"):
        if ratio > 0:
            wf = -e * w0 * (ratio if law == "poisson" else math.sqrt(ratio))
            pn = None
        else:
            wf = 0.0
            pn = (1 + e) * pc if law == "poisson" else pc
        r = resolve(W, (w0 * qt, w0 * qn), e, mu, law)
        assert close(r.compression_end, pc, 1e-12)
        assert r.locked == (ratio <= 0)
        text = PINNED.format(y=-math.sin(math.radians(60)) / 2, law=law, mu=mu)
        sol, ans = solved(text)
        assert abs(ans["rod.omega@2"] - wf) <= 1e-12 * w0, law
        if pn is not None:
            assert close(ans["J_n[A]@1->2"], pn, 1e-9)
            assert any("locks" in c.detail for c in sol.checks)


def test_two_path_law_impacts_in_sequence():
    """The rod of the examples strikes the floor at A (Poisson), then its upper end B a
    wall on the right (normal (-1, 0), energetic). Independently: each impact from the
    rigid-body kinematics, v_P = v_G + omega k x r, W from `delassus`, and the impulse
    applied as dv_G = P/m, d omega = (r x P)/I with P = P_t t + P_n n."""
    text = (EXAMPLES / "rod_rough_floor_poisson.mom").read_text().replace(
        "point A = rod.end(-)", "point A = rod.end(-)\npoint B = rod.end(+)").replace(
        'state 2 "just after impact"', 'state 2 "just after impact"\nstate 3').replace(
        "find rod.v@2", "impact 2 -> 3:\n    contact B with ground normal (-1, 0): "
        "restitution 0.7 energetic, friction 0.2\n\nfind rod.v@3, rod.omega@3, rod.v@2")
    m, I, th = 2.0, 2.0 / 12, math.radians(45)
    v, w = [1.2, -2.0], 0.0
    for end, n, e, mu, law in ((-1, (0.0, 1.0), 0.9, 0.5, "poisson"),
                               (1, (-1.0, 0.0), 0.7, 0.2, "energetic")):
        r = (end * 0.5 * math.cos(th), end * 0.5 * math.sin(th))
        t = (-n[1], n[0])
        vp = (v[0] - w * r[1], v[1] + w * r[0])
        W = delassus([(m, I, r)], n)
        res = resolve(W, (vp[0] * t[0] + vp[1] * t[1], vp[0] * n[0] + vp[1] * n[1]), e, mu, law)
        P = (res.impulse[0] * t[0] + res.impulse[1] * n[0],
             res.impulse[0] * t[1] + res.impulse[1] * n[1])
        v = [v[0] + P[0] / m, v[1] + P[1] / m]
        w += (r[0] * P[1] - r[1] * P[0]) / I
    sol, ans = solved(text)
    assert close(ans["rod.vx@3"], v[0], 1e-9) and close(ans["rod.vy@3"], v[1], 1e-9)
    assert close(ans["rod.omega@3"], w, 1e-9)
    assert len([c for c in sol.checks if c.name.startswith("impact law")]) == 2
