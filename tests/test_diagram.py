"""The impulse diagram (report/diagram.py, report/diagram_svg.py): which impulses act on
which body, where and which way, what is dropped and why; the SVG drawing to scale.

Expected impulses are closed forms derived here (impulse-momentum by hand), never the
program's own output.
"""
from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import pytest
from conftest import EXAMPLES

from momentum_cli.report.diagram import direction_words
from momentum_cli.run import read_source, solve_source

SVG = "{http://www.w3.org/2000/svg}"


def diagrams(path):
    res = solve_source(read_source(str(path)))
    assert res.report is not None, res.diagnostics
    return res.report.diagrams


def impulses_on(d, body):
    return {i.name: i for i in d.impulses if i.body == body}


def dropped(d):
    return [x.what + ": " + x.why for x in d.dropped]


# ---- the data --------------------------------------------------------------------------------
def test_rod_on_smooth_floor_normal_impulse_only():
    (d,) = diagrams(EXAMPLES / "seed_rod_drop_smooth.mom")
    assert d.title == "Impulse diagram, impact 2 -> 3"
    on = impulses_on(d, "rod")
    assert set(on) == {"J_n[A]"}  # smooth: no tangential impulse
    jn = on["J_n[A]"]
    assert jn.direction == pytest.approx((0.0, 1.0)) and jn.words.startswith("up")
    # it acts at the lower end: G + (L/2)(-cos 30, -sin 30) with G at y = 0
    assert jn.at[1] == pytest.approx(-0.25)
    # closed form, e = 1: J = -2 v1 / (1/m + r_x^2 / I_G), v1 = -sqrt(2 g h)
    m, L, g = 10.0, 1.0, 9.81
    rx = -L / 2 * math.cos(math.radians(30))
    J = 2 * math.sqrt(2 * g * 1.0) / (1 / m + rx * rx / (m * L * L / 12))
    assert jn.value == pytest.approx(J, rel=1e-9)
    text = dropped(d)
    assert any(t.startswith("weight of rod") and "zero duration" in t for t in text)
    assert any(t.startswith("friction at A") and "smooth" in t for t in text)


def test_rod_on_rough_floor_has_a_tangential_impulse():
    (d,) = diagrams(EXAMPLES / "seed_rod_drop_rough.mom")
    on = impulses_on(d, "rod")
    assert set(on) == {"J_n[A]", "J_t[A]"}
    assert on["J_t[A]"].direction == pytest.approx((-1.0, 0.0))  # t = n turned 90 deg ccw
    assert not any(x.startswith("friction at A") for x in dropped(d))
    assert any(x.startswith("weight of rod") for x in dropped(d))
    # plastic and no slip: A stops. With v_G = (vx, vy), A's velocity after is zero:
    # vx - w r_y = 0, vy + w r_x = 0, and m dv = J, I dw = r x J. Closed form via the
    # impulse about A: H_A conserved -> w2 = m r x v1 / (I + m r^2) (about A)
    m, L, g = 10.0, 1.0, 9.81
    th = math.radians(30)
    r = (L / 2 * math.cos(th), L / 2 * math.sin(th))  # from A to G
    v1 = -math.sqrt(2 * g)
    I = m * L * L / 12
    w2 = m * (r[0] * v1) / (I + m * (r[0] ** 2 + r[1] ** 2))
    vx2, vy2 = -w2 * r[1], w2 * r[0]  # v_G = w x r_{G/A}
    assert on["J_n[A]"].value == pytest.approx(m * (vy2 - v1), rel=1e-9)
    assert on["J_t[A]"].value * -1 == pytest.approx(m * vx2, rel=1e-9)


def test_pinned_rod_struck_pin_reactions_and_contact_pair():
    (d,) = diagrams(EXAMPLES / "rod_pinned_struck_energy.mom")
    rod, ball = impulses_on(d, "rod"), impulses_on(d, "ball")
    assert set(rod) == {"J_n[hit]", "Jx[O]", "Jy[O]"}
    assert set(ball) == {"J_n[hit]"}
    # equal and opposite along the normal
    a, b = rod["J_n[hit]"].direction, ball["J_n[hit]"].direction
    assert a == pytest.approx((1.0, 0.0)) and b == pytest.approx((-1.0, 0.0))
    assert "-n" in ball["J_n[hit]"].words
    # closed form about the pin: J = (1 + e) v / (1/m_b + d^2 / I_O), I_O = m L^2 / 3
    m, L, dd, mb, v, e = 4.0, 1.2, 0.9, 0.5, 6.0, 1.0
    IO = m * L * L / 3
    J = (1 + e) * v / (1 / mb + dd * dd / IO)
    assert rod["J_n[hit]"].value == pytest.approx(J, rel=1e-9)
    w = J * dd / IO
    assert rod["Jx[O]"].value == pytest.approx(m * w * L / 2 - J, rel=1e-9)
    assert rod["Jx[O]"].at == pytest.approx((0.0, 0.0), abs=1e-12)  # the pin, at the origin
    assert rod["J_n[hit]"].at == pytest.approx((0.0, -dd))  # hanging straight down
    assert any("into the plane" in x for x in dropped(d))  # g into the plane: no weight


def test_two_particles_plastic_each_has_the_pair():
    (d,) = diagrams(EXAMPLES / "seed_plastic_collision.mom")
    A, B = impulses_on(d, "A"), impulses_on(d, "B")
    assert set(A) == set(B) == {"J_n[A-B]", "J_t[A-B]"}  # rough: both components
    for k in A:
        assert A[k].direction == pytest.approx(tuple(-c for c in B[k].direction))
        assert A[k].value == pytest.approx(B[k].value)
    # common velocity (3*2, 2*3)/5: A's change of momentum is the impulse on it
    vx, vy = 2 * 3 / 5, 3 * 2 / 5
    dpA = (2 * (vx - 3), 2 * (vy - 0))
    n = A["J_n[A-B]"].direction
    t = A["J_t[A-B]"].direction
    got = tuple(A["J_n[A-B]"].value * n[k] + A["J_t[A-B]"].value * t[k] for k in range(2))
    assert got == pytest.approx(dpA, rel=1e-9)
    assert dropped(d) == []  # no gravity, no spring, a rough contact


def test_interval_keeps_the_weight():
    (d,) = diagrams(EXAMPLES / "seed_disk_wall.mom")
    assert d.kind == "interval"
    on = impulses_on(d, "disk")
    w = on["weight of disk x t"]
    assert w.direction == pytest.approx((0.0, -1.0)) and w.words == "down"
    # t from the seed's answer (the disk stops at 3.04808 s): m g t
    assert w.value == pytest.approx(20 * 10 * 3.04808, rel=1e-5)
    assert {"J_n[disk]", "J_t[disk]", "J[strut]"} <= set(on)
    assert not any(x.startswith("weight") for x in dropped(d))


def test_moments_of_a_bearing_are_angular_impulses():
    (d,) = diagrams(EXAMPLES / "seed_rod_disk_bearing.mom")
    rod, disk = impulses_on(d, "rod"), impulses_on(d, "disk")
    assert rod["M[bearing]"].moment and disk["M[bearing]"].moment
    assert rod["M[bearing]"].value == pytest.approx(disk["M[bearing]"].value)  # one unknown
    assert {rod["M[bearing]"].words, disk["M[bearing]"].words} == {"clockwise",
                                                                  "counter-clockwise"}


def test_direction_words():
    assert direction_words((0.0, 1.0)) == "up"
    assert direction_words((-1.0, 0.0)) == "to the left"
    assert direction_words((0.0, -1.0), "n") == "down (along n = (0, -1))"
    c = math.cos(math.radians(30))
    assert direction_words((c, 0.5), "n") == "along n = (0.866, 0.5)"


def test_lines_are_short_and_grouped_by_body():
    (d,) = diagrams(EXAMPLES / "seed_billiards_elastic.mom")
    lines = d.lines()
    assert lines[0] == "Impulse diagram, impact 1 -> 2"
    heads = [x.strip() for x in lines if x.startswith("  ") and not x.startswith("    ")]
    assert heads[:3] == ["A:", "B:", "C:"]
    assert all(x.isascii() for x in lines)


# ---- the drawing -----------------------------------------------------------------------------
def _parse(d):
    root = ET.fromstring(d.svg())
    assert root.tag == SVG + "svg" and root.get("viewBox")
    return root


def _groups(root, cls):
    return [g for g in root.iter(SVG + "g") if cls in (g.get("class") or "").split()]


@pytest.mark.parametrize("name, arrows", [("seed_rod_drop_smooth", 1), ("seed_rod_drop_rough", 2),
                                          ("seed_pendulum_wall", 3),
                                          ("seed_billiards_elastic", 4)])
def test_svg_has_an_arrow_per_impulse(name, arrows):
    (d,) = [x for x in diagrams(EXAMPLES / f"{name}.mom")]
    root = _parse(d)
    assert len(_groups(root, "impulse")) == arrows == len(d.impulses)
    labels = [t.text for g in _groups(root, "labels") for t in g.iter(SVG + "text")]
    for i in d.impulses:
        assert any(x.startswith(i.name + " = ") for x in labels)
    assert not any(e.tag.endswith("script") for e in root.iter())
    assert "href" not in d.svg()


def test_svg_bodies_to_scale():
    (d,) = diagrams(EXAMPLES / "seed_pendulum_wall.mom")
    root = _parse(d)
    k = float(root.get("data-scale"))
    (body,) = [g for g in _groups(root, "body") if g.get("data-body") == "pendulum"]
    rod = next(e for e in body if "rod" in (e.get("class") or ""))
    length = math.hypot(float(rod.get("x2")) - float(rod.get("x1")),
                        float(rod.get("y2")) - float(rod.get("y1")))
    assert length == pytest.approx(2.0 * k, abs=0.15)  # the composite's 2 m rod
    sphere = next(e for e in body if "sphere" in (e.get("class") or ""))
    assert float(sphere.get("r")) == pytest.approx(0.3 * k, abs=0.06)
    # the rod hangs straight down from the pin (angle -90 deg): x1 == x2
    assert float(rod.get("x1")) == pytest.approx(float(rod.get("x2")), abs=0.06)


def test_svg_is_deterministic():
    (a,) = diagrams(EXAMPLES / "seed_rod_drop_rough.mom")
    (b,) = diagrams(EXAMPLES / "seed_rod_drop_rough.mom")
    assert a.svg() == b.svg()


def test_every_example_renders_a_diagram():
    """Every worked example under examples/ (not the deliberately broken hard cases)."""
    files = sorted(EXAMPLES.glob("*.mom")) + sorted(EXAMPLES.glob("problem-set/**/*.mom"))
    seen = 0
    for path in files:
        res = solve_source(read_source(str(path)))
        if res.report is None:
            continue
        for d in res.report.diagrams:
            _parse(d)
            assert d.lines()[0] == d.title
            seen += 1
    assert seen >= 60


PLATE = """
problem "A plate's corner hits the floor"
gravity 9.81 m/s^2 down
body p: plate(mass = 2 kg, width = 0.4 m, height = 0.2 m)
point C = p at (-0.2 m, -0.1 m)
state 1 "before": p.angle = 20 deg, p.pos = (0, 0.3 m), p.v = (0, -2 m/s), p.omega = 0
state 2 "after"
impact 1 -> 2:
    contact C with ground normal (0, 1): restitution 0.5, friction 0.3
find p.omega@2
"""


def test_plate_corner_in_its_configuration_and_to_scale():
    from helpers import solve_text

    from momentum_cli.report.diagram import build_diagrams

    (d,) = build_diagrams(solve_text(PLATE))
    on = impulses_on(d, "p")
    assert set(on) == {"J_n[C]", "J_t[C]"}  # friction: a tangential impulse
    a = math.radians(20)
    corner = (-0.2 * math.cos(a) + 0.1 * math.sin(a), 0.3 - 0.2 * math.sin(a) - 0.1 * math.cos(a))
    assert on["J_n[C]"].at == pytest.approx(corner, abs=1e-12)
    root = _parse(d)
    k = float(root.get("data-scale"))
    poly = next(e for e in root.iter(SVG + "polygon") if "plate" in (e.get("class") or ""))
    pts = [tuple(map(float, p.split(","))) for p in poly.get("points").split()]
    sides = sorted(math.dist(pts[i], pts[(i + 1) % 4]) for i in range(4))
    assert sides == pytest.approx([0.2 * k, 0.2 * k, 0.4 * k, 0.4 * k], abs=0.15)
    # the surface is drawn through the corner it touches
    (s,) = d.surfaces
    assert s.at == pytest.approx(corner, abs=1e-12)


def test_json_carries_the_diagram_and_fits_the_schema():
    import json
    from importlib.resources import files

    jsonschema = pytest.importorskip("jsonschema")
    from momentum_cli.report.json_out import document, result_dict

    res = solve_source(read_source(str(EXAMPLES / "seed_pendulum_wall.mom")))
    doc = json.loads(document([result_dict(res.name, res.status, res.report)], "test"))
    schema = json.loads(files("momentum_cli").joinpath(
        "schema/momentum-result.schema.json").read_text(encoding="utf-8"))
    jsonschema.validate(doc, schema)
    (d,) = doc["results"][0]["diagrams"]
    assert {i["name"] for i in d["impulses"]} == {"J_n[B]", "Jx[O]", "Jy[O]"}
    assert d["lines"][0] == "Impulse diagram, impact 2 -> 3"


def test_diagram_for_is_the_first_match_of_a_scan():
    """diagram_for indexes the diagrams once per report (a long sequence of impacts looked
    each one up by a scan): it must return what the scan returns, for every transition,
    also when several reports are read in turn."""
    import sys

    from momentum_cli.report.model import diagram_for
    from momentum_cli.source import Source

    sys.path.insert(0, str(EXAMPLES.parent / "tests"))
    from test_hard import cradle_text

    reps = [solve_source(Source(f"cradle{n}.mom", cradle_text(n, "sequence"))).report
            for n in (4, 6)]
    reps.append(solve_source(read_source(str(EXAMPLES / "seed_pendulum_wall.mom"))).report)
    for _ in range(2):
        for rep in reps:
            assert rep.transitions
            for t in rep.transitions:
                scan = next((d for d in rep.diagrams
                             if d.kind == t["kind"] and d.key == t["key"]), None)
                assert diagram_for(rep, t) is scan
                assert scan is not None or t["kind"] == "energy"
