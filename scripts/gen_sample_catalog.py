#!/usr/bin/env python3
"""Writes the sample catalogues examples/catalog/ (mm) and
examples/catalog-inch/ (in), reproducibly (python3 stdlib only).

    python3 scripts/gen_sample_catalog.py [REPO_ROOT]

A manifest has one unit, so the inch parts live in their own catalogue.
The mm catalogue also holds a DXF drawn in inches ($INSUNITS = 1) and the
inch catalogue one drawn in mm, to exercise unit conversion.

Parts are kept small (30 to 150 mm, at most about 40 edges, arcs coarse)
so that the whole catalogue enumerates in seconds with the metric-25 kit.
DXF files are written by hand: R12 (AC1009, POLYLINE/VERTEX/SEQEND, LINE,
ARC, CIRCLE, no handles) like older CAD tools write, and R2000 (AC1015,
LWPOLYLINE with bulges, $INSUNITS). SVG files use paths with relative
commands, arcs, curves, transforms and class="access" shapes.
"""

import json
import math
import os
import sys

ROOT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")


def r4(x):
    v = round(x, 4)
    return 0.0 if v == 0 else v


def num(x):
    s = f"{r4(x):.4f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def pts(p):
    return [[r4(x), r4(y)] for x, y in p]


def rect(x0, y0, x1, y1):
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


# ---------------------------------------------------------------- shapes (mm)

def l_profile(w, h, t):
    return [(0, 0), (w, 0), (w, t), (t, t), (t, h), (0, h)]


def t_profile(w, h, t, s):
    c = w / 2
    return [(c - s / 2, 0), (c + s / 2, 0), (c + s / 2, h - t), (w, h - t), (w, h), (0, h),
            (0, h - t), (c - s / 2, h - t)]


def u_profile(w, h, t):
    return [(0, 0), (w, 0), (w, h), (w - t, h), (w - t, t), (t, t), (t, h), (0, h)]


def gear(teeth, r_root, r_tip, cx=0.0, cy=0.0):
    out = []
    step = 360.0 / teeth
    for i in range(teeth):
        a = i * step
        for da, r in ((-0.30, r_root), (-0.14, r_tip), (0.14, r_tip), (0.30, r_root)):
            ang = math.radians(a + da * step)
            out.append((cx + r * math.cos(ang), cy + r * math.sin(ang)))
    return out


def star(n, r_out, r_in):
    out = []
    for i in range(2 * n):
        r = r_out if i % 2 == 0 else r_in
        a = math.pi / 2 + i * math.pi / n
        out.append((r * math.cos(a), r * math.sin(a)))
    return out


def bulge(sweep_deg):
    """DXF bulge of an arc sweeping sweep_deg degrees (CCW when positive)."""
    return math.tan(math.radians(sweep_deg) / 4)


def housing_bosses(w, h):
    """Rectangle with a notch on top and two half-round bosses on the sides
    (exact half circles: bulge 1)."""
    return [(0, 0), (w, 0), (w, h * 0.3, 1.0), (w, h * 0.7), (w, h), (w * 0.6, h),
            (w * 0.6, h - 12), (w * 0.4, h - 12), (w * 0.4, h), (0, h), (0, h * 0.7, 1.0),
            (0, h * 0.3)]


def flange(r, ear, ear_w):
    """Round flange (radius r) with two ears ending in half circles, arcs
    exact."""
    half = math.degrees(math.asin(ear_w / 2 / r))
    xe = r + ear - ear_w / 2
    xr, yr = r * math.cos(math.radians(half)), ear_w / 2
    main = bulge(180 - 2 * half)
    return [(xr, yr, main), (-xr, yr), (-xe, ear_w / 2, 1.0), (-xe, -ear_w / 2), (-xr, -yr, main),
            (xr, -yr), (xe, -ear_w / 2, 1.0), (xe, ear_w / 2)]


def cam(base, lift, n=20):
    out = []
    for i in range(n):
        a = 2 * math.pi * i / n
        r = base + lift * max(0.0, math.cos(a)) ** 2
        out.append((r * math.cos(a), r * math.sin(a)))
    return out


def keyhole(r, w, l):
    """A disc of radius r (an exact arc of more than 300 degrees) on a
    stem of width w reaching down to y = -l."""
    half = math.degrees(math.asin(w / 2 / r))
    y0 = -r * math.cos(math.radians(half))
    return [(w / 2, y0, bulge(360 - 2 * half)), (-w / 2, y0), (-w / 2, -l), (w / 2, -l)]


# ------------------------------------------------------------------ writers

def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", newline="\n") as f:
        f.write(text)


def dxf_pairs(pairs):
    return "".join(f"{c:>3}\n{v}\n" for c, v in pairs)


def dxf_r2000(polys, insunits):
    """polys: list of (layer, [(x, y, bulge)], closed)."""
    pr = [(0, "SECTION"), (2, "HEADER"), (9, "$ACADVER"), (1, "AC1015"),
          (9, "$INSUNITS"), (70, insunits), (0, "ENDSEC"), (0, "SECTION"), (2, "ENTITIES")]
    h = 0x200
    for layer, vs, closed in polys:
        pr += [(0, "LWPOLYLINE"), (5, f"{h:X}"), (100, "AcDbEntity"), (8, layer),
               (100, "AcDbPolyline"), (90, len(vs)), (70, 1 if closed else 0)]
        h += 1
        for x, y, b in vs:
            pr += [(10, num(x)), (20, num(y))]
            if b:
                pr += [(42, num(b))]
    pr += [(0, "ENDSEC"), (0, "EOF")]
    return dxf_pairs(pr)


def dxf_r12(entities):
    """entities: list of tuples:
    ('LINE', layer, (x1, y1), (x2, y2)); ('ARC', layer, (cx, cy), r, a0, a1);
    ('CIRCLE', layer, (cx, cy), r); ('POLYLINE', layer, [(x, y, bulge)], closed)."""
    pr = [(0, "SECTION"), (2, "HEADER"), (9, "$ACADVER"), (1, "AC1009"), (0, "ENDSEC"),
          (0, "SECTION"), (2, "ENTITIES")]
    for e in entities:
        kind, layer = e[0], e[1]
        if kind == "LINE":
            (x1, y1), (x2, y2) = e[2], e[3]
            pr += [(0, "LINE"), (8, layer), (10, num(x1)), (20, num(y1)), (30, "0.0"),
                   (11, num(x2)), (21, num(y2)), (31, "0.0")]
        elif kind == "ARC":
            (cx, cy), r, a0, a1 = e[2], e[3], e[4], e[5]
            pr += [(0, "ARC"), (8, layer), (10, num(cx)), (20, num(cy)), (30, "0.0"),
                   (40, num(r)), (50, num(a0)), (51, num(a1))]
        elif kind == "CIRCLE":
            (cx, cy), r = e[2], e[3]
            pr += [(0, "CIRCLE"), (8, layer), (10, num(cx)), (20, num(cy)), (30, "0.0"),
                   (40, num(r))]
        elif kind == "POLYLINE":
            vs, closed = e[2], e[3]
            pr += [(0, "POLYLINE"), (8, layer), (66, 1), (10, "0.0"), (20, "0.0"), (30, "0.0"),
                   (70, 1 if closed else 0)]
            for x, y, b in vs:
                pr += [(0, "VERTEX"), (8, layer), (10, num(x)), (20, num(y)), (30, "0.0")]
                if b:
                    pr += [(42, num(b))]
            pr += [(0, "SEQEND"), (8, layer)]
    pr += [(0, "ENDSEC"), (0, "EOF")]
    return dxf_pairs(pr)


def svg(body, width, height, unit, viewbox):
    return (f'<?xml version="1.0" encoding="UTF-8"?>\n'
            f'<!-- generated by scripts/gen_sample_catalog.py -->\n'
            f'<svg xmlns="http://www.w3.org/2000/svg" width="{num(width)}{unit}" '
            f'height="{num(height)}{unit}" viewBox="{viewbox}">\n{body}</svg>\n')


def svg_points(p):
    return " ".join(f"{num(x)},{num(y)}" for x, y in p)


def toml_pts(p):
    """[x, y] points, or [x, y, bulge] vertices (bulges written in full so
    that arcs stay tangent where the drawing makes them tangent)."""
    def one(q):
        if len(q) == 3 and q[2]:
            return f"[{num(q[0])}, {num(q[1])}, {float(q[2])!r}]"
        return f"[{num(q[0])}, {num(q[1])}]"
    return "[" + ", ".join(one(q) for q in p) + "]"


# ----------------------------------------------------------------- catalogue

def mm_catalogue(base):
    entries = []  # (id, dict of toml fields)

    def inline(pid, outline, access=(), **kw):
        e = {"id": pid, "outline": outline}
        if access:
            e["access"] = list(access)
        e.update(kw)
        entries.append(e)

    def jsonfile(pid, outline, access=(), units=None, **kw):
        doc = {"part": pts(outline)}
        if units:
            doc = {"units": units, **doc}
        if access:
            doc["access"] = [pts(a) for a in access]
        write(os.path.join(base, "parts", pid + ".json"), json.dumps(doc, indent=1) + "\n")
        entries.append({"id": pid, "file": f"parts/{pid}.json", **kw})

    def fileentry(pid, name, **kw):
        entries.append({"id": pid, "file": f"parts/{name}", **kw})

    # Brackets and profiles.
    jsonfile("bracket-1", [(0, 0), (90, 0), (90, 40), (70, 60), (0, 60)], quantity=2400)
    inline("bracket-2", [(0, 0), (100, 0), (100, 20), (35, 20), (35, 70), (0, 70)])
    jsonfile("bracket-3", [(0, 0), (80, 0), (80, 15), (50, 15), (50, 30), (65, 30), (65, 45),
                           (0, 45)])
    inline("l-profile-1", l_profile(80, 60, 15), quantity=5000)
    # R12 LINE chain, entities shuffled and some reversed, as old CAD writes.
    lp = l_profile(120, 40, 12)
    lines = [(lp[i], lp[(i + 1) % len(lp)]) for i in range(len(lp))]
    order = [3, 0, 5, 1, 4, 2]
    ents = []
    for k in order:
        a, b = lines[k]
        ents.append(("LINE", "0", b, a) if k % 2 else ("LINE", "0", a, b))
    write(os.path.join(base, "parts", "l-profile-2.dxf"), dxf_r12(ents))
    fileentry("l-profile-2", "l-profile-2.dxf", quantity=800)
    inline("t-profile-1", t_profile(100, 80, 20, 25))
    jsonfile("t-profile-2", t_profile(70, 110, 15, 18))
    up = u_profile(90, 60, 15)
    write(os.path.join(base, "parts", "u-profile-1.dxf"),
          dxf_r2000([("PART", [(x, y, 0) for x, y in up], True)], 4))
    fileentry("u-profile-1", "u-profile-1.dxf", quantity=1500)
    inline("u-profile-2", u_profile(130, 45, 12))
    inline("z-clip", [(0, 0), (60, 0), (60, 30), (100, 30), (100, 45), (45, 45), (45, 15),
                      (0, 15)])
    # Housings with notches and bosses.
    inline("housing-1", housing_bosses(110, 70), quantity=300)
    inline("housing-2", housing_bosses(140, 80),
           access=[rect(60, 55, 80, 95)], quantity=300)
    # Bosses as bulge arcs (bulge 1 = half circle), an access region on
    # layer ACCESS and a bore on layer HOLES (ignored with a warning).
    w, h = 120.0, 70.0
    hv = [(0, 0, 0), (w, 0, 0), (w, 20, 1), (w, 50, 0), (w, h, 0), (70, h, 0), (70, 58, 0),
          (50, 58, 0), (50, h, 0), (0, h, 0), (0, 50, 1), (0, 20, 0)]
    write(os.path.join(base, "parts", "housing-3.dxf"), dxf_r2000([
        ("PART", hv, True),
        ("ACCESS", [(-5, 25, 0), (15, 25, 0), (15, 45, 0), (-5, 45, 0)], True),
        ("Holes", [(50, 35, 1), (70, 35, 1)], True),
    ], 4))
    fileentry("housing-3", "housing-3.dxf", quantity=300)
    inline("housing-4", [(0, 0), (60, 0), (60, 10), (75, 10), (75, 0), (140, 0), (140, 55),
                         (100, 55), (100, 65), (40, 65), (40, 55), (0, 55)])
    # Flanges and gear-like outlines.
    inline("flange-1", flange(30, 18, 20), quantity=1200)
    # LINE + ARC chain: an oval flange with flat sides.
    write(os.path.join(base, "parts", "flange-2.dxf"), dxf_r12([
        ("LINE", "0", (-30, -25), (30, -25)),
        ("ARC", "0", (30, 0), 25, 270, 90),
        ("LINE", "0", (30, 25), (-30, 25)),
        ("ARC", "0", (-30, 0), 25, 90, 270),
        ("CIRCLE", "BORE", (0, 0), 12),
    ]))
    fileentry("flange-2", "flange-2.dxf")
    inline("gear-8", gear(8, 26, 34), quantity=4000)
    jsonfile("gear-6", gear(6, 30, 40))
    inline("gear-10", gear(10, 40, 48))
    inline("cam-1", cam(25, 20))
    inline("star-knob", star(5, 45, 22))
    inline("hex-plate", [(40 * math.cos(math.radians(60 * i)), 40 * math.sin(math.radians(60 * i)))
                         for i in range(6)])
    inline("wedge", [(0, 0), (120, 0), (0, 50)])
    jsonfile("trapezoid", [(0, 0), (110, 0), (85, 50), (20, 50)])
    inline("keyhole-plate", keyhole(30, 20, 55))
    # Lever: R12 POLYLINE with bulge ends (half circles), as older CAD writes.
    write(os.path.join(base, "parts", "lever.dxf"), dxf_r12([
        ("POLYLINE", "0", [(0, 0, 0), (110, 0, 1), (110, 24, 0), (0, 24, 1)], True),
    ]))
    fileentry("lever", "lever.dxf", quantity=900)
    # Drawn in inches ($INSUNITS = 1): converted to mm on reading.
    bi = [(0, 0), (3.5, 0), (3.5, 0.75), (1.25, 0.75), (1.25, 2.25), (0, 2.25)]
    write(os.path.join(base, "parts", "bracket-inch.dxf"),
          dxf_r2000([("0", [(x, y, 0) for x, y in bi], True)], 1))
    fileentry("bracket-inch", "bracket-inch.dxf")
    # Access constraints.
    jsonfile("angle-plate", l_profile(100, 80, 20),
             access=[rect(60, -10, 110, 10)], quantity=600)
    # SVG: path with relative commands, class="access" rect; y points down.
    write(os.path.join(base, "parts", "cover.svg"), svg(
        '  <path id="cover" d="M 0 0 h 120 v 40 l -20 20 H 20 L 0 40 Z"/>\n'
        '  <rect class="access" x="50" y="-10" width="20" height="20"/>\n',
        130, 70, "mm", "-5 -15 130 80"))
    fileentry("cover", "cover.svg", quantity=700)
    # SVG: arcs (A), a cubic (C) and group transforms.
    write(os.path.join(base, "parts", "bracket-svg.svg"), svg(
        '  <g transform="translate(10 80) rotate(-90)">\n'
        '    <path d="M 0 0 L 70 0 A 15 15 0 0 1 70 30 L 40 30 '
        'C 35 30 30 35 30 40 L 30 90 L 0 90 Z"/>\n'
        '  </g>\n',
        110, 110, "mm", "0 0 110 110"))
    fileentry("bracket-svg", "bracket-svg.svg")
    write(os.path.join(base, "parts", "star-plate.svg"), svg(
        f'  <polygon transform="scale(2)" points="{svg_points(star(6, 30, 18))}"/>\n',
        140, 140, "mm", "-70 -70 140 140"))
    fileentry("star-plate", "star-plate.svg")
    # Parts no fixture of the sample kits can hold: smaller than the lattice
    # (three locators can never touch them), and a part whose whole edge is
    # under a keep-out region.
    inline("tiny-tab", rect(0, 0, 5, 4))
    inline("tiny-pin", [(3 * math.cos(math.radians(60 * i)), 3 * math.sin(math.radians(60 * i)))
                        for i in range(6)])
    inline("masked-plate", rect(0, 0, 60, 40), access=[rect(-10, -10, 70, 50)])
    # Per-part overrides.
    inline("plate-wrenches", rect(0, 0, 90, 50), top_k=3,
           wrenches=[[0.0, -200.0, 0.0], [150.0, 0.0, 2000.0]])

    lines = [
        "# Sample catalogue (mm), generated by scripts/gen_sample_catalog.py: do not edit.",
        'name = "sample-mm"',
        'units = "mm"',
        "# Circular arcs (DXF bulges, ARC, CIRCLE, SVG A, [x, y, bulge] outlines) are",
        "# exact (SPEC 8). Other curves (the Bezier corner of bracket-svg), and every",
        "# arc with `arcs = \"flatten\"` or `fixplan run --arcs flatten`, are flattened",
        "# coarsely (0.5 mm chord error) to keep edge counts, and so times, small.",
        "chord_tolerance = 0.5",
        "",
    ]
    lines += toml_entries(entries)
    write(os.path.join(base, "catalog.toml"), "\n".join(lines))
    return len(entries)


def toml_entries(entries):
    lines = []
    for e in entries:
        lines.append("[[part]]")
        for k, v in e.items():
            if k == "id" or k == "file":
                lines.append(f'{k} = "{v}"')
            elif k == "outline":
                lines.append(f"outline = {toml_pts(v)}")
            elif k == "access":
                lines.append("access = [" + ", ".join(toml_pts(a) for a in v) + "]")
            elif k == "wrenches":
                lines.append("wrenches = [" + ", ".join(
                    "[" + ", ".join(f"{float(x)}" for x in w) + "]" for w in v) + "]")
            elif k == "quantity":
                lines.append(f"quantity = {float(v)}")
            else:
                lines.append(f"{k} = {v}")
        lines.append("")
    return lines


def inch_catalogue(base):
    entries = []
    entries.append({"id": "in-bracket", "outline": [(0, 0), (4, 0), (4, 1), (1.5, 1), (1.5, 2.5),
                                                    (0, 2.5)], "quantity": 1000})
    entries.append({"id": "in-gear", "outline": gear(8, 1.1, 1.4)})
    entries.append({"id": "in-t", "outline": t_profile(4, 3, 0.75, 1)})
    doc = {"units": "in", "part": pts(u_profile(3.5, 2.25, 0.6))}
    write(os.path.join(base, "parts", "in-u.json"), json.dumps(doc, indent=1) + "\n")
    entries.append({"id": "in-u", "file": "parts/in-u.json"})
    hv = [(0, 0, 0), (4.5, 0, 0), (4.5, 0.8, 1), (4.5, 2, 0), (4.5, 2.75, 0), (0, 2.75, 0)]
    write(os.path.join(base, "parts", "in-housing.dxf"), dxf_r2000([
        ("PART", hv, True),
        ("keepout", [(1.5, 2.5, 0), (2.5, 2.5, 0), (2.5, 3.1, 0), (1.5, 3.1, 0)], True),
    ], 1))
    entries.append({"id": "in-housing", "file": "parts/in-housing.dxf", "quantity": 250})
    # Drawn in mm ($INSUNITS = 4): converted to inches on reading.
    write(os.path.join(base, "parts", "metric-plate.dxf"),
          dxf_r2000([("0", [(x, y, 0) for x, y in
                             [(0, 0), (100, 0), (100, 40), (60, 60), (0, 60)]], True)], 4))
    entries.append({"id": "metric-plate", "file": "parts/metric-plate.dxf"})
    write(os.path.join(base, "parts", "in-cover.svg"), svg(
        '  <path d="M0,0 H3.5 V1.2 Q3.5,1.8 2.9,1.8 H0 z"/>\n',
        3.5, 1.8, "in", "0 0 3.5 1.8"))
    entries.append({"id": "in-cover", "file": "parts/in-cover.svg"})
    entries.append({"id": "in-tiny", "outline": rect(0, 0, 0.2, 0.15)})
    lines = [
        "# Sample catalogue (inches), generated by scripts/gen_sample_catalog.py: do not edit.",
        'name = "sample-inch"',
        'units = "in"',
        "chord_tolerance = 0.02",
        "",
    ]
    lines += toml_entries(entries)
    write(os.path.join(base, "catalog.toml"), "\n".join(lines))
    return len(entries)


if __name__ == "__main__":
    n = mm_catalogue(os.path.join(ROOT, "examples", "catalog"))
    m = inch_catalogue(os.path.join(ROOT, "examples", "catalog-inch"))
    print(f"wrote {n} mm parts and {m} inch parts")
