"""scripts/lib/setup.sh: a failed step of the set-up fails the set-up.

Its functions run inside an && list (systole_setup), where bash's set -e does not act: each step
must check its commands itself. Here pip and cmake are replaced by commands that fail.
"""

import subprocess
from pathlib import Path

SETUP = Path(__file__).resolve().parents[1] / "lib" / "setup.sh"


def run_setup_function(tmp_path, body: str):
    """Source setup.sh with the venv and build folders in tmp_path, then run body."""
    script = f"""
set -euo pipefail
export SYSTOLE_VENV={tmp_path / 'venv'} SYSTOLE_BUILD={tmp_path / 'build'}
source {SETUP}
{body}
"""
    return subprocess.run(["bash", "-c", script], capture_output=True, text=True, timeout=60)


def test_a_failed_pip_install_fails_and_leaves_no_stamp(tmp_path):
    # python3 -m venv makes a venv whose pip fails (as behind a proxy without its certificate).
    body = """
python3() {
  mkdir -p "$SYSTOLE_VENV/bin"
  printf '#!/bin/sh\\necho "no network" >&2\\nexit 1\\n' > "$SYSTOLE_VENV/bin/pip"
  printf '#!/bin/sh\\nexit 0\\n' > "$SYSTOLE_VENV/bin/python"
  chmod +x "$SYSTOLE_VENV/bin/pip" "$SYSTOLE_VENV/bin/python"
}
systole_install_packages() { return 0; }
systole_install_pvpython() { return 0; }
systole_build() { echo BUILT; }
if systole_setup; then echo SETUP_PASSED; else echo SETUP_FAILED; fi
"""
    result = run_setup_function(tmp_path, body)
    assert "SETUP_FAILED" in result.stdout, result.stdout + result.stderr
    assert "BUILT" not in result.stdout
    assert "installing the Python packages" in result.stdout
    assert not (tmp_path / "venv" / ".requirements.sha256").exists()


def test_a_failed_build_fails_the_setup(tmp_path):
    body = """
mkdir -p "$SYSTOLE_BUILD" && touch "$SYSTOLE_BUILD/build.ninja"
cmake() { echo "compile error" >&2; return 1; }
systole_install_packages() { return 0; }
systole_install_pvpython() { return 0; }
systole_install_venv() { return 0; }
if systole_setup; then echo SETUP_PASSED; else echo SETUP_FAILED; fi
"""
    result = run_setup_function(tmp_path, body)
    assert "SETUP_FAILED" in result.stdout, result.stdout + result.stderr
    assert "the build failed" in result.stdout
    assert "build took" not in result.stdout
