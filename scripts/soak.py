#!/usr/bin/env python3
"""Soak test (issue 31; not in CI): thousands of parts, about 1% of them
hostile, run while the script SIGKILLs the run (and, with --workers, its
worker processes) at random moments and resumes it until it completes;
then every good part is compared with an uninterrupted run's.

    python3 scripts/soak.py --bin target/ci/fixplan-it --repeat 60 --minutes 3

Hostile parts (inline, one after every 100 good ones, in turn): an arc of
bulge 1e9 and a point 1e12 mm away (invalid), a self-crossing outline
(invalid), a part 1.5 m long (over its --part-setups budget), and one part
the run dies on (`--fault abort-on:ID`, as a part the OOM killer or a
stack overflow would end it on: the journal must make it `failed` after
two deaths, and the run go on). The uninterrupted reference run has no
fault, so the killer is an ordinary part there.

Prints the counts per outcome: kills, deaths by the killer, resumes,
statuses of the final file, good parts identical / failed by the
script's own kills (in flight at two of them, the second time alone:
the journal cannot tell an outside kill from a part's) / different /
missing. Exit code 1 if a good part differs otherwise or is missing.
"""

import argparse
import json
import os
import pathlib
import random
import re
import signal
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
SETUPS = "20000"

HOSTILE = [
    ("bulge", "outline = [[0, 0, 1e9], [10, 0], [5, 5]]"),
    ("far", "outline = [[0, 0], [1e12, 0], [0, 1]]"),
    ("cross", "outline = [[0, 0], [50, 50], [50, 0], [0, 50]]"),
    ("huge", "outline = [[0, 0], [1500, 0], [1500, 300], [0, 300]]"),
]
KILLER = "killer-0"


def catalogue(out: pathlib.Path, repeat: int) -> list:
    """The sample catalogue `repeat` times over with hostile parts mixed
    in; returns the hostile ids."""
    subprocess.run(
        [sys.executable, str(ROOT / "scripts/repeat_catalog.py"), str(ROOT / "examples/catalog"),
         str(repeat), str(out)], check=True, stdout=subprocess.DEVNULL)
    manifest = out / "catalog.toml"
    head, *parts = manifest.read_text().split("[[part]]")
    text, hostile, k = [head], [], 0
    for i, p in enumerate(parts):
        text.append("[[part]]" + p)
        if i % 100 == 50:
            if k == 2:
                pid, entry = KILLER, "outline = [[0, 0], [70, 0], [70, 40], [0, 40]]"
            else:
                name, entry = HOSTILE[k % len(HOSTILE)]
                pid = f"hostile-{name}-{k}"
            text.append(f'[[part]]\nid = "{pid}"\n{entry}\n\n')
            hostile.append(pid)
            k += 1
    manifest.write_text("".join(text))
    return hostile


def run_args(binary, cat, out, workers):
    a = [binary, "run", "--catalog", str(cat), "-o", str(out), "-q", "--threads", "2",
         "--part-setups", SETUPS]
    if workers:
        a += ["--workers", str(workers), "--transport", "zenoh"]
    return a


def export(binary, path) -> dict:
    out = subprocess.run([binary, "export", str(path), "--json"], capture_output=True, check=True)
    lines = {}
    for line in out.stdout.decode().splitlines():
        lines[json.loads(line)["part"]] = line
    return lines


def children(pid: int) -> list:
    """Processes whose parent is `pid` (its local workers)."""
    kids = []
    for d in pathlib.Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                stat = (d / "stat").read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                kids.append(int(d.name))
    return kids


def kill(pid: int) -> None:
    try:
        os.kill(pid, signal.SIGKILL)
    except ProcessLookupError:
        pass


def soak(binary, cat, out, workers, deadline, rng, counts):
    """Runs, kills and resumes until the run completes; fills `counts`."""
    resume = []
    while True:
        args = run_args(binary, cat, out, workers) + ["--fault", f"abort-on:{KILLER}"] + resume
        log = open(out.with_suffix(".log"), "w+b")
        p = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=log)
        stop = time.time() + rng.uniform(0.3, 3.0)
        kids = []
        while p.poll() is None and (time.time() < stop or time.time() > deadline):
            kids = children(p.pid) or kids
            if workers and kids and rng.random() < 0.02:
                kill(rng.choice(kids))
                counts["workers killed"] += 1
            if time.time() > stop + 60:
                break  # a hung run (all workers killed): killed below
            time.sleep(0.05)
        if p.poll() is None:
            kill(p.pid)
            counts["runs killed"] += 1
        p.wait()
        log.seek(0)
        err = log.read().decode(errors="replace")
        log.close()
        for k in kids:  # orphaned workers of a killed coordinator
            kill(k)
        if p.returncode == 0:
            return
        if p.returncode == -signal.SIGABRT:
            counts["deaths by the killer part"] += 1
        elif p.returncode != -signal.SIGKILL:
            counts["other exits"] += 1
            print(f"exit {p.returncode}: {err[-400:]}", file=sys.stderr)
        counts["resumes"] += 1
        resume = ["--resume"]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default=str(ROOT / "target/ci/fixplan-it"))
    ap.add_argument("--repeat", type=int, default=60, help="copies of the sample catalogue (35 parts each)")
    ap.add_argument("--minutes", type=float, default=3.0, help="stop killing after this long")
    ap.add_argument("--workers", type=int, default=0, help="run with N local workers (kills them too)")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    rng = random.Random(a.seed)
    with tempfile.TemporaryDirectory(prefix="fixplan-soak-") as tmp:
        tmp = pathlib.Path(tmp)
        hostile = catalogue(tmp / "cat", a.repeat)
        cat = tmp / "cat/catalog.toml"
        ref = tmp / "ref.mcap"
        t0 = time.time()
        subprocess.run(run_args(a.bin, cat, ref, 0), check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
        print(f"reference run: {time.time() - t0:.1f} s")
        want = export(a.bin, ref)
        counts = {k: 0 for k in ["runs killed", "workers killed", "deaths by the killer part",
                                 "other exits", "resumes"]}
        out = tmp / "soak.mcap"
        t0 = time.time()
        soak(a.bin, cat, out, a.workers, t0 + 60 * a.minutes, rng, counts)
        got = export(a.bin, out)
        statuses = {}
        for line in got.values():
            s = json.loads(line)["status"]
            statuses[s] = statuses.get(s, 0) + 1
        good = [i for i in want if i not in hostile]
        same = sum(1 for i in good if got.get(i) == want[i])
        missing = sum(1 for i in good if i not in got)
        changed = [i for i in good if i in got and got[i] != want[i]]
        # A good part in flight at two of the script's own kills (the
        # second time alone) is failed by design: the journal cannot tell
        # an outside kill from the part's. Anything else is a bug.
        unlucky = [i for i in changed if "killed the process twice" in got[i]]
        differ = [i for i in changed if i not in unlucky]
        print(f"parts: {len(want)} ({len(good)} good, {len(hostile)} hostile); soak {time.time() - t0:.0f} s"
              f"{' with ' + str(a.workers) + ' workers' if a.workers else ''}")
        for k, v in counts.items():
            print(f"  {k:28} {v}")
        print("  final statuses:            " + ", ".join(f"{k} {v}" for k, v in sorted(statuses.items())))
        for h in hostile:
            r = json.loads(got[h]) if h in got else {"status": "missing"}
            print(f"  {h:28} {r['status']}: {r.get('error', '')[:110]}")
        print(f"  good parts identical        {same}")
        print(f"  good parts failed by kills  {len(unlucky)} {unlucky[:5]}")
        print(f"  good parts different        {len(differ)} {differ[:5]}")
        print(f"  good parts missing          {missing}")
        return 1 if differ or missing else 0


if __name__ == "__main__":
    sys.exit(main())
