"""Property tests of `simulate` (hypothesis): the laws hold over time, across impacts.

Random scenes are written as problem text and simulated; what is checked comes from
the laws, not from the program: momentum is conserved where no external force or
impulse acts, kinetic energy is never gained in e <= 1 frictionless impacts (and kept
for e = 1), and the results do not depend on the frame's orientation, on the units the
file is written in, or on which of two mirror-image bodies is which.
"""
from __future__ import annotations

import math
import os

from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st

from momentum_cli.scene import build
from momentum_cli.sim.integrate import simulate
from momentum_cli.source import Source
from momentum_cli.syntax import parse

N = int(os.environ.get("MOMENTUM_PROPERTY_EXAMPLES", "150")) // 5
SETTINGS = settings(derandomize=True, max_examples=max(N, 5), deadline=None, database=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
FT, LB = 0.3048, 0.45359237

masses = st.floats(0.05, 20.0)
radii = st.floats(0.01, 0.3)
speeds = st.floats(-8.0, 8.0)
restitutions = st.floats(0.0, 1.0)


def sim(text: str, **kw):
    return simulate(build(parse(Source("p.mom", text))), **kw)


def momentum(res, k):
    vel = res.events[k].after
    return [sum(b.mass * vel[b.name][i] for b in res.model.bodies) for i in (0, 1)]


def kinetic(res, k):
    vel = res.events[k].after
    return sum(0.5 * b.mass * (vel[b.name][0] ** 2 + vel[b.name][1] ** 2) +
               0.5 * b.inertia * vel[b.name][2] ** 2 for b in res.model.bodies)


TWO_SPHERES = """
body a: sphere(mass = {ma} kg, radius = {ra} m)
body b: sphere(mass = {mb} kg, radius = {rb} m)
state 1: a.pos = (0, 0), b.pos = ({bx} m, {by} m), a.v = ({vax} m/s, {vay} m/s), \\
    b.v = ({vbx} m/s, {vby} m/s), a.omega = 0, b.omega = 0
simulate from 1:
    contact a with b: restitution {e}, smooth
    until t = 2 s
"""


@SETTINGS
@given(ma=masses, mb=masses, ra=radii, rb=radii, e=restitutions,
       angle=st.floats(-math.pi, math.pi), offset=st.floats(-0.9, 0.9), speed=st.floats(0.5, 6),
       vbx=speeds, vby=speeds)
def test_two_spheres_in_free_space_keep_momentum_and_lose_energy(ma, mb, ra, rb, e, angle,
                                                                    offset, speed, vbx, vby):
    # b starts 1 m away along `angle`; a heads for it, aimed off-centre by `offset` radii
    d = 1.0 + ra + rb
    bx, by = d * math.cos(angle), d * math.sin(angle)
    aim = angle + math.asin(offset * (ra + rb) / d)
    vax, vay = speed * math.cos(aim), speed * math.sin(aim)
    text = TWO_SPHERES.format(ma=ma, mb=mb, ra=ra, rb=rb, e=e, bx=bx, by=by, vax=vax, vay=vay,
                              vbx=vbx * 0.01, vby=vby * 0.01)
    res = sim(text)
    p0, p1 = momentum(res, 0), momentum(res, -1)
    scale = ma * speed + mb * math.hypot(vbx, vby) * 0.01
    assert all(abs(x - y) <= 1e-12 * scale for x, y in zip(p0, p1))  # no external impulse
    T0, T1 = kinetic(res, 0), kinetic(res, -1)
    assert T1 <= T0 * (1 + 1e-12)
    if e == 1.0:
        assert abs(T1 - T0) <= 1e-12 * T0
    hits = [ev for ev in res.events if ev.kind == "impact"]
    assert len(hits) <= 1  # two spheres in free space meet at most once


BOUNCE = """
gravity {g} {len_u}/s^2 along ({gx}, {gy})
body ball: sphere(mass = {m} {mass_u}, radius = {r} {len_u})
surface floor normal ({nx}, {ny}) at (0, 0)
state 1: ball.pos = ({x} {len_u}, {y} {len_u}), ball.v = ({vx} {len_u}/s, {vy} {len_u}/s), \\
    ball.omega = 0
simulate from 1:
    contact ball with floor: restitution {e}
    until 3 impacts
"""


def bounce(alpha, m, r, h, u, v, e, units="si"):
    """A ball thrown above a floor, the whole scene turned by alpha; in SI or US units."""
    c, s = math.cos(alpha), math.sin(alpha)

    def turn(x, y):
        return c * x - s * y, s * x + c * y

    x, y = turn(u * 0.0, h + r)
    vx, vy = turn(u, v)
    nx, ny = turn(0.0, 1.0)
    gx, gy = turn(0.0, -1.0)
    if units == "us":
        return BOUNCE.format(g=9.81 / FT, gx=gx, gy=gy, m=m / LB, mass_u="lbm", r=r / FT, nx=nx,
                             ny=ny, x=x / FT, y=y / FT, vx=vx / FT, vy=vy / FT, e=e,
                             len_u="ft")
    return BOUNCE.format(g=9.81, gx=gx, gy=gy, m=m, mass_u="kg", r=r, nx=nx, ny=ny, x=x, y=y,
                         vx=vx, vy=vy, e=e, len_u="m")


@SETTINGS
@given(alpha=st.floats(-math.pi, math.pi), m=masses, r=radii, h=st.floats(0.1, 3.0),
       u=speeds, v=speeds, e=st.floats(0.3, 1.0))
def test_bounces_do_not_depend_on_the_frame_or_the_units(alpha, m, r, h, u, v, e):
    upright = sim(bounce(0.0, m, r, h, u, v, e))
    turned = sim(bounce(alpha, m, r, h, u, v, e))
    us = sim(bounce(alpha, m, r, h, u, v, e, units="us"))
    t0 = [ev.t for ev in upright.events if ev.kind == "impact"]
    assert len(t0) == 3
    for other in (turned, us):
        t1 = [ev.t for ev in other.events if ev.kind == "impact"]
        assert all(abs(a - b) <= 1e-9 * max(1.0, a) for a, b in zip(t0, t1)) and len(t1) == 3
    c, s = math.cos(alpha), math.sin(alpha)
    for k, ev in enumerate(ev for ev in upright.events if ev.kind == "impact"):
        vx, vy, _ = ev.after["ball"]
        want = (c * vx - s * vy, s * vx + c * vy)
        for other in (turned, us):
            got = [e_ for e_ in other.events if e_.kind == "impact"][k].after["ball"]
            assert math.hypot(got[0] - want[0], got[1] - want[1]) <= 1e-9 * (1 + abs(u) + abs(v))
        # Newton's law at a smooth floor: the normal velocity reverses, times e
        before = ev.before["ball"]
        assert abs(vy + e * before[1]) <= 1e-9 * (1 + abs(before[1]))
        assert abs(vx - before[0]) <= 1e-12 * (1 + abs(before[0]))


MIRROR = """
gravity 9.81 m/s^2 down
body {p}: disk(mass = {m} kg, radius = {r} m)
body {q}: disk(mass = {m} kg, radius = {r} m)
surface floor normal (0, 1) at (0, 0)
state 1: {p}.pos = ({x} m, {y} m), {p}.v = ({u} m/s, {v} m/s), {p}.omega = {w} rad/s, \\
    {q}.pos = ({mx} m, {y} m), {q}.v = ({mu} m/s, {v} m/s), {q}.omega = {mw} rad/s
simulate from 1:
    contact {p} with floor: restitution {e}, friction {f}
    contact {q} with floor: restitution {e}, friction {f}
    contact {p} with {q}: restitution {e}
    until t = 1.5 s
"""


@SETTINGS
@given(m=masses, r=radii, x=st.floats(0.5, 2.0), y=st.floats(0.5, 2.0), u=speeds, v=speeds,
       w=st.floats(-20, 20), e=restitutions, f=st.floats(0.0, 0.8))
@example(m=1.0, r=0.25, x=1.0, y=1.0, u=0.0, v=0.0, w=0.0, e=0.0, f=0.0)  # mu = 0 chattered
@example(m=5.8125, r=0.25, x=1.0, y=0.5, u=3.0, v=0.0, w=0.0, e=0.25, f=0.0)  # fell through
def test_mirror_images_move_as_mirror_images(m, r, x, y, u, v, w, e, f):
    """Two disks thrown at each other symmetrically about x = 0 over a rough floor stay
    mirror images (x -> -x, vx -> -vx, omega -> -omega), whichever is named first."""
    assume(y > r + 0.01)
    text = MIRROR.format(p="L", q="R", m=m, r=r, x=-x, mx=x, y=y, u=u, mu=-u, v=v, w=w, mw=-w,
                         e=e, f=f)
    res = sim(text)
    fL, fR = res.frame(), res.frame()
    (xl, yl, _), (vxl, vyl, wl) = fL.pose["L"], fL.twist["L"]
    (xr, yr, _), (vxr, vyr, wr) = fR.pose["R"], fR.twist["R"]
    scale = 1 + abs(u) + abs(v) + abs(w) * r
    assert abs(xl + xr) <= 1e-9 * (1 + x) and abs(yl - yr) <= 1e-9 * (1 + y)
    assert abs(vxl + vxr) <= 1e-8 * scale and abs(vyl - vyr) <= 1e-8 * scale
    assert abs(wl + wr) * r <= 1e-8 * scale
    n = res.model.n
    lowest = min(min(s[1], s[4]) for s in res.states)  # the centres' heights (L.y, R.y)
    assert lowest >= r - 1e-6 and n == 6  # nothing falls through the floor
    swapped = sim(MIRROR.format(p="R", q="L", m=m, r=r, x=x, mx=-x, y=y, u=-u, mu=u, v=v, w=-w,
                                mw=w, e=e, f=f))
    assert [ev.kind for ev in swapped.events] == [ev.kind for ev in res.events]
    fs = swapped.frame()
    assert abs(fs.pose["L"][0] - xl) <= 1e-9 * (1 + x)
