"""Run a tool under Debian's python3 when the python3 that started it (a
pyenv or venv one first on PATH, say) lacks the packages the tool needs:
numpy, h5py, matplotlib and scipy come from Debian (tools/install-deps.sh).

    import debian_python
    debian_python.require("h5py", "numpy")     # before importing them
"""
import importlib.util
import os
import sys

DEBIAN = "/usr/bin/python3"


def require(*modules):
    """Return if every module is importable; else run the tool again with
    Debian's python3, or stop with a message if that is what lacks them."""
    missing = [m for m in modules if importlib.util.find_spec(m) is None]
    if not missing:
        return
    if os.access(DEBIAN, os.X_OK) and os.path.realpath(sys.executable) != os.path.realpath(DEBIAN):
        os.execv(DEBIAN, [DEBIAN] + sys.argv)
    raise SystemExit("%s: needs Debian's python3 with %s (tools/install-deps.sh)"
                     % (sys.argv[0], ", ".join(modules)))
