#!/usr/bin/env python3
"""Writes a catalogue that is another one N times over (ids suffixed -r0,
-r1, ...), for timing whole runs: `fixplan run --catalog OUT/catalog.toml`.

    python3 scripts/repeat_catalog.py examples/catalog 20 /tmp/catalog-x20

Part files are copied next to the new manifest; only manifests whose parts
are inline or under the catalogue's folder are supported.
"""
import pathlib
import re
import shutil
import sys


def main() -> None:
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    src, n, out = pathlib.Path(sys.argv[1]), int(sys.argv[2]), pathlib.Path(sys.argv[3])
    manifest = src / "catalog.toml" if src.is_dir() else src
    root = manifest.parent
    out.mkdir(parents=True, exist_ok=True)
    for entry in root.iterdir():
        if entry.is_dir():
            shutil.copytree(entry, out / entry.name, dirs_exist_ok=True)
    head, *parts = manifest.read_text().split("[[part]]")
    text = [head]
    for r in range(n):
        for p in parts:
            text.append("[[part]]" + re.sub(r'id = "([^"]+)"', lambda m: f'id = "{m.group(1)}-r{r}"', p))
    (out / "catalog.toml").write_text("".join(text))
    print(f"{out / 'catalog.toml'}: {n * len(parts)} parts")


if __name__ == "__main__":
    main()
