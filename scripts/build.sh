#!/usr/bin/env bash
# Installs missing Debian packages, then configures (Release, ccache) and builds
# cluttertamp, its plugins and its tests in ./build (or $CLUTTERTAMP_BUILD_DIR).
# --browser also installs Chromium and ChromeDriver for the browser tests.
# Safe to run again: installed packages and up-to-date targets are skipped.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${CLUTTERTAMP_BUILD_DIR:-build}"

./scripts/install-deps.sh "$@"
mkdir -p "$build_dir"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DCLUTTERTAMP_USE_CCACHE=ON > "$build_dir/configure.log" 2>&1 \
  || { cat "$build_dir/configure.log"; exit 1; }
cmake --build "$build_dir" -j"$(nproc)"
