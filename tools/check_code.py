#!/usr/bin/python3
"""Code conventions that a reviewer would otherwise have to catch by eye
(ARCHITECTURE.md §4), checked over the Fortran sources:

  1. every `allocate` statement has `stat=` (and `errmsg=`);
  2. no module keeps mutable state: a module's specification part declares
     only constants (`parameter`), types, interfaces and procedures (the
     one exception: a `volatile` flag that a signal handler sets, which
     cannot be passed as an argument, `base_stop`);
  3. only `driver_halt` stops the program (`stop` / `error stop`);
  4. the driver holds no `run%` object.

    check_code.py ROOT        (checks ROOT/modules and ROOT/src)
Exit status 0 when clean; each finding names file and line.
"""
import pathlib
import re
import sys


def statements(path):
    """(first line number, statement text) with continuations joined and
    comments dropped (a `!` outside quotes)."""
    buf, start = "", None
    for n, raw in enumerate(open(path, encoding="utf-8"), 1):
        line = strip_comment(raw.rstrip("\n"))
        if start is None:
            start = n
        cont = line.rstrip().endswith("&")
        piece = line.rstrip()[:-1] if cont else line
        piece = piece.strip()
        if piece.startswith("&"):
            piece = piece[1:]
        buf += piece
        if not cont:
            if buf.strip():
                for part in split_semicolons(buf):
                    yield start, part.strip()
            buf, start = "", None


def strip_comment(line):
    q = None
    for i, ch in enumerate(line):
        if q:
            if ch == q:
                q = None
        elif ch in "'\"":
            q = ch
        elif ch == "!":
            return line[:i]
    return line


def split_semicolons(s):
    parts, q, cur = [], None, ""
    for ch in s:
        if q:
            if ch == q:
                q = None
        elif ch in "'\"":
            q = ch
        elif ch == ";":
            parts.append(cur)
            cur = ""
            continue
        cur += ch
    parts.append(cur)
    return parts


def check_file(path, problems):
    in_module, in_spec, depth_type, depth_iface = False, False, 0, 0
    is_halt = path.name == "driver_halt.f90"
    for n, st in statements(path):
        low = st.lower()
        where = f"{path}:{n}"
        if re.match(r"^(deallocate)\b", low) is None and re.match(r"^(if\s*\(.*\)\s*)?allocate\s*\(", low):
            if "stat=" not in low.replace(" ", ""):
                problems.append(f"{where}: allocate without stat=: {st[:80]}")
        if re.match(r"^(if\s*\(.*\)\s*)?(error\s+)?stop\b", low) and not is_halt:
            problems.append(f"{where}: only driver_halt may stop the program: {st[:80]}")
        if re.search(r"run%", low):
            problems.append(f"{where}: run% (the driver passes its state explicitly)")
        m = re.match(r"^module\s+(\w+)\s*$", low)
        if m and m.group(1) != "procedure":
            in_module, in_spec = True, True
            continue
        if re.match(r"^end\s+module\b", low):
            in_module, in_spec = False, False
            continue
        if not in_spec:
            continue
        if low == "contains":
            in_spec = False
            continue
        if re.match(r"^(abstract\s+)?interface\b", low):
            depth_iface += 1
        elif re.match(r"^end\s+interface\b", low):
            depth_iface -= 1
        elif re.match(r"^type\s*(,.*)?::\s*\w+\s*$|^type\s+\w+\s*$", low):
            depth_type += 1
        elif re.match(r"^end\s+type\b", low):
            depth_type -= 1
        elif depth_type == 0 and depth_iface == 0 and "::" in low:
            attrs = low.split("::")[0]
            if re.match(r"^(use|public|private|procedure|generic|namelist)\b", attrs.strip()):
                continue
            if "parameter" not in attrs and "volatile" not in attrs:
                problems.append(f"{where}: module-level variable (mutable state): {st[:80]}")


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    problems, nfiles = [], 0
    for sub in ("modules", "src"):
        for path in sorted((root / sub).rglob("*.f90")):
            nfiles += 1
            check_file(path, problems)
    for p in problems:
        print("FAIL:", p)
    print(f"{nfiles} files checked; {len(problems)} finding(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
