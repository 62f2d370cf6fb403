#!/usr/bin/env bash
# Install what is missing and build LAMMPS with ELASTIC-SPH compiled in.
# Idempotent: a second run with nothing changed only checks and returns.
#
#   scripts/setup.sh            everything (system packages, LAMMPS source, build, venv)
#   scripts/setup.sh --plugin   also a plain LAMMPS with the PLUGIN package and
#                               the package built as a plugin for it (tests)
#   LAMMPS_SOURCE_DIR=/path     use your own LAMMPS tree instead of the pinned one
#   ESPH_CACHE=/path            where source, build and venv live (default ~/.cache/elastic-sph)
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

APT_PACKAGES=(build-essential cmake ninja-build ccache pkg-config xz-utils
              libopenmpi-dev openmpi-bin libeigen3-dev libyaml-dev googletest
              python3 python3-venv python3-dev valgrind clang-format
              libsuitesparse-dev libopenblas0-serial libpetsc-real-dev
              liblapack-dev libblas-dev)

install_system_packages() {
  local missing=()
  for p in "${APT_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  say "installing Debian packages: ${missing[*]}"
  as_root apt-get update -qq
  DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -qq --no-install-recommends "${missing[@]}" >"${TMPDIR:-/tmp}/esph-apt.log" 2>&1 ||
    { tail -20 "${TMPDIR:-/tmp}/esph-apt.log" >&2; die "apt-get install failed"; }
}

# Add a deb-src entry for trixie on the mirror this machine already uses, so
# `apt-get source` can fetch the pinned LAMMPS. No address is written into the repo.
ensure_deb_src() {
  local list=/etc/apt/sources.list.d/elastic-sph-src.sources
  [ -f "$list" ] && return 0
  local uri
  uri=$(awk '/^URIs:/ {print $2; exit}' /etc/apt/sources.list.d/debian.sources 2>/dev/null || true)
  [ -n "$uri" ] || uri=$(awk '$1=="deb" && $0 !~ /security/ {print $2; exit}' /etc/apt/sources.list 2>/dev/null || true)
  [ -n "$uri" ] || die "no Debian apt source found to derive a deb-src entry from; set LAMMPS_SOURCE_DIR to a LAMMPS tree"
  say "adding deb-src (trixie) on $uri"
  printf 'Types: deb-src\nURIs: %s\nSuites: trixie\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' \
    "$uri" | as_root tee "$list" >/dev/null
  as_root apt-get update -qq
}

fetch_lammps() {
  [ -f "$LAMMPS_SOURCE_DIR/src/version.h" ] && return 0
  [ "$LAMMPS_SOURCE_DIR" = "$ESPH_CACHE/src/$LAMMPS_ORIG_TOPDIR" ] ||
    die "LAMMPS_SOURCE_DIR=$LAMMPS_SOURCE_DIR has no src/version.h; point it at a LAMMPS source tree"
  local dl="$ESPH_CACHE/download"
  mkdir -p "$dl" "$ESPH_CACHE/src"
  if [ ! -f "$dl/$LAMMPS_ORIG_TARBALL" ]; then
    ensure_deb_src
    say "fetching LAMMPS source package $LAMMPS_DEB_VERSION"
    # The .dsc is reported missing (404) on these mirrors while the tarball
    # arrives; we verify the tarball ourselves below, so that error is expected.
    (cd "$dl" && apt-get source --download-only "lammps=$LAMMPS_DEB_VERSION" >apt-source.log 2>&1) || true
    [ -f "$dl/$LAMMPS_ORIG_TARBALL" ] || { cat "$dl/apt-source.log" >&2; die "could not download $LAMMPS_ORIG_TARBALL"; }
  fi
  echo "$LAMMPS_ORIG_SHA256  $dl/$LAMMPS_ORIG_TARBALL" | sha256sum -c --quiet ||
    { rm -f "$dl/$LAMMPS_ORIG_TARBALL"; die "sha256 mismatch for $LAMMPS_ORIG_TARBALL (deleted; rerun)"; }
  say "unpacking $LAMMPS_ORIG_TARBALL"
  tar -xJf "$dl/$LAMMPS_ORIG_TARBALL" -C "$ESPH_CACHE/src"
  [ -f "$LAMMPS_SOURCE_DIR/src/version.h" ] || die "unpacked tarball has no $LAMMPS_ORIG_TOPDIR/src/version.h"
}

# LAMMPS's unit-test harness downloads googletest by URL; offline we pack
# Debian's googletest sources into a reproducible tarball and hand it over.
pack_googletest() {
  GTEST_TARBALL="$ESPH_CACHE/download/googletest-debian.tar.gz"
  if [ ! -f "$GTEST_TARBALL" ]; then
    mkdir -p "$ESPH_CACHE/download"
    tar --sort=name --mtime=@0 --owner=0 --group=0 --numeric-owner -C /usr/src -cf - googletest |
      gzip -n >"$GTEST_TARBALL.tmp"
    mv "$GTEST_TARBALL.tmp" "$GTEST_TARBALL"
  fi
  GTEST_MD5=$(md5sum "$GTEST_TARBALL" | cut -d' ' -f1)
}

# The stamp of a clone's build tree: the options it was last configured with.
# A tree from before the stamp, or from other options, is reconfigured in
# place: cmake with the -D flags over the existing cache, then ninja rebuilds
# what the options touch (a new package adds its include directory to every
# file's command line: all of LAMMPS again, mostly from ccache).
options_stamp() { printf '%s\n' "$@" | sha1sum | cut -c1-40; }

configure_and_build() {
  mkdir -p "$ESPH_BUILD"
  local stamp="$ESPH_BUILD/esph-options.sha1" want
  want=$(options_stamp "${ESPH_LAMMPS_OPTIONS[@]}")
  if [ ! -f "$ESPH_BUILD/build.ninja" ] || [ "$(cat "$stamp" 2>/dev/null)" != "$want" ]; then
    pack_googletest
    local launcher=()
    command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
    if [ -f "$ESPH_BUILD/build.ninja" ]; then
      say "reconfiguring $ESPH_BUILD: the LAMMPS options changed (ESPH_LAMMPS_OPTIONS, scripts/common.sh)"
    else
      say "configuring LAMMPS + ELASTIC-SPH in $ESPH_BUILD"
    fi
    cmake -S "$ESPH_ROOT" -B "$ESPH_BUILD" -G Ninja "${launcher[@]}" \
      -DLAMMPS_ROOT="$LAMMPS_SOURCE_DIR" "${ESPH_LAMMPS_OPTIONS[@]}" \
      -DENABLE_TESTING=on -DGTEST_URL="file://$GTEST_TARBALL" -DGTEST_MD5="$GTEST_MD5" \
      -DPython_EXECUTABLE="$(command -v python3)" >"$ESPH_BUILD/configure.log" 2>&1 ||
      { tail -40 "$ESPH_BUILD/configure.log" >&2; die "cmake configure failed (log: $ESPH_BUILD/configure.log)"; }
    echo "$want" >"$stamp"
  fi
  # Let ccache match objects across build trees of different clones.
  export CCACHE_BASEDIR="$ESPH_CACHE" CCACHE_NOHASHDIR=1
  say "building (ninja, $ESPH_JOBS jobs)"
  cmake --build "$ESPH_BUILD" -j "$ESPH_JOBS" --target lmp esph_testers >"$ESPH_BUILD/build.log" 2>&1 ||
    { grep -E 'error|Error' "$ESPH_BUILD/build.log" | head -30 >&2; die "build failed (log: $ESPH_BUILD/build.log)"; }
}

# The plugin route, as a user with their own LAMMPS takes it: a LAMMPS of the
# same tree built with PKG_PLUGIN and without this package (the host), and
# the plugin built from plugin/CMakeLists.txt against its headers. The host
# tree's name holds its options (common.sh), so it needs no stamp.
build_plugin_route() {
  export CCACHE_BASEDIR="$ESPH_CACHE" CCACHE_NOHASHDIR=1
  local launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  if [ ! -f "$ESPH_HOST_BUILD/build.ninja" ]; then
    mkdir -p "$ESPH_HOST_BUILD"
    say "configuring a plain LAMMPS with the PLUGIN package in $ESPH_HOST_BUILD"
    cmake -S "$LAMMPS_SOURCE_DIR/cmake" -B "$ESPH_HOST_BUILD" -G Ninja "${launcher[@]}" \
      "${ESPH_HOST_OPTIONS[@]}" >"$ESPH_HOST_BUILD/configure.log" 2>&1 ||
      { tail -40 "$ESPH_HOST_BUILD/configure.log" >&2; die "host LAMMPS configure failed"; }
  fi
  say "building the plain LAMMPS (ninja, $ESPH_JOBS jobs)"
  cmake --build "$ESPH_HOST_BUILD" -j "$ESPH_JOBS" --target lmp >"$ESPH_HOST_BUILD/build.log" 2>&1 ||
    { grep -E 'error|Error' "$ESPH_HOST_BUILD/build.log" | head -30 >&2; die "host LAMMPS build failed (log: $ESPH_HOST_BUILD/build.log)"; }
  if [ ! -f "$ESPH_PLUGIN_BUILD/build.ninja" ]; then
    say "configuring the plugin in $ESPH_PLUGIN_BUILD"
    cmake -S "$ESPH_ROOT/plugin" -B "$ESPH_PLUGIN_BUILD" -G Ninja "${launcher[@]}" \
      -DLAMMPS_SOURCE_DIR="$LAMMPS_SOURCE_DIR/src" -DESPH_PLUGIN_TESTS=on \
      >"$ESPH_PLUGIN_BUILD.configure.log" 2>&1 ||
      { tail -40 "$ESPH_PLUGIN_BUILD.configure.log" >&2; die "plugin configure failed"; }
  fi
  say "building the plugin"
  cmake --build "$ESPH_PLUGIN_BUILD" -j "$ESPH_JOBS" >"$ESPH_PLUGIN_BUILD/build.log" 2>&1 ||
    { grep -E 'error|Error' "$ESPH_PLUGIN_BUILD/build.log" | head -30 >&2; die "plugin build failed (log: $ESPH_PLUGIN_BUILD/build.log)"; }
}

setup_venv() {
  if [ ! -x "$ESPH_VENV/bin/python" ]; then
    say "creating virtual environment $ESPH_VENV"
    python3 -m venv "$ESPH_VENV"
  fi
  local req="$ESPH_ROOT/python/requirements.txt" stamp="$ESPH_VENV/.requirements.sha1"
  local want; want=$(sha1sum "$req" | cut -c1-40)
  if [ "$(cat "$stamp" 2>/dev/null)" != "$want" ]; then
    say "installing Python requirements"
    "$ESPH_VENV/bin/pip" install -q --upgrade pip >/dev/null
    "$ESPH_VENV/bin/pip" install -q -r "$req"
    echo "$want" >"$stamp"
  fi
  # The lammps module of the same LAMMPS tree, loading liblammps.so of our
  # build: a package directory of symlinks, so a rebuild needs no reinstall.
  local site; site=$("$ESPH_VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
  rm -rf "$site/lammps" && mkdir -p "$site/lammps"
  ln -s "$LAMMPS_SOURCE_DIR"/python/lammps/* "$site/lammps/"
  ln -s "$ESPH_BUILD/liblammps.so" "$site/lammps/liblammps.so"
  # our driver package, editable, pointing at this clone
  if ! "$ESPH_VENV/bin/python" -c "import esph, sys; sys.exit(not esph.__file__.startswith('$ESPH_ROOT/'))" 2>/dev/null; then
    "$ESPH_VENV/bin/pip" install -q --no-deps -e "$ESPH_ROOT/python" >"$ESPH_VENV/esph-install.log" 2>&1 ||
      { tail -20 "$ESPH_VENV/esph-install.log" >&2; die "pip install of python/ failed"; }
  fi
}

main() {
  install_system_packages
  fetch_lammps
  configure_and_build
  [ "${1:-}" = "--plugin" ] && build_plugin_route
  setup_venv
  say "ready: $ESPH_LMP ($(ls -1 "$ESPH_BUILD"/liblammps.so* | head -1))"
}
main "$@"
