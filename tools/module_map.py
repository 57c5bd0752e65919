#!/usr/bin/python3
"""The module map: which folder's modules use which other folders' (from
the `use` statements of modules/*/*.f90 and src/*.f90), with the number of
modules and lines in each folder, and the folder cycles (pairs of folders
that use each other). ARCHITECTURE.md section 2 states the intended order.

    module_map.py [ROOT]
"""
import collections
import pathlib
import re
import sys


def folder_of(path, root):
    rel = path.relative_to(root).parts
    return rel[1] if rel[0] == "modules" else rel[0]


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    files = sorted(root.glob("modules/*/*.f90")) + sorted(root.glob("src/*.f90"))
    where, size, count = {}, collections.Counter(), collections.Counter()
    for f in files:
        folder = folder_of(f, root)
        count[folder] += 1
        text = f.read_text(encoding="utf-8")
        size[folder] += text.count("\n")
        for m in re.finditer(r"^\s*module\s+(\w+)\s*$", text, re.I | re.M):
            where[m.group(1).lower()] = folder
    uses = collections.defaultdict(collections.Counter)
    for f in files:
        folder = folder_of(f, root)
        for m in re.finditer(r"^\s*use\s*(?:,\s*\w+\s*::)?\s*(\w+)", f.read_text(encoding="utf-8"), re.I | re.M):
            other = where.get(m.group(1).lower())
            if other and other != folder:
                uses[folder][other] += 1
    for folder in sorted(count, key=lambda k: (k == "src", k)):
        edges = ", ".join(f"{o} ({n})" for o, n in sorted(uses[folder].items()))
        print(f"{folder:10s} {count[folder]:3d} files {size[folder]:6d} lines  uses: {edges or '-'}")
    cycles = sorted({tuple(sorted((a, b))) for a in uses for b in uses[a] if a in uses.get(b, {})})
    print("folder cycles: " + (", ".join(f"{a} <-> {b}" for a, b in cycles) or "none"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
