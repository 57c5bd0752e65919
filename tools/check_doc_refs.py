#!/usr/bin/env python3
"""Fails on a dangling reference in the docs.

    check_doc_refs.py ROOT

Scans the repository at ROOT (not build/ or out/):
  - every Markdown file for names of Markdown files, and the sources
    (*.f90, *.py, *.sh, CMakeLists.txt) for names of the docs (capitals:
    `PARTICLES.md`, `input/README.md`; lower-case names there are outputs
    the tools write), or a path out of the repository: each must be
    a file of the repository (a bare name: at the root, in docs/ or next to
    the citing file; a path: from the root or from the citing file), never
    outside it;
  - every section a name cites (`PARTICLES.md §2.5`, `PARTICLES.md 1.13`,
    `PARTICLES.md section 4`): the file must have a heading with that
    number;
  - in the user docs (README.md, input/README.md, docs/*.md except the
    design notes that name other projects' files), every back-quoted path
    into the repository (`src/...`, `modules/...`, `tests/...`, `tools/...`,
    `input/...`, `docs/...`, `hardcases/...`, `regression/...`, `cmake/...`):
    it must exist (a glob may match; `<name>` and NNNNN placeholders are
    globs). Paths under build/ and out/ are what runs write, not checked.
Prints each dangling reference as FILE:LINE: text; exit status 1 if any.
"""
import glob
import os
import re
import sys

root = os.path.abspath(sys.argv[1])
SKIP_DIRS = {"build", "out", ".git", "__pycache__"}
SOURCES = (".f90", ".py", ".sh", ".in")
# design notes that name other projects' files (their paths are not ours)
FOREIGN_PATHS = {os.path.join("docs", "PARTICLES.md")}
OUTPUTS = ("build/", "out/")   # what runs write: not in a clean clone
TOP = ("src/", "modules/", "tests/", "tools/", "input/", "docs/", "hardcases/", "regression/", "cmake/", ".ci/")
MD_REF = re.compile(r"(?<![\w./$}-])((?:\.\./|\./)?(?:[\w.-]+/)*[\w-]+\.md)\b")
SECTION = re.compile(r"([\w-]+\.md)\)?,?\s*(?:§\s*|section\s+|sections\s+)?(\d+(?:\.\d+)*)(?![\w.]*\.md)")
TICKED = re.compile(r"`([^`\s]+)`")


def files():
    for d, dirs, names in os.walk(root):
        dirs[:] = [x for x in dirs if x not in SKIP_DIRS]
        for n in names:
            yield os.path.join(d, n)


def headings(path):
    nums = set()
    for line in open(path, encoding="utf-8"):
        m = re.match(r"#+\s+(\d+(?:\.\d+)*)\.?\s", line)
        if m:
            nums.add(m.group(1))
    return nums


def resolve_md(ref, citing):
    if ref.startswith("../") and not os.path.abspath(os.path.join(os.path.dirname(citing), ref)).startswith(root):
        return None
    cands = [os.path.join(os.path.dirname(citing), ref), os.path.join(root, ref)]
    if "/" not in ref:
        cands.append(os.path.join(root, "docs", ref))
    for c in cands:
        c = os.path.abspath(c)
        if c.startswith(root + os.sep) and os.path.isfile(c):
            return c
    return None


def path_exists(p):
    p = p.rstrip(".,;:)")
    p = re.sub(r":\d+(-\d+)?$", "", p)          # file:line
    p = re.sub(r"<[^>]*>", "*", p)              # <name> placeholders
    p = re.sub(r"N{3,}", "*", p)
    if any(c in p for c in "$("):
        return True
    return bool(glob.glob(os.path.join(root, p)))


bad = []
for path in sorted(files()):
    rel = os.path.relpath(path, root)
    is_md = path.endswith(".md")
    if not (is_md or path.endswith(SOURCES) or os.path.basename(path) == "CMakeLists.txt"):
        continue
    try:
        lines = open(path, encoding="utf-8").read().splitlines()
    except UnicodeDecodeError:
        continue
    for no, line in enumerate(lines, 1):
        for m in MD_REF.finditer(line):
            ref = m.group(1)
            if ref.startswith(OUTPUTS):
                continue
            if not is_md and not re.fullmatch(r"[A-Z][A-Z_]*\.md", os.path.basename(ref)) and "../" not in ref:
                continue
            target = resolve_md(ref, path)
            if target is None:
                bad.append(f"{rel}:{no}: {ref} is not a file of the repository")
        for m in SECTION.finditer(line):
            target = resolve_md(m.group(1), path)
            if target and m.group(2) not in headings(target):
                bad.append(f"{rel}:{no}: {m.group(1)} has no section {m.group(2)}")
        if is_md and rel not in FOREIGN_PATHS:
            for m in TICKED.finditer(line):
                p = m.group(1)
                if p.startswith(TOP) and not path_exists(p):
                    bad.append(f"{rel}:{no}: `{p}` does not exist")
for b in bad:
    print(b)
print(f"{len(bad)} dangling reference(s)")
sys.exit(1 if bad else 0)
