#!/usr/bin/python3
"""Code conventions that a reviewer would otherwise have to catch by eye
(ARCHITECTURE.md §4), checked over the Fortran sources:

  1. every `allocate` statement has `stat=` (and `errmsg=`);
  2. no module keeps mutable state: a module's specification part declares
     only constants (`parameter`), types, interfaces and procedures (the
     one exception: a `volatile` flag that a signal handler sets, which
     cannot be passed as an argument, `base_stop`);
  3. only `driver_halt` stops the program (`stop` / `error stop`);
  4. the driver holds no `run%` object;
  5. MPI is called only in the parallel layer and the I/O package
     (`modules/parallel`, `modules/io`): nowhere else `use mpi_f08`, `use
     mpi` or `call MPI_...`;
  6. `modules/` holds no whole state: no module there uses a `driver_`
     module (where `state_t` lives) or names `state_t`;
  7. `src/` holds no package kernels: outside its set-up, output, restart
     and diagnostics files (SRC_SETUP_AND_OUTPUT) no loop runs over a
     grid's cells or nodes (index ranges clo/chi, nlo/nhi, ulo, slo/shi,
     ni/nj/nk, gn, or ncell, nnode) or over particles (np); such loops
     belong to the packages' kernels in `modules/`;
  8. the folders of `modules/` are layers: a module in modules/F is named
     F_<something>, in a file of its own name, and the folders' `use`
     graph has no cycle (a folder that uses another is not used by it,
     directly or through others).

    check_code.py ROOT        (checks ROOT/modules and ROOT/src)
    check_code.py --self-test (each rule finds its breach in a made-up tree,
                               and a clean tree passes)
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


# src/ files that may loop over the grid or the particles: set-up, output,
# restart and diagnostics (rule 7)
SRC_SETUP_AND_OUTPUT = {"driver_scene.f90", "driver_scene_config.f90", "driver_prerun.f90", "driver_config.f90",
                        "driver_restart.f90", "driver_output.f90", "driver_matsum.f90", "driver_state.f90"}

GRID_LOOP = re.compile(r"^(\w+:\s*)?do\s+\w+\s*=.*(%(clo|chi|nlo|nhi|ulo|slo|shi|ni|nj|nk|gn)\b|\bncell\b|\bnnode\b|%np\b)")


def check_file(path, problems, uses):
    in_module, in_spec, depth_type, depth_iface = False, False, 0, 0
    is_halt = path.name == "driver_halt.f90"
    folder = path.parent.name
    in_src = folder == "src"
    mpi_allowed = folder in ("parallel", "io")
    kernels_banned = in_src and path.name not in SRC_SETUP_AND_OUTPUT
    for n, st in statements(path):
        low = st.lower()
        where = f"{path}:{n}"
        if not mpi_allowed and (re.match(r"^use\s*(,\s*intrinsic\s*)?(::\s*)?mpi(_f08)?\b", low)
                                or re.match(r"^(if\s*\(.*\)\s*)?call\s+MPI_[A-Z]", st)):
            problems.append(f"{where}: MPI outside modules/parallel and modules/io: {st[:80]}")
        if not in_src and (re.match(r"^use\s+driver_", low) or re.search(r"\bstate_t\b", low)):
            problems.append(f"{where}: the whole state (driver_*, state_t) in modules/: {st[:80]}")
        if kernels_banned and GRID_LOOP.match(low):
            problems.append(f"{where}: a loop over the grid or the particles in src/ (a kernel: modules/): {st[:80]}")
        if re.match(r"^(deallocate)\b", low) is None and re.match(r"^(if\s*\(.*\)\s*)?allocate\s*\(", low):
            if "stat=" not in low.replace(" ", ""):
                problems.append(f"{where}: allocate without stat=: {st[:80]}")
        if re.match(r"^(if\s*\(.*\)\s*)?(error\s+)?stop\b", low) and not is_halt:
            problems.append(f"{where}: only driver_halt may stop the program: {st[:80]}")
        if re.search(r"run%", low):
            problems.append(f"{where}: run% (the driver passes its state explicitly)")
        if not in_src:
            u = re.match(r"^use\s*(?:,\s*non_intrinsic\s*)?(?:::\s*)?(\w+)", low)
            if u:
                uses.append((folder, u.group(1), where, st[:80]))
        m = re.match(r"^module\s+(\w+)\s*$", low)
        if m and m.group(1) != "procedure":
            if not in_src and (m.group(1) != path.stem or not m.group(1).startswith(folder + "_")):
                problems.append(f"{where}: module {m.group(1)} in modules/{folder}: a module there is named "
                                f"{folder}_<name>, in a file of that name")
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


def folder_cycles(folders, uses, problems):
    """Rule 8: every use of a module of another folder of modules/ that
    lies on a cycle of the folders' use graph, reported at its first use."""
    edges = {}
    for frm, mod, where, st in uses:
        to = mod.split("_")[0]
        if to in folders and to != frm:
            edges.setdefault((frm, to), (where, st))
    succ = {}
    for a, b in edges:
        succ.setdefault(a, set()).add(b)

    def path_to(a, goal):
        seen, todo = {a: None}, [a]
        while todo:
            x = todo.pop()
            for y in sorted(succ.get(x, ())):
                if y not in seen:
                    seen[y] = x
                    todo.append(y)
        if goal not in seen:
            return None
        chain = [goal]
        while chain[-1] != a:
            chain.append(seen[chain[-1]])
        return chain[::-1]

    for (a, b), (where, st) in sorted(edges.items()):
        back = path_to(b, a)
        if back:
            problems.append(f"{where}: folder cycle {' -> '.join([a] + back)}: {st}")


def check_tree(root):
    problems, nfiles, uses = [], 0, []
    for sub in ("modules", "src"):
        for path in sorted((root / sub).rglob("*.f90")):
            nfiles += 1
            check_file(path, problems, uses)
    folders = {p.name for p in (root / "modules").iterdir() if p.is_dir()}
    folder_cycles(folders, uses, problems)
    return problems, nfiles


# (file, body, the finding it must give or None): the self-test's tree
SELF_TEST = [
    ("modules/base/base_ok.f90", "module base_ok\n  integer, parameter :: n = 1\ncontains\n  subroutine f(a)\n"
     "    real, allocatable :: a(:)\n    integer :: s\n    allocate(a(n), stat=s)\n  end subroutine f\nend module base_ok\n",
     None),
    ("modules/base/base_alloc.f90", "module base_alloc\ncontains\n  subroutine f(a)\n    real, allocatable :: a(:)\n"
     "    allocate(a(3))\n  end subroutine f\nend module base_alloc\n", "allocate without stat="),
    ("modules/base/base_state.f90", "module base_state\n  integer :: count = 0\nend module base_state\n", "mutable state"),
    ("modules/base/base_halt.f90", "module base_halt\ncontains\n  subroutine f()\n    stop 1\n  end subroutine f\n"
     "end module base_halt\n", "only driver_halt may stop"),
    ("src/driver_run.f90", "module driver_run\ncontains\n  subroutine f(run)\n    integer :: run\n"
     "    run%n = 1\n  end subroutine f\nend module driver_run\n", "run%"),
    ("modules/rezone/rezone_mpi.f90", "module rezone_mpi\n  use mpi_f08, only: MPI_Barrier\nend module rezone_mpi\n",
     "MPI outside"),
    ("src/driver_mpi.f90", "module driver_mpi\ncontains\n  subroutine f(c)\n    integer :: c\n"
     "    call MPI_Barrier(c)\n  end subroutine f\nend module driver_mpi\n", "MPI outside"),
    ("modules/parallel/parallel_ok.f90", "module parallel_ok\n  use mpi_f08\nend module parallel_ok\n", None),
    ("modules/base/named.f90", "module base_other\nend module base_other\n", "a module there is named base_<name>"),
    ("modules/eos/eos_up.f90", "module eos_up\n  use mesh_down, only: f\nend module eos_up\n", "folder cycle eos -> mesh -> eos"),
    ("modules/mesh/mesh_down.f90", "module mesh_down\n  use eos_up, only: g\nend module mesh_down\n", "folder cycle mesh -> eos -> mesh"),
    ("modules/mesh/mesh_base.f90", "module mesh_base\n  use base_ok, only: n\nend module mesh_base\n", None),
    ("modules/remap/remap_whole.f90", "module remap_whole\n  use driver_state, only: state_t\nend module remap_whole\n",
     "the whole state"),
    ("src/driver_kernel.f90", "module driver_kernel\ncontains\n  subroutine f(g, a)\n    integer :: g, a(:), c\n"
     "    do c = 1, g%ncell\n      a(c) = 0\n    end do\n  end subroutine f\nend module driver_kernel\n",
     "a loop over the grid or the particles in src/"),
    ("src/driver_scene.f90", "module driver_scene\ncontains\n  subroutine f(g, a)\n    integer :: g, a(:), k\n"
     "    do k = g%clo(3), g%chi(3)\n      a(k) = 0\n    end do\n  end subroutine f\nend module driver_scene\n",
     None),
]


def self_test():
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp)
        for name, body, _ in SELF_TEST:
            (root / name).parent.mkdir(parents=True, exist_ok=True)
            (root / name).write_text(body, encoding="utf-8")
        problems, _ = check_tree(root)
        bad = 0
        for name, _, finding in SELF_TEST:
            mine = [p for p in problems if p.startswith(str(root / name) + ":")]
            ok = (not mine) if finding is None else any(finding in p for p in mine)
            print(("ok  " if ok else "BAD ") + name + ": " + (", ".join(p.split(": ", 1)[1] for p in mine) or "clean"))
            bad += not ok
    print(f"self-test: {len(SELF_TEST) - bad} of {len(SELF_TEST)} as expected")
    return 1 if bad else 0


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    problems, nfiles = check_tree(root)
    for p in problems:
        print("FAIL:", p)
    print(f"{nfiles} files checked; {len(problems)} finding(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
