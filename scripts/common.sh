# Shared paths and helpers for the project scripts. Source it; do not run it.
# Everything heavy (LAMMPS source, build tree, virtual environment) lives outside
# the clone, under ESPH_CACHE, so a fresh clone reuses it and `git clean` never
# throws a 15-minute build away.
set -euo pipefail

ESPH_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
ESPH_CACHE=${ESPH_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/elastic-sph}

# Pinned LAMMPS: Debian's source package of the 4 Feb 2025 release.
LAMMPS_DEB_VERSION=20250204+dfsg.1-2
LAMMPS_ORIG_TARBALL=lammps_20250204+dfsg.1.orig.tar.xz
LAMMPS_ORIG_SHA256=3671165bd52fad36734e0a9136c5bc5ecb225e03988f8c89aa13366a8b53b1c7
LAMMPS_ORIG_TOPDIR=lammps-4Feb2025

# A user's own LAMMPS tree wins over the pinned one.
LAMMPS_SOURCE_DIR=${LAMMPS_SOURCE_DIR:-$ESPH_CACHE/src/$LAMMPS_ORIG_TOPDIR}

# One build tree per clone (CMake ties a build tree to one source path) and per
# LAMMPS tree; ccache makes a new one cheap.
_esph_key=$(printf '%s|%s' "$ESPH_ROOT" "$LAMMPS_SOURCE_DIR" | sha1sum | cut -c1-12)
ESPH_BUILD=${ESPH_BUILD:-$ESPH_CACHE/build-$_esph_key}
ESPH_VENV=${ESPH_VENV:-$ESPH_BUILD/venv}
ESPH_LMP=$ESPH_BUILD/lmp
# What LAMMPS is built with. RHEO (with BPM, which it needs) is there for the
# fluid coupling of issue 35 (studies/fsi_rheo). A change to these lists
# reaches existing trees: setup.sh re-runs cmake on a clone's own build tree
# when the options' stamp in it differs (incremental, the venv kept), and the
# host tree, shared by the clones, is keyed by its options, so a clone with
# other options gets its own (ccache makes it cheap) and never rebuilds
# another's under it. Removing an option does not unset it in an existing
# tree's CMakeCache.txt: delete the tree for that.
ESPH_LAMMPS_OPTIONS=(-DCMAKE_BUILD_TYPE=Release -DBUILD_MPI=on -DBUILD_OMP=off
  -DBUILD_SHARED_LIBS=on -DLAMMPS_EXCEPTIONS=on -DDOWNLOAD_EIGEN3=off
  -DPKG_MOLECULE=on -DPKG_MACHDYN=on -DPKG_BPM=on -DPKG_RHEO=on)
# LAMMPS 4Feb2025 finds LAPACK for RHEO but links it into liblammps only for
# ELECTRODE and ML-POD (its cmake/CMakeLists.txt:720-722), so a plain build
# with RHEO fails to link lmp (dpotrf_, dpotri_ of compute rheo/kernel
# undefined); the host gets -llapack at the end of its link lines (our
# CMakeLists.txt does the same for the in-tree build).
ESPH_HOST_OPTIONS=(-DCMAKE_BUILD_TYPE=Release -DBUILD_MPI=on -DBUILD_OMP=off
  -DBUILD_SHARED_LIBS=on -DDOWNLOAD_EIGEN3=off
  -DPKG_PLUGIN=on -DPKG_MOLECULE=on -DPKG_BPM=on -DPKG_RHEO=on
  "-DCMAKE_CXX_STANDARD_LIBRARIES=-llapack")

# The plugin route: a plain LAMMPS of the same tree with the PLUGIN package
# (a user's LAMMPS; one per LAMMPS tree and host options, shared by the
# clones), and the plugin built from this clone's sources against it.
_esph_host_key=$(printf '%s|%s' "$LAMMPS_SOURCE_DIR" "${ESPH_HOST_OPTIONS[*]}" | sha1sum | cut -c1-12)
ESPH_HOST_BUILD=${ESPH_HOST_BUILD:-$ESPH_CACHE/host-$_esph_host_key}
ESPH_PLUGIN_BUILD=${ESPH_PLUGIN_BUILD:-$ESPH_BUILD/plugin}
ESPH_PLUGIN=$ESPH_PLUGIN_BUILD/elasticsphplugin.so
ESPH_JOBS=${ESPH_JOBS:-$(nproc)}

say() { printf '[esph] %s\n' "$*" >&2; }
die() { printf '[esph] error: %s\n' "$*" >&2; exit 1; }

# Run a command as root (directly, or through sudo when we are not root).
as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi
}

# Environment for anything that loads liblammps from our build.
esph_env() {
  export PATH="$ESPH_VENV/bin:$ESPH_BUILD:$PATH"
  export LAMMPS_SOURCE_DIR ESPH_BUILD ESPH_LMP ESPH_ROOT ESPH_HOST_BUILD ESPH_PLUGIN
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  export OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}
  # OpenBLAS (under CHOLMOD in min_style sph/newton) falls back to generic
  # SSE3 kernels when a virtual machine hides the CPU model; with AVX2 the
  # Haswell kernels are safe and make the factorisation about 1.4x faster
  if [ -z "${OPENBLAS_CORETYPE:-}" ] && grep -qw avx2 /proc/cpuinfo 2>/dev/null; then
    export OPENBLAS_CORETYPE=Haswell
  fi
}
