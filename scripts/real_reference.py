#!/usr/bin/env python3
"""Independent reference for the real CAD files in catalog/tests/real/.

    python3 scripts/real_reference.py            # rewrite expected.json
    python3 scripts/real_reference.py --check    # recompute and compare
    python3 scripts/real_reference.py --show F   # print one file's loops
    python3 scripts/real_reference.py --catalog  # rewrite examples/real/catalog.toml

Reads every DXF with ezdxf and every SVG with svgelements (both installed
with pip, neither shares a line with fixplan's readers) and writes, per
file, the part's outline as fixplan should find it: the largest closed
loop of the drawing's curves, as its area, perimeter and bounding box in
millimetres, in fixplan's part coordinates (SVG's y axis points down, a
part's up, so SVG y is negated, as fixplan does).

What the reference takes as the drawing, so that a disagreement means a
reader is wrong and not that the two looked at different things:
- DXF: model space only; INSERTs (and MINSERT grids) exploded by ezdxf with
  their transforms, nested to any depth; DIMENSION, TEXT, HATCH, POINT and
  the like are not outline; LINE, ARC, CIRCLE, LWPOLYLINE and 2D POLYLINE
  (bulges exact), ELLIPSE and SPLINE (flattened to 1e-4 drawing units) are.
  Units from `$INSUNITS`; a unitless file takes the `units` options.json
  gives it (what its manifest entry would say).
- SVG: every shape svgelements renders (paths, rects, circles, ellipses,
  polygons, polylines, lines, `use`), transforms applied; `width`/`height`
  and `viewBox` by SVG's rules, 96 px per inch for unitless lengths;
  circular arcs exact, other curves flattened to about 1e-4 mm.
- Both: zero-length pieces and exact duplicates are dropped, pieces are
  joined end to end within 0.01 mm into loops (CIRCLEs, closed polylines
  and closed subpaths are loops of their own), the `layers` and
  `ignore_layers` options of the entry apply (DXF).

Loops are measured exactly: a circular arc adds its chord to the area and
its circular segment `r^2/2 (t - sin t)`, its length `r t`, and its axis
extremes to the bounding box.
"""

import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REAL = os.path.join(HERE, "..", "catalog", "tests", "real")
EXPECTED = os.path.join(REAL, "expected.json")
# The same set as one catalogue for the benches, written from expected.json.
CATALOG = os.path.join(HERE, "..", "examples", "real", "catalog.toml")
# Per-file read options: what a manifest entry would give (units of a
# unitless file, layers to read or ignore). Kept beside the files.
OPTIONS = os.path.join(REAL, "options.json")

JOIN_MM = 0.01
FLAT = 1e-4  # flattening distance, in drawing units (DXF) or mm (SVG)
INSUNITS_MM = {1: 25.4, 2: 304.8, 4: 1.0, 5: 10.0, 6: 1000.0}
UNIT_MM = {"mm": 1.0, "in": 25.4, "cm": 10.0, "m": 1000.0, "ft": 304.8}
# What --check allows between the committed and the recomputed figures;
# both come from the same files and libraries, so only library versions
# move them.
CHECK_REL = 1e-6


# --- pieces: ("L", p0, p1) or ("A", centre, r, a0, sweep), sweep signed,
# counter-clockwise positive; points are (x, y) tuples in mm.


def line(p0, p1):
    return ("L", p0, p1)


def arc(c, r, a0, sweep):
    return ("A", c, r, a0, sweep)


def start(s):
    if s[0] == "L":
        return s[1]
    _, c, r, a0, _ = s
    return (c[0] + r * math.cos(a0), c[1] + r * math.sin(a0))


def end(s):
    if s[0] == "L":
        return s[2]
    _, c, r, a0, sw = s
    return (c[0] + r * math.cos(a0 + sw), c[1] + r * math.sin(a0 + sw))


def reverse(s):
    if s[0] == "L":
        return ("L", s[2], s[1])
    _, c, r, a0, sw = s
    return ("A", c, r, a0 + sw, -sw)


def length(s):
    if s[0] == "L":
        return math.dist(s[1], s[2])
    return abs(s[2] * s[4])


def arc_through(p0, pm, p1):
    """The circular arc from p0 through pm to p1, or a line if they are in
    a row."""
    ax, ay = p0
    bx, by = pm
    cx, cy = p1
    d = 2 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by))
    span = max(math.dist(p0, pm), math.dist(pm, p1), 1e-300)
    if abs(d) < 1e-12 * span * span:
        return line(p0, p1)
    a2, b2, c2 = ax * ax + ay * ay, bx * bx + by * by, cx * cx + cy * cy
    ux = (a2 * (by - cy) + b2 * (cy - ay) + c2 * (ay - by)) / d
    uy = (a2 * (cx - bx) + b2 * (ax - cx) + c2 * (bx - ax)) / d
    r = math.dist((ux, uy), p0)
    a0 = math.atan2(ay - uy, ax - ux)
    a1 = math.atan2(cy - uy, cx - ux)
    ccw = (bx - ax) * (cy - by) - (by - ay) * (cx - bx) > 0
    if ccw:
        sw = (a1 - a0) % (2 * math.pi)
    else:
        sw = -((a0 - a1) % (2 * math.pi))
    return arc((ux, uy), r, a0, sw)


def measure(loop):
    """Signed area, perimeter and bounding box of a closed loop of pieces."""
    area = 0.0
    per = 0.0
    xs, ys = [], []
    for s in loop:
        p0, p1 = start(s), end(s)
        area += (p0[0] * p1[1] - p1[0] * p0[1]) / 2
        per += length(s)
        xs += [p0[0], p1[0]]
        ys += [p0[1], p1[1]]
        if s[0] == "A":
            _, c, r, a0, sw = s
            t = abs(sw)
            area += math.copysign(r * r / 2 * (t - math.sin(t)), sw)
            lo, hi = (a0, a0 + sw) if sw > 0 else (a0 + sw, a0)
            k = math.ceil(lo / (math.pi / 2))
            while k * math.pi / 2 <= hi:
                a = k * math.pi / 2
                xs.append(c[0] + r * math.cos(a))
                ys.append(c[1] + r * math.sin(a))
                k += 1
    return area, per, [min(xs), min(ys), max(xs), max(ys)]


def circle_loop(c, r):
    return [arc(c, r, 0.0, math.pi), arc(c, r, math.pi, math.pi)]


def polyline_pieces(pts):
    return [line(a, b) for a, b in zip(pts, pts[1:])]


# --- joining pieces into loops


def build_loops(pieces, loops, tol):
    """Adds to `loops` the closed chains of `pieces` (joined end to end
    within `tol`); returns the number of chains left open and the number
    of joints where more than two pieces meet."""
    pieces = [s for s in pieces if length(s) > 1e-9]
    uniq = {}
    for s in pieces:
        m = mid(s)
        key = tuple(sorted([rnd(start(s), tol), rnd(end(s), tol)])) + (rnd(m, tol),)
        uniq.setdefault(key, s)
    pieces = list(uniq.values())
    # Endpoint index on a grid of cell `tol`.
    grid = {}

    def cell(p):
        return (math.floor(p[0] / tol), math.floor(p[1] / tol))

    ends = []  # (piece index, 0 = start / 1 = end, point)
    for i, s in enumerate(pieces):
        for k, p in ((0, start(s)), (1, end(s))):
            ends.append((i, k, p))
            grid.setdefault(cell(p), []).append(len(ends) - 1)

    def near(p, skip_piece):
        cx, cy = cell(p)
        out = []
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for e in grid.get((cx + dx, cy + dy), ()):
                    i, k, q = ends[e]
                    if i != skip_piece and math.dist(p, q) <= tol:
                        out.append((i, k))
        return out

    branch = sum(1 for (i, k, p) in ends if len(near(p, i)) > 1)
    used = [False] * len(pieces)
    open_chains = 0
    for i0 in range(len(pieces)):
        if used[i0]:
            continue
        used[i0] = True
        chain = [pieces[i0]]
        closed = math.dist(start(chain[0]), end(chain[0])) <= tol and chain[0][0] == "A"
        while not closed:
            p = end(chain[-1])
            if len(chain) > 1 and math.dist(p, start(chain[0])) <= tol:
                closed = True
                break
            nxt = [(i, k) for i, k in near(p, -1) if not used[i]]
            if not nxt:
                break
            i, k = nxt[0]
            used[i] = True
            chain.append(pieces[i] if k == 0 else reverse(pieces[i]))
        if closed:
            loops.append(chain)
        else:
            # Walk back from the first piece's start too, to count the
            # chain once.
            p = start(chain[0])
            while True:
                nxt = [(i, k) for i, k in near(p, -1) if not used[i]]
                if not nxt:
                    break
                i, k = nxt[0]
                used[i] = True
                s = pieces[i] if k == 1 else reverse(pieces[i])
                chain.insert(0, s)
                p = start(s)
            open_chains += 1
    return open_chains, branch


def inside(m, o):
    """Whether loop `m` lies inside loop `o` (both (measure, pieces)):
    its box inside o's and its first point inside o's polygon."""
    (_, _, b), loop = m
    (_, _, ob), oloop = o
    if not (b[0] >= ob[0] and b[1] >= ob[1] and b[2] <= ob[2] and b[3] <= ob[3]):
        return False
    x, y = start(loop[0])
    poly = []
    for s in oloop:
        if s[0] == "L":
            poly.append(s[1])
        else:
            _, c, r, a0, sw = s
            n = max(8, int(abs(sw) * 32))
            poly += [(c[0] + r * math.cos(a0 + sw * i / n), c[1] + r * math.sin(a0 + sw * i / n))
                     for i in range(n)]
    odd = False
    for (x0, y0), (x1, y1) in zip(poly, poly[1:] + poly[:1]):
        if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
            odd = not odd
    return odd


def mid(s):
    if s[0] == "L":
        return ((s[1][0] + s[2][0]) / 2, (s[1][1] + s[2][1]) / 2)
    _, c, r, a0, sw = s
    return (c[0] + r * math.cos(a0 + sw / 2), c[1] + r * math.sin(a0 + sw / 2))


def rnd(p, tol):
    return (round(p[0] / tol), round(p[1] / tol))


# --- DXF with ezdxf


def dxf_drawing(path, opts):
    import ezdxf
    from ezdxf import recover

    try:
        doc = ezdxf.readfile(path)
    except ezdxf.DXFStructureError:
        # Files some writers leave without subclass markers (OpenJsCad):
        # ezdxf's recover mode reads them, fixplan should too.
        doc, _ = recover.readfile(path)
    ins = header_insunits(path)
    if ins in INSUNITS_MM:
        scale, units_from = INSUNITS_MM[ins], f"$INSUNITS {ins}"
    elif ins == 0 and "units" in opts:
        scale, units_from = UNIT_MM[opts["units"]], f"unitless, entry units {opts['units']}"
    else:
        raise SystemExit(f"{path}: $INSUNITS {ins} and no units option")
    layers = set(opts.get("layers", [])) or None
    ignore = set(opts.get("ignore_layers", []))
    pieces, loops, kinds, skipped = [], [], {}, {}

    def p2(v):
        return (v.x * scale, v.y * scale)

    def take(e, layer):
        t = e.dxftype()
        if t == "INSERT":
            lay = e.dxf.layer
            for sub in (e.multi_insert() if e.mcount > 1 else [e]):
                for v in sub.virtual_entities():
                    take(v, v.dxf.layer if v.dxf.layer != "0" else lay)
            return
        if layers is not None and layer not in layers or layer in ignore:
            skipped[t] = skipped.get(t, 0) + 1
            return
        kinds[t] = kinds.get(t, 0) + 1
        if t == "LINE":
            pieces.append(line(p2(e.dxf.start), p2(e.dxf.end)))
        elif t == "ARC":
            pieces.append(dxf_arc(e.ocs().to_wcs(e.dxf.center), e.dxf.radius,
                                  e.start_point, e.end_point,
                                  (e.dxf.end_angle - e.dxf.start_angle) % 360 or 360,
                                  e.dxf.extrusion.z < 0, scale))
        elif t == "CIRCLE":
            loops.append(circle_loop(p2(e.ocs().to_wcs(e.dxf.center)), e.dxf.radius * scale))
        elif t in ("LWPOLYLINE", "POLYLINE"):
            if t == "POLYLINE" and not e.is_2d_polyline:
                skipped[t] = skipped.get(t, 0) + 1
                return
            sub = []
            for v in e.virtual_entities():
                if v.dxftype() == "LINE":
                    sub.append(line(p2(v.dxf.start), p2(v.dxf.end)))
                elif v.dxftype() == "ARC":
                    sub.append(dxf_arc(v.ocs().to_wcs(v.dxf.center), v.dxf.radius,
                                       v.start_point, v.end_point,
                                       (v.dxf.end_angle - v.dxf.start_angle) % 360 or 360,
                                       v.dxf.extrusion.z < 0, scale))
            if e.is_closed and sub:
                build_loops(sub, loops, JOIN_MM)  # its own loop
            else:
                pieces.extend(sub)
        elif t == "ELLIPSE":
            if abs(e.dxf.ratio - 1) < 1e-9:
                span = (e.dxf.end_param - e.dxf.start_param) % (2 * math.pi)
                r = e.dxf.major_axis.magnitude
                if span < 1e-12 or abs(span - 2 * math.pi) < 1e-12:
                    loops.append(circle_loop(p2(e.dxf.center), r * scale))
                else:
                    pieces.append(dxf_arc(e.dxf.center, r, e.start_point, e.end_point,
                                          math.degrees(span), e.dxf.extrusion.z < 0, scale))
            else:
                curve(e, scale, pieces, loops)
        elif t == "SPLINE":
            curve(e, scale, pieces, loops)
        else:
            kinds.pop(t)
            skipped[t] = skipped.get(t, 0) + 1

    for e in doc.modelspace():
        take(e, e.dxf.layer)
    return pieces, loops, kinds, skipped, units_from, scale


def header_insunits(path):
    """`$INSUNITS` as the file writes it, 0 when it does not: ezdxf fills
    a header the file lacks with its own defaults."""
    with open(path, "rb") as f:
        lines = [l.strip() for l in f.read().decode("latin-1").splitlines()]
    for i in range(0, len(lines) - 3, 1):
        if lines[i] == "9" and lines[i + 1] == "$INSUNITS":
            return int(lines[i + 3])
        if lines[i] == "0" and lines[i + 1] == "ENDSEC":
            break
    return 0


def dxf_arc(c, r, p0, p1, span_deg, clockwise, scale):
    c = (c.x * scale, c.y * scale)
    p0 = (p0.x * scale, p0.y * scale)
    sw = math.radians(span_deg) * (-1 if clockwise else 1)
    a0 = math.atan2(p0[1] - c[1], p0[0] - c[0])
    return arc(c, r * scale, a0, sw)


def curve(e, scale, pieces, loops):
    pts = [(v.x * scale, v.y * scale) for v in e.flattening(FLAT)]
    sub = polyline_pieces(pts)
    if len(pts) > 2 and math.dist(pts[0], pts[-1]) <= JOIN_MM:
        build_loops(sub, loops, JOIN_MM)
    else:
        pieces.extend(sub)


# --- SVG with svgelements


def svg_drawing(path, opts):
    import svgelements as se

    px = 25.4 / 96  # mm per CSS pixel
    svg = se.SVG.parse(path, ppi=96)
    pieces, loops, kinds, skipped = [], [], {}, {}

    def p2(q):
        return (float(q[0]) * px, -float(q[1]) * px)

    for el in svg.elements():
        if not isinstance(el, se.Shape):
            continue
        if el.values.get("visibility") == "hidden" or el.values.get("display") == "none":
            continue
        t = type(el).__name__
        kinds[t] = kinds.get(t, 0) + 1
        p = abs(se.Path(el))
        sub = []
        for seg in p:
            if isinstance(seg, se.Move):
                flush(sub, pieces, loops, False)
                sub = []
            elif isinstance(seg, se.Close):
                a, b = p2(seg.start), p2(seg.end)
                if math.dist(a, b) > 0:
                    sub.append(line(a, b))
                flush(sub, pieces, loops, True)
                sub = []
            elif isinstance(seg, se.Line):
                sub.append(line(p2(seg.start), p2(seg.end)))
            elif isinstance(seg, se.Arc) and abs(seg.rx - seg.ry) <= 1e-9 * max(seg.rx, seg.ry):
                sub.append(arc_through(p2(seg.start), p2(seg.point(0.5)), p2(seg.end)))
            else:
                n = max(16, int(seg.length(error=1e-6) * px / 0.02))
                pts = [p2(seg.point(i / n)) for i in range(n + 1)]
                sub.extend(polyline_pieces(pts))
        flush(sub, pieces, loops, False)
    w = svg.values.get("width")
    units_from = f"width {w!r}, viewBox {svg.values.get('viewBox')!r}"
    return pieces, loops, kinds, skipped, units_from, px


def flush(sub, pieces, loops, closed):
    if not sub:
        return
    if closed:
        build_loops(sub, loops, JOIN_MM)
    else:
        pieces.extend(sub)


# --- per file


def reference(name, opts):
    path = os.path.join(REAL, name)
    if name.lower().endswith(".dxf"):
        pieces, loops, kinds, skipped, units_from, _ = dxf_drawing(path, opts)
    else:
        pieces, loops, kinds, skipped, units_from, _ = svg_drawing(path, opts)
    open_chains, branch = build_loops(pieces, loops, JOIN_MM)
    measured = sorted(((measure(l), l) for l in loops), key=lambda m: -abs(m[0][0]))
    if not measured:
        raise SystemExit(f"{name}: no closed loop")
    # The parts: the largest loop, or with `sheet` every loop inside no
    # other, in a fixed order (by bounding box) for a stable file; the
    # test matches them whatever order the reader gives.
    if opts.get("sheet"):
        outer = [m for i, m in enumerate(measured)
                 if not any(inside(m, o) for o in measured[:i])]
        outer.sort(key=lambda m: (round(m[0][2][0], 3), round(m[0][2][1], 3)))
    else:
        outer = measured[:1]
    # A part's holes: the loops whose smallest enclosing loop is the
    # part's outline (SPEC 9; loops inside a hole are not counted).
    parent = []
    for i, m in enumerate(measured):
        parent.append(next((j for j in range(i - 1, -1, -1) if inside(m, measured[j])), None))
    index = {id(m): i for i, m in enumerate(measured)}
    parts = [{"area_mm2": abs(a), "perimeter_mm": p, "bbox_mm": b,
              "holes": sum(1 for q in parent if q == index[id(o)])}
             for o in outer for (a, p, b) in [o[0]]]
    return {
        "file": name,
        "options": opts,
        "units_from": units_from,
        "parts": parts,
        "loops": len(measured),
        "open_chains": open_chains,
        "branch_joints": branch,
        "entities": dict(sorted(kinds.items())),
        "not_outline": dict(sorted(skipped.items())),
    }


def compute():
    with open(OPTIONS) as f:
        options = json.load(f)
    names = sorted(n for n in os.listdir(REAL) if n.lower().endswith((".dxf", ".svg")))
    missing = sorted(set(options) - set(names))
    if missing:
        raise SystemExit(f"options.json names files that are not there: {missing}")
    return [reference(n, options.get(n, {})) for n in names]


def rounded(x):
    if isinstance(x, float):
        return float(f"{x:.9g}")
    if isinstance(x, list):
        return [rounded(v) for v in x]
    if isinstance(x, dict):
        return {k: rounded(v) for k, v in x.items()}
    return x


def close(a, b):
    if isinstance(a, float) or isinstance(b, float):
        return abs(a - b) <= CHECK_REL * max(1.0, abs(a), abs(b))
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(close(x, y) for x, y in zip(a, b))
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(close(a[k], b[k]) for k in a)
    return a == b


CATALOG_HEAD = """\
# The real-files test set (catalog/tests/real, read with the options of
# its expected.json) as one catalogue, for `fixplan bench --compare-flatten
# --catalog examples/real/catalog.toml`. Written from expected.json;
# parts without arcs are skipped by --compare-flatten.
# Rewrite with `python3 scripts/real_reference.py --catalog`.
name = "real"
units = "mm"
"""


def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    return json.dumps(v)


def write_catalog():
    """examples/real/catalog.toml: one part per file of expected.json, its
    read options as manifest keys, so the benches read what the test
    reads."""
    with open(EXPECTED) as f:
        files = json.load(f)["files"]
    out = [CATALOG_HEAD]
    for g in files:
        name = g["file"]
        out.append("\n[[part]]\n")
        out.append(f'id = "{name.replace(".", "_")}"\n')
        out.append(f"file = '../../catalog/tests/real/{name}'\n")
        for k, v in g["options"].items():
            out.append(f"{k} = {toml_value(v)}\n")
    with open(CATALOG, "w") as f:
        f.write("".join(out))
    print(f"real_reference: {len(files)} files written to examples/real/catalog.toml")
    return 0


def main(argv):
    if len(argv) > 1 and argv[1] == "--catalog":
        return write_catalog()
    if len(argv) > 1 and argv[1] == "--show":
        with open(OPTIONS) as f:
            opts = json.load(f).get(argv[2], {})
        print(json.dumps(rounded(reference(argv[2], opts)), indent=1))
        return 0
    got = {"about": "written by scripts/real_reference.py from ezdxf and svgelements; do not edit",
           "join_tolerance_mm": JOIN_MM,
           "files": rounded(compute())}
    if len(argv) > 1 and argv[1] == "--check":
        with open(EXPECTED) as f:
            want = json.load(f)
        bad = [g["file"] for g, w in zip(got["files"], want["files"]) if not close(g, w)]
        if len(got["files"]) != len(want["files"]) or bad:
            print(f"real_reference: expected.json disagrees with ezdxf/svgelements for {bad or 'the file list'}")
            return 1
        print(f"real_reference: {len(got['files'])} files agree with expected.json")
        return 0
    with open(EXPECTED, "w") as f:
        json.dump(got, f, indent=1)
        f.write("\n")
    for g in got["files"]:
        p = g["parts"][0]
        print(f"{g['file']:42} parts {len(g['parts'])} {p['area_mm2']:12.3f} {p['perimeter_mm']:10.3f} loops {g['loops']} open {g['open_chains']} branch {g['branch_joints']}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
