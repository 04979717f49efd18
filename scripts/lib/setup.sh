# Shared set-up for scripts/run, scripts/test and scripts/bench (sourced, not run).
# Installs what is missing (Debian packages, the Python venv), then configures and builds.
# Idempotent: a second call finds everything in place and only rebuilds what changed.

SYSTOLE_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
SYSTOLE_BUILD=${SYSTOLE_BUILD:-$SYSTOLE_ROOT/build}
SYSTOLE_VENV=${SYSTOLE_VENV:-$SYSTOLE_ROOT/.venv}
# ccache hits across clones (CI builds a fresh clone): hash paths relative to the source.
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$SYSTOLE_ROOT}

# Debian 12 packages Systole needs (deal.II 9.4 brings PETSc, p4est, Trilinos and MPI).
# libopenblas0-serial replaces the reference BLAS/LAPACK behind the Debian alternatives (no
# rebuild): MUMPS factorizes the mechanics tangent 3-4 times faster with it. The serial
# variant, because every MPI rank already has its core. chromium: the headless browser that
# renders scripts/report.py's page in the pytest (scripts/tests/test_report.py). gmsh and its
# Python module: scripts/make_biv_mesh.py regenerates meshes/biv_coarse.msh (the tests read
# the shipped file and need neither). The gmsh C++ API (gmsh.h, libgmsh: reading .msh files)
# comes with libdeal.ii-dev, which depends on libgmsh-dev. paraview (its libraries) and xvfb
# (xvfb-run, with xauth): the ParaView tests of scripts/tests/test_xdmf_vtk.py and the ParaView
# picture scripts/run puts in the report. Debian's pvpython is in python3-paraview, which
# declares Conflicts: python3-vtk9, which libvtk9-dev needs: the install below goes without
# recommends (paraview recommends python3-paraview), and systole_install_pvpython unpacks
# python3-paraview's files into the checkout instead of installing it.
SYSTOLE_PACKAGES=(
  libdeal.ii-dev libsundials-dev libhdf5-mpi-dev libeigen3-dev libvtk9-dev libopenblas0-serial
  catch2 cmake ninja-build ccache mold clang-format-14 g++ git
  openmpi-bin python3 python3-venv
  chromium
  gmsh python3-gmsh
  paraview xvfb xauth
)
# Where systole_install_pvpython unpacks python3-paraview (gitignored).
SYSTOLE_PARAVIEW=${SYSTOLE_PARAVIEW:-$SYSTOLE_ROOT/.paraview}

say() { printf '[systole] %s\n' "$*"; }

systole_install_packages() {
  local missing=()
  for p in "${SYSTOLE_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' ||
      missing+=("$p")
  done
  if [ ${#missing[@]} -eq 0 ]; then
    return 0
  fi
  say "installing missing Debian packages: ${missing[*]}"
  if [ "$(id -u)" -ne 0 ]; then
    say "error: these packages are missing and installing them needs root: ${missing[*]}"
    return 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -q
  apt-get install -y -q --no-install-recommends "${missing[@]}"
}

# The venv: the pinned packages of scripts/requirements.txt, then scripts/' own packages
# (systole_post, systole_bench; scripts/pyproject.toml) installed editable, so that any script,
# check or test imports them without touching sys.path. The editable install builds offline
# (no build isolation: the venv's setuptools and the pinned wheel). The stamp covers both files.
systole_install_venv() {
  local req=$SYSTOLE_ROOT/scripts/requirements.txt
  local project=$SYSTOLE_ROOT/scripts/pyproject.toml
  local stamp=$SYSTOLE_VENV/.requirements.sha256
  local want
  want=$(cat "$req" "$project" | sha256sum | cut -d' ' -f1)
  if [ -x "$SYSTOLE_VENV/bin/python" ] && [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ]; then
    return 0
  fi
  say "creating the Python venv $SYSTOLE_VENV from scripts/requirements.txt and scripts/pyproject.toml"
  # Every step checked: these functions run inside an && list, where set -e does not act, and a
  # stamp written after a failed install would hide the failure from every later run.
  rm -f "$stamp"
  python3 -m venv "$SYSTOLE_VENV" &&
    "$SYSTOLE_VENV/bin/pip" install -q --disable-pip-version-check -r "$req" &&
    "$SYSTOLE_VENV/bin/pip" install -q --disable-pip-version-check --no-build-isolation \
      --no-deps -e "$SYSTOLE_ROOT/scripts" || {
    say "error: installing the Python packages of scripts/requirements.txt into $SYSTOLE_VENV" \
      "failed (see pip's message above; behind a proxy, pip may need its certificate: PIP_CERT)"
    return 1
  }
  echo "$want" > "$stamp"
}

# pvpython without python3-paraview installed: its files (pvpython, ParaView's own vtkmodules)
# unpacked with dpkg -x into $SYSTOLE_PARAVIEW, at the exact version of the installed paraview
# (its libraries), no root needed once paraview is installed. Run by its absolute path,
# $SYSTOLE_PARAVIEW/usr/bin/pvpython imports the prefix's modules before the system's (through
# a relative path it picks python3-vtk9's vtkmodules and crashes). It renders under xvfb-run
# only: Debian's build has neither EGL nor OSMesa. Exports SYSTOLE_PVPYTHON (where it is set
# already, that pvpython is used and nothing is unpacked); systole_post.pvpython finds it.
systole_install_pvpython() {
  if [ -n "${SYSTOLE_PVPYTHON:-}" ]; then
    return 0
  fi
  local version stamp=$SYSTOLE_PARAVIEW/.version pvpython=$SYSTOLE_PARAVIEW/usr/bin/pvpython
  version=$(dpkg-query -W -f='${Version}' paraview 2>/dev/null) || {
    say "error: Debian's paraview is not installed (pvpython needs its libraries)"
    return 1
  }
  if [ ! -x "$pvpython" ] || [ "$(cat "$stamp" 2>/dev/null)" != "$version" ]; then
    say "unpacking python3-paraview $version (pvpython) into $SYSTOLE_PARAVIEW"
    local tmp deb sandbox=()
    tmp=$(mktemp -d) || return 1
    # As root, apt-get download hands the file to the user _apt, who cannot write here.
    if [ "$(id -u)" -eq 0 ]; then
      sandbox=(-o APT::Sandbox::User=root)
    fi
    if ! (cd "$tmp" && apt-get download -q "${sandbox[@]}" "python3-paraview=$version" \
        >/dev/null 2>&1); then
      if [ "$(id -u)" -eq 0 ]; then
        # Package lists missing or older than the installed paraview.
        apt-get update -q >/dev/null
        (cd "$tmp" && apt-get download -q "${sandbox[@]}" "python3-paraview=$version" \
          >/dev/null) || true
      fi
    fi
    deb=$(find "$tmp" -name 'python3-paraview_*.deb' -print -quit)
    if [ -z "$deb" ]; then
      rm -rf "$tmp"
      say "error: could not download python3-paraview=$version (apt-get download); as root," \
        "apt-get update refreshes the package lists, or set SYSTOLE_PVPYTHON to a pvpython"
      return 1
    fi
    rm -rf "$SYSTOLE_PARAVIEW"
    if ! dpkg -x "$deb" "$SYSTOLE_PARAVIEW" || ! "$pvpython" --version >/dev/null 2>&1; then
      rm -rf "$tmp" "$SYSTOLE_PARAVIEW"
      say "error: python3-paraview $version unpacked into $SYSTOLE_PARAVIEW does not run"
      return 1
    fi
    rm -rf "$tmp"
    echo "$version" > "$stamp"
  fi
  export SYSTOLE_PVPYTHON=$pvpython
}

systole_build() {
  local jobs
  jobs=$(nproc)
  if [ ! -f "$SYSTOLE_BUILD/build.ninja" ]; then
    say "configuring (Release) in $SYSTOLE_BUILD"
    cmake -S "$SYSTOLE_ROOT" -B "$SYSTOLE_BUILD" -G Ninja \
      -DCMAKE_BUILD_TYPE=Release \
      -DPython3_EXECUTABLE="$SYSTOLE_VENV/bin/python" >"$SYSTOLE_BUILD.configure.log" 2>&1 || {
        cat "$SYSTOLE_BUILD.configure.log"
        return 1
      }
  fi
  say "building with $jobs jobs"
  local t0=$SECONDS
  cmake --build "$SYSTOLE_BUILD" -j "$jobs" || {
    say "error: the build failed (the compiler's message is above)"
    return 1
  }
  say "build took $((SECONDS - t0)) s"
}

systole_setup() {
  systole_install_packages && systole_install_pvpython && systole_install_venv && systole_build
}
