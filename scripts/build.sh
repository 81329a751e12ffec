#!/usr/bin/env bash
# Installs missing Debian packages, then configures (Release, ccache) and builds
# cluttertamp, its plugins and its tests in ./build (or $CLUTTERTAMP_BUILD_DIR).
# --browser also installs Chromium and ChromeDriver for the browser tests.
# --sanitize builds everything with AddressSanitizer and UndefinedBehaviorSanitizer in
# ./build-sanitize (or $CLUTTERTAMP_BUILD_DIR); run its tests with
#   ctest --test-dir build-sanitize --output-on-failure -j2
# Safe to run again: installed packages and up-to-date targets are skipped.
set -euo pipefail
cd "$(dirname "$0")/.."
sanitize=OFF
deps=()
for arg in "$@"; do
  case "$arg" in
    --sanitize) sanitize=ON ;;
    *) deps+=("$arg") ;;
  esac
done
if [ "$sanitize" = ON ]; then build_dir="${CLUTTERTAMP_BUILD_DIR:-build-sanitize}"; else build_dir="${CLUTTERTAMP_BUILD_DIR:-build}"; fi

./scripts/install-deps.sh "${deps[@]}"
mkdir -p "$build_dir"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DCLUTTERTAMP_USE_CCACHE=ON -DCLUTTERTAMP_SANITIZE="$sanitize" \
  > "$build_dir/configure.log" 2>&1 \
  || { cat "$build_dir/configure.log"; exit 1; }
cmake --build "$build_dir" -j"$(nproc)"
