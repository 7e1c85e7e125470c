#!/usr/bin/env python3
"""Finds file import cycles in the workspace's crates.

Every `.rs` file under a crate's `src/` is a module (`a/b.rs` and `a/b/mod.rs`
are `crate::a::b`). A file depends on another when it names a path into it:
`use crate::x::y`, `crate::x::Y` in code, `super::...`, `self::...`, with
brace groups expanded. A path resolves to the longest prefix that is a module
file, so `crate::Part` re-exported by `lib.rs` is a dependency on `lib.rs`.
`mod x;` declarations are not dependencies. Inside an inline `mod tests { }`
`super` is the file itself, so unit tests add no edge.

Prints each cycle (strongly connected component of more than one file) and
exits 1 if there is one; prints the number of files and edges otherwise.

    python3 scripts/import_cycles.py            # every crate of the workspace
    python3 scripts/import_cycles.py --edges    # also list every edge
"""
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CRATES = ["core", "catalog", "worker", "coordinator", "tests"]


def modules(src):
    """Maps a module path (tuple) to its file."""
    mods = {}
    for dirpath, _, files in os.walk(src):
        for f in files:
            if not f.endswith(".rs"):
                continue
            rel = os.path.relpath(os.path.join(dirpath, f), src)
            parts = rel[:-3].split(os.sep)
            if parts[-1] in ("mod", "lib", "main"):
                parts = parts[:-1]
            if parts and parts[0] == "bin":
                continue  # binaries are their own crates
            mods[tuple(parts)] = os.path.join(dirpath, f)
    return mods


def strip_comments(text):
    """The code without comments, and with string and char literals emptied."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            i = n if j < 0 else j + 2
        elif c == "r" and re.match(r'r#*"', text[i:i + 10]) and not (i and (text[i - 1].isalnum() or text[i - 1] == "_")):
            hashes = re.match(r"r(#*)\"", text[i:]).group(1)
            j = text.find('"' + hashes, i + 2 + len(hashes))
            out.append('""')
            i = n if j < 0 else j + 1 + len(hashes)
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            out.append('""')
            i = j + 1
        elif c == "'" and re.match(r"'(\\.[^']*|[^\\'])'", text[i:i + 12]):
            m = re.match(r"'(\\.[^']*|[^\\'])'", text[i:i + 12])
            out.append("' '")
            i += m.end()
        else:
            out.append(c)
            i += 1
    return "".join(out)


def expand_use(tree):
    """`a::{b, c::{d, e}}` -> ['a::b', 'a::c::d', 'a::c::e']."""
    tree = tree.strip()
    m = re.match(r"^(.*?)::\{(.*)\}$", tree, re.S)
    if not m:
        return [tree.split(" as ")[0].strip()]
    prefix, inner = m.group(1), m.group(2)
    out, depth, cur = [], 0, ""
    for ch in inner:
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        if ch == "," and depth == 0:
            out.append(cur)
            cur = ""
        else:
            cur += ch
    out.append(cur)
    res = []
    for item in out:
        if item.strip():
            for e in expand_use(item):
                res.append(prefix + "::" + e if e != "self" else prefix)
    return res


def inline_mod_spans(text):
    """Character spans of inline `mod name { ... }` blocks."""
    spans = []
    for m in re.finditer(r"\bmod\s+\w+\s*\{", text):
        depth, i = 1, m.end()
        while i < len(text) and depth:
            depth += {"{": 1, "}": -1}.get(text[i], 0)
            i += 1
        spans.append((m.start(), i))
    return spans


def paths_in(text):
    """(position, path) of every module path the file names."""
    found = []
    for m in re.finditer(r"\buse\s+([^;]+);", text):
        for p in expand_use(re.sub(r"\s+", "", m.group(1))):
            found.append((m.start(), p))
    for m in re.finditer(r"(?<![\w:])(\w+(?:::\w+)+)", text):
        found.append((m.start(), m.group(1)))
    return found


def resolve(path, here, in_inline, mods):
    segs = path.split("::")
    if segs[0] == "crate":
        base, rest = (), segs[1:]
    elif (here + (segs[0],)) in mods:
        base, rest = here, segs  # a child module, named relatively
    elif segs[0] in ("super", "self"):
        base = list(here)
        rest = segs
        if in_inline and rest[0] == "super":
            rest = rest[1:]  # `super` of an inline module is this file
        while rest and rest[0] in ("super", "self"):
            if rest[0] == "super" and base:
                base.pop()
            rest = rest[1:]
        base = tuple(base)
    else:
        return None
    best = base if base in mods else None
    for i in range(1, len(rest) + 1):
        cand = base + tuple(rest[:i])
        if cand in mods:
            best = cand
    return best


def graph(crate):
    src = os.path.join(ROOT, crate, "src")
    mods = modules(src)
    edges = {}
    for mod, path in mods.items():
        text = strip_comments(open(path, encoding="utf-8").read())
        spans = inline_mod_spans(text)
        # A file `a/b.rs` is module a::b; `super` from it is `a`.
        for pos, p in paths_in(text):
            inl = any(s <= pos < e for s, e in spans)
            target = resolve(p, mod, inl, mods)
            if target is not None and target != mod:
                edges.setdefault(mod, set()).add(target)
    return mods, edges


def sccs(nodes, edges):
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            out.append(comp)

    sys.setrecursionlimit(10000)
    for v in nodes:
        if v not in index:
            visit(v)
    return out


def name(crate, mod):
    return crate + "::" + ("::".join(mod) if mod else "(root)")


def main():
    bad = 0
    nfiles = nedges = 0
    for crate in CRATES:
        if not os.path.isdir(os.path.join(ROOT, crate, "src")):
            continue
        mods, edges = graph(crate)
        nfiles += len(mods)
        nedges += sum(len(v) for v in edges.values())
        if "--edges" in sys.argv:
            for a in sorted(edges):
                for b in sorted(edges[a]):
                    print(f"{name(crate, a)} -> {name(crate, b)}")
        for comp in sccs(sorted(mods), edges):
            if len(comp) > 1:
                bad += 1
                names = sorted(name(crate, m) for m in comp)
                print("cycle: " + " <-> ".join(names))
        # Folders: the top-level modules of the crate must depend on each
        # other one way too (files of one folder may use each other).
        tops = {m[:1] for m in mods if m}
        top_edges = {}
        for a, bs in edges.items():
            for b in bs:
                if a[:1] and b[:1] and a[:1] != b[:1]:
                    top_edges.setdefault(a[:1], set()).add(b[:1])
        for comp in sccs(sorted(tops), top_edges):
            if len(comp) > 1:
                bad += 1
                names = sorted(name(crate, m) for m in comp)
                print("folder cycle: " + " <-> ".join(names))
    if bad:
        print(f"{bad} import cycles")
        return 1
    print(f"no import cycle: {nfiles} files, {nedges} import edges")
    return 0


if __name__ == "__main__":
    sys.exit(main())
