"""Shared by the plotting tools (plot_pile.py, plot_sweep.py, plastic_zone.py): their Python
modules come from Debian packages, which only the system Python has. When another Python is
first on PATH (pyenv, conda) and lacks them, the tool runs again under /usr/bin/python3."""
import importlib
import os
import sys


def require(script, modules, needs):
    """Imports `modules` (names), or re-runs `script` (the tool's __file__) with /usr/bin/python3
    when this is another Python, or exits with "<tool>: needs <needs>" when it is the system one."""
    try:
        for m in modules:
            importlib.import_module(m)
    except ImportError:
        if os.path.exists("/usr/bin/python3") and os.path.realpath(sys.executable) != os.path.realpath("/usr/bin/python3"):
            os.execv("/usr/bin/python3", ["/usr/bin/python3", os.path.abspath(script)] + sys.argv[1:])
        tool = os.path.splitext(os.path.basename(script))[0]
        sys.exit(f"{tool}: needs {needs}")
