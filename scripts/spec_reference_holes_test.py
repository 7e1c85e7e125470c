#!/usr/bin/env python3
"""Self-checks of scripts/spec_reference.py on SPEC section 9 (parts with holes).

Standard library only.  usage: python3 scripts/spec_reference_holes_test.py [--quick]

Expectations are computed by hand (closed forms) or by code written here
independently of the reference (numerical integration, distance to the
material).  --quick skips the slow parts (the no-holes regression against the
pre-section-9 reference and the full frame case).  Prints 'N passed, N failed'
last and exits non-zero on any failure.
"""
import copy
import json
import math
import os
import random
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import spec_reference as S  # noqa: E402

CASES = os.path.join(HERE, 'spec_cases_holes')
OLD_CASES = os.path.join(HERE, 'spec_cases')
# the reference as it was before section 9 (its results agree with the Rust)
PRE_HOLES_COMMIT = '8e9afe9'
QUICK = '--quick' in sys.argv

passed = 0
failed = 0


def check(name, cond, detail=''):
    global passed, failed
    if cond:
        passed += 1
        print('ok    %s' % name)
    else:
        failed += 1
        print('FAIL  %s %s' % (name, detail))


def load(name):
    with open(os.path.join(CASES, name + '.json')) as fh:
        return json.load(fh)


_solved = {}


def solve(case, key=None):
    if key is not None and key in _solved:
        return _solved[key]
    res = S.solve(copy.deepcopy(case))
    if key is not None:
        _solved[key] = res
    return res


def id_of(f):
    """a fixture's identity, independent of the pose's translation"""
    return (tuple(f['segments']), tuple(map(tuple, f['locators'])),
            f['clamp']['segment'], f['clamp']['rotation_deg'], tuple(f['clamp']['mount']))


def ids(res):
    return sorted(id_of(f) for f in res['fixtures'])


def strip(res):
    res = copy.deepcopy(res)
    res.pop('seconds', None)
    return res


def circ(cx, cy, R):
    return [[cx - R, cy, 1], [cx + R, cy, 1]]


def rect(x0, y0, x1, y1):
    return [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]


# ------------------------------------------------- independent geometry
def bulge_arc(p0, p1, b):
    """centre, radius, start angle, signed sweep of a DXF bulge edge"""
    sweep = 4 * math.atan(b)
    dx, dy = p1[0] - p0[0], p1[1] - p0[1]
    c = math.hypot(dx, dy)
    half = sweep / 2
    R = c / (2 * abs(math.sin(half)))
    # centre: from the chord midpoint along the left normal, by R cos(half) (signed)
    h = c / 2 / math.tan(half)
    mx, my = (p0[0] + p1[0]) / 2, (p0[1] + p1[1]) / 2
    C = (mx - dy / c * h, my + dx / c * h)
    return C, R, math.atan2(p0[1] - C[1], p0[0] - C[0]), sweep


def loop_curves(loop):
    out = []
    n = len(loop)
    for i in range(n):
        p0 = loop[i]
        p1 = loop[(i + 1) % n]
        b = p0[2] if len(p0) > 2 else 0
        if b == 0:
            out.append(('line', (p0[0], p0[1]), (p1[0], p1[1])))
        else:
            out.append(('arc',) + bulge_arc(p0, p1, b))
    return out


def dist_curve(p, cv):
    if cv[0] == 'line':
        a, b = cv[1], cv[2]
        ab = (b[0] - a[0], b[1] - a[1])
        t = ((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / (ab[0] ** 2 + ab[1] ** 2)
        t = max(0.0, min(1.0, t))
        return math.hypot(p[0] - a[0] - t * ab[0], p[1] - a[1] - t * ab[1])
    _, C, R, a0, sw = cv
    ang = math.atan2(p[1] - C[1], p[0] - C[0])
    rel = (ang - a0) * (1 if sw > 0 else -1) % (2 * math.pi)
    if rel <= abs(sw):
        return abs(math.hypot(p[0] - C[0], p[1] - C[1]) - R)
    ends = [(C[0] + R * math.cos(a0), C[1] + R * math.sin(a0)),
            (C[0] + R * math.cos(a0 + sw), C[1] + R * math.sin(a0 + sw))]
    return min(math.hypot(p[0] - e[0], p[1] - e[1]) for e in ends)


def flatten(loop, per_turn=256):
    pts = []
    for cv in loop_curves(loop):
        if cv[0] == 'line':
            pts.append(cv[1])
        else:
            _, C, R, a0, sw = cv
            m = max(2, int(abs(sw) / (2 * math.pi) * per_turn))
            for k in range(m):
                a = a0 + sw * k / m
                pts.append((C[0] + R * math.cos(a), C[1] + R * math.sin(a)))
    return pts


def in_poly(p, poly):
    x, y = p
    inside = False
    j = len(poly) - 1
    for i in range(len(poly)):
        xi, yi = poly[i]
        xj, yj = poly[j]
        if (yi > y) != (yj > y) and x < xi + (y - yi) * (xj - xi) / (yj - yi):
            inside = not inside
        j = i
    return inside


class Material:
    """the part region of a case, built here from the case's vertices"""

    def __init__(self, case):
        loops = [case['part']] + list(case.get('holes') or [])
        self.curves = [cv for lp in loops for cv in loop_curves(lp)]
        self.outline = flatten(case['part'])
        self.holes = [flatten(h) for h in case.get('holes') or []]

    def contains(self, p):
        return in_poly(p, self.outline) and not any(in_poly(p, h) for h in self.holes)

    def dist(self, p):
        """distance to the material (0 inside); the flattened inside test is
        only used far from the boundary, where it is exact"""
        d = min(dist_curve(p, cv) for cv in self.curves)
        if d > 1e-3 and self.contains(p):
            return 0.0
        return d


def grid_props(inside, x0, y0, x1, y1, n):
    """area, centroid, radius of gyration by the midpoint rule on an n x n grid"""
    hx, hy = (x1 - x0) / n, (y1 - y0) / n
    A = Sx = Sy = Jo = 0.0
    for i in range(n):
        x = x0 + (i + 0.5) * hx
        for j in range(n):
            y = y0 + (j + 0.5) * hy
            if inside(x, y):
                A += 1
                Sx += x
                Sy += y
                Jo += x * x + y * y
    cx, cy = Sx / A, Sy / A
    rho = math.sqrt(Jo / A - cx * cx - cy * cy)
    return A * hx * hy, (cx, cy), rho


def close(a, b, rel):
    return abs(a - b) <= rel * max(1.0, abs(b))


# ------------------------------------------------- 9.5 metric
def test_metric():
    # square washer: 40 x 40 with a central bore R = 8
    A0 = 1600 - 64 * math.pi
    J0 = 40 ** 4 / 6 - math.pi * 8 ** 4 / 2
    A, c, rho = S.material_props(load('washer-square'))
    check('metric washer-square area', close(A, A0, 1e-12), (A, A0))
    check('metric washer-square centroid', abs(c[0] - 20) < 1e-9 and abs(c[1] - 20) < 1e-9, c)
    check('metric washer-square rho', close(rho, math.sqrt(J0 / A0), 1e-12), (rho, math.sqrt(J0 / A0)))

    # round washer: R 20 with bore 8, both about the origin
    A, c, rho = S.material_props(load('washer-round'))
    check('metric washer-round area', close(A, math.pi * (400 - 64), 1e-12), A)
    check('metric washer-round centroid', math.hypot(*c) < 1e-9, c)
    check('metric washer-round rho', close(rho, math.sqrt((400 + 64) / 2), 1e-12), rho)

    # plate 50 x 30 with an off-centre bore R = 6 at (15, 15)
    case = load('plate-bore')
    a_h = math.pi * 36
    A0 = 1500 - a_h
    cx0 = (1500 * 25 - a_h * 15) / A0
    cy0 = 15.0
    Jo = 1500 * ((50 ** 2 + 30 ** 2) / 12 + 25 ** 2 + 15 ** 2) - (a_h * 36 / 2 + a_h * (15 ** 2 + 15 ** 2))
    rho0 = math.sqrt(Jo / A0 - cx0 ** 2 - cy0 ** 2)
    A, c, rho = S.material_props(case)
    check('metric plate-bore area', close(A, A0, 1e-12), (A, A0))
    check('metric plate-bore centroid', abs(c[0] - cx0) < 1e-9 and abs(c[1] - cy0) < 1e-9, (c, cx0))
    check('metric plate-bore rho', close(rho, rho0, 1e-12), (rho, rho0))
    # and against a numerical integration (midpoint grid), the region built here
    gA, gc, grho = grid_props(lambda x, y: (x - 15) ** 2 + (y - 15) ** 2 > 36, 0, 0, 50, 30, 700)
    check('metric plate-bore grid area', close(gA, A, 2e-3), (gA, A))
    check('metric plate-bore grid centroid', math.dist(gc, c) < 0.02, (gc, c))
    check('metric plate-bore grid rho', close(grho, rho, 2e-3), (grho, rho))

    # flange: R 28 round, bore 10, bolt holes 3.5 and 4.5 at (19, 0) and (0, 19)
    case = load('flange-bolts')
    holes = [(0, 0, 10), (19, 0, 3.5), (0, 19, 4.5)]
    A0 = math.pi * 28 ** 2 - sum(math.pi * R * R for _, _, R in holes)
    Sx = -sum(math.pi * R * R * x for x, _, R in holes)
    Sy = -sum(math.pi * R * R * y for _, y, R in holes)
    Jo = math.pi * 28 ** 4 / 2 - sum(math.pi * R ** 4 / 2 + math.pi * R * R * (x * x + y * y) for x, y, R in holes)
    cx0, cy0 = Sx / A0, Sy / A0
    rho0 = math.sqrt(Jo / A0 - cx0 ** 2 - cy0 ** 2)
    A, c, rho = S.material_props(case)
    check('metric flange area', close(A, A0, 1e-12), (A, A0))
    check('metric flange centroid', math.dist(c, (cx0, cy0)) < 1e-9, (c, (cx0, cy0)))
    check('metric flange rho', close(rho, rho0, 1e-12), (rho, rho0))
    # Monte Carlo (fixed seed) with the Material built here from the bulges
    rnd = random.Random(12345)
    N = 200000
    n_in = 0
    sx = sy = so = 0.0
    for _ in range(N):
        x, y = rnd.uniform(-28, 28), rnd.uniform(-28, 28)
        if x * x + y * y < 28 * 28 and all((x - hx) ** 2 + (y - hy) ** 2 > R * R for hx, hy, R in holes):
            n_in += 1
            sx += x
            sy += y
            so += x * x + y * y
    mA = n_in / N * 56 * 56
    mc = (sx / n_in, sy / n_in)
    mrho = math.sqrt(so / n_in - mc[0] ** 2 - mc[1] ** 2)
    # standard errors: area ~0.3 %, centroid ~0.05, rho ~0.1 %
    check('metric flange Monte Carlo area', close(mA, A, 0.015), (mA, A))
    check('metric flange Monte Carlo centroid', math.dist(mc, c) < 0.25, (mc, c))
    check('metric flange Monte Carlo rho', close(mrho, rho, 0.01), (mrho, rho))

    # a slot hole (two lines, two half circles) listed either way: same material
    a1 = S.material_props(load('slot-hole-ccw'))
    a2 = S.material_props(load('slot-hole-cw'))
    A0 = 1500 - (100 + 25 * math.pi)
    check('metric slot area', close(a1[0], A0, 1e-12), (a1[0], A0))
    check('metric slot cw == ccw', max(abs(a1[0] - a2[0]), math.dist(a1[1], a2[1]), abs(a1[2] - a2[2])) < 1e-9,
          (a1, a2))

    # the score uses the material: a bore changes the score of a fixture that
    # does not touch it (same ids, different centroid / rho)
    plate = load('plate-bore')
    plate['holes'] = []
    A, c, rho = S.material_props(plate)
    check('metric plate without bore', close(A, 1500, 1e-12) and math.dist(c, (25, 15)) < 1e-12, (A, c))


# ------------------------------------------------- 9.3 segments
def plate_with_bore(R, cx=25.0, cy=15.0):
    case = load('plate-bore')
    case['holes'] = [circ(cx, cy, R)]
    return case


def segments_of(case):
    """segments as the solver builds them (lattice units)"""
    verts, hole_verts, _ = S.part_loops(case)
    l = case['kit']['spacing']
    edges = S.loop_edges(verts, l)
    loops = [(0, len(edges))]
    for hv in hole_verts:
        he = S.loop_edges(hv, l)
        loops.append((len(edges), len(he)))
        edges += he
    segs, _ = S.build_segments_arcs(edges, [], case['kit']['locator_radius'] / l,
                                    case['params']['edge_trim'] / l, loops)
    return segs, len(verts)


def test_segments():
    r = 3.0
    l = 10.0
    for R, want in ((2.0, 0), (3.0, 0), (3.0 + 5e-9, 0), (3.0 + 2e-8, 2), (3.5, 2), (8.0, 2)):
        segs, n_out = segments_of(plate_with_bore(R))
        hole = [s for s in segs if s.edge >= n_out]
        check('bore R=%r: %d hole segments' % (R, want), len(hole) == want, len(hole))
        if want:
            rho = (R - r) / l
            ok = all(s.kind == 'arc' and not s.convex and abs(s.rho - rho) < 1e-14 for s in hole)
            check('bore R=%r: concave arcs of radius R - r' % R, ok, [(s.kind, s.rho) for s in hole])
            # smooth joints: not trimmed, each half circle whole
            ok = all(s.s0 == 0.0 and abs(s.s1 - math.pi * rho) < 1e-12 for s in hole)
            check('bore R=%r: half circles untrimmed (smooth joints)' % R, ok,
                  [(s.s0, s.s1, math.pi * rho) for s in hole])
        outer = [s for s in segs if s.edge < n_out]
        check('bore R=%r: the outline keeps its 4 segments' % R, len(outer) == 4, len(outer))
    # through the solver: a bore of R = r gives no hole segment, R > r gives two
    for R, want in ((3.0, [0, 0, 0, 0]), (4.0, [0, 0, 0, 0, 1, 1])):
        case = plate_with_bore(R)
        res = S.solve(case, max_seconds=-1)     # segments only
        check('solve bore R=%r segment_loops' % R, res['segment_loops'] == want, res['segment_loops'])
    # slot narrower than 2r: nothing on its walls; exactly 2r: the lines stay
    res = S.solve(load('slot-narrow'), max_seconds=-1)
    check('slot 5 < 2r: no hole segment', res['segment_loops'] == [0, 0, 0, 0], res['segment_loops'])
    case = load('slot-narrow')
    case['holes'] = [[[15, 11], [35, 11, 1], [35, 19], [15, 19, 1]]]   # width 8 > 2r
    res = S.solve(case, max_seconds=-1)
    check('slot 8 > 2r: 2 lines, 2 arcs on its walls',
          res['segment_loops'] == [0, 0, 0, 0, 1, 1, 1, 1] and res['segment_kinds'][4:] == ['arc', 'line', 'arc', 'line'],
          (res['segment_loops'], res['segment_kinds']))
    # C41: a slot exactly 2r wide keeps its straight walls (grown onto one line
    # at distance exactly r from both), its round ends (R = r) give nothing;
    # 0.01 mm narrower gives nothing at all
    for holes, want in (([[[15, 12], [35, 12, 1], [35, 18], [15, 18, 1]]], [0] * 4 + [1] * 2),
                        ([rect(15, 12, 35, 18)], [0] * 4 + [1] * 2),
                        ([rect(15, 12, 35, 17.99)], [0] * 4)):
        case = load('slot-narrow')
        case['holes'] = holes
        res = S.solve(case, max_seconds=-1)
        check('slot %s: segment_loops %s' % (json.dumps(holes[0]), want), res['segment_loops'] == want,
              res['segment_loops'])
    # numbering: outline first, then holes in input order (hole 1's segments before hole 0's
    # would be wrong); window (4 lines) listed before the bore
    case = load('plate-bore')
    case['part'] = rect(0, 0, 80, 30)
    case['holes'] = [rect(40, 8, 60, 22), circ(15, 15, 6)]
    res = S.solve(case, max_seconds=-1)
    check('numbering over loops', res['segment_loops'] == [0] * 4 + [1] * 4 + [2] * 2 and
          res['segment_kinds'] == ['line'] * 8 + ['arc'] * 2, (res['segment_loops'], res['segment_kinds']))
    # an access constraint inside a bore (9.3: rule 3 unchanged): bore R = 8 at
    # (25, 15), grown arcs of radius 5; access square [31, 32] x [13, 17].
    # The grown circle comes within r = 3 of the square for |phi| < phi0, where
    # it meets the circle of radius 3 about the corner (31, 17) / (31, 13):
    # (5c - 6)^2 + (5s - 2)^2 = 9, i.e. 3c + s = 2.8.  Each half circle loses
    # 5 phi0 at its right end, where edge_trim now applies (no smooth joint
    # left there); its left end (joint at (17, 15)) stays untrimmed.
    case = plate_with_bore(8.0)
    case['access'] = [rect(31, 13, 32, 17)]
    res = S.solve(case, max_seconds=-1)
    c = (16.8 - math.sqrt(16.8 ** 2 - 4 * 10 * 6.84)) / 20
    phi0 = math.atan2(2.8 - 3 * c, c)
    want = 5 * (math.pi - phi0) - 1.0
    ok = res['segment_loops'] == [0, 0, 0, 0, 1, 1]
    if ok:
        verts, hole_verts, _ = S.part_loops(case)
        edges = S.loop_edges(verts, l)
        n_out = len(edges)
        edges += S.loop_edges(hole_verts[0], l)
        acc = [[(x / l, y / l) for x, y in a] for a in case['access']]
        segs, _ = S.build_segments_arcs(edges, acc, r / l, 1.0 / l, [(0, n_out), (n_out, 2)])
        lens = [(sg.s1 - sg.s0) * l for sg in segs if sg.edge >= n_out]
        ok = len(lens) == 2 and all(abs(x - want) < 1e-9 for x in lens)
    else:
        lens = None
    check('access square inside a bore: arcs shortened to %.6f' % want, ok, (res['segment_loops'], lens))
    # window: its walls grow inward by r, corners trimmed by r each side of the
    # concave corner plus edge_trim: a 20 x 14 window gives lines of 20 - 6 - 2
    # and 14 - 6 - 2 (lattice units / 10)
    segs, n_out = segments_of(load('window-plate'))
    # (each end keeps the points at distance >= r - eps from the material:
    # eps = 1e-9 lattice units = 1e-8 mm longer at both ends)
    lens = sorted((s.s1 - s.s0) * l for s in segs if s.edge >= n_out)
    want = [6.0 + 2e-8, 6.0 + 2e-8, 12.0 + 2e-8, 12.0 + 2e-8]
    check('window wall segment lengths', all(abs(x - y) < 1e-12 for x, y in zip(lens, want)), lens)


def keyhole_hole():
    """a round hole R 6 at (15, 15) with a slot 4 wide to x = 35, listed CCW"""
    x = 15 + math.sqrt(36 - 4)
    sweep = 2 * math.pi - 2 * math.atan2(2, x - 15)
    return [[x, 13], [35, 13], [35, 17], [x, 17, math.tan(sweep / 4)]]


def sampled_segments_check(name, case, step_mm=0.01):
    """segments against dense sampling of every grown edge, the distance to
    the material computed here: each run of points at distance >= r - eps
    longer than 2 edge_trim is one segment, its ends edge_trim inside the
    run's ends (0 at a smooth joint), and no segment elsewhere"""
    l = case['kit']['spacing']
    r = case['kit']['locator_radius'] / l
    trim = case['params']['edge_trim'] / l
    h = step_mm / l
    verts, hole_verts, _ = S.part_loops(case)
    edges = S.loop_edges(verts, l)
    loops = [(0, len(edges))]
    for hv in hole_verts:
        he = S.loop_edges(hv, l)
        loops.append((len(edges), len(he)))
        edges += he
    segs, smooth = S.build_segments_arcs(edges, [], r, trim, loops)
    nxt = {}
    for st, cnt in loops:
        for k in range(cnt):
            nxt[st + k] = st + (k + 1) % cnt
    mat = Material(case)
    bad = []
    n_runs = 0
    for i, e in enumerate(edges):
        f = S.grow_feature(e, i, r)
        mine = [sg for sg in segs if sg.edge == i]
        if f is None:
            if mine:
                bad.append(('segments on a vanished feature', i))
            continue
        L = f.length
        m = max(2, int(L / h))
        ok = []
        for k in range(m + 1):
            p = f.point(L * k / m)
            ok.append(mat.dist((p[0] * l, p[1] * l)) / l >= r - 1e-9)
        runs = []
        k = 0
        while k <= m:
            if ok[k]:
                j = k
                while j + 1 <= m and ok[j + 1]:
                    j += 1
                runs.append((L * k / m, L * j / m))
                k = j + 1
            else:
                k += 1
        tol = 1.01 * L / m
        used = set()
        for lo, hi in runs:
            a = lo if (lo == 0.0 and smooth[i]) else lo + trim
            b = hi if (hi == L and smooth[nxt[i]]) else hi - trim
            inside = [sg for sg in mine if lo - tol <= (sg.s0 + sg.s1) / 2 <= hi + tol]
            if b - a > 2 * tol:
                n_runs += 1
                if len(inside) != 1 or abs(inside[0].s0 - a) > tol or abs(inside[0].s1 - b) > tol:
                    bad.append((i, (lo, hi), [(sg.s0, sg.s1) for sg in inside]))
                used.update(id(sg) for sg in inside)
            elif b - a < -2 * tol and inside:
                bad.append(('segment in a short run', i, (lo, hi)))
            else:
                used.update(id(sg) for sg in inside)     # borderline length: either way
        if any(id(sg) not in used for sg in mine):
            bad.append(('segment outside every run', i))
    check('%s: %d segments match dense sampling (%d runs)' % (name, len(segs), n_runs), not bad, bad[:3])


def test_segments_sampled():
    l_window = [[10, 5], [40, 5], [40, 15], [20, 15], [20, 25], [10, 25]]
    for name, holes in (('L-shaped window', [l_window]),
                        ('keyhole hole', [keyhole_hole()]),
                        ('slot hole', load('slot-hole-cw')['holes']),
                        ('bore + window + narrow slot', [circ(9, 9, 5), rect(20, 4, 44, 14),
                                                         [[15, 20], [40, 20, 1], [40, 25], [15, 25, 1]]])):
        case = load('plate-bore')
        case['holes'] = holes
        sampled_segments_check(name, case)
    sampled_segments_check('flange', load('flange-bolts'))


# ------------------------------------------------- 9.1 validation
def test_validation():
    want = {
        'invalid-hole-crosses-outline': 'part: hole 1 crosses the outline at (50, 10)',
        'invalid-hole-in-hole': 'part: hole 1 lies inside hole 0',
        'invalid-hole-touches-outline': 'part: hole 0 touches the outline at (50, 15)',
        'invalid-holes-touch': 'part: hole 1 touches hole 0 at (20, 15)',
    }
    for name, msg in want.items():
        try:
            S.solve(load(name))
            got = None
        except S.Invalid as ex:
            got = str(ex)
        check('invalid %s' % name, got == msg, got)
    base = load('plate-bore')
    more = [
        ([circ(70, 15, 5)], 'part: hole 0 lies outside the outline'),
        ([circ(15, 15, 6), circ(35, 15, 6), circ(24, 15, 4)], 'part: hole 2 crosses hole 0 at'),
        ([circ(15, 15, 6), rect(10, 10, 20, 20)], 'part: hole 1 crosses hole 0 at'),
        ([rect(10, 10, 20, 20), circ(15, 15, 5)], 'part: hole 1 touches hole 0 at'),
        ([circ(15, 15, 4), rect(10, 10, 20, 20)], 'part: hole 0 lies inside hole 1'),
        ([[[10, 10], [20, 20], [20, 10], [10, 20]]], 'part: hole 0: edge 0 crosses edge 2 at (15, 15)'),
        ([[[10, 10], [20, 10], [30, 10]]], 'part: hole 0'),
        ([[[10, 10], [20, 10]]], 'part: hole 0: fewer than 3 vertices'),
        ([[[10, 10], [20, 10], [float('inf'), 3]]], 'part: hole 0: vertex 2 is not a finite point'),
        ([circ(15, 15, 6), [[0, 5], [10, 5], [10, 10]]], 'part: hole 1 touches the outline at (0, 5)'),
        ([[[40, 10], [50, 15], [40, 20]]], 'part: hole 0 touches the outline at (50, 15)'),
        ([[[40, 10], [50 + 1e-12, 15], [40, 20]]], 'part: hole 0 '),  # within tolerance: shares a point
    ]
    for holes, prefix in more:
        case = copy.deepcopy(base)
        case['holes'] = holes
        try:
            S.solve(case, max_seconds=-1)
            got = None
        except S.Invalid as ex:
            got = str(ex)
        check('invalid %s' % prefix, got is not None and got.startswith(prefix), (json.dumps(holes), got))
    # valid: tiny play, a hole close to (but not at) the outline, a hole inside the outline near a hole
    for holes in ([circ(15, 15, 3.0001)], [[[40, 10], [49.999, 15], [40, 20]]],
                  [circ(15, 15, 6), circ(27.01, 15, 6)]):
        case = copy.deepcopy(base)
        case['holes'] = holes
        try:
            res = S.solve(case, max_seconds=-1)
            got = res['status']
        except S.Invalid as ex:
            got = str(ex)
        check('valid %s' % json.dumps(holes), got == 'timeout', got)
    # a part's result with an invalid hole through main(): status invalid, exit 1
    with tempfile.NamedTemporaryFile('w', suffix='.json', delete=False) as fh:
        json.dump(load('invalid-hole-in-hole'), fh)
    p = subprocess.run([sys.executable, os.path.join(HERE, 'spec_reference.py'), fh.name],
                       capture_output=True, text=True)
    os.unlink(fh.name)
    out = json.loads(p.stdout)
    check('main: invalid status and exit code', p.returncode == 1 and out == {
        'status': 'invalid', 'error': 'part: hole 1 lies inside hole 0'}, (p.returncode, p.stdout))


# ------------------------------------------------- 9.2 orientation
def reverse_with_bulges(loop):
    n = len(loop)
    b = [p[2] if len(p) > 2 else 0 for p in loop]
    out = [[loop[0][0], loop[0][1], -b[n - 1]]]
    for k in range(1, n):
        out.append([loop[n - k][0], loop[n - k][1], -b[n - k - 1]])
    return out


def test_orientation():
    r1 = strip(solve(load('slot-hole-ccw'), 'slot-ccw'))
    r2 = strip(solve(load('slot-hole-cw'), 'slot-cw'))
    check('slot hole ccw vs cw: identical result', r1 == r2 and r1['status'] == 'ok',
          (r1['counts'], r2['counts']))
    case = load('plate-bore')
    a = strip(solve(case, 'plate-bore'))
    case2 = copy.deepcopy(case)
    case2['holes'] = [reverse_with_bulges(h) for h in case['holes']]
    b = strip(solve(case2))
    check('round bore listed cw (bulges -1): identical result', a == b, (a['counts'], b['counts']))
    case3 = copy.deepcopy(case)
    case3['holes'][0] = case3['holes'][0][1:] + case3['holes'][0][:1]    # other start vertex
    c = strip(solve(case3))
    check('round bore from its other vertex: same counts', c['counts'] == a['counts'], (c['counts'], a['counts']))
    # outline listed clockwise too
    case4 = copy.deepcopy(case)
    case4['part'] = reverse_with_bulges(case['part'])
    d = solve(case4)
    check('outline cw, bore ccw: same counts and fixture ids', d['counts'] == a['counts'] and ids(d) == ids(a),
          (d['counts'], a['counts']))


# ------------------------------------------------- translation
def translate(case, dx, dy):
    case = copy.deepcopy(case)

    def mv(loop):
        return [[p[0] + dx, p[1] + dy] + list(p[2:]) for p in loop]
    case['part'] = mv(case['part'])
    case['holes'] = [mv(h) for h in case.get('holes') or []]
    case['access'] = [mv(a) for a in case.get('access') or []]
    return case


def test_translation():
    # exact for these two (no decision lands on a boundary)
    for name, (dx, dy) in (('plate-bore', (123.4, -56.7)), ('flange-bolts', (40.0, 33.3))):
        a = solve(load(name), name)
        b = solve(translate(load(name), dx, dy))
        check('translation %s: same counts' % name, a['counts'] == b['counts'], (a['counts'], b['counts']))
        check('translation %s: same fixture ids' % name, ids(a) == ids(b))
        sa = sorted(f['score'] for f in a['fixtures'])
        sb = sorted(f['score'] for f in b['fixtures'])
        check('translation %s: same scores' % name, len(sa) == len(sb) and
              all(abs(x - y) <= 1e-9 * max(1, x) for x, y in zip(sa, sb)))
    # a rectilinear part has contacts exactly at segment ends (s = s0 + eps):
    # rounding after a translation decides those borderline fixtures
    # (SPEC 1) differently, so only the fixtures that are not borderline must agree
    name = 'window-plate'
    a = solve(load(name), name)
    b = solve(translate(load(name), -31.25, 7.5))
    na = sorted(id_of(f) for f in a['fixtures'] if not f['borderline'])
    nb = sorted(id_of(f) for f in b['fixtures'] if not f['borderline'])
    check('translation %s: same non-borderline fixture ids (%d)' % (name, len(na)), na == nb and len(na) > 0)
    bl = [f for f in a['fixtures'] + b['fixtures'] if f['borderline']]
    check('translation %s: the others are borderline by less than 1e-12' % name,
          all(f['min_margin'] < 1e-12 for f in bl if id_of(f) not in set(ids(a)) & set(ids(b))))


# ------------------------------------------------- contacts and clearance
def part_frame(f, P):
    th = math.radians(f['pose']['theta_deg'])
    x, y = P[0] - f['pose']['x'], P[1] - f['pose']['y']
    return (math.cos(th) * x + math.sin(th) * y, -math.sin(th) * x + math.cos(th) * y)


D = [(1, 0), (0, 1), (-1, 0), (0, -1)]
E = [(0, 1), (-1, 0), (0, -1), (1, 0)]


def clamp_polys(case, f):
    """clamp body and plunger (plate frame, catalogue units) of a fixture"""
    l = case['kit']['spacing']
    k = f['clamp']['rotation_deg'] // 90
    d, e = D[k], E[k]
    m = f['clamp']['mount']
    t = f['clamp']['extension']

    def place(poly, ext):
        return [(m[0] * l + (x + ext) * d[0] + y * e[0], m[1] * l + (x + ext) * d[1] + y * e[1]) for x, y in poly]
    return place(case['kit']['clamp']['body'], 0.0), place(case['kit']['clamp']['plunger'], t)


def test_contacts(names):
    for name in names:
        case = load(name)
        res = solve(case, name)
        l = case['kit']['spacing']
        r = case['kit']['locator_radius']
        mat = Material(case)
        worst = 0.0
        n = 0
        on_hole = 0
        for f in res['fixtures']:
            pts = [(L[0] * l, L[1] * l) for L in f['locators']] + [tuple(f['clamp']['contact'])]
            segs = f['segments'] + [f['clamp']['segment']]
            for P, sg in zip(pts, segs):
                q = part_frame(f, P)
                d = mat.dist(q)
                worst = max(worst, abs(d - r))
                n += 1
                on_hole += res['segment_loops'][sg] > 0
        check('%s: %d contacts at distance r from the material (worst %.2e)' % (name, n, worst),
              n > 0 and worst <= 1e-9 * l, worst)
        if any(x > 0 for x in res['segment_loops']):
            check('%s: some contacts on hole walls (%d)' % (name, on_hole), on_hole > 0)


def test_clearance():
    # direct: the margin of a polygon against the material of the window plate
    case = load('window-plate')
    verts, hole_verts, _ = S.part_loops(case)
    edges = S.loop_edges(verts)
    for hv in hole_verts:
        edges += S.loop_edges(hv)
    bb = S.region_bbox(edges)
    mc = 1.0

    def margin(poly, mc=mc):
        return S.poly_region_margin(poly, S.bbox(poly), edges, bb, mc)
    inside = rect(17, 15, 33, 25)             # 2 mm from the window walls
    check('polygon inside the window: clear', margin(inside) >= 0, margin(inside))
    tight = rect(15.5, 15, 33, 25)             # 0.5 mm from a wall
    check('polygon 0.5 from the window wall: not clear', margin(tight) < 0, margin(tight))
    check('polygon 0.5 from the wall, min_clearance 0: clear', margin(tight, 0.0) >= 0)
    over = rect(10, 15, 33, 25)               # over the hole and the material
    check('polygon over hole and material: not clear', margin(over) < 0, margin(over))
    check('polygon over hole and material, min_clearance 0: overlaps', margin(over, 0.0) < 0)
    cover = rect(12, 10, 38, 30)               # covers the whole window
    check('polygon covering the window: not clear', margin(cover) < 0 and margin(cover, 0.0) < 0)
    outside = rect(-20, -20, -5, -5)
    check('polygon outside the part: clear', margin(outside) >= 0)
    around = rect(-10, -10, 60, 50)
    check('polygon around the whole part: not clear', margin(around) < 0 and margin(around, 0.0) < 0)

    if QUICK:
        print('skip  frame-window-clamp (--quick)')
        return
    # in a solved case: the frame's clamp body fits in its window in some fixtures,
    # and every body / plunger is >= min_clearance from the material
    name = 'frame-window-clamp'
    case = load(name)
    res = solve(case, name)
    mat = Material(case)
    win = case['holes'][0]
    n_in = 0
    worst = math.inf
    for f in res['fixtures']:
        body, plunger = clamp_polys(case, f)
        bq = [part_frame(f, P) for P in body]
        pq = [part_frame(f, P) for P in plunger]
        if all(win[0][0] < x < win[2][0] and win[0][1] < y < win[2][1] for x, y in bq):
            n_in += 1
        for poly in (bq, pq):
            # polygon-vs-material clearance, from here: boundary sampling of the polygon
            for i in range(len(poly)):
                a, b = poly[i], poly[(i + 1) % len(poly)]
                for k in range(11):
                    p = (a[0] + (b[0] - a[0]) * k / 10, a[1] + (b[1] - a[1]) * k / 10)
                    worst = min(worst, mat.dist(p))
    check('%s: %d fixtures with the clamp body inside the window' % (name, n_in), n_in > 0)
    check('%s: body and plunger >= min_clearance from the material (sampled, min %.6f)' % (name, worst),
          worst >= case['params']['min_clearance'] - 1e-9, worst)


# ------------------------------------------------- no holes: unchanged
def run_ref(script, path, extra=()):
    p = subprocess.run([sys.executable, script, path] + list(extra), capture_output=True, text=True)
    return p.returncode, [ln for ln in p.stdout.splitlines() if not ln.startswith(' "seconds"')]


# cases whose result C47 (tangency within rounding) changed on purpose: the
# number of tangential setups that went (a contact exactly at a smooth joint)
C47_FEWER = {'arc-d-shape.json': 1, 'arc-fillet-rect.json': 5, 'arc-stadium.json': 5}


def run_json(script, path):
    p = subprocess.run([sys.executable, script, path], capture_output=True, text=True)
    res = json.loads(p.stdout) if p.returncode == 0 else {}
    res.pop('seconds', None)
    return res


def c47_subset(old, cur, path, n):
    """the result is the old one without exactly the fixtures of the setups C47
    removed: counts down by those, every other field and fixture unchanged, and
    every removed fixture borderline"""
    ra, rb = run_json(old, path), run_json(cur, path)
    if not ra or not rb:
        check('no holes, C47 change only: %s (both run)' % n, False)
        return

    def body(f):
        return json.dumps({k: v for k, v in f.items() if k != 'rank'}, sort_keys=True)
    fa = [body(f) for f in ra['fixtures']]
    fb = [body(f) for f in rb['fixtures']]
    gone = [f for f in ra['fixtures'] if body(f) not in set(fb)]
    ca, cb = dict(ra['counts']), dict(rb['counts'])
    want = dict(ca, setups=ca['setups'] - C47_FEWER[n], candidates=ca['candidates'] - len(gone),
                admissible=ca['admissible'] - len(gone))
    da, db = ra.get('arc_diagnostics', {}), rb.get('arc_diagnostics', {})
    rest_a = {k: v for k, v in ra.items() if k not in ('counts', 'fixtures', 'arc_diagnostics')}
    rest_b = {k: v for k, v in rb.items() if k not in ('counts', 'fixtures', 'arc_diagnostics')}
    ok = (cb == want and [f for f in fa if f in set(fb)] == fb and len(fb) == len(fa) - len(gone)
          and all(f['borderline'] for f in gone) and rest_a == rest_b
          and db.get('tangential') == da.get('tangential', 0) - C47_FEWER[n])
    check('no holes, output changed by C47 only: %s (%d setups, %d borderline fixtures fewer)'
          % (n, C47_FEWER[n], len(gone)), ok, (ca, cb, len(gone)))


def test_no_holes_unchanged():
    cur = os.path.join(HERE, 'spec_reference.py')
    names = sorted(n for n in os.listdir(OLD_CASES) if n.endswith('.json'))
    # "holes": [] is the same as no holes (always checked, cheap case)
    path = os.path.join(OLD_CASES, 'arc-keyhole.json')
    with open(path) as fh:
        case = json.load(fh)
    case['holes'] = []
    a = strip(S.solve(copy.deepcopy(case)))
    case.pop('holes')
    b = strip(S.solve(case))
    check('"holes": [] == no holes', a == b and 'segment_loops' not in a)
    if QUICK:
        print('skip  no-holes regression against %s (--quick)' % PRE_HOLES_COMMIT)
        return
    try:
        old_src = subprocess.run(['git', '-C', HERE, 'show', PRE_HOLES_COMMIT + ':scripts/spec_reference.py'],
                                 capture_output=True, text=True, check=True).stdout
    except (subprocess.CalledProcessError, OSError) as ex:
        check('pre-section-9 reference available (git show %s)' % PRE_HOLES_COMMIT, False, ex)
        return
    with tempfile.TemporaryDirectory() as td:
        old = os.path.join(td, 'spec_reference_old.py')
        with open(old, 'w') as fh:
            fh.write(old_src)
        for n in names:
            path = os.path.join(OLD_CASES, n)
            if n in C47_FEWER:
                c47_subset(old, cur, path, n)
                continue
            ra = run_ref(old, path)
            rb = run_ref(cur, path)
            check('no holes, unchanged output: %s' % n, ra == rb and ra[0] == 0)
        # the generic (arc) code path as well, on one arc-free case
        n = 'l-shape.json'
        ra = run_ref(old, os.path.join(OLD_CASES, n), ['--generic'])
        rb = run_ref(cur, os.path.join(OLD_CASES, n), ['--generic'])
        check('no holes, unchanged output: %s --generic' % n, ra == rb)


# ------------------------------------------------- expected results of the cases
def test_case_results():
    # counts found by this reference when the cases were made: a regression
    # guard (not an independent truth)
    want = {
        'washer-round': ('no_fixture', [4, 16, 0, 0, 0]),
        'washer-square': ('ok', [6, 50, 1352, 1964, 1484]),
        'plate-bore': ('ok', [6, 50, 1292, 1220, 960]),
        'window-plate': ('ok', [8, 112, 2178, 2285, 1929]),
        'slot-narrow': ('ok', [4, 16, 960, 692, 692]),
        # C47: one tangential setup fewer each (its contacts lie exactly at
        # smooth joints, in neither segment); were 319/341/293 and 1425
        'bore-near-edge': ('ok', [6, 50, 318, 336, 288]),
        'slot-hole-ccw': ('ok', [8, 112, 1424, 1512, 1232]),
        'slot-hole-cw': ('ok', [8, 112, 1424, 1512, 1232]),
        'flange-bolts': ('ok', [8, 112, 416, 157, 32]),
    }
    if not QUICK:
        want['frame-window-clamp'] = ('ok', [8, 112, 4440, 6073, 4524])
    keys = ['segments', 'combinations', 'setups', 'candidates', 'admissible']
    for name, (st, cnt) in want.items():
        res = solve(load(name), name)
        got = (res['status'], [res['counts'][k] for k in keys])
        check('case %s: %s %s' % (name, st, cnt), got == (st, cnt), got)
    # slot narrower than 2r: the same fixtures (ids) as the plate without the slot
    case = load('slot-narrow')
    a = solve(case, 'slot-narrow')
    case['holes'] = []
    b = S.solve(case)
    check('slot narrower than 2r: same fixture ids as the plate without it', ids(a) == ids(b) and
          a['counts'] == b['counts'])
    # ... but not the same scores (the material changed)
    sa = {id_of(f): f['score'] for f in a['fixtures']}
    sb = {id_of(f): f['score'] for f in b['fixtures']}
    check('slot narrower than 2r: the scores see the slot', any(abs(sa[i] - sb[i]) > 1e-9 for i in sa))


# ------------------------------------------------- C47: tangency within rounding
def test_c47():
    T = S.ULP_T
    check('C47: rounding-size tangency is one double root',
          S.line_circle_taus(3.0, 1.8 + 2.5e-16, 1.8, 7.0) == [3.0] and
          S.line_circle_taus(3.0, -(1.8 - 2.5e-16), 1.8, 7.0) == [3.0])
    two = S.line_circle_taus(3.0, 1.8 - 1e-12, 1.8, 7.0)
    check('C47: a gap above 64 ulps x scale keeps its two roots', len(two) == 2 and
          1e-12 > T * 7.0 and abs(two[1] - two[0] - 2 * math.sqrt(1.8 ** 2 - (1.8 - 1e-12) ** 2)) < 1e-15, two)
    check('C47: a near miss (<= 1e-9) is one point, a miss none',
          S.line_circle_taus(0.0, 1.8 + 5e-10, 1.8, 7.0) == [0.0] and
          S.line_circle_taus(0.0, 1.8 + 2e-9, 1.8, 7.0) == [])
    # the D-shape: two locators on the bottom line and the third on the arc
    # where the bottom line runs into it (collinear (0,0), (1,1), (2,2)): the
    # exact double root puts the third contact at the joint, s = 0
    with open(os.path.join(OLD_CASES, 'arc-d-shape.json')) as fh:
        case = json.load(fh)
    segs, _ = segments_of(case)
    combo = S.ArcCombo([segs[1], segs[1], segs[2]])
    Ls = ((0, 0), (1, 1), (2, 2))
    poses = combo.solve(Ls)
    worst = 0.0
    for th, w, tang, jd in poses:
        ct, st = math.cos(th), math.sin(th)
        p = (ct * 2 + st * 2 - w[0], -st * 2 + ct * 2 - w[1])
        s3 = segs[2].feat.param(p)
        worst = max(worst, min(abs(s3 - segs[2].s0), abs(segs[2].s1 - s3)))
        worst = max(worst, 0.0 if tang else 1.0)
    check('C47: D-shape (1,1,2) collinear: %d tangential poses, contact at the joint (%.1e)'
          % (len(poses), worst), len(poses) == 2 and worst <= 1e-12, worst)
    # the slot: top outline + slot bottom wall parallel, third on the slot's end
    # arc: both hole contacts exactly at the wall/arc joints
    case = load('slot-hole-cw')
    segs, _ = segments_of(case)
    combo = S.ArcCombo([segs[2], segs[4], segs[7]])
    Ls = ((0, 0), (2, 2), (1, 2))
    poses = combo.solve(Ls)
    worst = 0.0
    for th, w, tang, jd in poses:
        ct, st = math.cos(th), math.sin(th)
        for k in (1, 2):
            Lx, Ly = Ls[k]
            sg = (segs[4], segs[7])[k - 1]
            p = (ct * Lx + st * Ly - w[0], -st * Lx + ct * Ly - w[1])
            sv = sg.feat.param(p)
            worst = max(worst, min(abs(sv - sg.s0), abs(sg.s1 - sv)))
    check('C47: slot (2,4,7): %d poses, hole contacts at the joints (%.1e)' % (len(poses), worst),
          len(poses) >= 1 and worst <= 1e-12, worst)
    res = solve(case, 'slot-hole-cw')
    keys = ['segments', 'combinations', 'setups', 'candidates', 'admissible']
    check('C47: arc-d-shape counts 4/16/246/456/456',
          [S.solve(json.load(open(os.path.join(OLD_CASES, 'arc-d-shape.json'))))['counts'][k]
           for k in keys] == [4, 16, 246, 456, 456])
    check('C47: slot-hole-cw 1424 setups', res['counts']['setups'] == 1424, res['counts'])


def main():
    t0 = time.time()
    test_metric()
    test_segments()
    test_segments_sampled()
    test_validation()
    test_orientation()
    test_translation()
    names = ['plate-bore', 'window-plate', 'washer-square', 'bore-near-edge', 'slot-hole-ccw', 'flange-bolts']
    if not QUICK:
        names.append('frame-window-clamp')
    test_contacts(names)
    test_clearance()
    test_case_results()
    test_c47()
    test_no_holes_unchanged()
    print('(%.1f s)' % (time.time() - t0))
    print('%d passed, %d failed' % (passed, failed))
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
