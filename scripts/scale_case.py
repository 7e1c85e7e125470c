#!/usr/bin/env python3
"""Scale a case file's part (and access regions) by a factor, on a bigger
plate, keeping the lattice, locators and clamp: the way issue 15 grows
housing-57 into a part with millions of fixtures.

    scripts/scale_case.py examples/cases/housing-57.json 3 56 \
        > examples/cases/large/housing-57-x3.json
"""
import json
import sys


def scale(case, factor, holes):
    """Part outline, access regions and plate scaled; bulges unchanged (an
    arc's bulge does not depend on its size)."""
    case["part"] = [
        [round(v[0] * factor, 10), round(v[1] * factor, 10)] + list(v[2:]) for v in case["part"]
    ]
    case["access"] = [
        [[round(p[0] * factor, 10), round(p[1] * factor, 10)] for p in region]
        for region in case.get("access", [])
    ]
    case["kit"]["cols"] = holes
    case["kit"]["rows"] = holes
    return case


def main():
    if len(sys.argv) != 4:
        sys.exit("usage: scale_case.py CASE.json FACTOR HOLES")
    with open(sys.argv[1]) as f:
        case = json.load(f)
    out = scale(case, float(sys.argv[2]), int(sys.argv[3]))
    json.dump(out, sys.stdout, indent=1)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
