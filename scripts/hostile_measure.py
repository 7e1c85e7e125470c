#!/usr/bin/env python3
"""Counts per outcome of fixplan on hostile inputs (issue 31), for the
before/after figures: crash (panic, abort, signal), hang (past the
timeout), silent (exit 0 on a damaged results file whose export differs
from the sound one's, or a damaged result kept by --resume), clear
(a non-zero exit with a message, or exit 0 with the sound output).

Usage: scripts/hostile_measure.py BIN [--timeout S] [--flips N]
Run from the repository root; makes its inputs in a temporary directory
(the small fixed ones are tests/hostile/). Not run by CI: it is slow."""
import argparse, collections, os, random, shutil, subprocess, sys, tempfile

def run(cmd, timeout, cwd=None):
    try:
        p = subprocess.run(cmd, capture_output=True, timeout=timeout, cwd=cwd)
    except subprocess.TimeoutExpired:
        return "hang", b"", b""
    err = p.stderr
    if p.returncode < 0 or p.returncode >= 128 or p.returncode == 101 or b"panicked" in err:
        return "crash", p.stdout, err
    return ("ok" if p.returncode == 0 else "error"), p.stdout, err

def part_cases(tmp):
    """Hostile parts, kits and manifests: (name, argv tail)."""
    d = os.path.join(tmp, "parts")
    os.makedirs(d, exist_ok=True)
    def w(name, text):
        path = os.path.join(d, name)
        with open(path, "w") as f:
            f.write(text)
        return path
    good = '{"part": [[0,0],[90,0],[90,40],[0,40]]}'
    cases = {}
    cases["bulge-1e9.json"] = w("bulge-1e9.json", '{"part": [[0,0,1e9],[10,0],[5,5]]}')
    cases["bulge-1e-320.json"] = w("bulge-1e-320.json", '{"part": [[0,0,1e-320],[10,0],[5,5]]}')
    lines = "".join(f"0\nLWPOLYLINE\n8\n0\n90\n3\n70\n1\n10\n0\n20\n0\n42\n-1e9\n10\n10\n20\n0\n10\n5\n20\n5\n")
    cases["bulge-neg-1e9.dxf"] = w("bulge-neg-1e9.dxf", "0\nSECTION\n2\nENTITIES\n" + lines + "0\nENDSEC\n0\nEOF\n")
    cases["nested-g.svg"] = w("nested-g.svg", '<svg xmlns="http://www.w3.org/2000/svg">' + "<g>" * 200000 + '<path d="M0 0 h90 v40 h-90 Z"/>' + "</g>" * 200000 + "</svg>")
    n = 20000
    import math
    ring = [[round(50 * math.cos(2 * math.pi * i / n), 6), round(50 * math.sin(2 * math.pi * i / n), 6)] for i in range(n)]
    cases["vertices-20000.json"] = w("vertices-20000.json", '{"part": %s}' % ring)
    out = []
    for name, path in cases.items():
        man = w(name + ".toml", f'name = "h"\nunits = "mm"\n[[part]]\nid = "good-a"\noutline = [[0,0],[90,0],[90,40],[0,40]]\n[[part]]\nid = "bad"\nfile = "{os.path.basename(path)}"\n[[part]]\nid = "good-b"\noutline = [[0,0],[60,0],[60,30],[0,30]]\n')
        out.append((name, ["--catalog", man]))
    man = w("units-in.toml", 'name = "h"\nunits = "mm"\n[[part]]\nid = "big"\nfile = "big.json"\nunits = "in"\n')
    w("big.json", '{"part": [[0,0],[110,0],[110,20],[0,20]]}')
    out.append(("manifest-units-in", ["--catalog", man]))
    fifo = os.path.join(d, "fifo.json")
    if not os.path.exists(fifo):
        os.mkfifo(fifo)
    man = w("fifo.toml", 'name = "h"\nunits = "mm"\n[[part]]\nid = "f"\nfile = "fifo.json"\n[[part]]\nid = "good"\noutline = [[0,0],[90,0],[90,40],[0,40]]\n')
    out.append(("manifest-fifo", ["--catalog", man]))
    fifo_dir = os.path.join(tmp, "fifo-dir")
    os.makedirs(fifo_dir, exist_ok=True)
    with open(os.path.join(fifo_dir, "good.json"), "w") as f:
        f.write(good)
    if not os.path.exists(os.path.join(fifo_dir, "pipe.json")):
        os.mkfifo(os.path.join(fifo_dir, "pipe.json"))
    out.append(("directory-fifo", ["--catalog", fifo_dir]))
    base_kit = open("tests/hostile/kit-base.toml").read()
    for name, old, new in [("kit-rows-1e8", "rows = 20", "rows = 100000000"),
                           ("kit-axis-offset-1e300", "axis_offset = 0.0", "axis_offset = -1e300")]:
        k = w(name + ".toml", base_kit.replace(old, new))
        man = w(name + "-cat.toml", 'name = "h"\nunits = "mm"\n[[part]]\nid = "good"\noutline = [[0,0],[90,0],[90,40],[0,40]]\n')
        out.append((name, ["--catalog", man, "--kit", k]))
    return out

def damaged_files(sound, flips, seed):
    """(name, bytes) of damaged copies of a sound results file."""
    data = open(sound, "rb").read()
    rng = random.Random(seed)
    out = []
    b = bytearray(data); b[9 + 7] = 0xFF  # header length, top byte
    out.append(("header-length-ff", bytes(b)))
    for i in range(flips):
        b = bytearray(data)
        at = rng.randrange(8, len(b) - 8)
        b[at] ^= 1 << rng.randrange(8)
        out.append((f"flip-{at}", bytes(b)))
    # Flips inside the parts' chunk records (opcode 0x06), where the
    # crate's reader handed out messages before the chunk's CRC failed.
    chunks, pos = [], 8
    while pos + 9 <= len(data):
        op, n = data[pos], int.from_bytes(data[pos + 1:pos + 9], "little")
        if op == 0x06:
            chunks.append((pos, pos + 9 + n))
        if op == 0x0F:
            break
        pos += 9 + n
    for i in range(flips // 2):
        s, e = chunks[rng.randrange(len(chunks))]
        b = bytearray(data)
        at = rng.randrange(s, e)
        b[at] ^= 1 << rng.randrange(8)
        out.append((f"chunk-flip-{at}", bytes(b)))
    for i in range(max(1, flips // 4)):
        b = bytearray(data)
        at = rng.randrange(8, len(b) - 8)
        b[at:at + 8] = bytes(rng.randrange(256) for _ in range(8))
        out.append((f"smash-{at}", bytes(b)))
    return out

def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bin")
    ap.add_argument("--timeout", type=float, default=10)
    ap.add_argument("--flips", type=int, default=40)
    ap.add_argument("--seed", type=int, default=31)
    ap.add_argument("--skip-parts", action="store_true")
    ap.add_argument("--skip-files", action="store_true", help="only the part, kit and manifest cases")
    a = ap.parse_args()
    bin = os.path.abspath(a.bin)
    tmp = tempfile.mkdtemp(prefix="hostile-")
    counts = collections.Counter()
    try:
        if not a.skip_parts:
            for name, args in part_cases(tmp):
                out = os.path.join(tmp, "out.mcap")
                o, _, err = run([bin, "run", "-q", "-o", out] + args, a.timeout)
                print(f"run {name}: {o} {err.decode(errors='replace').strip().splitlines()[-1:] }", flush=True)
                counts["run:" + o] += 1
                for f in (out, out + ".partial"):
                    if os.path.exists(f):
                        os.remove(f)
        sound = os.path.join(tmp, "sound.mcap")
        if not a.skip_files:
            run([bin, "run", "-q", "-o", sound, "--catalog", "tests/hostile/small-catalog.toml"], 600)
            want = run([bin, "export", sound, "--json"], 60)[1]
        for name, bytes_ in ([] if a.skip_files else damaged_files(sound, a.flips, a.seed)):
            path = os.path.join(tmp, "damaged.mcap")
            open(path, "wb").write(bytes_)
            for cmd in (["export", path, "--json"], ["show", path]):
                o, out, err = run([bin] + cmd, a.timeout)
                if o == "ok" and cmd[0] == "export" and out != want:
                    o = "silent"
                counts[f"{cmd[0]}:{o}"] += 1
                if o in ("crash", "hang", "silent"):
                    print(f"{cmd[0]} {name}: {o} {err.decode(errors='replace').strip()[-200:]}", flush=True)
            final = os.path.join(tmp, "resumed.mcap")
            shutil.copy(path, final + ".partial")
            o, _, err = run([bin, "run", "-q", "--resume", "-o", final, "--catalog", "tests/hostile/small-catalog.toml"], a.timeout * 6)
            if o == "ok":
                got = run([bin, "export", final, "--json"], 60)[1]
                if got != want:
                    o = "silent"
            counts[f"resume:{o}"] += 1
            if o in ("crash", "hang", "silent"):
                print(f"resume {name}: {o} {err.decode(errors='replace').strip()[-200:]}", flush=True)
            for f in (final, final + ".partial"):
                if os.path.exists(f):
                    os.remove(f)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    for k in sorted(counts):
        print(f"{k} {counts[k]}")

main()
