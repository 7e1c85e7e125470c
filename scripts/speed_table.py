#!/usr/bin/env python3
"""Regenerate the README's speed table with one command.

    python3 scripts/speed_table.py            # release build, measure, rewrite README.md
    python3 scripts/speed_table.py --print    # measure and print, README untouched
    python3 scripts/speed_table.py --bin target/release/fixplan --repeat 5

Builds `fixplan` in release mode (unless --bin names one), then measures on
one core (`taskset -c 1` when the machine has it): the bundled bench cases
with full counts and in top-10 mode (`fixplan bench --markdown`), and the
big cases of examples/cases/large in top-10 mode only (their full counts
take minutes). The rows replace what lies between the README's
`speed-table` markers, with a line saying when, where and from which
commit they were taken. Times are the fastest of --repeat runs; counts are
exact and must not move unless the enumeration changed.
"""

import argparse
import datetime
import glob
import os
import platform
import re
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
README = os.path.join(ROOT, "README.md")
BEGIN = "<!-- speed-table: begin (written by scripts/speed_table.py) -->"
END = "<!-- speed-table: end -->"

# Brost & Goldberg (1996), Table 1: their Lisp implementation on a 1996
# workstation, for the two parts of the paper we reproduce as cases.
PAPER = {"gluegun-28": "129.4 s", "housing-57": "3 h 21 min"}


def build_release():
    subprocess.run(
        ["cargo", "build", "--release", "--locked", "--bin", "fixplan"],
        cwd=ROOT,
        check=True,
    )
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    return os.path.join(target, "release", "fixplan")


def one_core(cmd):
    """Pins the measurement to core 1 where taskset exists: the README's
    figures are one-core figures, and a second core would blur them."""
    if shutil.which("taskset") and (os.cpu_count() or 1) > 1:
        return ["taskset", "-c", "1"] + cmd
    return cmd


def bench_rows(binary, args):
    out = subprocess.run(
        one_core([binary, "bench", "--markdown"] + args),
        cwd=ROOT,
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    lines = [l for l in out.splitlines() if l.startswith("|")]
    if len(lines) < 3:
        sys.exit(f"fixplan bench --markdown printed no rows:\n{out}")
    return lines[0], lines[2:]


def with_paper_column(header, rows):
    out = [header + " Brost & Goldberg (1996) |", "|---" * header.count("|") + "|"]
    for row in rows:
        name = re.match(r"\| `([^`]+)`", row)
        out.append(row + f" {PAPER.get(name.group(1) if name else '', '-')} |")
    return out


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def commit():
    try:
        rev = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no"],
            cwd=ROOT,
            capture_output=True,
            text=True,
        ).stdout.strip()
        return rev + ("+changes" if dirty else "")
    except OSError:
        return "unknown"


def table(binary, repeat):
    header, small = bench_rows(binary, ["--repeat", str(repeat)])
    large_cases = sorted(glob.glob(os.path.join(ROOT, "examples/cases/large/*.json")))
    _, large = bench_rows(binary, ["--top-k-only", "--repeat", str(max(1, repeat // 5))] + large_cases)
    when = datetime.date.today().isoformat()
    build = "Release build" if "/release/" in binary else f"Binary {binary}"
    intro = (
        f"{build}, one core, max clamp angle 45 degrees, grid step 1; {when}, "
        f"commit {commit()}, {cpu_model()}. Times are the enumeration's (the part "
        f"prepared once, outside the clock; the tables it works out on first use, "
        f"pair bounds and pivot points, inside it, for every run as in a real run), "
        f"fastest of {repeat} runs "
        f"({max(1, repeat // 5)} for the large cases, top-10 mode only)."
    )
    return [intro, ""] + with_paper_column(header, small + large)


def write_readme(lines):
    text = open(README).read()
    if BEGIN not in text or END not in text:
        sys.exit(f"README.md has no speed-table markers ({BEGIN} ... {END})")
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    with open(README, "w") as f:
        f.write(head + BEGIN + "\n" + "\n".join(lines) + "\n" + END + tail)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--bin", help="a fixplan binary to measure (default: build release)")
    parser.add_argument("--repeat", type=int, default=20, help="runs per part; the fastest counts")
    parser.add_argument("--print", action="store_true", help="print the table, leave README.md")
    args = parser.parse_args()
    binary = args.bin or build_release()
    lines = table(binary, args.repeat)
    if args.print:
        print("\n".join(lines))
    else:
        write_readme(lines)
        print(f"README.md: speed table rewritten ({len(lines) - 4} parts)")


if __name__ == "__main__":
    main()
