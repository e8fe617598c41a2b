"""Draw an ImpulseDiagram as one self-contained SVG element (report stage).

In: an `ImpulseDiagram` (report/diagram.py). Out: `<svg ...>...</svg>` text: the bodies to
scale in their configuration, surfaces hatched, pins, impulse arrows labelled, velocities
before (dashed) and after (solid), a legend. No ids, no external references, no script;
coordinates with one decimal, so the text is deterministic (golden-testable).
"""
from __future__ import annotations

import math
from xml.sax.saxutils import escape

from ..numbers import fmt_num
from .. import units

W = 800  # the drawing's width in px; the height follows the legend
TOP, SIDE, PLOT_H = 44, 24, 420
IMPULSE, BEFORE, AFTER, MOMENT = "#c62828", "#1565c0", "#2e7d32", "#6a1b9a"
BODY_FILL, BODY_LINE, GROUND = "#cfd8dc", "#37474f", "#555555"
ROUND_FILLED = {"disk", "cylinder", "sphere"}
ROUND_RINGS = {"ring", "hoop", "shell"}
DOT = 5.0  # px: a particle, a point
HALO = ' stroke="#ffffff" stroke-width="3" paint-order="stroke"'  # a label over lines


def _n(x: float) -> str:
    s = f"{x:.1f}"
    return "0.0" if s == "-0.0" else s


def _shown(d, si_value, dim, si_unit: str) -> str:
    """A value in the reader's units (`d.show`), its unit with a middle dot."""
    x, unit = d.show(si_value, dim, si_unit)
    return _v(x, unit.replace("*", "·"))


def _v(x: float | None, unit: str) -> str:
    if x is None:
        return "?"
    return f"{fmt_num(0.0 if abs(x) < 1e-12 else x, 4)} {unit}"


def _rot(r, a: float) -> tuple:
    c, s = math.cos(a), math.sin(a)
    return (r[0] * c - r[1] * s, r[0] * s + r[1] * c)


class _Frame:
    """World (m, y up) to picture (px, y down): one scale for both axes."""

    def __init__(self, box, width: float, height: float):
        x0, y0, x1, y1 = box
        self.k = min(width / max(x1 - x0, 1e-12), height / max(y1 - y0, 1e-12))
        self.ox = SIDE + (width - (x1 - x0) * self.k) / 2 - x0 * self.k
        self.oy = TOP + (height - (y1 - y0) * self.k) / 2 + y1 * self.k

    def p(self, x: float, y: float) -> tuple:
        return (self.ox + x * self.k, self.oy - y * self.k)


def _part_points(b, part):
    """The world points that bound one part of a body (for the picture's box)."""
    kind, c, dims, rot = part
    cx, cy = _rot(c, b.angle)
    cx, cy = b.x + cx, b.y + cy
    a = b.angle + rot
    if kind == "rod":
        h = dims.get("length", 0.0) / 2
        e = _rot((h, 0.0), a)
        return [(cx + e[0], cy + e[1]), (cx - e[0], cy - e[1])]
    if kind == "plate":
        w, h = dims.get("width", 0.0) / 2, dims.get("height", 0.0) / 2
        return [(cx + q[0], cy + q[1]) for q in
                (_rot((sx * w, sy * h), a) for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1)))]
    r = dims.get("radius", 0.0)
    return [(cx - r, cy - r), (cx + r, cy + r)]


def _box(d) -> tuple:
    pts = [(b.x, b.y) for b in d.bodies]
    for b in d.bodies:
        for part in b.parts:
            pts.extend(_part_points(b, part))
    pts += [i.at for i in d.impulses] + [s.at for s in d.surfaces] + [p for _, p in d.pins]
    pts += [p for link in d.links for p in link[2:]]
    xs, ys = [p[0] for p in pts] or [0.0], [p[1] for p in pts] or [0.0]
    x0, x1, y0, y1 = min(xs), max(xs), min(ys), max(ys)
    size = max(x1 - x0, y1 - y0, 1e-9)
    if size < 1e-6:
        size = 1.0
    return x0, y0, x1, y1, size


class _Layout:
    """What is already drawn (shapes, surfaces, labels), so that an arrow's shaft and a
    label keep out of them where they can."""

    def __init__(self):
        self.segments: list = []  # ((x1, y1), (x2, y2), half width) in px
        self.circles: list = []  # ((cx, cy), r)
        self.boxes: list = []  # label boxes (x0, y0, x1, y1)

    def hits(self, x: float, y: float, labels: bool = False) -> bool:
        if labels and any(b[0] <= x <= b[2] and b[1] <= y <= b[3] for b in self.boxes):
            return True
        for (a, b, w) in self.segments:
            if _dist_seg((x, y), a, b) <= w:
                return True
        return any(math.hypot(x - c[0], y - c[1]) <= r for c, r in self.circles)

    def crossing(self, p, q) -> int:
        """How many of 6 samples of the shaft from p (the point it acts at, where it may
        touch the body) to q lie on something drawn."""
        return sum(self.hits(p[0] + (q[0] - p[0]) * f, p[1] + (q[1] - p[1]) * f, True)
                   for f in (0.25, 0.4, 0.55, 0.7, 0.85, 1.0))

    def label(self, x: float, y: float, text: str, anchor: str) -> tuple:
        """A free place near (x, y) for a label (nudged down, then up)."""
        w = 7.2 * len(text)
        x0 = x - (w if anchor == "end" else w / 2 if anchor == "middle" else 0)
        x += max(0.0, 4 - x0) - max(0.0, x0 + w - (W - 4))  # inside the picture
        x0 = x - (w if anchor == "end" else w / 2 if anchor == "middle" else 0)
        shifts = [(0, dy) for dy in (0, 15, -15, 30, -30, 45, -45, 60, -60)]
        shifts += [(dx, dy) for dx in (-(w + 12), w + 12) for dy in (0, 15, -15)]
        for strict in (True, False):  # off the shapes too if it can, else off labels only
            for dx, dy in shifts:
                box = (x0 + dx, y + dy - 12, x0 + dx + w, y + dy + 3)
                if box[0] < 4 or box[2] > W - 4:
                    continue
                if strict and any(self.hits(px, py) for px in (box[0], (box[0] + box[2]) / 2,
                                                                box[2])
                                  for py in (box[1] + 2, box[3] - 2)):
                    continue
                if not any(box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3]
                           for b in self.boxes):
                    self.boxes.append(box)
                    return x + dx, y + dy
        self.boxes.append((x, y - 12, x + w, y + 3))
        return x, y


def _dist_seg(p, a, b) -> float:
    ax, ay = a
    dx, dy = b[0] - ax, b[1] - ay
    L2 = dx * dx + dy * dy
    f = 0.0 if L2 == 0 else max(0.0, min(1.0, ((p[0] - ax) * dx + (p[1] - ay) * dy) / L2))
    return math.hypot(p[0] - ax - f * dx, p[1] - ay - f * dy)


def render_svg(d) -> str:
    x0, y0, x1, y1, size = _box(d)
    arrow = 0.32 * size  # an impulse arrow's length (m): every impulse the same
    pad = arrow + 0.18 * size
    frame = _Frame((x0 - pad, y0 - pad, x1 + pad, y1 + pad), W - 2 * SIDE, PLOT_H)
    k = frame.k
    legend = _legend_lines(d)
    height = TOP + PLOT_H + 20 + 18 * (len(legend) + 2)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {W} {height}" '
           f'width="{W}" height="{height}" font-family="sans-serif" font-size="13" '
           f'style="max-width:100%;height:auto" data-scale="{k:.6g}" role="img" '
           f'aria-label="{escape(d.title, {chr(34): "&quot;"})}">',
           f'<rect x="0" y="0" width="{W}" height="{height}" fill="#ffffff"/>',
           f'<text x="{SIDE}" y="26" font-size="16" font-weight="bold">{escape(d.title)}</text>']
    lay = _Layout()
    bodies, names = [], []
    for b in d.bodies:  # first, so that the labels below keep off them
        bodies.extend(_body(frame, b, lay))
        names.append((b.name, frame.p(b.x, b.y)))
    for s in d.surfaces:
        out.extend(_surface(frame, s, 0.9 * size, lay))
    for name, at in d.pins:
        out.extend(_pin(frame, name, at, lay))
    for label, kind, a, b in d.links:
        out.extend(_link(frame, label, kind, a, b))
    out.extend(bodies)
    vmax = max([math.hypot(*v) for b in d.bodies for v in (b.v_before, b.v_after)
                if v is not None] + [0.0])
    for b in d.bodies:
        for v, colour, dash, when in ((b.v_before, BEFORE, ' stroke-dasharray="6 4"', "before"),
                                      (b.v_after, AFTER, "", "after")):
            if v is None or vmax == 0 or math.hypot(*v) < 1e-9 * vmax:
                continue
            L = 0.28 * size * math.hypot(*v) / vmax
            u = (v[0] / math.hypot(*v), v[1] / math.hypot(*v))
            tail, head = (b.x, b.y), (b.x + L * u[0], b.y + L * u[1])
            label = f"v{d.before if when == 'before' else d.after} = " \
                    f"{_shown(d, math.hypot(*v), units.VELOCITY, 'm/s')}"
            out.extend(_arrow(frame, tail, head, colour, 2.0, dash, label, f"velocity {when}",
                              lay, at_head=True))
    seen: dict = {}
    for i in _drawn(d):
        if i.moment:
            key = (round(i.at[0], 9), round(i.at[1], 9))
            n = seen.get(key, 0)
            seen[key] = n + 1
            out.extend(_moment(d, frame, i, 0.12 * size + n * 0.05 * size, lay))
            continue
        if i.direction is None:
            continue
        label = f"{i.name} = {_shown(d, i.value, units.IMPULSE, 'N*s')}"
        tail, head = _place_impulse(frame, lay, i, arrow)
        pull = math.hypot(tail[0] - i.at[0], tail[1] - i.at[1]) < \
            math.hypot(head[0] - i.at[0], head[1] - i.at[1])
        out.extend(_arrow(frame, tail, head, IMPULSE, 2.5, "", label, "impulse", lay,
                          at_head=pull))
    for name, (gx, gy) in names:  # last: in a free place
        lx, ly = lay.label(gx + 8, gy - 8, name, "start")
        out.append(f'<text class="label" x="{_n(lx)}" y="{_n(ly)}" font-weight="bold" '
                   f'fill="{BODY_LINE}"{HALO}>{escape(name)}</text>')
    # labels last, with a white halo: on top of every line
    labels = [x for x in out if x.startswith('<text class="label"')]
    out = [x for x in out if not x.startswith('<text class="label"')]
    out += ['<g class="labels">'] + labels + ['</g>']
    out.extend(_legend(d, legend, TOP + PLOT_H + 20))
    out.append("</svg>")
    return "\n".join(out) + "\n"


def _place_impulse(frame, lay, i, arrow: float) -> tuple:
    """(tail, head) of an impulse arrow: pushing at its point from outside, or pulling
    away from it, or beside it, whichever crosses less of the drawing."""
    d, p = i.direction, i.at
    push = ((p[0] - arrow * d[0], p[1] - arrow * d[1]), p)
    pull = (p, (p[0] + arrow * d[0], p[1] + arrow * d[1]))
    best, score = None, None
    side = 9.0 / frame.k  # a small shift across the arrow, in m
    for shift in (0.0, side, -side, 2 * side, -2 * side):
        for tail, head in (push, pull):
            o = (-d[1] * shift, d[0] * shift)
            t2, h2 = (tail[0] + o[0], tail[1] + o[1]), (head[0] + o[0], head[1] + o[1])
            a, b = frame.p(*t2), frame.p(*h2)
            # the end at the point may touch it; measure the shaft away from the point
            c = lay.crossing(b, a) if (tail, head) == push else lay.crossing(a, b)
            c += 0.6 * abs(shift) / side
            if score is None or c < score:
                best, score = (t2, h2), c
    return best


def _arrow(frame, tail, head, colour, width, dash, label, cls, lay, at_head=False) -> list[str]:
    (x1, y1), (x2, y2) = frame.p(*tail), frame.p(*head)
    L = math.hypot(x2 - x1, y2 - y1)
    if L < 1e-9:
        return []
    ux, uy = (x2 - x1) / L, (y2 - y1) / L
    hl, hw = 11.0, 4.5
    bx, by = x2 - hl * ux, y2 - hl * uy
    poly = f"{_n(x2)},{_n(y2)} {_n(bx - hw * uy)},{_n(by + hw * ux)} " \
           f"{_n(bx + hw * uy)},{_n(by - hw * ux)}"
    tx, ty = (x2, y2) if at_head else (x1, y1)
    sx = 1 if at_head else -1  # the label sits beyond the free end
    tx, ty = tx + sx * 6 * ux, ty + sx * 6 * uy
    ex = ux * sx
    anchor = "start" if ex > 0.3 else ("end" if ex < -0.3 else "middle")
    ty += 4 + (10 if uy * sx > 0.3 else (-4 if uy * sx < -0.3 else 0))
    tx, ty = lay.label(tx, ty, label, anchor)
    lay.segments.append(((x1, y1), (x2, y2), 2.0))
    return [f'<g class="{cls}">',
            f'<line x1="{_n(x1)}" y1="{_n(y1)}" x2="{_n(bx)}" y2="{_n(by)}" stroke="{colour}" '
            f'stroke-width="{width}"{dash}/>',
            f'<polygon points="{poly}" fill="{colour}"/>',
            f'<text class="label" x="{_n(tx)}" y="{_n(ty)}" fill="{colour}" '
            f'text-anchor="{anchor}"{HALO}>'
            f'{escape(label)}</text>',
            '</g>']


def _moment(d, frame, i, radius: float, lay) -> list[str]:
    """An angular impulse: a three-quarter arc around its point, arrowhead at the end."""
    cx, cy = frame.p(*i.at)
    r = max(radius * frame.k, 14.0)
    ccw = i.words == "counter-clockwise"
    a0, a1 = (-0.75 * math.pi, 0.75 * math.pi)
    if not ccw:
        a0, a1 = a1, a0
    p0 = (cx + r * math.cos(a0), cy - r * math.sin(a0))
    p1 = (cx + r * math.cos(a1), cy - r * math.sin(a1))
    sweep = 0 if ccw else 1  # picture y is down: counter-clockwise is sweep 0
    # the tangent at the end, in the turning sense
    t = (-math.sin(a1), -math.cos(a1)) if ccw else (math.sin(a1), math.cos(a1))
    hl, hw = 10.0, 4.5
    bx, by = p1[0] - hl * t[0], p1[1] - hl * t[1]
    poly = f"{_n(p1[0])},{_n(p1[1])} {_n(bx - hw * t[1])},{_n(by + hw * t[0])} " \
           f"{_n(bx + hw * t[1])},{_n(by - hw * t[0])}"
    label = f"{i.name} = {_shown(d, i.value, units.ANGULAR_IMPULSE, 'N*m*s')}"
    lx, ly = lay.label(cx, cy - r - 6, label, "middle")
    return ['<g class="impulse moment">',
            f'<path d="M {_n(p0[0])} {_n(p0[1])} A {_n(r)} {_n(r)} 0 1 {sweep} '
            f'{_n(p1[0])} {_n(p1[1])}" fill="none" stroke="{MOMENT}" stroke-width="2.5"/>',
            f'<polygon points="{poly}" fill="{MOMENT}"/>',
            f'<text class="label" x="{_n(lx)}" y="{_n(ly)}" fill="{MOMENT}" '
            f'text-anchor="middle"{HALO}>'
            f'{escape(label)}</text>',
            '</g>']


def _surface(frame, s, length: float, lay) -> list[str]:
    """A fixed surface through the contact point, hatched on the side it pushes from."""
    n = s.normal
    t = (-n[1], n[0])
    h = length / 2
    a = (s.at[0] - h * t[0], s.at[1] - h * t[1])
    b = (s.at[0] + h * t[0], s.at[1] + h * t[1])
    (ax, ay), (bx, by) = frame.p(*a), frame.p(*b)
    out = ['<g class="surface">',
           f'<line x1="{_n(ax)}" y1="{_n(ay)}" x2="{_n(bx)}" y2="{_n(by)}" stroke="{GROUND}" '
           f'stroke-width="2"/>']
    lay.segments.append(((ax, ay), (bx, by), 4.0))
    L = math.hypot(bx - ax, by - ay)
    ux, uy = (bx - ax) / L, (by - ay) / L
    nx, ny = n[0], -n[1]  # the normal in picture coordinates
    step = 12.0
    m = int(L // step)
    for q in range(m + 1):
        px, py = ax + ux * q * step, ay + uy * q * step
        # short strokes into the surface (against the normal), slanted along it
        ex, ey = px - 9 * nx - 6 * ux, py - 9 * ny - 6 * uy
        out.append(f'<line x1="{_n(px)}" y1="{_n(py)}" x2="{_n(ex)}" y2="{_n(ey)}" '
                   f'stroke="{GROUND}" stroke-width="1"/>')
    lx, ly = lay.label(bx + 4, by - 4, s.name, "start")
    out.append(f'<text x="{_n(lx)}" y="{_n(ly)}" fill="{GROUND}">{escape(s.name)}</text>')
    out.append("</g>")
    return out


def _link(frame, label: str, kind: str, a, b) -> list[str]:
    """A joint between two bodies' points: a spring as a zigzag, others a thin bar."""
    (x1, y1), (x2, y2) = frame.p(*a), frame.p(*b)
    if kind != "spring":
        return [f'<g class="joint"><line x1="{_n(x1)}" y1="{_n(y1)}" x2="{_n(x2)}" '
                f'y2="{_n(y2)}" stroke="{GROUND}" stroke-width="2" stroke-dasharray="2 3"/>'
                f'<title>{escape(kind + " " + label)}</title></g>']
    L = math.hypot(x2 - x1, y2 - y1)
    ux, uy = (x2 - x1) / L, (y2 - y1) / L
    pts = [(x1, y1)]
    m = 10
    for q in range(1, m):
        s = (-1) ** q * 6
        f = q / m
        pts.append((x1 + ux * L * f - uy * s, y1 + uy * L * f + ux * s))
    pts.append((x2, y2))
    return [f'<g class="joint"><polyline points="{" ".join(f"{_n(x)},{_n(y)}" for x, y in pts)}" '
            f'fill="none" stroke="{GROUND}" stroke-width="1.5"/>'
            f'<title>{escape(kind + " " + label)}</title></g>']


def _pin(frame, name: str, at, lay) -> list[str]:
    x, y = frame.p(*at)
    lay.circles.append(((x, y + 9), 9.0))
    out = ['<g class="pin">',
           f'<polygon points="{_n(x)},{_n(y)} {_n(x - 10)},{_n(y + 16)} {_n(x + 10)},{_n(y + 16)}" '
           f'fill="none" stroke="{GROUND}" stroke-width="1.5"/>',
           f'<line x1="{_n(x - 14)}" y1="{_n(y + 16)}" x2="{_n(x + 14)}" y2="{_n(y + 16)}" '
           f'stroke="{GROUND}" stroke-width="2"/>']
    for q in range(5):
        px = x - 12 + 6 * q
        out.append(f'<line x1="{_n(px)}" y1="{_n(y + 16)}" x2="{_n(px - 5)}" y2="{_n(y + 22)}" '
                   f'stroke="{GROUND}" stroke-width="1"/>')
    out.append(f'<circle cx="{_n(x)}" cy="{_n(y)}" r="3.5" fill="#ffffff" stroke="{GROUND}" '
               'stroke-width="1.5"/>')
    lx, ly = lay.label(x + 14, y + 14, name, "start")
    out.append(f'<text x="{_n(lx)}" y="{_n(ly)}" fill="{GROUND}">{escape(name)}</text>')
    out.append("</g>")
    return out


def _body(frame, b, lay) -> list[str]:
    k = frame.k
    out = [f'<g class="body" data-body="{escape(b.name)}" data-shape="{escape(b.shape)}">']
    for kind, c, dims, rot in b.parts:
        cw = _rot(c, b.angle)
        cx, cy = frame.p(b.x + cw[0], b.y + cw[1])
        a = b.angle + rot
        if kind == "rod":
            h = dims.get("length", 0.0) / 2
            e = _rot((h, 0.0), a)
            (x1, y1), (x2, y2) = frame.p(b.x + cw[0] - e[0], b.y + cw[1] - e[1]), \
                frame.p(b.x + cw[0] + e[0], b.y + cw[1] + e[1])
            lay.segments.append(((x1, y1), (x2, y2), 5.0))
            out.append(f'<line class="part rod" x1="{_n(x1)}" y1="{_n(y1)}" x2="{_n(x2)}" '
                       f'y2="{_n(y2)}" stroke="{BODY_LINE}" stroke-width="7" '
                       f'stroke-linecap="butt" data-length="{dims.get("length", 0.0):.6g}"/>')
        elif kind == "plate":
            w, h = dims.get("width", 0.0) / 2, dims.get("height", 0.0) / 2
            signs = ((1, 1), (-1, 1), (-1, -1), (1, -1))
            corners = [frame.p(b.x + cw[0] + r[0], b.y + cw[1] + r[1]) for r in
                       (_rot((sx * w, sy * h), a) for sx, sy in signs)]
            pts = " ".join(f"{_n(q[0])},{_n(q[1])}" for q in corners)
            lay.circles.append(((cx, cy), min(w, h) * k))
            lay.segments.extend((corners[q], corners[(q + 1) % 4], 3.0) for q in range(4))
            out.append(f'<polygon class="part plate" points="{pts}" fill="{BODY_FILL}" '
                       f'stroke="{BODY_LINE}" stroke-width="2" '
                       f'data-width="{dims.get("width", 0.0):.6g}" '
                       f'data-height="{dims.get("height", 0.0):.6g}"/>')
        elif "radius" in dims and dims["radius"] > 0:
            r = dims["radius"]
            ring = kind in ROUND_RINGS
            lay.circles.append(((cx, cy), r * k + 2))
            out.append(f'<circle class="part {escape(kind)}" cx="{_n(cx)}" cy="{_n(cy)}" '
                       f'r="{_n(r * k)}" fill="{"none" if ring else BODY_FILL}" '
                       f'stroke="{BODY_LINE}" stroke-width="{3 if ring else 2}" '
                       f'data-radius="{r:.6g}"/>')
            if kind in ROUND_FILLED | ROUND_RINGS:  # a radius line shows how it is turned
                e = _rot((r, 0.0), a)
                ex, ey = frame.p(b.x + cw[0] + e[0], b.y + cw[1] + e[1])
                out.append(f'<line x1="{_n(cx)}" y1="{_n(cy)}" x2="{_n(ex)}" y2="{_n(ey)}" '
                           f'stroke="{BODY_LINE}" stroke-width="1"/>')
        else:  # a particle or a point-like part
            lay.circles.append(((cx, cy), DOT + 2))
            out.append(f'<circle class="part {escape(kind)}" cx="{_n(cx)}" cy="{_n(cy)}" '
                       f'r="{DOT + 1}" fill="{BODY_LINE}"/>')
    gx, gy = frame.p(b.x, b.y)
    out.append(f'<circle cx="{_n(gx)}" cy="{_n(gy)}" r="2.5" fill="#000000"/>')
    out.append("</g>")
    return out


def _drawn(d) -> list:
    """The impulses drawn: the reaction of a pair on its second body is left out where it
    acts at the same point as on the first (equal and opposite; the legend says so)."""
    first: dict = {}
    out = []
    for i in d.impulses:
        j = first.get(i.name)
        if j is not None and j.body != i.body and \
                math.hypot(j.at[0] - i.at[0], j.at[1] - i.at[1]) < 1e-9 * (1 + abs(j.at[0])):
            continue
        first.setdefault(i.name, i)
        out.append(i)
    return out


def _legend_lines(d) -> list[str]:
    out = []
    drawn = {id(i) for i in _drawn(d)}
    pairs: dict = {}
    for i in d.impulses:
        if id(i) not in drawn:
            pairs.setdefault(i.body, []).append(i.name)
    for body, names in pairs.items():
        out.append(f"{', '.join(names)} on {body}: equal and opposite to those drawn (same point)")
    for b in d.bodies:
        if b.omega_before is not None or b.omega_after is not None:
            out.append(f"{b.name}: ω{d.before} = {_v(b.omega_before, 'rad/s')}, "
                       f"ω{d.after} = {_v(b.omega_after, 'rad/s')} (counter-clockwise +)")
    for x in d.dropped:
        out.append(f"dropped: {x.what}: {x.why}")
    out.extend(d.notes)
    return out


def _legend(d, lines: list[str], y: float) -> list[str]:
    out = ['<g class="legend">']
    x = SIDE
    for colour, dash, what in ((IMPULSE, "", "impulse (assumed direction; value signed)"),
                               (BEFORE, ' stroke-dasharray="6 4"', f"velocity at {d.before}"),
                               (AFTER, "", f"velocity at {d.after}")):
        out.append(f'<line x1="{x}" y1="{_n(y - 4)}" x2="{x + 28}" y2="{_n(y - 4)}" '
                   f'stroke="{colour}" stroke-width="2.5"{dash}/>')
        out.append(f'<text x="{x + 34}" y="{_n(y)}">{escape(what)}</text>')
        x += 34 + 7 * len(what) + 24
    for k, line in enumerate(lines):
        out.append(f'<text x="{SIDE}" y="{_n(y + 20 + 18 * k)}" fill="#333333">'
                   f'{escape(line)}</text>')
    out.append("</g>")
    return out
