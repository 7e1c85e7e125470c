#!/usr/bin/env python3
"""Independent reference implementation of SPEC.md (fixplan), standard library only.

Written from /work/shared/SPEC.md alone (no look at the Rust code), to be
compared with the production implementation.

usage: python3 scripts/spec_reference.py CASE.json [--max-seconds N]

Sections 1-9 (polygons, circular arcs, holes).  Self-checks of section 9:
scripts/spec_reference_holes_test.py; hole cases: scripts/spec_cases_holes/.

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

SECTION 8 (outlines with circular arcs), written from SPEC.md and this file only
 C22 Arc-free parts (every bulge 0 or absent) take the unchanged polygon code
     above, so their output is byte-identical to before (no segment_kinds key
     either; `--generic` forces the arc code on them as a self-check: same
     counts/fixtures up to rounding and borderline setups).  Reason: req. 1.
 C23 Bulge b: included angle 4 atan(b), R = c (1 + b^2) / (4 |b|), centre at
     the chord midpoint + c (1 - b^2) / (4 b) times the chord's left normal
     (DXF).  Reason: standard DXF geometry; SPEC gives only the angle rule.
 C24 Validation with arcs: >= 2 vertices, finite x, y, b, no repeated vertex;
     non-adjacent edges may not touch (tolerance 1e-9 x max(1, |coords|),
     near-tangency counts as touching); adjacent edges may meet only within
     1e-7 x scale of their shared vertex (a tangent joint's double
     intersection is computed only to ~sqrt(rounding)); co-circular
     overlapping arcs and folded-back lines are invalid; true area 0 is
     invalid.  Reason: SPEC says "simple" on true curves but gives no tolerance.
 C25 Grown arcs: convex R + r, concave R - r, no feature (and no segment) when
     R - r <= eps.  True-boundary / access removal exactly as SPEC 2 with the
     true region: a point goes when dist(point, true region) < r - eps (0
     inside, by winding number of chords + signed circular segments) or its
     distance to a filled access polygon is < r (C3).  Found by cutting the
     feature at every crossing with the level-set curves (offset lines, end
     point circles, concentric circles R_j +- (r - eps)) and deciding each
     piece at its midpoint.  Reason: exact and simple; checked against dense
     sampling on every arc case.
 C26 Smooth joint (no edge_trim): the piece end is exactly the grown edge's
     end (nothing removed there) and the vertex has |t_in x t_out| <= 1e-6,
     t_in . t_out > 0 with the tangents of the true edges, one edge an arc.
 C27 Contact parameter on an arc: s = rho_e x (angle from the grown edge's
     start, in the edge's own turning sense, in [0, 2 pi)); strictly inside =
     s0 + eps < s < s1 - eps, so a contact at a smooth joint (s = 0 on one
     side, s = length on the other) is in neither segment.
 C28 Poses with >= 1 arc.  Two parallel lines (|n1 x n2| <= eps) + arc: theta
     from the two lines in closed form (rules of C6), w from the line-circle
     intersection (a miss by <= 1e-9 counts as one tangent point, a
     tangency within rounding is the exact double root: C47).  Otherwise
     w is eliminated: the two other equations are made linear (a line, or
     the difference of two arc equations), w = adj(M) b / det M, and
     G(theta) = |det c_q - adj(M) b|^2 - rho_q^2 det^2 (c_q = R^T L_q - C_q)
     is a trigonometric polynomial of degree <= 4 (entries of M, b and c_q
     have degree <= 1), recovered exactly from 16 samples.  All its roots are
     isolated by subdivision with the bounds |G^(j)| <= sum k^j |c_k|: an
     interval is dropped when |G(lo)| + |G(hi)| > max|G'| h, solved by
     bisection where G is provably monotone, split at the single critical
     point where G' is provably monotone, else halved.  Critical points with
     |G| <= 1e-6 x scale are kept as double-root candidates.  Where det M is
     ~0 at a root (1e-7 relative) w comes from the remaining linear equation
     and the circle.  Every candidate is Newton-polished on the full 3x3
     system and kept iff each locator is within 1e-9 (lattice units) of its
     line/arc.  Reason: provably misses no root (up to rounding); the exact
     degree bound is asserted at run time.
 C29 Continuum: G == 0 at all 16 samples (<= 1e-12 x scale) -> no pose for
     that triple (arc_diagnostics.continua); det M == 0 for every theta ->
     no pose (arc_diagnostics.degenerate; never met in the cases here).
     Reason: SPEC 8.4 "a continuum has no pose".
 C30 Tangential: |det J| <= 1e-6, J the 3x3 Jacobian in (theta, w_x, w_y)
     of the equations (distance form) in the canonical plate frame (L1 at
     the origin, lattice units), rows scaled to unit length.  A double-root
     candidate whose residuals pass (a near miss by <= 1e-9 included) is a
     tangential pose.  Duplicates merged by the rules of 8.4.  Setup margin
     (borderline): s margins, 0 if tangential, else |det J| - 1e-6.  Reason:
     SPEC does not fix the frame of J; borderline either way.
 C31 Arc contact normals (8.3) use the posed centre and the locator / tip
     centre; the part-frame normal for the score is the same in the part
     frame.  If a (nearly singular, tangential) setup makes a clamp lambda
     > eps in the plate frame round to <= 0 in the part-frame score, the
     score is reported as 1e300 (not finite; JSON has no infinity).
 C32 Clamp on an arc: for each axis line (integer j) the 0/1/2 intersections
     with the posed grown circle (disc < 0: none, disc = 0 or a tangency
     within rounding (C47): one); each point
     must be strictly inside the segment (C27), pass the angle test (C9)
     with the arc normal there, and have all lambda > eps; then it counts
     as a candidate.  Borderline also when rho_e - |offset| < 1e-6 (8.5).
 C33 Clearance against the true posed region: exact segment-arc distance
     (crossings, end points, foot of the centre on the segment), containment
     by winding number (C12 otherwise unchanged; bounding box with arc
     extremes for the 1e-3 prefilter).  min_clearance 0: best-effort overlap
     test (transversal crossings, strictly inside vertices/midpoints).
 C34 Distance annuli (C7) for a pair with an arc: min/max over 33 samples
     per segment widened by half of both sample steps (arc length >= chord),
     a sound necessary condition.
 C35 Output for parts with arcs adds "segment_kinds" (8.6) and
     "arc_diagnostics" {continua, degenerate, tangential}.

SECTION 9 (parts with holes), written from SPEC.md and this file only
 C36 Input: "holes" absent, null or [] = no holes: the code paths above, so
     the output is byte-identical to before (spec_reference_holes_test.py
     diffs every case of scripts/spec_cases/ against commit 8e9afe9; the
     three that C47 changed on purpose are checked to differ only by the
     removed tangential setups and their borderline fixtures).  A part
     with >= 1 hole always takes the arc code path (C22-C35), even when every
     edge is straight, so its result has "segment_kinds" and
     "arc_diagnostics" too, and "segment_loops" (9.6) right after
     "segment_kinds".  Reason: one code path for the part region.
 C37 Validation order: the outline (unchanged messages), then every hole in
     input order: first the hole as a loop of its own, by the outline's rules
     (straight-only: C21, >= 3 vertices; with arcs: C24), message prefix
     "part: hole k: ", e.g. "part: hole 1: edge 0 crosses edge 2 at (x, y)";
     then hole k against the outline (contact, then containment), then
     against each hole j < k (contact, then containment either way); access
     constraints and the kit after all holes.  Messages:
       "part: hole k crosses the outline at (x, y)"
       "part: hole k touches the outline at (x, y)"
       "part: hole k lies outside the outline"
       "part: hole k crosses hole j at (x, y)"   (j < k)
       "part: hole k touches hole j at (x, y)"
       "part: hole a lies inside hole b"         (whichever contains which)
     prefixed "part: " like every message naming the part (section 7);
     coordinates in catalogue units with %g (so "(12.5, 3)", not the SPEC
     example's "(12.5, 3.0)", as C21 already does for edges).  Reason: SPEC
     9.1 gives two examples, not the list; compare messages by their words.
 C38 Sharing a point: two loops share a point when a pair of their edges
     meets with the tolerance tol = 1e-9 x max(1, |outline coordinates|)
     (C24's intersection test, near-tangency included) or comes closer than
     tol (exact closest pair of line/arc edges).  The polygon outline's own
     validation is exact (C21); between loops the C24 tolerance is used for
     every part.  The reported point is the first meeting point found (hole
     edges in input order, then the other loop's edges), or the hole's
     point of the closest pair.  "crosses" vs "touches": the hole's edges are
     cut at the meeting points and each piece judged at its midpoint (pieces
     within tol of the other loop skipped): pieces strictly inside AND
     strictly outside the other loop = crosses, otherwise touches (tangent
     circles, a vertex on a wall, a shared stretch of wall).  Reason: SPEC's
     parenthesis "meets a loop without crossing it touches it".
 C39 "Strictly inside the outline" / "inside another hole" (no contact found)
     is decided at the hole's first vertex (winding number, C43); a hole
     outside the outline is invalid ("lies outside the outline").  A hole
     inside another is reported whichever was listed first.  Reason: 9.1
     names the condition but no message for a hole outside the outline.
 C40 Orientation (9.2): each hole's orientation is the sign of its true area
     (arcs included, as 8.1's rule for the outline); a CCW hole is reversed by
     8.1's rule (each bulge negated and moved with its edge), so a round hole
     listed either way becomes two half circles with b = -1 (concave).
     Edges: outline (CCW) first, then hole 0 (CW), hole 1, ...; segments in
     (edge, position) order; segment_loops[i] = 0 (outline) or k + 1.
 C41 Segments (9.3): C25 with the part region = all loops: a grown-edge
     point goes when its distance to the part region is < r - eps, the
     region tested by the winding number over every loop (0 inside a hole,
     the holes being CW) and the distance taken to every edge of every loop;
     cuts at the level sets of every other edge, holes' included.  Concave
     arcs have radius R - r, no feature when R - r <= eps (lattice units:
     a bore with R - r = 1e-8 mm = 1e-9 lattice offers nothing; 2e-8 mm
     does).  Smooth joints (C26) are looked up inside the loop: vertex i of
     a loop joins the loop's previous edge and edge i; the end of a loop's
     last edge is the loop's first vertex.  A slot of width exactly 2r keeps
     its straight walls (their grown lines coincide at distance exactly r
     from both walls: not "narrower than 2r").  Reason: 9.3 as written.
 C42 Clearance (9.4): C33 with every loop: boundary distance to every edge of
     every loop, and containment by "a polygon vertex in the part region
     (winding over all loops) or an outline vertex inside the polygon"; with
     boundaries apart by >= min_clearance this is exact (the material is
     connected; a polygon whose boundary lies in a hole lies inside it, one
     covering a hole has its boundary in the material or around the whole
     part).  min_clearance 0: C33's overlap test over all loops (a hole
     vertex or edge midpoint strictly inside the polygon is an overlap).
 C43 Inside test (all parts, arcs): the chord-polygon crossing count with
     signed circular segments (C25) is ambiguous for a point exactly on an
     arc's chord (e.g. on the centre line of a round outline, where both half
     circles share the chord: the washer's hole vertex (-8, 0) was found
     outside the outline).  Such a point, and only such a point, is decided
     by the sum of the angles the true edges subtend at it instead.  No
     earlier result changes (checked on every case of scripts/spec_cases/).
 C44 Metric (9.5): C15/C23's exact true-region sums (chord polygon plus
     signed circular segments) over all loops; the holes, being CW, subtract
     their area, first and polar second moments; c and rho from the totals.
     Checked against closed forms, a grid and Monte Carlo.
 C45 Concentric arcs only (a round outline and a round bore: the washer):
     the three equations do not change when the part turns about the common
     centre, so a setup has either no solution or a continuum: no pose
     either way (8.4), and the round washer has no fixture.  In C28 G(theta)
     is then constant (non-zero: no root); collinear locator triples make
     the linear part singular for every theta (arc_diagnostics.degenerate).
 C46 Clamp tip, plunger or body inside a hole: nothing special; the clamp may
     push on a hole's wall from inside the hole (its segments are segments
     like any other), and 9.4 decides the clearance.

TANGENCY WITHIN ROUNDING (added after comparing with the production solver)
 C47 A line meeting a circle where both are known to rounding: the line of w
     left by two parallel lines against the arc locator's circle (C28), and a
     clamp axis line against a posed grown circle (C32).  With dl the signed
     distance of the line from the centre, the meeting points are
     tau0 -+ sqrt(rho^2 - dl^2).  When | |dl| - rho | <= 64 ulps (64 x 2^-52)
     x scale, scale = the sum of the magnitudes dl is computed from (parallel
     pair: |L_j| + |c_j| + |L_q| + |C_q| + rho; clamp: |j| + |y0| + |R C| +
     |t| + rho; lattice units), the meeting is an exact tangency: the one
     double root tau0 (one pose; for the clamp one point whose normal is
     perpendicular to the axis, so never a candidate, C9).
     Why: dl carries a rounding error of a few ulps of those magnitudes, and
     an exact tangency then comes out as two roots sqrt(2 rho |err|) ~ 1e-8
     apart.  SPEC 8.4 merges the two into one tangential pose anyway, but the
     survivor put its contact ~1e-8 (> eps) inside a segment, where the exact
     double root puts it exactly at a smooth joint: in neither segment (8.4,
     last sentence), so no setup.  This is the case of three locators on one
     straight line, two on a straight edge (or on two parallel ones) and the
     third where a parallel edge runs tangentially into an arc (fillet,
     stadium end, D-shape, a slot's end, a bore's joint).  64 ulps: measured
     on every case here, the tangencies come out within 4.3e-16 x scale and
     the nearest non-tangent meeting is 5e-11 x scale (clamp) / 9e-5 x scale
     (poses) away; a real near-tangency that close would be tangential, so
     borderline (8.4), either way.  Not applied in C28's rank-deficient branch:
     there theta is a root of G, accurate only to ~1e-8 near a double root,
     so dl is not a rounding-size quantity; Newton polish and 8.4's merge
     decide there as before (its tangencies here came out at up to 2e-13 x
     scale, none at a joint: no count differs from the Rust there).
     Effect (setups): arc-d-shape 247 -> 246, arc-fillet-rect 1005 -> 1000,
     arc-stadium 557 -> 552, bracket-arcs 2421 -> 2411, slot-hole-cw and
     slot-hole-ccw 1425 -> 1424, bore-near-edge 319 -> 318 (fixtures: the
     borderline ones of those setups); nothing else changes in the cases of
     scripts/spec_cases*, bracket-arcs, rectangle-mm and gluegun-28 (the
     clamp use changes no output there).
"""
import sys
import json
import math
import time
import bisect

EPS = 1e-9
BORDER = 1e-6
# debugging aid: SPEC_REF_SETUPS=FILE lists every arc setup (segments, locators,
# theta in degrees, tangential, margin), one JSON array a line
SETUP_LOG = open(__import__('os').environ['SPEC_REF_SETUPS'], 'w') \
    if __import__('os').environ.get('SPEC_REF_SETUPS') else None


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
    __slots__ = ('idx', 'edge', 'P0', 'u', 'n', 'c', 's0', 's1', 'E0', 'E1',
                 'kind', 'feat', 'C', 'rho', 'sg', 'a0', 'convex')


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
                s.kind = 'line'
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
    if min(mu) <= 0.0:
        # only reachable with arcs: a (tangential, borderline) setup whose W is
        # nearly singular, so a clamp lambda > eps in the plate frame rounds to
        # <= 0 in the part frame: no finite score (C31)
        return 1e300
    best = 0.0
    for p in applied:
        l0 = matvec(Mi, p)
        l0 = (-l0[0], -l0[1], -l0[2], 0.0)
        s = max(-l0[i] / mu[i] for i in range(4))
        m = max(l0[i] + s * mu[i] for i in range(4))
        if m > best:
            best = m
    return best


# ---------------------------------------------------------------- arcs (SPEC 8)
TWO_PI = 2.0 * math.pi


def norm_angle(a):
    """angle in [0, 2 pi)"""
    a = math.fmod(a, TWO_PI)
    if a < 0.0:
        a += TWO_PI
    if a >= TWO_PI:
        a = 0.0
    return a


class Edge:
    """one edge of the true outline (part frame, lattice units)"""
    __slots__ = ('kind', 'P0', 'P1', 'u', 'L', 'C', 'R', 'sweep', 'sg', 'a0')


def make_edge(P0, P1, b):
    e = Edge()
    e.P0, e.P1 = P0, P1
    dx, dy = P1[0] - P0[0], P1[1] - P0[1]
    c = math.hypot(dx, dy)
    if b == 0.0:
        e.kind = 'line'
        e.L = c
        e.u = (dx / c, dy / c) if c > 0 else (1.0, 0.0)
        return e
    e.kind = 'arc'
    e.sweep = 4.0 * math.atan(b)
    e.sg = 1 if b > 0 else -1
    e.R = c * (1.0 + b * b) / (4.0 * abs(b))
    off = c * (1.0 - b * b) / (4.0 * b)
    nl = (-dy / c, dx / c)
    e.C = ((P0[0] + P1[0]) / 2 + off * nl[0], (P0[1] + P1[1]) / 2 + off * nl[1])
    e.a0 = math.atan2(P0[1] - e.C[1], P0[0] - e.C[0])
    e.L = e.R * abs(e.sweep)
    return e


def arc_rel(a0, sg, ang):
    """angle travelled from a0 in the arc's own direction, in [0, 2 pi)"""
    return norm_angle((ang - a0) * sg)


def edge_tangents(e):
    """unit tangent at start and at end (direction of travel)"""
    if e.kind == 'line':
        return e.u, e.u
    a1 = e.a0 + e.sweep
    return ((-e.sg * math.sin(e.a0), e.sg * math.cos(e.a0)),
            (-e.sg * math.sin(a1), e.sg * math.cos(a1)))


def pt_edge_dist(p, e):
    if e.kind == 'line':
        return math.sqrt(pt_seg_dist2(p, e.P0, e.P1))
    dx, dy = p[0] - e.C[0], p[1] - e.C[1]
    d = math.hypot(dx, dy)
    if d == 0.0:
        return e.R
    if arc_rel(e.a0, e.sg, math.atan2(dy, dx)) <= abs(e.sweep):
        return abs(d - e.R)
    return min(math.dist(p, e.P0), math.dist(p, e.P1))


def region_contains(p, edges):
    """winding number of the true outline around p is non-zero
    (chord polygon + signed circular segments); boundary points arbitrary"""
    x, y = p
    w = 0
    for e in edges:
        a, b = e.P0, e.P1
        o = orient(a, b, p)
        if a[1] <= y:
            if b[1] > y and o > 0:
                w += 1
        else:
            if b[1] <= y and o < 0:
                w -= 1
        if e.kind == 'arc':
            if o == 0 and dot(sub(p, a), sub(b, p)) > 0:
                # p exactly on an arc's chord (which is no boundary): the
                # crossing count above is ambiguous there (SPEC 9, C43)
                return winding_by_angles(p, edges) != 0
            if math.hypot(x - e.C[0], y - e.C[1]) < e.R and o * e.sg < 0:
                w += e.sg
    return w != 0


def winding_by_angles(p, edges):
    """winding number of the true loops around p (not on them) as the sum of
    the angles the edges subtend at p; an arc subtends its chord's angle, plus
    2 pi sg when p lies between chord and arc, or exactly sg pi when p lies
    on the chord"""
    tot = 0.0
    for e in edges:
        va, vb = sub(e.P0, p), sub(e.P1, p)
        o = crs(va, vb)
        dl = math.atan2(o, dot(va, vb))
        if e.kind == 'arc':
            if o == 0 and dot(va, vb) < 0:
                dl = e.sg * math.pi
            elif o * e.sg < 0 and math.hypot(p[0] - e.C[0], p[1] - e.C[1]) < e.R:
                dl += TWO_PI * e.sg
        tot += dl
    return int(round(tot / TWO_PI))


def region_dist(p, edges):
    if region_contains(p, edges):
        return 0.0
    return min(pt_edge_dist(p, e) for e in edges)


def edge_bbox(e):
    xs = [e.P0[0], e.P1[0]]
    ys = [e.P0[1], e.P1[1]]
    if e.kind == 'arc':
        for k in range(4):
            ang = k * math.pi / 2
            if arc_rel(e.a0, e.sg, ang) <= abs(e.sweep):
                xs.append(e.C[0] + e.R * math.cos(ang))
                ys.append(e.C[1] + e.R * math.sin(ang))
    return (min(xs), min(ys), max(xs), max(ys))


def region_bbox(edges):
    bbs = [edge_bbox(e) for e in edges]
    return (min(b[0] for b in bbs), min(b[1] for b in bbs),
            max(b[2] for b in bbs), max(b[3] for b in bbs))


def true_area_props(edges):
    """area, centroid, radius of gyration of the true region (chord polygon plus
    signed circular segments = sector minus triangle (C, P0, P1))"""
    A = Sx = Sy = J = 0.0

    def tri_terms(x1, y1, x2, y2):
        k = x1 * y2 - x2 * y1
        return (k / 2, (x1 + x2) * k / 6, (y1 + y2) * k / 6,
                (x1 * x1 + x1 * x2 + x2 * x2 + y1 * y1 + y1 * y2 + y2 * y2) * k / 12)

    def add(t, sgn=1.0):
        nonlocal A, Sx, Sy, J
        A += sgn * t[0]
        Sx += sgn * t[1]
        Sy += sgn * t[2]
        J += sgn * t[3]

    for e in edges:
        add(tri_terms(e.P0[0], e.P0[1], e.P1[0], e.P1[1]))
        if e.kind == 'arc':
            th, R, (cx, cy) = e.sweep, e.R, e.C
            a0, a1 = e.a0, e.a0 + e.sweep
            ds = math.sin(a1) - math.sin(a0)
            dc = math.cos(a0) - math.cos(a1)
            sec = (R * R * th / 2,
                   cx * R * R * th / 2 + R ** 3 / 3 * ds,
                   cy * R * R * th / 2 + R ** 3 / 3 * dc,
                   (cx * cx + cy * cy) * R * R * th / 2 + 2 * R ** 3 / 3 * (cx * ds + cy * dc)
                   + R ** 4 * th / 4)
            add(sec)
            # minus triangle C -> P0 -> P1
            pts = (e.C, e.P0, e.P1)
            for i in range(3):
                p, q = pts[i], pts[(i + 1) % 3]
                add(tri_terms(p[0], p[1], q[0], q[1]), -1.0)
    cx, cy = Sx / A, Sy / A
    Jc = J - A * (cx * cx + cy * cy)
    return A, (cx, cy), math.sqrt(Jc / A)


def true_signed_area(edges):
    A = 0.0
    for e in edges:
        A += 0.5 * (e.P0[0] * e.P1[1] - e.P1[0] * e.P0[1])
        if e.kind == 'arc':
            A += 0.5 * e.R * e.R * (e.sweep - math.sin(e.sweep))
    return A


# -- intersections of curves (lines given as segments, arcs as Edge)
def line_circle_params(P, u, Q, rad):
    """t with |P + t u - Q| = rad (u not necessarily unit); [] / [t] / [t1, t2]"""
    dx, dy = P[0] - Q[0], P[1] - Q[1]
    a = u[0] * u[0] + u[1] * u[1]
    b = u[0] * dx + u[1] * dy
    c = dx * dx + dy * dy - rad * rad
    disc = b * b - a * c
    if disc < 0:
        return []
    if disc == 0:
        return [-b / a]
    sq = math.sqrt(disc)
    return [(-b - sq) / a, (-b + sq) / a]


def circle_circle_points(C1, R1, C2, R2):
    dx, dy = C2[0] - C1[0], C2[1] - C1[1]
    d = math.hypot(dx, dy)
    if d == 0.0 or d > R1 + R2 or d < abs(R1 - R2):
        return []
    a = (R1 * R1 - R2 * R2 + d * d) / (2 * d)
    h2 = R1 * R1 - a * a
    h = math.sqrt(h2) if h2 > 0 else 0.0
    mx, my = C1[0] + a * dx / d, C1[1] + a * dy / d
    if h == 0.0:
        return [(mx, my)]
    return [(mx - h * dy / d, my + h * dx / d), (mx + h * dy / d, my - h * dx / d)]


def in_span(e, p, tol=0.0):
    rel = arc_rel(e.a0, e.sg, math.atan2(p[1] - e.C[1], p[0] - e.C[0]))
    return rel <= abs(e.sweep) + tol or rel >= TWO_PI - tol


def edge_edge_points(e, f, tol):
    """intersection points of two edges (with tolerance tol, lattice/catalogue
    units); 'overlap' if they share a piece of curve"""
    if e.kind == 'line' and f.kind == 'line':
        if segs_intersect(e.P0, e.P1, f.P0, f.P1):
            a, b, c, d = e.P0, e.P1, f.P0, f.P1
            den = crs(sub(b, a), sub(d, c))
            if den != 0:
                tt = crs(sub(c, a), sub(d, c)) / den
                return [(a[0] + tt * (b[0] - a[0]), a[1] + tt * (b[1] - a[1]))]
            # collinear overlap
            return 'overlap'
        return []
    if e.kind == 'arc' and f.kind == 'line':
        e, f = f, e
    if e.kind == 'line':
        u = sub(e.P1, e.P0)
        out = []
        L = math.hypot(u[0], u[1])
        # tolerate near-tangency: widen the radius by tol
        ts = line_circle_params(e.P0, u, f.C, f.R)
        if not ts:
            ts2 = line_circle_params(e.P0, u, f.C, f.R + tol)
            if ts2:
                ts = [sum(ts2) / len(ts2)]
        for t in ts:
            if -tol / L <= t <= 1 + tol / L:
                p = (e.P0[0] + t * u[0], e.P0[1] + t * u[1])
                if in_span(f, p, tol / f.R):
                    out.append(p)
        return out
    # arc-arc
    if math.dist(e.C, f.C) <= tol and abs(e.R - f.R) <= tol:
        # same circle: overlap unless the spans meet at most at end points
        for g, h in ((e, f), (f, e)):
            for frac in (0.25, 0.5, 0.75):
                ang = g.a0 + g.sweep * frac
                p = (g.C[0] + g.R * math.cos(ang), g.C[1] + g.R * math.sin(ang))
                if in_span(h, p, 0.0):
                    return 'overlap'
        return [p for p in (e.P0, e.P1) if in_span(f, p, tol / f.R)]
    pts = circle_circle_points(e.C, e.R, f.C, f.R)
    if not pts:
        d = math.dist(e.C, f.C)
        if abs(d - (e.R + f.R)) <= tol or abs(d - abs(e.R - f.R)) <= tol:
            pts = circle_circle_points(e.C, e.R + tol if d > e.R + f.R - tol else e.R, f.C, f.R) \
                or circle_circle_points(e.C, e.R, f.C, f.R + tol)
            if pts:
                pts = [((pts[0][0] + pts[-1][0]) / 2, (pts[0][1] + pts[-1][1]) / 2)]
    return [p for p in pts if in_span(e, p, tol / e.R) and in_span(f, p, tol / f.R)]


def validate_outline(verts, name):
    """SPEC 8.1: validation on the true curves. verts: [(x, y, b)] (any orientation).
    returns the edge list (not yet normalised)."""
    n = len(verts)
    if n < 2:
        raise Invalid("%s: fewer than 2 vertices" % name)
    seen = {}
    for i, p in enumerate(verts):
        k = (p[0], p[1])
        if k in seen:
            raise Invalid("%s: vertex %d repeats vertex %d at (%g, %g)" % (name, i, seen[k], k[0], k[1]))
        seen[k] = i
    edges = [make_edge((verts[i][0], verts[i][1]), (verts[(i + 1) % n][0], verts[(i + 1) % n][1]),
                       verts[i][2]) for i in range(n)]
    scale = max(1.0, max(max(abs(v[0]), abs(v[1])) for v in verts))
    tol = 1e-9 * scale        # crossing tolerance
    vtol = 1e-7 * scale       # an adjacent pair may meet near its shared vertex
    for i in range(n):
        for j in range(i + 1, n):
            e, f = edges[i], edges[j]
            shared = []
            if j == i + 1:
                shared.append(e.P1)
            if i == 0 and j == n - 1:
                shared.append(e.P0)
            if shared and e.kind == 'line' and f.kind == 'line':
                # adjacent lines: must not fold back
                sv = shared[0]
                o1 = e.P0 if sv is e.P1 else e.P1
                o2 = f.P1 if sv is f.P0 else f.P0
                if orient(o1, sv, o2) == 0 and dot(sub(o1, sv), sub(o2, sv)) > 0:
                    raise Invalid("%s: edge %d overlaps edge %d at (%g, %g)" % (name, i, j, sv[0], sv[1]))
                continue
            pts = edge_edge_points(e, f, tol)
            if pts == 'overlap':
                raise Invalid("%s: edge %d overlaps edge %d" % (name, i, j))
            for p in pts:
                if any(math.dist(p, s) <= vtol for s in shared):
                    continue
                raise Invalid("%s: edge %d crosses edge %d at (%g, %g)" % (name, i, j, p[0], p[1]))
    if true_signed_area(edges) == 0.0:
        raise Invalid("%s: zero area" % name)
    return edges


# -- grown features and segments of an outline with arcs
class Feature:
    """grown edge: line (P0, u, n, length) or arc (C, rho, a0, sg, length)"""
    __slots__ = ('kind', 'edge', 'P0', 'u', 'n', 'C', 'rho', 'a0', 'sg', 'convex', 'length')

    def point(self, s):
        if self.kind == 'line':
            return (self.P0[0] + s * self.u[0], self.P0[1] + s * self.u[1])
        ang = self.a0 + self.sg * s / self.rho
        return (self.C[0] + self.rho * math.cos(ang), self.C[1] + self.rho * math.sin(ang))

    def param(self, p):
        """s of a point on (or near) the feature"""
        if self.kind == 'line':
            return (p[0] - self.P0[0]) * self.u[0] + (p[1] - self.P0[1]) * self.u[1]
        rel = arc_rel(self.a0, self.sg, math.atan2(p[1] - self.C[1], p[0] - self.C[0]))
        return self.rho * rel

    def cut_line(self, nv, h):
        """s values where nv . p = h (nv unit)"""
        if self.kind == 'line':
            den = nv[0] * self.u[0] + nv[1] * self.u[1]
            if abs(den) < 1e-15:
                return []
            return [(h - nv[0] * self.P0[0] - nv[1] * self.P0[1]) / den]
        x = (h - nv[0] * self.C[0] - nv[1] * self.C[1]) / self.rho
        if x < -1.0 or x > 1.0:
            return []
        psi = math.atan2(nv[1], nv[0])
        al = math.acos(x)
        return [self.rho * arc_rel(self.a0, self.sg, psi + al),
                self.rho * arc_rel(self.a0, self.sg, psi - al)]

    def cut_circle(self, Q, rad):
        if rad <= 0:
            return []
        if self.kind == 'line':
            return line_circle_params(self.P0, self.u, Q, rad)
        out = []
        for p in circle_circle_points(self.C, self.rho, Q, rad):
            out.append(self.param(p))
        return out


def grow_feature(e, i, r):
    f = Feature()
    f.edge = i
    if e.kind == 'line':
        f.kind = 'line'
        f.u = e.u
        f.n = (e.u[1], -e.u[0])
        f.P0 = (e.P0[0] + r * f.n[0], e.P0[1] + r * f.n[1])
        f.length = e.L
        return f
    f.kind = 'arc'
    f.convex = e.sg > 0
    f.rho = e.R + r if f.convex else e.R - r
    if f.rho <= EPS:
        return None
    f.C, f.a0, f.sg = e.C, e.a0, e.sg
    f.length = f.rho * abs(e.sweep)
    return f


def breakpoints_edge(f, e, Rr):
    """s values where the distance from the feature to edge e may cross Rr"""
    out = []
    if e.kind == 'line':
        nv = (e.u[1], -e.u[0])
        h = nv[0] * e.P0[0] + nv[1] * e.P0[1]
        out += f.cut_line(nv, h + Rr)
        out += f.cut_line(nv, h - Rr)
        # slab ends (not needed for the level set, harmless)
        out += f.cut_circle(e.P0, Rr)
        out += f.cut_circle(e.P1, Rr)
    else:
        out += f.cut_circle(e.C, e.R + Rr)
        out += f.cut_circle(e.C, abs(e.R - Rr))
        out += f.cut_circle(e.P0, Rr)
        out += f.cut_circle(e.P1, Rr)
    return out


def build_segments_arcs(edges, access, r, trim, loops=None):
    """SPEC 2 + 8.2 for an outline with arcs (edges CCW, lattice units).
    loops (SPEC 9): [(first edge, number of edges)] of each closed loop of
    `edges` (outline CCW, holes CW); None = one loop."""
    n = len(edges)
    if loops is None:
        loops = [(0, n)]
    prv, nxt = [0] * n, [0] * n
    for st_, cnt in loops:
        for k in range(cnt):
            prv[st_ + k] = st_ + (k - 1) % cnt
            nxt[st_ + k] = st_ + (k + 1) % cnt
    acc_edges = []
    for poly in access:
        m = len(poly)
        acc_edges.append([make_edge(poly[j], poly[(j + 1) % m], 0.0) for j in range(m)])
    # smooth joints: vertex i joins edge i-1 (in) and edge i (out)
    smooth = []
    for i in range(n):
        ein, eout = edges[prv[i]], edges[i]
        t_in = edge_tangents(ein)[1]
        t_out = edge_tangents(eout)[0]
        smooth.append(abs(crs(t_in, t_out)) <= 1e-6 and dot(t_in, t_out) > 0
                      and (ein.kind == 'arc' or eout.kind == 'arc'))
    segs = []
    Rr = r - EPS
    for i, e in enumerate(edges):
        f = grow_feature(e, i, r)
        if f is None:
            continue
        L = f.length
        cuts = []
        for j, g in enumerate(edges):
            if j != i:
                cuts += breakpoints_edge(f, g, Rr)
        for ae in acc_edges:
            for g in ae:
                cuts += breakpoints_edge(f, g, r)
        cuts = sorted(set(s for s in cuts if 0.0 < s < L))
        ts = [0.0] + cuts + [L]
        kept = []
        for x, y in zip(ts, ts[1:]):
            if y - x <= 0:
                continue
            p = f.point((x + y) / 2)
            removed = region_dist(p, edges) < Rr
            if not removed:
                for poly in access:
                    if point_in_poly(p, poly) or pt_poly_bdist(p, poly) < r:
                        removed = True
                        break
            if removed:
                continue
            if kept and kept[-1][1] == x:
                kept[-1] = (kept[-1][0], y)
            else:
                kept.append((x, y))
        for x, y in kept:
            a = x if (x == 0.0 and smooth[i]) else x + trim
            b = y if (y == L and smooth[nxt[i]]) else y - trim
            if b - a > EPS:
                s = Seg()
                s.edge = i
                s.kind = f.kind
                s.s0, s.s1 = a, b
                s.feat = f
                if f.kind == 'line':
                    s.P0, s.u, s.n = f.P0, f.u, f.n
                    s.c = dot(f.n, f.P0)
                else:
                    s.C, s.rho, s.sg, s.a0, s.convex = f.C, f.rho, f.sg, f.a0, f.convex
                s.E0 = f.point(a)
                s.E1 = f.point(b)
                segs.append(s)
    for k, s in enumerate(segs):
        s.idx = k
    return segs, smooth


def seg_samples(sg, m=32):
    f = sg.feat
    return [f.point(sg.s0 + (sg.s1 - sg.s0) * i / m) for i in range(m + 1)], (sg.s1 - sg.s0) / m


def seg_dist_bounds(si, sj, same):
    """sound bounds [lo, hi] on |p - q| for p on si, q on sj (arcs sampled; every
    point is within half a sample step, in arc length, of a sample)"""
    A, ha = seg_samples(si)
    B, hb = seg_samples(sj)
    lo, hi = math.inf, 0.0
    for p in A:
        for q in B:
            d = math.hypot(p[0] - q[0], p[1] - q[1])
            if d < lo:
                lo = d
            if d > hi:
                hi = d
    sl = (ha + hb) / 2 + 1e-9
    if same:
        return 0.0, hi + sl
    return max(0.0, lo - sl), hi + sl


# -- poses of setups with arcs (SPEC 8.4)
NDFT = 16
DFT_TH = [TWO_PI * m / NDFT for m in range(NDFT)]
DFT_CS = [(math.cos(t), math.sin(t)) for t in DFT_TH]
DFT_K = 7
DFT_TAB = [[(math.cos(k * t), math.sin(k * t)) for t in DFT_TH] for k in range(DFT_K + 1)]
TANG = 1e-6       # |det J| (unit rows) <= this: tangential
RESID = 1e-9      # a reported pose has every locator within this of its feature
ULP_T = 64 * 2.0 ** -52  # C47: a line-circle tangency up to 64 ulps of its terms is exact


def line_circle_taus(tau0, dl, rho, scale):
    """C47: parameters tau along a line at signed distance dl from a circle's
    centre (tau0 = the foot of the centre) where it meets the circle of radius
    rho; `scale` bounds the magnitudes dl was computed from.  A tangency within
    rounding (| |dl| - rho | <= ULP_T * scale) is the exact double root tau0;
    a miss by <= RESID still counts as one tangent point (C28)."""
    gap = abs(dl) - rho
    if abs(gap) <= ULP_T * scale:
        return [tau0]
    if gap > 0:
        return [tau0] if gap <= RESID else []
    sq = math.sqrt(rho * rho - dl * dl)
    return [tau0 - sq, tau0 + sq]


def trig_eval(a, b, th):
    """G, G', G'' of G = a0 + sum a_k cos k th + b_k sin k th"""
    c1, s1 = math.cos(th), math.sin(th)
    ck, sk = 1.0, 0.0
    g, g1, g2 = a[0], 0.0, 0.0
    for k in range(1, len(a)):
        ck, sk = ck * c1 - sk * s1, sk * c1 + ck * s1
        t = a[k] * ck + b[k] * sk
        g += t
        g1 += k * (b[k] * ck - a[k] * sk)
        g2 -= k * k * t
    return g, g1, g2


def trig_roots(a, b, gscale):
    """all roots of the trigonometric polynomial on [0, 2 pi): list of (theta,
    'simple' | 'crit').  'crit' = a local extremum of G with |G| small and no
    sign change (a double root, or a near miss; the caller decides by residuals).
    Exclusion by derivative bounds (sound up to rounding)."""
    K = len(a) - 1
    mags = [math.hypot(a[k], b[k]) for k in range(K + 1)]
    tail = sum(mags[1:])
    slack = 1e-12 * gscale
    if a[0] - tail > slack or a[0] + tail < -slack:
        return []
    M1 = sum(k * mags[k] for k in range(1, K + 1))
    M2 = sum(k * k * mags[k] for k in range(1, K + 1))
    M3 = sum(k ** 3 * mags[k] for k in range(1, K + 1))
    crit_tol = 1e-6 * gscale
    out = []

    def G(t):
        return trig_eval(a, b, t)

    def bisect_root(lo, hi, glo, which):
        # which = 0: root of G; 1: root of G'
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if mid <= lo or mid >= hi:
                break
            gm = G(mid)[which]
            if gm == 0.0:
                return mid
            if (gm < 0) == (glo < 0):
                lo, glo = mid, gm
            else:
                hi = mid
        return 0.5 * (lo + hi)

    def monotone(lo, hi, vlo, vhi):
        if vlo[0] == 0.0:
            out.append((lo, 'simple'))
        elif vhi[0] != 0.0 and (vlo[0] < 0) != (vhi[0] < 0):
            out.append((bisect_root(lo, hi, vlo[0], 0), 'simple'))

    N0 = 32
    grid = [TWO_PI * i / N0 for i in range(N0 + 1)]
    vals = [G(t) for t in grid]
    stack = [(grid[i], grid[i + 1], vals[i], vals[i + 1]) for i in range(N0)]
    while stack:
        lo, hi, vlo, vhi = stack.pop()
        h = hi - lo
        if abs(vlo[0]) + abs(vhi[0]) > M1 * h + slack:
            continue
        if abs(vlo[1]) + abs(vhi[1]) > M2 * h + slack:
            monotone(lo, hi, vlo, vhi)
            continue
        if abs(vlo[2]) + abs(vhi[2]) > M3 * h + slack:
            # G' monotone: at most one critical point
            if vlo[1] != 0.0 and vhi[1] != 0.0 and (vlo[1] < 0) == (vhi[1] < 0):
                monotone(lo, hi, vlo, vhi)
                continue
            if vlo[1] == 0.0:
                c = lo
            elif vhi[1] == 0.0:
                c = hi
            else:
                c = bisect_root(lo, hi, vlo[1], 1)
            vc = G(c)
            if c > lo:
                monotone(lo, c, vlo, vc)
            if c < hi:
                monotone(c, hi, vc, vhi)
            elif vc[0] == 0.0:
                out.append((c, 'simple'))
            if abs(vc[0]) <= crit_tol:
                out.append((c, 'crit'))
            continue
        if h < 1e-12:
            mid = 0.5 * (lo + hi)
            if abs(G(mid)[0]) <= crit_tol:
                out.append((mid, 'crit'))
            continue
        mid = 0.5 * (lo + hi)
        vm = G(mid)
        stack.append((lo, mid, vlo, vm))
        stack.append((mid, hi, vm, vhi))
    return out


class ArcCombo:
    """pose solver for one segment combination (a, b, c) with at least one arc"""

    def __init__(self, S):
        self.S = S
        self.kinds = [s.kind for s in S]
        self.lines = [k for k in range(3) if S[k].kind == 'line']
        self.arcs = [k for k in range(3) if S[k].kind == 'arc']
        self.parallel = False
        if len(self.lines) == 2:
            n1, n2 = S[self.lines[0]].n, S[self.lines[1]].n
            if abs(crs(n1, n2)) <= EPS:
                self.parallel = True
        self.q = self.arcs[0]
        self.others = [k for k in range(3) if k != self.q]
        self.degenerate = 0     # eliminations that were singular for every theta
        self.continua = 0

    # residuals (distances) and Jacobian rows of the three equations
    def resid_jac(self, Ls, th, w):
        ct, st = math.cos(th), math.sin(th)
        res, rows = [], []
        for k in range(3):
            Lx, Ly = Ls[k]
            p = (ct * Lx + st * Ly - w[0], -st * Lx + ct * Ly - w[1])
            dp = (-st * Lx + ct * Ly, -ct * Lx - st * Ly)
            sg = self.S[k]
            if sg.kind == 'line':
                res.append(sg.n[0] * p[0] + sg.n[1] * p[1] - sg.c)
                rows.append((sg.n[0] * dp[0] + sg.n[1] * dp[1], -sg.n[0], -sg.n[1]))
            else:
                vx, vy = p[0] - sg.C[0], p[1] - sg.C[1]
                d = math.hypot(vx, vy)
                res.append(d - sg.rho)
                if d == 0:
                    rows.append((0.0, 0.0, 0.0))
                else:
                    rows.append(((vx * dp[0] + vy * dp[1]) / d, -vx / d, -vy / d))
        return res, rows

    @staticmethod
    def unit_det(rows):
        M = []
        for r in rows:
            nr = math.sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2])
            if nr == 0:
                return 0.0
            M.append((r[0] / nr, r[1] / nr, r[2] / nr))
        return det3(M)

    def polish(self, Ls, th, w):
        res, rows = self.resid_jac(Ls, th, w)
        best = (max(abs(x) for x in res), th, w, rows)
        for _ in range(8):
            d = det3(rows)
            if abs(self.unit_det(rows)) <= TANG or d == 0:
                break
            Mi = inv3(rows, d)
            dx = matvec(Mi, res)
            th2 = th - dx[0]
            w2 = (w[0] - dx[1], w[1] - dx[2])
            res2, rows2 = self.resid_jac(Ls, th2, w2)
            m2 = max(abs(x) for x in res2)
            if not m2 < best[0]:
                break
            th, w, res, rows = th2, w2, res2, rows2
            best = (m2, th, w, rows)
        return best

    def linsys(self, Ls, ct, st):
        """rows, rhs of the two linear equations, cc_q and rho_q, at theta"""
        S = self.S
        cc = {}
        for k in self.arcs:
            Lx, Ly = Ls[k]
            cc[k] = (ct * Lx + st * Ly - S[k].C[0], -st * Lx + ct * Ly - S[k].C[1])
        q = self.q
        cq = cc[q]
        rq = S[q].rho
        R, B = [], []
        for k in self.others:
            if S[k].kind == 'line':
                Lx, Ly = Ls[k]
                n = S[k].n
                R.append(n)
                B.append(n[0] * (ct * Lx + st * Ly) + n[1] * (-st * Lx + ct * Ly) - S[k].c)
            else:
                ck = cc[k]
                R.append((2 * (cq[0] - ck[0]), 2 * (cq[1] - ck[1])))
                B.append(cq[0] * cq[0] + cq[1] * cq[1] - ck[0] * ck[0] - ck[1] * ck[1]
                         - rq * rq + S[k].rho * S[k].rho)
        return R, B, cq, rq

    def solve(self, Ls):
        """list of poses (theta, w, tangential, |det J|)"""
        if self.parallel:
            cands = self.solve_parallel(Ls)
        else:
            cands = self.solve_general(Ls)
        poses = []
        for th, w, kind in cands:
            m, th, w, rows = self.polish(Ls, th, w)
            if not m <= RESID:
                continue
            jd = abs(self.unit_det(rows))
            th = norm_angle(th)
            poses.append([th, w, jd <= TANG, jd, m])
        # one pose per solution (SPEC 8.4); of duplicates keep the most accurate
        poses.sort(key=lambda p: p[4])
        out = []
        for p in poses:
            dup = False
            for o in out:
                dth = abs(p[0] - o[0])
                dth = min(dth, TWO_PI - dth)
                dw = math.hypot(p[1][0] - o[1][0], p[1][1] - o[1][1])
                if (dth <= 1e-9 and dw <= 1e-6) or (p[2] and o[2] and dth <= 1e-6 and dw <= 1e-6):
                    dup = True
                    break
            if not dup:
                out.append(p)
        out.sort(key=lambda p: p[0])
        return [p[:4] for p in out]

    def solve_parallel(self, Ls):
        S = self.S
        j, k = self.lines
        n = S[j].n
        sig = 1.0 if dot(n, S[k].n) > 0 else -1.0
        v = (Ls[j][0] - Ls[k][0], Ls[j][1] - Ls[k][1])
        A = dot(n, v)
        B = crs(n, v)
        Cc = S[j].c - sig * S[k].c
        rh = math.hypot(A, B)
        dlt = rh - abs(Cc)
        if dlt < -EPS:
            return []
        phi = math.atan2(B, A)
        if dlt <= EPS:
            ths = [phi if Cc >= 0 else phi + math.pi]
        else:
            al = math.acos(max(-1.0, min(1.0, Cc / rh)))
            ths = [phi - al, phi + al]
        q = self.q
        out = []
        nperp = (-n[1], n[0])
        for th in ths:
            ct, st = math.cos(th), math.sin(th)
            Lx, Ly = Ls[j]
            beta = n[0] * (ct * Lx + st * Ly) + n[1] * (-st * Lx + ct * Ly) - S[j].c
            Lx, Ly = Ls[q]
            cq = (ct * Lx + st * Ly - S[q].C[0], -st * Lx + ct * Ly - S[q].C[1])
            dl = dot(cq, n) - beta
            rho = S[q].rho
            tau0 = dot(cq, nperp)
            # magnitudes dl is computed from (C47)
            scale = (math.hypot(*Ls[j]) + abs(S[j].c) + math.hypot(*Ls[q])
                     + math.hypot(*S[q].C) + rho)
            taus = line_circle_taus(tau0, dl, rho, scale)
            for tau in taus:
                out.append((th, (beta * n[0] + tau * nperp[0], beta * n[1] + tau * nperp[1]), 'simple'))
        return out

    def G_at(self, Ls, ct, st):
        R, B, cq, rq = self.linsys(Ls, ct, st)
        (r1x, r1y), (r2x, r2y) = R
        b1, b2 = B
        det = r1x * r2y - r1y * r2x
        ax = r2y * b1 - r1y * b2
        ay = -r2x * b1 + r1x * b2
        wx, wy = det * cq[0] - ax, det * cq[1] - ay
        t1 = wx * wx + wy * wy
        t2 = rq * rq * det * det
        return t1 - t2, t1 + t2, det, math.hypot(r1x, r1y) * math.hypot(r2x, r2y)

    def solve_general(self, Ls):
        gs, sc, dets, dsc = [], 0.0, 0.0, 0.0
        for ct, st in DFT_CS:
            g, s_, d, ds = self.G_at(Ls, ct, st)
            gs.append(g)
            sc = max(sc, s_)
            dets = max(dets, abs(d))
            dsc = max(dsc, ds)
        if dets <= 1e-12 * max(dsc, 1e-300):
            self.degenerate += 1
            return []
        if max(abs(g) for g in gs) <= 1e-12 * sc:
            self.continua += 1
            return []
        a = [0.0] * (DFT_K + 1)
        b = [0.0] * (DFT_K + 1)
        a[0] = sum(gs) / NDFT
        for k in range(1, DFT_K + 1):
            tab = DFT_TAB[k]
            a[k] = 2.0 / NDFT * sum(g * t[0] for g, t in zip(gs, tab))
            b[k] = 2.0 / NDFT * sum(g * t[1] for g, t in zip(gs, tab))
        # G has degree <= 4 (see C28); the rest is rounding
        tail = max(abs(x) for x in a[5:] + b[5:])
        assert tail <= 1e-9 * sc, ('degree', tail, sc)
        a, b = a[:5], b[:5]
        roots = trig_roots(a, b, sc)
        out = []
        for th, kind in roots:
            ct, st = math.cos(th), math.sin(th)
            R, B, cq, rq = self.linsys(Ls, ct, st)
            (r1x, r1y), (r2x, r2y) = R
            b1, b2 = B
            det = r1x * r2y - r1y * r2x
            ws = []
            if abs(det) > 1e-7 * math.hypot(r1x, r1y) * math.hypot(r2x, r2y):
                ws.append(((r2y * b1 - r1y * b2) / det, (-r2x * b1 + r1x * b2) / det))
            else:
                # rank-deficient linear part: one linear equation and the circle
                i = 0 if math.hypot(*R[0]) >= math.hypot(*R[1]) else 1
                rv, bv = R[i], B[i]
                nr = math.hypot(*rv)
                if nr == 0:
                    continue
                nv = (rv[0] / nr, rv[1] / nr)
                beta = bv / nr
                pv = (-nv[1], nv[0])
                dl = dot(cq, nv) - beta
                disc = rq * rq - dl * dl
                tau0 = dot(cq, pv)
                taus = [tau0] if disc <= 0 else [tau0 - math.sqrt(disc), tau0 + math.sqrt(disc)]
                for tau in taus:
                    ws.append((beta * nv[0] + tau * pv[0], beta * nv[1] + tau * pv[1]))
            for w in ws:
                out.append((th, w, kind))
        return out


# -- clearance against the true posed region
def pose_edges(edges, ct, st, t):
    out = []
    th = math.atan2(st, ct)
    for e in edges:
        f = Edge()
        f.kind = e.kind
        f.P0 = (ct * e.P0[0] - st * e.P0[1] + t[0], st * e.P0[0] + ct * e.P0[1] + t[1])
        f.P1 = (ct * e.P1[0] - st * e.P1[1] + t[0], st * e.P1[0] + ct * e.P1[1] + t[1])
        if e.kind == 'line':
            f.L = e.L
            f.u = (ct * e.u[0] - st * e.u[1], st * e.u[0] + ct * e.u[1])
        else:
            f.C = (ct * e.C[0] - st * e.C[1] + t[0], st * e.C[0] + ct * e.C[1] + t[1])
            f.R, f.sweep, f.sg, f.L = e.R, e.sweep, e.sg, e.L
            f.a0 = e.a0 + th
        out.append(f)
    return out


def seg_edge_dist(A, B, e):
    """distance between the closed segment [A, B] and edge e"""
    if e.kind == 'line':
        return seg_seg_dist(A, B, e.P0, e.P1)
    u = sub(B, A)
    for t in line_circle_params(A, u, e.C, e.R):
        if 0.0 <= t <= 1.0:
            p = (A[0] + t * u[0], A[1] + t * u[1])
            if in_span(e, p):
                return 0.0
    best = min(pt_edge_dist(A, e), pt_edge_dist(B, e),
               math.sqrt(pt_seg_dist2(e.P0, A, B)), math.sqrt(pt_seg_dist2(e.P1, A, B)))
    L2 = u[0] * u[0] + u[1] * u[1]
    if L2 > 0:
        t = ((e.C[0] - A[0]) * u[0] + (e.C[1] - A[1]) * u[1]) / L2
        if 0.0 < t < 1.0:
            F = (A[0] + t * u[0], A[1] + t * u[1])
            if (F[0], F[1]) != e.C and in_span(e, F):
                best = min(best, abs(math.dist(F, e.C) - e.R))
    return best


def region_strictly_contains(p, edges):
    return region_contains(p, edges) and min(pt_edge_dist(p, e) for e in edges) > EPS


def poly_region_overlap(A, edges):
    """interiors intersect (best effort, for min_clearance == 0)"""
    na = len(A)
    for i in range(na):
        a0, a1 = A[i], A[(i + 1) % na]
        u = sub(a1, a0)
        for e in edges:
            if e.kind == 'line':
                d1 = orient(e.P0, e.P1, a0)
                d2 = orient(e.P0, e.P1, a1)
                d3 = orient(a0, a1, e.P0)
                d4 = orient(a0, a1, e.P1)
                if ((d1 > EPS and d2 < -EPS) or (d1 < -EPS and d2 > EPS)) and \
                   ((d3 > EPS and d4 < -EPS) or (d3 < -EPS and d4 > EPS)):
                    return True
            else:
                ts = line_circle_params(a0, u, e.C, e.R)
                if len(ts) == 2 and ts[1] - ts[0] > EPS:
                    for t in ts:
                        if EPS < t < 1 - EPS:
                            p = (a0[0] + t * u[0], a0[1] + t * u[1])
                            if in_span(e, p) and math.dist(p, e.P0) > EPS and math.dist(p, e.P1) > EPS:
                                return True
    for i in range(na):
        if region_strictly_contains(A[i], edges):
            return True
        m = ((A[i][0] + A[(i + 1) % na][0]) / 2, (A[i][1] + A[(i + 1) % na][1]) / 2)
        if region_strictly_contains(m, edges):
            return True
    for e in edges:
        pts = [e.P0]
        if e.kind == 'arc':
            ang = e.a0 + e.sweep / 2
            pts.append((e.C[0] + e.R * math.cos(ang), e.C[1] + e.R * math.sin(ang)))
        else:
            pts.append(((e.P0[0] + e.P1[0]) / 2, (e.P0[1] + e.P1[1]) / 2))
        for p in pts:
            if strictly_inside(p, A):
                return True
    return False


def poly_region_margin(A, Abb, edges, Ebb, mc):
    """margin (>= 0 ok, < 0 fail) of polygon A against the filled true region"""
    gap = bbox_gap(Abb, Ebb)
    if gap >= mc + 1e-3:
        return gap - mc
    na = len(A)
    d = math.inf
    for i in range(na):
        a0, a1 = A[i], A[(i + 1) % na]
        for e in edges:
            x = seg_edge_dist(a0, a1, e)
            if x < d:
                d = x
    if mc <= EPS:
        if poly_region_overlap(A, edges):
            return -1.0
        return d if d > 0 else 0.0
    m = d - mc
    if m < -EPS:
        return m
    if region_contains(A[0], edges) or point_in_poly(edges[0].P0, A):
        return -1.0
    return m


def add_fixture(fixtures, setup, score, sg, k, m, text, q, s, fit, margin, l):
    """Appends a fixture record (catalogue units) with its ranking key (C16)."""
    a, b, c, Ls, th, ct, st, t, ss, pp, smargin = setup
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


def line_clamp_candidates(sg, rot, t, Mi, D, E, cosmax, y0, base_margin):
    """SPEC 4's candidates on line segment sg for a setup posed by (rot, t):
    the open form-closure interval of s (lambda affine in s), then for each
    rotation k the plunger axis lines j meeting it, with the angle test.
    Yields (k, d, e, j, q, s, margin, f): tip centre q (plate frame) at
    parameter s, inward normal f, decision margin so far."""
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
    for i in range(3):
        if beta[i] > 0:
            lo = max(lo, (EPS - alpha[i]) / beta[i])
        elif beta[i] < 0:
            hi = min(hi, (EPS - alpha[i]) / beta[i])
        elif alpha[i] <= EPS:
            return
    if lo >= hi:
        return
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
            q = (Q0[0] + s * U[0], Q0[1] + s * U[1])
            lam_q = [alpha[i] + beta[i] * s for i in range(3)]
            margin = min(base_margin, min(x - EPS for x in lam_q),
                         s - sg.s0 - EPS, sg.s1 - EPS - s, cosang - EPS)
            if cosmax > EPS:
                margin = min(margin, cosang - cosmax)
            yield k, d, e, j, q, s, margin, f


def mount_search(q, d, e, j, Ls, r, tmin, tmax, mholes, alt, cols, rows, body, plunger,
                 mc, part_margin, posed_acc, acc_bb):
    """SPEC 4's mount search for a tip at q on axis line j of rotation (d, e):
    mounts by increasing extension, the first that passes holes, plate fit
    and clearance.  part_margin(poly, bb) is the clearance margin against
    the posed part (a polygon, or the true region of an outline with arcs).
    Returns (found, fail_margin), found = (m, text, fit, margin) or None."""
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
            x_ = part_margin(poly, bb)
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
    return found, fail_margin


def contact_normal_part(sg, p):
    """inward normal (part frame) of a contact at part-frame point p on segment sg"""
    if sg.kind == 'line':
        return (-sg.n[0], -sg.n[1])
    dx, dy = sg.C[0] - p[0], sg.C[1] - p[1]
    if not sg.convex:
        dx, dy = -dx, -dy
    return (dx / sg.rho, dy / sg.rho)


def process_setup_arcs(setup, segs, r, y0, tmin, tmax, cosmax, mc, mholes, alt, cols, rows,
                       EDG, ACC, body, plunger, D, E, counts, fixtures, applied, cen_m, rho_m,
                       q_scale, l):
    """process_setup for parts with arcs (SPEC 8.3, 8.5): line clamp segments as in
    section 4, arc clamp segments by line-circle intersections."""
    a, b, c, Ls, th, ct, st, t, ss, pp, smargin = setup

    def rot(v):
        return (ct * v[0] - st * v[1], st * v[0] + ct * v[1])

    def unrot(v):
        return (ct * v[0] + st * v[1], -st * v[0] + ct * v[1])

    S = (segs[a], segs[b], segs[c])
    cols3 = []
    nparts = []
    for k in range(3):
        fp = contact_normal_part(S[k], pp[k])
        nparts.append(fp)
        f = rot(fp)
        q = Ls[k]
        cols3.append((f[0], f[1], q[0] * f[1] - q[1] * f[0]))
    M = columns_matrix(cols3)
    dW = det3(M)
    if abs(dW) <= EPS:
        return
    Mi = inv3(M, dW)
    base_margin = min(smargin, abs(dW) - EPS)
    cache = {}

    def posed():
        if not cache:
            pe = pose_edges(EDG, ct, st, t)
            cache['part'] = (pe, region_bbox(pe))
            pa = [[(ct * x - st * y + t[0], st * x + ct * y + t[1]) for x, y in A] for A in ACC]
            cache['acc'] = (pa, [bbox(A) for A in pa])
        return cache

    def finish(sg, k, d, e, j, q, s, margin, f_part, p_part):
        # tip vs locators (independent of mount)
        tipm = min(math.hypot(q[0] - L[0], q[1] - L[1]) - 2 * r for L in Ls)
        if tipm < -EPS:
            return
        margin = min(margin, abs(tipm))
        pc_ = posed()
        (posed_part, part_bb), (posed_acc, acc_bb) = pc_['part'], pc_['acc']
        found, fail_margin = mount_search(q, d, e, j, Ls, r, tmin, tmax, mholes, alt, cols, rows,
                                          body, plunger, mc,
                                          lambda poly, bb: poly_region_margin(poly, bb, posed_part, part_bb, mc),
                                          posed_acc, acc_bb)
        if found is None:
            return
        m, text, fit, mmarg = found
        margin = min(margin, mmarg, fail_margin)
        pts = [(x * q_scale, y * q_scale) for x, y in pp]
        pts.append((p_part[0] * q_scale, p_part[1] * q_scale))
        nfs = nparts + [f_part]
        score = score_contacts(pts, nfs, applied, cen_m, rho_m)
        add_fixture(fixtures, setup, score, sg, k, m, text, q, s, fit, margin, l)

    for sg in segs:
        if sg.kind == 'line':
            for k, d, e, j, q, s, margin, _ in line_clamp_candidates(
                    sg, rot, t, Mi, D, E, cosmax, y0, base_margin):
                counts['candidates'] += 1
                p_part = (sg.P0[0] + s * sg.u[0], sg.P0[1] + s * sg.u[1])
                finish(sg, k, d, e, j, q, s, margin, (-sg.n[0], -sg.n[1]), p_part)
            continue
        # arc clamp segment (SPEC 8.5)
        RC = rot(sg.C)
        Cp = (RC[0] + t[0], RC[1] + t[1])
        rho = sg.rho
        for k in range(4):
            d = D[k]
            e = E[k]
            ce = Cp[0] * e[0] + Cp[1] * e[1]
            jlo = math.floor(ce - rho - y0) - 1
            jhi = math.ceil(ce + rho - y0) + 1
            for j in range(jlo, jhi + 1):
                off = j + y0 - ce
                disc = rho * rho - off * off
                if disc < 0:
                    continue
                if abs(abs(off) - rho) <= ULP_T * (abs(j) + abs(y0) + math.hypot(*RC)
                                                   + math.hypot(*t) + rho):
                    disc = 0.0      # C47: a tangency within rounding is exact
                sq = math.sqrt(disc)
                tmarg = rho - abs(off)
                base = (Cp[0] + off * e[0], Cp[1] + off * e[1])
                pts = [(base[0] + sq * d[0], base[1] + sq * d[1])]
                if sq > 0:
                    pts.append((base[0] - sq * d[0], base[1] - sq * d[1]))
                for q in pts:
                    if sg.convex:
                        f = ((Cp[0] - q[0]) / rho, (Cp[1] - q[1]) / rho)
                    else:
                        f = ((q[0] - Cp[0]) / rho, (q[1] - Cp[1]) / rho)
                    cosang = d[0] * f[0] + d[1] * f[1]
                    if cosang <= EPS or cosang < cosmax - EPS:
                        continue
                    p_part = unrot((q[0] - t[0], q[1] - t[1]))
                    s = sg.feat.param(p_part)
                    if not (sg.s0 + EPS < s < sg.s1 - EPS):
                        continue
                    wq = (f[0], f[1], q[0] * f[1] - q[1] * f[0])
                    lv = matvec(Mi, wq)
                    lam_q = (-lv[0], -lv[1], -lv[2])
                    if not min(lam_q) > EPS:
                        continue
                    counts['candidates'] += 1
                    margin = min(base_margin, min(x - EPS for x in lam_q),
                                 s - sg.s0 - EPS, sg.s1 - EPS - s, cosang - EPS, tmarg)
                    if cosmax > EPS:
                        margin = min(margin, cosang - cosmax)
                    finish(sg, k, d, e, j, q, s, margin, unrot(f), p_part)


# ---------------------------------------------------------------- holes (SPEC 9)
def closest_on_edge(p, e):
    """the point of edge e nearest to p"""
    if e.kind == 'line':
        ab = sub(e.P1, e.P0)
        L2 = dot(ab, ab)
        t = 0.0 if L2 <= 0 else max(0.0, min(1.0, dot(sub(p, e.P0), ab) / L2))
        return (e.P0[0] + t * ab[0], e.P0[1] + t * ab[1])
    dx, dy = p[0] - e.C[0], p[1] - e.C[1]
    d = math.hypot(dx, dy)
    if d > 0.0 and in_span(e, p):
        return (e.C[0] + e.R * dx / d, e.C[1] + e.R * dy / d)
    return e.P0 if math.dist(p, e.P0) <= math.dist(p, e.P1) else e.P1


def edge_edge_closest(e, f):
    """(distance, point on e) of the closest pair of two edges that do not
    intersect (every local minimum of the distance between a line and a circle
    or two circles is at an end point or on the normal through a centre)"""
    best = (math.inf, e.P0)

    def cand(p_e, q_f):
        nonlocal best
        d = math.dist(p_e, q_f)
        if d < best[0]:
            best = (d, p_e)
    for p in (e.P0, e.P1):
        cand(p, closest_on_edge(p, f))
    for q in (f.P0, f.P1):
        cand(closest_on_edge(q, e), q)
    for g, h, swap in ((e, f, False), (f, e, True)):
        if g.kind == 'arc' and h.kind == 'line':
            F = closest_on_edge(g.C, h)          # foot of the centre on the line
            G = closest_on_edge(F, g)
            if swap:
                cand(F, G)
            else:
                cand(G, F)
    if e.kind == 'arc' and f.kind == 'arc':
        dx, dy = f.C[0] - e.C[0], f.C[1] - e.C[1]
        d = math.hypot(dx, dy)
        if d > 0:
            u = (dx / d, dy / d)
            for s1 in (1, -1):
                p = (e.C[0] + s1 * e.R * u[0], e.C[1] + s1 * e.R * u[1])
                if not in_span(e, p):
                    continue
                for s2 in (1, -1):
                    q = (f.C[0] + s2 * f.R * u[0], f.C[1] + s2 * f.R * u[1])
                    if in_span(f, q):
                        cand(p, q)
    return best


def edge_frac(e, p):
    """position of a point of edge e as a fraction of the edge, in [0, 1]"""
    if e.kind == 'line':
        ab = sub(e.P1, e.P0)
        return max(0.0, min(1.0, dot(sub(p, e.P0), ab) / dot(ab, ab)))
    rel = arc_rel(e.a0, e.sg, math.atan2(p[1] - e.C[1], p[0] - e.C[0]))
    if rel > abs(e.sweep):       # just before the start (tolerance)
        rel = 0.0 if rel > (abs(e.sweep) + TWO_PI) / 2 else abs(e.sweep)
    return rel / abs(e.sweep)


def edge_at(e, fr):
    if e.kind == 'line':
        return (e.P0[0] + fr * (e.P1[0] - e.P0[0]), e.P0[1] + fr * (e.P1[1] - e.P0[1]))
    ang = e.a0 + e.sweep * fr
    return (e.C[0] + e.R * math.cos(ang), e.C[1] + e.R * math.sin(ang))


def loop_contact(A, B, tol):
    """first point where loop A (edges) meets loop B within tol, or None"""
    for e in A:
        for f in B:
            pts = edge_edge_points(e, f, tol)
            if pts == 'overlap':
                for q, g in ((e.P0, f), (e.P1, f), (f.P0, e), (f.P1, e)):
                    if pt_edge_dist(q, g) <= tol:
                        return q
                return e.P0
            if pts:
                return pts[0]
            d, p = edge_edge_closest(e, f)
            if d <= tol:
                return p
    return None


def loop_sides(A, B, tol):
    """(has a piece strictly inside B, has a piece strictly outside B): each
    edge of A is cut where it meets B and each piece judged at its midpoint"""
    has_in = has_out = False
    for e in A:
        fr = [0.0, 1.0]
        for f in B:
            pts = edge_edge_points(e, f, tol)
            if pts == 'overlap':
                continue
            fr += [edge_frac(e, p) for p in pts]
        fr = sorted(set(fr))
        for x, y in zip(fr, fr[1:]):
            for w in (0.5, 0.25, 0.75):
                m = edge_at(e, x + w * (y - x))
                if min(pt_edge_dist(m, f) for f in B) <= tol:
                    continue
                if region_contains(m, B):
                    has_in = True
                else:
                    has_out = True
                break
    return has_in, has_out


def check_holes(outline, holes, scale):
    """SPEC 9.1 across loops (each loop already valid on its own).
    outline, holes: edge lists in catalogue units, any orientation."""
    tol = 1e-9 * scale
    for k, H in enumerate(holes):
        p = loop_contact(H, outline, tol)
        if p is not None:
            has_in, has_out = loop_sides(H, outline, tol)
            verb = 'crosses' if (has_in and has_out) else 'touches'
            raise Invalid("part: hole %d %s the outline at (%g, %g)" % (k, verb, p[0], p[1]))
        if not region_contains(H[0].P0, outline):
            raise Invalid("part: hole %d lies outside the outline" % k)
        for j in range(k):
            G = holes[j]
            p = loop_contact(H, G, tol)
            if p is not None:
                has_in, has_out = loop_sides(H, G, tol)
                verb = 'crosses' if (has_in and has_out) else 'touches'
                raise Invalid("part: hole %d %s hole %d at (%g, %g)" % (k, verb, j, p[0], p[1]))
            if region_contains(H[0].P0, G):
                raise Invalid("part: hole %d lies inside hole %d" % (k, j))
            if region_contains(G[0].P0, H):
                raise Invalid("part: hole %d lies inside hole %d" % (j, k))


def reverse_loop(verts):
    """SPEC 8.1 / 9.2: (v0, v1, ..., v(n-1)) -> (v0, v(n-1), ..., v1), each
    bulge negated and moved with its edge"""
    nv = len(verts)
    return [(verts[0][0], verts[0][1], -verts[nv - 1][2])] + \
        [(verts[nv - k][0], verts[nv - k][1], -verts[nv - k - 1][2]) for k in range(1, nv)]


def loop_edges(verts, scale=1.0):
    nv = len(verts)
    return [make_edge((verts[i][0] / scale, verts[i][1] / scale),
                      (verts[(i + 1) % nv][0] / scale, verts[(i + 1) % nv][1] / scale), verts[i][2])
            for i in range(nv)]


def parse_holes(raw_holes, outline_verts):
    """validates the holes of a part (SPEC 9.1) and normalises each to
    clockwise (SPEC 9.2); returns the list of normalised vertex lists"""
    if not isinstance(raw_holes, list):
        raise Invalid("part: holes is not a list of loops")
    hverts = []
    hedges = []
    for k, h in enumerate(raw_holes):
        name = 'part: hole %d' % k
        if not isinstance(h, list):
            raise Invalid("%s: not a list of vertices" % name)
        vs = parse_vertices(h, name)
        if any(v[2] != 0.0 for v in vs):
            es = validate_outline(vs, name)
        else:
            validate_polygon([[x, y] for x, y, _ in vs], name)
            es = loop_edges(vs)
        hverts.append(vs)
        hedges.append(es)
    scale = max(1.0, max(max(abs(v[0]), abs(v[1])) for v in outline_verts))
    check_holes(loop_edges(outline_verts), hedges, scale)
    out = []
    for vs, es in zip(hverts, hedges):
        if true_signed_area(es) > 0:
            vs = reverse_loop(vs)
        out.append(vs)
    return out


# ---------------------------------------------------------------- main solver
def parse_vertices(raw, name):
    out = []
    for i, p in enumerate(raw):
        if not isinstance(p, (list, tuple)) or len(p) not in (2, 3) or \
           not all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in p):
            raise Invalid("%s: vertex %d is not a finite point" % (name, i))
        out.append((float(p[0]), float(p[1]), float(p[2]) if len(p) == 3 else 0.0))
    return out


def part_loops(case):
    """validates the part of a case (outline, then holes: SPEC 1, 8.1, 9.1) and
    normalises it (SPEC 9.2): returns (outline vertices CCW, [hole vertices
    CW], outline has arcs), vertices (x, y, bulge) in catalogue units"""
    verts = parse_vertices(case['part'], 'part')
    has_arcs = any(v[2] != 0.0 for v in verts)
    if has_arcs:
        edges_phys = validate_outline(verts, 'part')
    else:
        validate_polygon([[v[0], v[1]] for v in verts], 'part')
    holes_raw = case.get('holes') or []
    hole_verts = parse_holes(holes_raw, verts) if holes_raw else []
    # normalise to CCW (SPEC 8.1: the orientation is the sign of the true area;
    # reversing moves each bulge with its edge and flips its sign)
    if has_arcs:
        if true_signed_area(edges_phys) < 0:
            verts = reverse_loop(verts)
    else:
        if signed_area([(x, y) for x, y, _ in verts]) < 0:
            verts = reverse_loop(verts)
    return verts, hole_verts, has_arcs


def material_props(case):
    """area, centroid, radius of gyration of the part region (SPEC 9.5), in
    catalogue units"""
    verts, hole_verts, _ = part_loops(case)
    edges = loop_edges(verts)
    for hv in hole_verts:
        edges += loop_edges(hv)
    return true_area_props(edges)


def solve(case, max_seconds=None, generic=False):
    t_start = time.time()
    units = case.get('units', 'mm')
    part = case['part']
    access = case.get('access') or []
    kit = case['kit']
    params = case.get('params') or {}
    verts, hole_verts, has_arcs = part_loops(case)
    has_holes = len(hole_verts) > 0
    arc_path = has_arcs or generic or has_holes
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

    part = [(x, y) for x, y, _ in verts]
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

    EDG = None
    loop_of = None
    if arc_path:
        # SPEC 9.2: outline edges first, then each (clockwise) hole's, in input order
        EDG = loop_edges(verts, l)
        loops = [(0, len(EDG))]
        loop_of = [0] * len(EDG)
        for hk, hv in enumerate(hole_verts):
            he = loop_edges(hv, l)
            loops.append((len(EDG), len(he)))
            loop_of += [hk + 1] * len(he)
            EDG += he
        segs, _smooth = build_segments_arcs(EDG, ACC, r, trim, loops)
    else:
        segs = build_segments(P, ACC, r, trim)
    nseg = len(segs)
    counts = {'segments': nseg, 'combinations': 0, 'setups': 0, 'candidates': 0, 'admissible': 0}

    # quality metric setup
    if arc_path:
        _, cen, rho = true_area_props(EDG)
    else:
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
            if segs[i].kind == 'arc' or segs[j].kind == 'arc':
                dlo[i][j], dhi[i][j] = seg_dist_bounds(segs[i], segs[j], i == j)
            elif i == j:
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
    diag = {'continua': 0, 'degenerate': 0, 'tangential': 0}
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
                if S[0].kind == 'arc' or S[1].kind == 'arc' or S[2].kind == 'arc':
                    enumerate_arc_combo(a, b, c, S, rng, pts_q, n2_q, pts_all, n2_all, dlo, dhi, SL,
                                        counts, diag,
                                        lambda setup: process_setup_arcs(
                                            setup, segs, r, y0, tmin, tmax, cosmax, mc, mholes, alt,
                                            cols, rows, EDG, ACC, body, plunger, D, E, counts,
                                            fixtures, applied, cen_m, rho_m, q_scale, l))
                    continue
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
                            if arc_path:
                                process_setup_arcs(setup, segs, r, y0, tmin, tmax, cosmax, mc, mholes,
                                                   alt, cols, rows, EDG, ACC, body, plunger, D, E,
                                                   counts, fixtures, applied, cen_m, rho_m, q_scale, l)
                            else:
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
    res = {'status': status, 'counts': counts, 'fixtures': out,
           'seconds': round(time.time() - t_start, 3)}
    if arc_path:
        res['segment_kinds'] = [s.kind for s in segs]
        if has_holes:
            res['segment_loops'] = [loop_of[s.edge] for s in segs]
        res['arc_diagnostics'] = diag
    return res


def enumerate_arc_combo(a, b, c, S, rng, pts_q, n2_q, pts_all, n2_all, dlo, dhi, SL, counts, diag,
                        process):
    """setups of a combination with at least one arc (SPEC 8.4)"""
    solver = ArcCombo(S)
    for (_, i2, j2) in rng(pts_q, n2_q, dlo[a][b], dhi[a][b]):
        L2 = (i2, j2)
        for (_, i3, j3) in rng(pts_all, n2_all, dlo[a][c], dhi[a][c]):
            if i3 == i2 and j3 == j2:
                continue
            dd = math.hypot(i3 - i2, j3 - j2)
            if dd < dlo[b][c] - SL or dd > dhi[b][c] + SL:
                continue
            Ls = ((0, 0), L2, (i3, j3))
            for th, w, tang, jd in solver.solve(Ls):
                ct, st = math.cos(th), math.sin(th)
                ss, pp = [], []
                ok = True
                margin = 1.0 if tang is False else 0.0
                if not tang:
                    margin = min(margin, jd - TANG)
                for k in range(3):
                    Lx, Ly = Ls[k]
                    p = (ct * Lx + st * Ly - w[0], -st * Lx + ct * Ly - w[1])
                    sg = S[k]
                    sv = sg.feat.param(p)
                    if not (sg.s0 + EPS < sv < sg.s1 - EPS):
                        ok = False
                        if SETUP_LOG is not None and min(abs(sv - sg.s0), abs(sv - sg.s1)) < 1e-5:
                            SETUP_LOG.write(json.dumps(['rejected', a, b, c, Ls, math.degrees(th), tang,
                                                        k, sv - sg.s0, sg.s1 - sv]) + '\n')
                        break
                    margin = min(margin, sv - sg.s0 - EPS, sg.s1 - EPS - sv)
                    ss.append(sv)
                    pp.append(p)
                if not ok:
                    continue
                if a == b and not ss[0] < ss[1]:
                    continue
                if b == c and not ss[1] < ss[2]:
                    continue
                counts['setups'] += 1
                if tang:
                    diag['tangential'] += 1
                if SETUP_LOG is not None:
                    SETUP_LOG.write(json.dumps([a, b, c, Ls, math.degrees(th), tang, margin]) + '\n')
                tx = ct * w[0] - st * w[1]
                ty = st * w[0] + ct * w[1]
                process((a, b, c, Ls, th, ct, st, (tx, ty), ss, pp, margin))
    diag['continua'] += solver.continua
    diag['degenerate'] += solver.degenerate


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
        for k, d, e, j, q, s, margin, f in line_clamp_candidates(
                sg, rot, t, Mi, D, E, cosmax, y0, base_margin):
            counts['candidates'] += 1
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
            found, fail_margin = mount_search(q, d, e, j, Ls, r, tmin, tmax, mholes, alt, cols, rows,
                                              body, plunger, mc,
                                              lambda poly, bb: poly_poly_margin(poly, bb, posed_part, part_bb, mc),
                                              posed_acc, acc_bb)
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
            add_fixture(fixtures, setup, score, sg, k, m, text, q, s, fit, margin, l)


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
        res = solve(case, ms, generic='--generic' in argv)
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
