#!/usr/bin/env python3
"""Independent reference implementation of SPEC.md (fixplan), standard library only.

Written from /work/shared/SPEC.md alone (no look at the Rust code), to be
compared with the production implementation.

usage: python3 scripts/spec_reference.py CASE.json [--max-seconds N]

Prints {"status", "counts": {segments, combinations, setups, candidates,
admissible}, "fixtures": [...]} with ALL admissible fixtures (top_k ignored),
sorted by the spec's ranking.

INTERPRETATION CHOICES (where SPEC is silent or ambiguous)
----------------------------------------------------------
 C1  Units: every length (part, access, r, spacing-relative clamp geometry,
     axis offset, travel, edge_trim, min_clearance) is divided by the spacing
     l; eps = 1e-9 applies in lattice units everywhere (also for det W, the
     lambdas, cosines, contact-parameter margins, t limits, clearances).
 C2  Step 2 (true boundary): a point of grown edge i is removed when its
     distance to some *other* part edge j is < r - eps (its own edge is at
     exactly r). Grown-edge points inside the part are always within r of
     some edge, so "distance to the filled polygon" reduces to this.  The set
     {s : dist(p(s), edge j) < R} is one open interval (convex function),
     computed exactly (endpoint disks + slab).
 C3  Step 3 (access): removed where distance to the filled access polygon is
     < r exactly (no eps, as written: "less than r"), i.e. within r of an
     access edge or inside the access polygon.
 C4  Step 4: kept pieces are closed intervals [x, y]; after trimming,
     [x + trim, y - trim] is kept iff its length > eps.  Pieces touching at a
     single point are treated as nothing.
 C5  "Strictly inside a segment": s0 + eps < s < s1 - eps, where [s0, s1]
     is the trimmed segment.  Used for locators and for the clamp contact.
 C6  Pose equation A cos + B sin = C (coefficients from the left null vector
     lambda = col1 x col2 of the 3x2 normal matrix): rho = hypot(A, B);
     all |lambda_k| <= eps -> "all normals parallel", combination discarded.
     rho <= eps -> no pose (a continuum would be needed; not a finite pose).
     rho - |C| < -eps -> 0 poses; |rho - |C|| <= eps -> one (double) pose
     theta = atan2(B, A) (+pi if C < 0); otherwise 2 poses.  w is then the
     least-squares solution of the three (consistent) line equations.
 C7  Canonical form: L1 = origin on segment a; L2 on b; L3 on c; if a == b
     then s(L1) < s(L2); if b == c then s(L2) < s(L3).  L2 in Q, L3 any other
     lattice point.  Grid step / parity apply to L2 and L3 in the canonical
     frame (both invariant under the 90-degree rotations and the even
     translation to the origin).  Enumeration is brute force over lattice
     points restricted by exact distance annuli (|L_i - L_j| must lie in
     [dist(seg_i, seg_j), maxdist(seg_i, seg_j)], slack 1e-7), which is a
     necessary condition, so the set found is unchanged.
 C8  Form-closure interval on segment sigma: {s : lambda_i(s) > eps for all
     i} intersected with (s0 + eps, s1 - eps); a clamp contact on an axis line
     must lie strictly inside that open interval (no extra eps on top).  Any
     segment may take the clamp, including a, b, c.
 C9  Angle test: d.f > eps AND d.f >= cos(max_clamp_angle) - eps.
 C10 Travel: t_min - eps <= t <= t_max + eps; mounts tried by increasing t.
 C11 Tip/locator overlap: overlap iff |q - L| < 2r - eps (touching allowed).
 C12 Clearance: for min_clearance > eps, a polygon (body or plunger) fails
     against a filled polygon (posed part / posed access) if the boundary
     distance < min_clearance - eps or one contains a vertex of the other;
     against a locator disk if the disk centre is inside the polygon or
     dist(centre, polygon boundary) < r + min_clearance - eps.  For
     min_clearance <= eps only a true overlap fails (proper edge crossing or
     a vertex / edge midpoint strictly inside the other polygon; for disks,
     centre distance < r - eps).
 C13 Mount-hole kind on an alternating plate: dowel <=> (i + j) even in the
     canonical frame (L1 at origin is a dowel hole).  Mount holes must differ
     from L1, L2, L3; nothing is said about holes under the part, so no test.
 C14 Plate fit: rotation 0 or 90 deg of the canonical points (locators and
     mount holes), then an integer translation with even i+j on an
     alternating plate (any on square) such that all lie in
     [0, cols-1] x [0, rows-1].  Fixed-order: the first mount that passes
     ALL tests (including plate fit) is the mount.
 C15 Quality metric computed in lattice units in the part frame (the default
     metric is scale-free); the contact point used is the locator/tip centre
     on the grown edge (moving along f does not change the torque).  For the
     user wrench list the contact points are in catalogue units (part frame,
     torque about the part origin).  lambda0 is the particular solution with
     the clamp coefficient 0; mu = (lambda_clamp-direction, 1).
 C16 Ranking: sort by (score, a, b, c, L2, L3, theta_rad, clamp segment,
     rotation index k, m) with raw floats (no tolerance on score ties).
 C17 Defaults when params are missing: edge_trim 1 mm / 0.04 in,
     min_clearance 1 mm / 0.04 in, max angle 45, grid_step 1.
 C18 Borderline flag: set when any decision margin met along the way for that
     fixture (contact s margins, double-root margin, |det W|, lambda margins,
     angle cosines, travel limits, tip distance, clearances, and the failing
     margin of every earlier mount that was rejected) is below 1e-6 (lattice
     units).  Best effort: excluded near-boundary candidates are not listed.
 C20 Extra output fields beyond the brief: pose, clamp.contact, contacts_s
     (contact parameters in units), plate placement, min_margin, seconds.
     Status "timeout" if --max-seconds ran out (counts are then partial).
 C21 Validation: non-adjacent edges may not touch; adjacent collinear edges
     may not fold back; the crossing test runs before the zero-area test.
 C19 theta reported in degrees in [0, 360); pose (x, y) and extension and
     contact in catalogue units in the canonical frame.
"""
import sys
import json
import math
import time
import bisect

EPS = 1e-9
BORDER = 1e-6


class Invalid(Exception):
    pass


# ---------------------------------------------------------------- geometry
def sub(a, b):
    return (a[0] - b[0], a[1] - b[1])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1]


def crs(a, b):
    return a[0] * b[1] - a[1] * b[0]


def signed_area(poly):
    s = 0.0
    n = len(poly)
    for i in range(n):
        x1, y1 = poly[i]
        x2, y2 = poly[(i + 1) % n]
        s += x1 * y2 - x2 * y1
    return 0.5 * s


def pt_seg_dist2(p, a, b):
    abx, aby = b[0] - a[0], b[1] - a[1]
    apx, apy = p[0] - a[0], p[1] - a[1]
    L2 = abx * abx + aby * aby
    if L2 <= 0.0:
        return apx * apx + apy * apy
    t = (apx * abx + apy * aby) / L2
    if t < 0.0:
        t = 0.0
    elif t > 1.0:
        t = 1.0
    dx = apx - t * abx
    dy = apy - t * aby
    return dx * dx + dy * dy


def orient(a, b, c):
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def segs_intersect(a, b, c, d):
    """closed segments intersect (incl. touching)"""
    d1 = orient(c, d, a)
    d2 = orient(c, d, b)
    d3 = orient(a, b, c)
    d4 = orient(a, b, d)
    if ((d1 > 0 and d2 < 0) or (d1 < 0 and d2 > 0)) and \
       ((d3 > 0 and d4 < 0) or (d3 < 0 and d4 > 0)):
        return True

    def on(p, q, r):
        return min(p[0], q[0]) <= r[0] <= max(p[0], q[0]) and \
            min(p[1], q[1]) <= r[1] <= max(p[1], q[1])
    if d1 == 0 and on(c, d, a):
        return True
    if d2 == 0 and on(c, d, b):
        return True
    if d3 == 0 and on(a, b, c):
        return True
    if d4 == 0 and on(a, b, d):
        return True
    return False


def seg_seg_dist(a, b, c, d):
    if segs_intersect(a, b, c, d):
        return 0.0
    return math.sqrt(min(pt_seg_dist2(a, c, d), pt_seg_dist2(b, c, d),
                         pt_seg_dist2(c, a, b), pt_seg_dist2(d, a, b)))


def point_in_poly(p, poly):
    """ray casting; boundary points arbitrary"""
    x, y = p
    inside = False
    n = len(poly)
    j = n - 1
    for i in range(n):
        xi, yi = poly[i]
        xj, yj = poly[j]
        if (yi > y) != (yj > y):
            xc = xi + (y - yi) * (xj - xi) / (yj - yi)
            if x < xc:
                inside = not inside
        j = i
    return inside


def pt_poly_bdist(p, poly):
    n = len(poly)
    return math.sqrt(min(pt_seg_dist2(p, poly[i], poly[(i + 1) % n]) for i in range(n)))


def bbox(poly):
    xs = [p[0] for p in poly]
    ys = [p[1] for p in poly]
    return (min(xs), min(ys), max(xs), max(ys))


def bbox_gap(b1, b2):
    dx = max(0.0, b1[0] - b2[2], b2[0] - b1[2])
    dy = max(0.0, b1[1] - b2[3], b2[1] - b1[3])
    return math.hypot(dx, dy)


def strictly_inside(p, poly):
    return point_in_poly(p, poly) and pt_poly_bdist(p, poly) > EPS


def polys_overlap(A, B):
    """interiors intersect (best effort, for min_clearance == 0)"""
    na, nb = len(A), len(B)
    for i in range(na):
        a0, a1 = A[i], A[(i + 1) % na]
        for j in range(nb):
            b0, b1 = B[j], B[(j + 1) % nb]
            d1 = orient(b0, b1, a0)
            d2 = orient(b0, b1, a1)
            d3 = orient(a0, a1, b0)
            d4 = orient(a0, a1, b1)
            if ((d1 > EPS and d2 < -EPS) or (d1 < -EPS and d2 > EPS)) and \
               ((d3 > EPS and d4 < -EPS) or (d3 < -EPS and d4 > EPS)):
                return True
    for P, Q in ((A, B), (B, A)):
        n = len(P)
        for i in range(n):
            if strictly_inside(P[i], Q):
                return True
            m = ((P[i][0] + P[(i + 1) % n][0]) / 2, (P[i][1] + P[(i + 1) % n][1]) / 2)
            if strictly_inside(m, Q):
                return True
    return False


def poly_poly_margin(A, Abb, B, Bbb, mc):
    """returns margin (>= 0 ok, < 0 fail) of polygon A against filled polygon B"""
    gap = bbox_gap(Abb, Bbb)
    if gap >= mc + 1e-3:
        return gap - mc  # lower bound, enough
    if mc <= EPS:
        if polys_overlap(A, B):
            return -1.0
        # touching allowed; margin = boundary distance (0 when touching)
        d = min_bdist(A, B)
        return d if d > 0 else 0.0
    d = min_bdist(A, B)
    m = d - mc
    if m < -EPS:
        return m
    # boundaries far enough apart: check containment
    if point_in_poly(A[0], B) or point_in_poly(B[0], A):
        return -1.0
    return m


def min_bdist(A, B):
    na, nb = len(A), len(B)
    best = float('inf')
    for i in range(na):
        a0, a1 = A[i], A[(i + 1) % na]
        for j in range(nb):
            d = seg_seg_dist(a0, a1, B[j], B[(j + 1) % nb])
            if d < best:
                best = d
    return best


def poly_disk_margin(A, Abb, c, r, mc):
    gx = max(0.0, Abb[0] - c[0], c[0] - Abb[2])
    gy = max(0.0, Abb[1] - c[1], c[1] - Abb[3])
    gap = math.hypot(gx, gy) - r
    if gap >= mc + 1e-3:
        return gap - mc
    if point_in_poly(c, A):
        return -1.0
    d = pt_poly_bdist(c, A) - r
    return d - mc


# ---------------------------------------------------------------- validation
def validate_polygon(poly, name):
    n = len(poly)
    if n < 3:
        raise Invalid("%s: fewer than 3 vertices" % name)
    for i, p in enumerate(poly):
        if len(p) != 2 or not all(isinstance(v, (int, float)) and math.isfinite(v) for v in p):
            raise Invalid("%s: vertex %d is not a finite point" % (name, i))
    seen = {}
    for i, p in enumerate(poly):
        k = (float(p[0]), float(p[1]))
        if k in seen:
            raise Invalid("%s: vertex %d repeats vertex %d at (%g, %g)" % (name, i, seen[k], k[0], k[1]))
        seen[k] = i
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        for j in range(i + 1, n):
            c, d = poly[j], poly[(j + 1) % n]
            if j == i + 1 or (i == 0 and j == n - 1):
                # adjacent: must not fold back (collinear overlap)
                shared = b if j == i + 1 else a
                other1 = a if j == i + 1 else b
                other2 = d if j == i + 1 else c
                if orient(other1, shared, other2) == 0:
                    v1 = sub(other1, shared)
                    v2 = sub(other2, shared)
                    if dot(v1, v2) > 0:
                        raise Invalid("%s: edge %d overlaps edge %d at (%g, %g)" % (name, i, j, shared[0], shared[1]))
                continue
            if segs_intersect(a, b, c, d):
                # intersection point (approx)
                den = crs(sub(b, a), sub(d, c))
                if den != 0:
                    tt = crs(sub(c, a), sub(d, c)) / den
                    x, y = a[0] + tt * (b[0] - a[0]), a[1] + tt * (b[1] - a[1])
                else:
                    x, y = c
                raise Invalid("%s: edge %d crosses edge %d at (%g, %g)" % (name, i, j, x, y))
    if abs(signed_area(poly)) <= 0.0:
        raise Invalid("%s: zero area" % name)


# ---------------------------------------------------------------- segments
def removal_interval(P0, u, A, B, R):
    """open interval of s where dist(P0 + s u, [A, B]) < R, or None"""
    los, his = [], []
    for C in (A, B):
        dx, dy = P0[0] - C[0], P0[1] - C[1]
        b = u[0] * dx + u[1] * dy
        c = dx * dx + dy * dy - R * R
        disc = b * b - c
        if disc > 0:
            sq = math.sqrt(disc)
            los.append(-b - sq)
            his.append(-b + sq)
    Lx, Ly = B[0] - A[0], B[1] - A[1]
    L = math.hypot(Lx, Ly)
    if L > 0:
        v = (Lx / L, Ly / L)
        nv = (v[1], -v[0])
        d0 = sub(P0, A)
        lo, hi = -math.inf, math.inf
        ok = True
        for c0, c1, a, b, strict in ((dot(d0, v), dot(u, v), 0.0, L, False),
                                     (dot(d0, nv), dot(u, nv), -R, R, True)):
            if abs(c1) < 1e-15:
                if not ((a < c0 < b) if strict else (a <= c0 <= b)):
                    ok = False
                    break
            else:
                sa, sb = (a - c0) / c1, (b - c0) / c1
                lo = max(lo, min(sa, sb))
                hi = min(hi, max(sa, sb))
        if ok and lo < hi:
            los.append(lo)
            his.append(hi)
    if not los:
        return None
    return (min(los), max(his))


def inside_intervals(P0, u, length, poly):
    ts = [0.0, length]
    n = len(poly)
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        e = sub(b, a)
        den = crs(u, e)
        if abs(den) < 1e-15:
            continue
        w = sub(a, P0)
        s = crs(w, e) / den
        tt = crs(w, u) / den
        if -1e-12 <= tt <= 1 + 1e-12 and 0 < s < length:
            ts.append(s)
    ts.sort()
    out = []
    for x, y in zip(ts, ts[1:]):
        if y - x <= 0:
            continue
        m = (x + y) / 2
        if point_in_poly((P0[0] + m * u[0], P0[1] + m * u[1]), poly):
            out.append((x, y))
    return out


def subtract(lo, hi, ivs):
    pieces = []
    cur = lo
    for a, b in sorted(ivs):
        if b <= cur:
            continue
        if a >= hi:
            break
        if a > cur:
            pieces.append((cur, a))
        cur = max(cur, b)
        if cur >= hi:
            break
    if cur < hi:
        pieces.append((cur, hi))
    return pieces


class Seg:
    __slots__ = ('idx', 'edge', 'P0', 'u', 'n', 'c', 's0', 's1', 'E0', 'E1')


def build_segments(part, access, r, trim):
    n = len(part)
    segs = []
    for i in range(n):
        v0, v1 = part[i], part[(i + 1) % n]
        ex, ey = v1[0] - v0[0], v1[1] - v0[1]
        L = math.hypot(ex, ey)
        u = (ex / L, ey / L)
        nn = (u[1], -u[0])
        P0 = (v0[0] + r * nn[0], v0[1] + r * nn[1])
        ivs = []
        for j in range(n):
            if j == i:
                continue
            iv = removal_interval(P0, u, part[j], part[(j + 1) % n], r - EPS)
            if iv:
                ivs.append(iv)
        for poly in access:
            m = len(poly)
            for j in range(m):
                iv = removal_interval(P0, u, poly[j], poly[(j + 1) % m], r)
                if iv:
                    ivs.append(iv)
            ivs.extend(inside_intervals(P0, u, L, poly))
        for x, y in subtract(0.0, L, ivs):
            a, b = x + trim, y - trim
            if b - a > EPS:
                s = Seg()
                s.edge = i
                s.P0, s.u, s.n = P0, u, nn
                s.c = dot(nn, P0)
                s.s0, s.s1 = a, b
                s.E0 = (P0[0] + a * u[0], P0[1] + a * u[1])
                s.E1 = (P0[0] + b * u[0], P0[1] + b * u[1])
                segs.append(s)
    for k, s in enumerate(segs):
        s.idx = k
    return segs


# ---------------------------------------------------------------- linear algebra
def det3(M):
    return (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1])
            - M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0])
            + M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]))


def inv3(M, d):
    a, b, c = M[0]
    e, f, g = M[1]
    h, i, j = M[2]
    return [[(f * j - g * i) / d, (c * i - b * j) / d, (b * g - c * f) / d],
            [(g * h - e * j) / d, (a * j - c * h) / d, (c * e - a * g) / d],
            [(e * i - f * h) / d, (b * h - a * i) / d, (a * f - b * e) / d]]


def matvec(M, v):
    return (M[0][0] * v[0] + M[0][1] * v[1] + M[0][2] * v[2],
            M[1][0] * v[0] + M[1][1] * v[1] + M[1][2] * v[2],
            M[2][0] * v[0] + M[2][1] * v[1] + M[2][2] * v[2])


def columns_matrix(cols):
    return [[cols[0][r], cols[1][r], cols[2][r]] for r in range(3)]


def fib_dirs(N=256):
    out = []
    g = math.pi * (3 - math.sqrt(5))
    for i in range(N):
        z = 1 - (2 * i + 1) / N
        phi = i * g
        rr = math.sqrt(max(0.0, 1 - z * z))
        out.append((rr * math.cos(phi), rr * math.sin(phi), z))
    return out


def area_props(poly):
    A = 0.0
    cx = cy = 0.0
    Ix = Iy = 0.0
    n = len(poly)
    for i in range(n):
        x1, y1 = poly[i]
        x2, y2 = poly[(i + 1) % n]
        k = x1 * y2 - x2 * y1
        A += k
        cx += (x1 + x2) * k
        cy += (y1 + y2) * k
        Ix += (y1 * y1 + y1 * y2 + y2 * y2) * k
        Iy += (x1 * x1 + x1 * x2 + x2 * x2) * k
    A /= 2
    cx /= 6 * A
    cy /= 6 * A
    J0 = (Ix + Iy) / 12
    Jc = J0 - A * (cx * cx + cy * cy)
    return A, (cx, cy), math.sqrt(Jc / A)


def score_contacts(pts, fs, applied, cen, rho):
    """pts, fs: 4 contacts (3 locators then clamp) in part frame.
    applied: list of 3-vectors in the same metric space.
    returns max lambda."""
    ws = []
    for p, f in zip(pts, fs):
        q = (p[0] - cen[0], p[1] - cen[1])
        ws.append((f[0], f[1], crs(q, f) / rho))
    M = columns_matrix(ws[:3])
    d = det3(M)
    Mi = inv3(M, d)
    lc = matvec(Mi, ws[3])
    mu = (-lc[0], -lc[1], -lc[2], 1.0)
    best = 0.0
    for p in applied:
        l0 = matvec(Mi, p)
        l0 = (-l0[0], -l0[1], -l0[2], 0.0)
        s = max(-l0[i] / mu[i] for i in range(4))
        m = max(l0[i] + s * mu[i] for i in range(4))
        if m > best:
            best = m
    return best


# ---------------------------------------------------------------- main solver
def solve(case, max_seconds=None):
    t_start = time.time()
    units = case.get('units', 'mm')
    part = case['part']
    access = case.get('access') or []
    kit = case['kit']
    params = case.get('params') or {}
    validate_polygon(part, 'part')
    for ai, a in enumerate(access):
        validate_polygon(a, 'access constraint %d' % ai)
    l = float(kit['spacing'])
    cols, rows = int(kit['cols']), int(kit['rows'])
    pattern = kit.get('pattern', 'square')
    alt = pattern == 'alternating'
    r_phys = float(kit['locator_radius'])
    if not (l > 0 and r_phys > 0):
        raise Invalid("kit: spacing and locator radius must be positive")
    if alt and not r_phys < l * math.sqrt(2) / 2:
        raise Invalid("kit: locator radius too large for alternating plate")
    if not alt and not r_phys < l / 2:
        raise Invalid("kit: locator radius too large for square plate")
    clamp = kit['clamp']
    mm = 1.0 if units == 'mm' else (25.4 if units == 'in' else 1.0)
    trim_phys = params.get('edge_trim')
    if trim_phys is None:
        trim_phys = 1.0 if units != 'in' else 0.04
    mc_phys = params.get('min_clearance')
    if mc_phys is None:
        mc_phys = 1.0 if units != 'in' else 0.04
    max_angle = params.get('max_clamp_angle_deg')
    if max_angle is None:
        max_angle = 45.0
    gstep = int(params.get('grid_step') or 1)
    wrenches = params.get('wrenches')

    # normalise to CCW
    part = [(float(x), float(y)) for x, y in part]
    if signed_area(part) < 0:
        part = [part[0]] + part[:0:-1]
    part_phys = part
    P = [(x / l, y / l) for x, y in part]
    ACC = [[(float(x) / l, float(y) / l) for x, y in a] for a in access]
    r = r_phys / l
    trim = trim_phys / l
    mc = mc_phys / l
    y0 = float(clamp.get('axis_offset', 0.0)) / l
    tmin, tmax = (float(v) / l for v in clamp['travel'])
    body = [(float(x) / l, float(y) / l) for x, y in clamp['body']]
    plunger = [(float(x) / l, float(y) / l) for x, y in clamp['plunger']]
    mholes = []
    for h in clamp['mount_holes']:
        kind = h[2] if len(h) > 2 else None
        mholes.append((int(h[0]), int(h[1]), kind))
    cosmax = math.cos(math.radians(max_angle))

    segs = build_segments(P, ACC, r, trim)
    nseg = len(segs)
    counts = {'segments': nseg, 'combinations': 0, 'setups': 0, 'candidates': 0, 'admissible': 0}

    # quality metric setup
    _, cen, rho = area_props(P)
    if wrenches is None:
        applied = fib_dirs(256)
        q_scale = 1.0
        cen_m, rho_m = cen, rho
    else:
        applied = [(float(w[0]), float(w[1]), float(w[2])) for w in wrenches]
        q_scale = l
        cen_m, rho_m = (0.0, 0.0), 1.0

    # distance bounds between segments
    dlo = [[0.0] * nseg for _ in range(nseg)]
    dhi = [[0.0] * nseg for _ in range(nseg)]
    for i in range(nseg):
        for j in range(nseg):
            A0, A1, B0, B1 = segs[i].E0, segs[i].E1, segs[j].E0, segs[j].E1
            if i == j:
                dlo[i][j] = 0.0
                dhi[i][j] = math.dist(A0, A1)
            else:
                dlo[i][j] = seg_seg_dist(A0, A1, B0, B1)
                dhi[i][j] = max(math.dist(A0, B0), math.dist(A0, B1), math.dist(A1, B0), math.dist(A1, B1))
    DM = max((max(row) for row in dhi), default=0.0)
    RAD = int(math.ceil(DM)) + 1
    pts_all = []
    for i in range(-RAD, RAD + 1):
        for j in range(-RAD, RAD + 1):
            if i == 0 and j == 0:
                continue
            if i % gstep or j % gstep:
                continue
            if alt and (i + j) % 2:
                continue
            n2 = i * i + j * j
            if n2 <= DM * DM + 1e-6:
                pts_all.append((n2, i, j))
    pts_all.sort()
    pts_q = [p for p in pts_all if p[1] > 0 and p[2] >= 0]
    n2_all = [p[0] for p in pts_all]
    n2_q = [p[0] for p in pts_q]
    SL = 1e-7

    def rng(lst, keys, lo, hi):
        a = bisect.bisect_left(keys, (max(0.0, lo - SL)) ** 2 if lo > SL else 0.0)
        b = bisect.bisect_right(keys, (hi + SL) ** 2)
        return lst[a:b]

    D = [(1, 0), (0, 1), (-1, 0), (0, -1)]
    E = [(0, 1), (-1, 0), (0, -1), (1, 0)]
    body_bb_local = bbox(body)
    fixtures = []
    timed_out = False

    for a in range(nseg):
        for b in range(a, nseg):
            for c in range(b, nseg):
                if a == c:
                    continue
                counts['combinations'] += 1
                if max_seconds is not None and time.time() - t_start > max_seconds:
                    timed_out = True
                    continue
                S = (segs[a], segs[b], segs[c])
                n1, n2, n3 = S[0].n, S[1].n, S[2].n
                lam = (n2[0] * n3[1] - n3[0] * n2[1],
                       n3[0] * n1[1] - n1[0] * n3[1],
                       n1[0] * n2[1] - n2[0] * n1[1])
                if max(abs(x) for x in lam) <= EPS:
                    continue
                Cc = lam[0] * S[0].c + lam[1] * S[1].c + lam[2] * S[2].c
                # normal equations for w
                m11 = n1[0] ** 2 + n2[0] ** 2 + n3[0] ** 2
                m12 = n1[0] * n1[1] + n2[0] * n2[1] + n3[0] * n3[1]
                m22 = n1[1] ** 2 + n2[1] ** 2 + n3[1] ** 2
                md = m11 * m22 - m12 * m12
                for (_, i2, j2) in rng(pts_q, n2_q, dlo[a][b], dhi[a][b]):
                    L2 = (i2, j2)
                    A2 = n2[0] * i2 + n2[1] * j2
                    B2 = n2[0] * j2 - n2[1] * i2
                    for (_, i3, j3) in rng(pts_all, n2_all, dlo[a][c], dhi[a][c]):
                        if i3 == i2 and j3 == j2:
                            continue
                        dd = math.hypot(i3 - i2, j3 - j2)
                        if dd < dlo[b][c] - SL or dd > dhi[b][c] + SL:
                            continue
                        A3 = n3[0] * i3 + n3[1] * j3
                        B3 = n3[0] * j3 - n3[1] * i3
                        Ath = lam[1] * A2 + lam[2] * A3
                        Bth = lam[1] * B2 + lam[2] * B3
                        rh = math.hypot(Ath, Bth)
                        if rh <= EPS:
                            continue
                        dlt = rh - abs(Cc)
                        if dlt < -EPS:
                            continue
                        phi = math.atan2(Bth, Ath)
                        if dlt <= EPS:
                            thetas = [phi if Cc >= 0 else phi + math.pi]
                        else:
                            al = math.acos(max(-1.0, min(1.0, Cc / rh)))
                            thetas = [phi - al, phi + al]
                        for th in thetas:
                            th = th % (2 * math.pi)
                            if th >= 2 * math.pi:
                                th = 0.0
                            ct, st = math.cos(th), math.sin(th)
                            r1 = -S[0].c
                            r2 = A2 * ct + B2 * st - S[1].c
                            r3 = A3 * ct + B3 * st - S[2].c
                            g1 = n1[0] * r1 + n2[0] * r2 + n3[0] * r3
                            g2 = n1[1] * r1 + n2[1] * r2 + n3[1] * r3
                            wx = (m22 * g1 - m12 * g2) / md
                            wy = (m11 * g2 - m12 * g1) / md
                            Ls = ((0, 0), L2, (i3, j3))
                            ss = []
                            pp = []
                            ok = True
                            margin = abs(dlt) if abs(dlt) < 1.0 else 1.0
                            for k in range(3):
                                Lx, Ly = Ls[k]
                                px = ct * Lx + st * Ly - wx
                                py = -st * Lx + ct * Ly - wy
                                sg = S[k]
                                sv = (px - sg.P0[0]) * sg.u[0] + (py - sg.P0[1]) * sg.u[1]
                                if not (sg.s0 + EPS < sv < sg.s1 - EPS):
                                    ok = False
                                    break
                                margin = min(margin, sv - sg.s0 - EPS, sg.s1 - EPS - sv)
                                ss.append(sv)
                                pp.append((px, py))
                            if not ok:
                                continue
                            if a == b and not ss[0] < ss[1]:
                                continue
                            if b == c and not ss[1] < ss[2]:
                                continue
                            counts['setups'] += 1
                            tx = ct * wx - st * wy
                            ty = st * wx + ct * wy
                            setup = (a, b, c, Ls, th, ct, st, (tx, ty), ss, pp, margin)
                            process_setup(setup, segs, r, y0, tmin, tmax, cosmax, mc, mholes, alt,
                                          cols, rows, P, ACC, body, plunger, D, E, counts, fixtures,
                                          applied, cen_m, rho_m, q_scale, l)
    fixtures.sort(key=lambda f: f['_key'])
    out = []
    for rank, f in enumerate(fixtures, 1):
        f.pop('_key')
        f['rank'] = rank
        out.append(f)
    counts['admissible'] = len(out)
    status = 'ok' if out else 'no_fixture'
    if timed_out:
        status = 'timeout'
    return {'status': status, 'counts': counts, 'fixtures': out,
            'seconds': round(time.time() - t_start, 3)}


def plate_fit(points, alt, cols, rows):
    for rot in (0, 1):
        if rot:
            pts = [(-y, x) for x, y in points]
        else:
            pts = points
        xs = [p[0] for p in pts]
        ys = [p[1] for p in pts]
        mnx, mny = min(xs), min(ys)
        W = max(xs) - mnx
        H = max(ys) - mny
        if W > cols - 1 or H > rows - 1:
            continue
        for ox in range(0, cols - W):
            for oy in range(0, rows - H):
                Tx, Ty = ox - mnx, oy - mny
                if alt and (Tx + Ty) % 2:
                    continue
                return (rot, Tx, Ty)
    return None


def process_setup(setup, segs, r, y0, tmin, tmax, cosmax, mc, mholes, alt, cols, rows,
                  P, ACC, body, plunger, D, E, counts, fixtures, applied, cen_m, rho_m, q_scale, l):
    a, b, c, Ls, th, ct, st, t, ss, pp, smargin = setup

    def rot(v):
        return (ct * v[0] - st * v[1], st * v[0] + ct * v[1])

    S = (segs[a], segs[b], segs[c])
    fs = []
    cols3 = []
    for k in range(3):
        rn = rot(S[k].n)
        f = (-rn[0], -rn[1])
        fs.append(f)
        q = Ls[k]
        cols3.append((f[0], f[1], q[0] * f[1] - q[1] * f[0]))
    M = columns_matrix(cols3)
    dW = det3(M)
    if abs(dW) <= EPS:
        return
    Mi = inv3(M, dW)
    base_margin = min(smargin, abs(dW) - EPS)
    posed_part = None
    posed_acc = None
    part_bb = None
    acc_bb = None
    for sg in segs:
        rn = rot(sg.n)
        f = (-rn[0], -rn[1])
        U = rot(sg.u)
        RP = rot(sg.P0)
        Q0 = (RP[0] + t[0], RP[1] + t[1])
        w0 = (f[0], f[1], Q0[0] * f[1] - Q0[1] * f[0])
        w1z = U[0] * f[1] - U[1] * f[0]
        al0 = matvec(Mi, w0)
        alpha = (-al0[0], -al0[1], -al0[2])
        beta = (-w1z * Mi[0][2], -w1z * Mi[1][2], -w1z * Mi[2][2])
        lo, hi = sg.s0 + EPS, sg.s1 - EPS
        empty = False
        for i in range(3):
            if beta[i] > 0:
                lo = max(lo, (EPS - alpha[i]) / beta[i])
            elif beta[i] < 0:
                hi = min(hi, (EPS - alpha[i]) / beta[i])
            elif alpha[i] <= EPS:
                empty = True
        if empty or lo >= hi:
            continue
        for k in range(4):
            d = D[k]
            e = E[k]
            cosang = d[0] * f[0] + d[1] * f[1]
            if cosang <= EPS or cosang < cosmax - EPS:
                continue
            ue = U[0] * e[0] + U[1] * e[1]
            qe0 = Q0[0] * e[0] + Q0[1] * e[1]
            v1, v2 = qe0 + lo * ue, qe0 + hi * ue
            jlo = math.floor(min(v1, v2) - y0) - 1
            jhi = math.ceil(max(v1, v2) - y0) + 1
            for j in range(jlo, jhi + 1):
                s = (j + y0 - qe0) / ue
                if not (lo < s < hi):
                    continue
                counts['candidates'] += 1
                q = (Q0[0] + s * U[0], Q0[1] + s * U[1])
                lam_q = [alpha[i] + beta[i] * s for i in range(3)]
                margin = min(base_margin, min(x - EPS for x in lam_q),
                             s - sg.s0 - EPS, sg.s1 - EPS - s, cosang - EPS)
                if cosmax > EPS:
                    margin = min(margin, cosang - cosmax)
                # tip vs locators (independent of mount)
                tipm = min(math.hypot(q[0] - L[0], q[1] - L[1]) - 2 * r for L in Ls)
                if tipm < -EPS:
                    continue
                margin = min(margin, abs(tipm))
                if posed_part is None:
                    posed_part = [(ct * x - st * y + t[0], st * x + ct * y + t[1]) for x, y in P]
                    part_bb = bbox(posed_part)
                    posed_acc = [[(ct * x - st * y + t[0], st * x + ct * y + t[1]) for x, y in A] for A in ACC]
                    acc_bb = [bbox(A) for A in posed_acc]
                qd = q[0] * d[0] + q[1] * d[1]
                a_hi = math.floor(qd - tmin + EPS)
                a_lo = math.ceil(qd - tmax - EPS)
                found = None
                fail_margin = 1.0
                for av in range(a_hi, a_lo - 1, -1):
                    text = qd - av
                    m = (av * d[0] + j * e[0], av * d[1] + j * e[1])
                    mm_ = min(text - tmin, tmax - text)
                    holes = []
                    okh = True
                    for hx, hy, kind in mholes:
                        H = (m[0] + hx * d[0] + hy * e[0], m[1] + hx * d[1] + hy * e[1])
                        if H in Ls:
                            okh = False
                            break
                        if alt and kind is not None:
                            dow = (H[0] + H[1]) % 2 == 0
                            if (kind == 'dowel') != dow:
                                okh = False
                                break
                        holes.append(H)
                    if not okh:
                        continue
                    fit = plate_fit(list(Ls) + holes, alt, cols, rows)
                    if fit is None:
                        continue
                    # clearance
                    def place(poly, ext):
                        return [(m[0] + (x + ext) * d[0] + y * e[0], m[1] + (x + ext) * d[1] + y * e[1])
                                for x, y in poly]
                    cm = 1.0
                    bad = False
                    for poly in (place(body, 0.0), place(plunger, text)):
                        bb = bbox(poly)
                        x_ = poly_poly_margin(poly, bb, posed_part, part_bb, mc)
                        cm = min(cm, x_)
                        if x_ < -EPS:
                            bad = True
                            break
                        for A, Abb in zip(posed_acc, acc_bb):
                            x_ = poly_poly_margin(poly, bb, A, Abb, mc)
                            cm = min(cm, x_)
                            if x_ < -EPS:
                                bad = True
                                break
                        if bad:
                            break
                        for L in Ls:
                            if mc <= EPS:
                                x_ = 1.0 if not point_in_poly(L, poly) else -1.0
                                if x_ > 0:
                                    x_ = pt_poly_bdist(L, poly) - r
                                    if x_ < -EPS:
                                        x_ = -1.0
                            else:
                                x_ = poly_disk_margin(poly, bb, L, r, mc)
                            cm = min(cm, x_)
                            if x_ < -EPS:
                                bad = True
                                break
                        if bad:
                            break
                    if bad:
                        fail_margin = min(fail_margin, abs(cm))
                        continue
                    found = (m, text, fit, min(abs(cm), abs(mm_)))
                    break
                if found is None:
                    continue
                m, text, fit, mmarg = found
                margin = min(margin, mmarg, fail_margin)
                # score, part frame
                pts = [(x * q_scale, y * q_scale) for x, y in pp]
                pc = (sg.P0[0] + s * sg.u[0], sg.P0[1] + s * sg.u[1])
                pts.append((pc[0] * q_scale, pc[1] * q_scale))
                nfs = [(-S[0].n[0], -S[0].n[1]), (-S[1].n[0], -S[1].n[1]),
                       (-S[2].n[0], -S[2].n[1]), (-sg.n[0], -sg.n[1])]
                score = score_contacts(pts, nfs, applied, cen_m, rho_m)
                L2, L3 = Ls[1], Ls[2]
                key = (score, a, b, c, tuple(L2), tuple(L3), th, sg.idx, k, tuple(m))
                fixtures.append({
                    '_key': key,
                    'score': score,
                    'segments': [a, b, c],
                    'locators': [list(x) for x in Ls],
                    'theta_deg': math.degrees(th),
                    'pose': {'x': t[0] * l, 'y': t[1] * l, 'theta_deg': math.degrees(th)},
                    'clamp': {'segment': sg.idx, 'rotation_deg': 90 * k, 'mount': list(m),
                              'extension': text * l, 'contact': [q[0] * l, q[1] * l]},
                    'contacts_s': [x * l for x in ss] + [s * l],
                    'plate': {'rotation_deg': 90 * fit[0], 'translation': [fit[1], fit[2]]},
                    'borderline': margin < BORDER,
                    'min_margin': margin,
                })


def main(argv):
    if len(argv) < 2:
        print('usage: spec_reference.py CASE.json [--max-seconds N]', file=sys.stderr)
        return 2
    path = argv[1]
    ms = None
    if '--max-seconds' in argv:
        ms = float(argv[argv.index('--max-seconds') + 1])
    with open(path) as fh:
        case = json.load(fh)
    try:
        res = solve(case, ms)
    except Invalid as ex:
        print(json.dumps({'status': 'invalid', 'error': str(ex)}))
        return 1
    except (KeyError, TypeError, ValueError) as ex:
        print(json.dumps({'status': 'invalid', 'error': 'malformed case: %r' % (ex,)}))
        return 1
    print(json.dumps(res, indent=1))
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
