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
# comes with libdeal.ii-dev, which depends on libgmsh-dev. Not Debian's ParaView: its
# python3-paraview (pvpython) conflicts with python3-vtk9, which libvtk9-dev needs; where
# pvpython and xvfb-run are installed, the ParaView tests of scripts/tests/test_xdmf_vtk.py
# run and scripts/run puts a ParaView picture in the report.
SYSTOLE_PACKAGES=(
  libdeal.ii-dev libsundials-dev libhdf5-mpi-dev libeigen3-dev libvtk9-dev libopenblas0-serial
  catch2 cmake ninja-build ccache mold clang-format-14 g++ git
  openmpi-bin python3 python3-venv
  chromium
  gmsh python3-gmsh
)

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
  python3 -m venv "$SYSTOLE_VENV"
  "$SYSTOLE_VENV/bin/pip" install -q --disable-pip-version-check -r "$req"
  "$SYSTOLE_VENV/bin/pip" install -q --disable-pip-version-check --no-build-isolation --no-deps \
    -e "$SYSTOLE_ROOT/scripts"
  echo "$want" > "$stamp"
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
  cmake --build "$SYSTOLE_BUILD" -j "$jobs"
  say "build took $((SECONDS - t0)) s"
}

systole_setup() {
  systole_install_packages && systole_install_venv && systole_build
}
