#!/usr/bin/env python3
"""Writes the hand-made SPEC 9 cases (parts with holes) of this folder.

usage (from the repository root): python3 scripts/spec_cases_holes/gen_cases.py

Kit and parameters are those of scripts/spec_cases/l-shape.json (spacing 10,
12 x 12 plate, locator radius 3, the two-hole clamp).  These cases are NOT in
scripts/spec_cases/ because the Rust solver does not read holes yet; they are
for scripts/spec_reference.py and scripts/spec_reference_holes_test.py.
"""
import json, copy, os
base = json.load(open('scripts/spec_cases/l-shape.json'))
kit = base['kit']
def case(name, part, holes, angle=45, pattern='square', access=None, mc=1.0):
    c = {'units': 'mm', 'part': part, 'holes': holes, 'access': access or [],
         'kit': copy.deepcopy(kit),
         'params': {'max_clamp_angle_deg': angle, 'edge_trim': 1.0, 'min_clearance': mc,
                    'grid_step': 1, 'top_k': 0, 'wrenches': None}}
    c['kit']['pattern'] = pattern
    json.dump(c, open('scripts/spec_cases_holes/%s.json' % name, 'w'), indent=1)
    open('scripts/spec_cases_holes/%s.json' % name, 'a').write('\n')
def circ(cx, cy, R):
    return [[cx - R, cy, 1], [cx + R, cy, 1]]
rect = lambda x0, y0, x1, y1: [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
case('washer-round', circ(0, 0, 20), [circ(0, 0, 8)], angle=90)
case('washer-square', rect(0, 0, 40, 40), [circ(20, 20, 8)])
case('plate-bore', rect(0, 0, 50, 30), [circ(15, 15, 6)])
case('window-plate', rect(0, 0, 50, 40), [rect(15, 13, 35, 27)])
case('slot-narrow', rect(0, 0, 50, 30), [[[15, 12.5], [35, 12.5, 1], [35, 17.5], [15, 17.5, 1]]])
case('bore-near-edge', rect(0, 0, 50, 30), [circ(9, 15, 5)], pattern='alternating')
case('frame-window-clamp', rect(0, 0, 56, 40), [rect(10, 10, 46, 30)])
case('flange-bolts', circ(0, 0, 28), [circ(0, 0, 10), circ(19, 0, 3.5), circ(0, 19, 4.5)], angle=60)
ccw = [[20, 10], [30, 10, 1], [30, 20], [20, 20, 1]]
cw = [[20, 10, -1], [20, 20], [30, 20, -1], [30, 10]]
case('slot-hole-ccw', rect(0, 0, 50, 30), [ccw])
case('slot-hole-cw', rect(0, 0, 50, 30), [cw])
case('invalid-hole-crosses-outline', rect(0, 0, 50, 30), [circ(15, 15, 6), rect(40, 10, 55, 20)])
case('invalid-hole-in-hole', rect(0, 0, 50, 30), [rect(10, 5, 40, 25), circ(25, 15, 4)])
case('invalid-hole-touches-outline', rect(0, 0, 50, 30), [circ(44, 15, 6)])
case('invalid-holes-touch', rect(0, 0, 50, 30), [circ(15, 15, 5), rect(20, 10, 30, 20)])
