#!/usr/bin/env bash
# Installs the Debian 12 packages cluttertamp builds and tests with (ompl-demos: the
# tests load bench logs with ompl_benchmark_statistics; parallel: the GNU parallel
# recipe); with --browser also Chromium and ChromeDriver, which the browser tests drive
# (headless); with --slurm also Slurm and munge, for scripts/test-slurm.sh.
# Idempotent: packages already installed are skipped, and apt is not touched at all
# when nothing is missing. Needs root (or sudo) only when something must be installed.
set -euo pipefail

packages=(
  build-essential cmake pkg-config ccache git
  libeigen3-dev libfcl-dev libompl-dev liburdfdom-dev libbullet-dev libassimp-dev libqhull-dev libtinyxml-dev
  libboost-dev libboost-graph-dev libboost-filesystem-dev libboost-system-dev
  libboost-serialization-dev libboost-program-options-dev
  libyaml-cpp-dev libgtest-dev libgmock-dev
  nlohmann-json3-dev libcli11-dev
  libcpp-httplib-dev libjs-three
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib
  ompl-demos parallel
)
for arg in "$@"; do
  case "$arg" in
    --browser) packages+=(chromium chromium-driver) ;;
    --slurm) packages+=(slurm-wlm munge) ;;
    *) echo "install-deps: unknown option $arg (known: --browser, --slurm)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
echo "install-deps: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
