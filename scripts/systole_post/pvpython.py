"""Where pvpython is: the one lookup of the ParaView tests and scripts/run.

Debian's pvpython is in python3-paraview, which cannot be installed beside libvtk9-dev
(Conflicts: python3-vtk9); scripts/lib/setup.sh (systole_install_pvpython) unpacks its files
into the checkout's .paraview prefix and exports SYSTOLE_PVPYTHON. pvpython must run by its
absolute path (through a relative one it imports the system's vtkmodules and crashes) and, to
render, under xvfb-run (Debian's ParaView has neither EGL nor OSMesa), whose Xvfb must not
reset: by default Xvfb resets when its last client disconnects, and pvpython, which closes
its first connection and opens another at once, then gets "bad X server connection" and
aborts (1 run in 5 on a loaded machine).

    python -m systole_post.pvpython --path          # the pvpython path, or exit 1 saying why
    python -m systole_post.pvpython SCRIPT [ARG...] # SCRIPT in pvpython under xvfb-run
"""

import os
import shutil
import sys
from pathlib import Path

#: The checkout (scripts/systole_post/ is two levels below it).
ROOT = Path(__file__).resolve().parents[2]

#: pvpython inside the prefix systole_install_pvpython unpacks python3-paraview into.
PREFIX_PVPYTHON = Path(".paraview") / "usr" / "bin" / "pvpython"

#: How to get pvpython and xvfb-run, for the messages of the tests and scripts/run.
HOW_TO_INSTALL = ("the set-up of scripts/test and scripts/run installs both "
                  "(scripts/lib/setup.sh: the packages paraview xvfb xauth, as root, then "
                  "systole_install_pvpython unpacks python3-paraview into .paraview/), or "
                  "set SYSTOLE_PVPYTHON")


def _executable(path) -> bool:
    return Path(path).is_file() and os.access(path, os.X_OK)


def find_pvpython(root: Path = ROOT) -> Path | None:
    """The absolute path of pvpython: SYSTOLE_PVPYTHON, then the checkout's .paraview prefix,
    then PATH; None if none is there. SYSTOLE_PVPYTHON, where set, is the only candidate."""
    variable = os.environ.get("SYSTOLE_PVPYTHON")
    if variable:
        candidates = [variable]
    else:
        candidates = [root / PREFIX_PVPYTHON, shutil.which("pvpython")]
    for candidate in candidates:
        if candidate and _executable(candidate):
            return Path(os.path.abspath(candidate))
    return None


#: Xvfb's arguments: xvfb-run's default screen, and no reset when the last client leaves.
XVFB_ARGS = "-screen 0 1280x1024x24 -noreset"


def pvpython_command(root: Path = ROOT) -> list[str] | None:
    """The command that runs pvpython without a display (xvfb-run -a pvpython), or None."""
    pvpython, xvfb_run = find_pvpython(root), shutil.which("xvfb-run")
    if pvpython is None or xvfb_run is None:
        return None
    return [xvfb_run, "-a", "-s", XVFB_ARGS, str(pvpython)]


def missing_message(root: Path = ROOT) -> str:
    """Which of pvpython and xvfb-run is missing, and the fix."""
    missing = [name for name, found in (("pvpython", find_pvpython(root)),
                                        ("xvfb-run", shutil.which("xvfb-run"))) if not found]
    variable = os.environ.get("SYSTOLE_PVPYTHON")
    where = f" (SYSTOLE_PVPYTHON={variable} is not an executable)" if variable and \
        "pvpython" in missing else ""
    return f"{' and '.join(missing) or 'nothing'} missing{where}: {HOW_TO_INSTALL}"


def main(argv: list[str]) -> int:
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 1
    command = pvpython_command()
    if command is None:
        print(missing_message(), file=sys.stderr)
        return 1
    if argv == ["--path"]:
        print(command[-1])
        return 0
    os.execv(command[0], command + argv)
    return 1  # not reached


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
