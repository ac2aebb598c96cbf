#!/usr/bin/env bash
# Installs linkfit's build dependencies from Debian packages (only those missing; safe to run
# twice), builds the project in build/ (Release) and installs it (to /usr/local, or
# $LINKFIT_PREFIX). Run as root or with sudo available.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake libeigen3-dev libceres-dev libnlopt-cxx-dev libgtest-dev
          nlohmann-json3-dev libcli11-dev librsvg2-bin libxml2-utils libpng-dev)
./scripts/install_packages.sh "${packages[@]}"

[ "${1:-}" = "--deps-only" ] && exit 0
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
# The CLI, the libraries, their headers and the CMake package, to /usr/local (or
# LINKFIT_PREFIX): `linkfit` on the PATH and find_package(linkfit CONFIG) in any project.
install_prefix=${LINKFIT_PREFIX:-/usr/local}
if [ -w "$install_prefix" ] || [ "$(id -u)" = 0 ]; then
  cmake --install build --prefix "$install_prefix" >/dev/null
else
  sudo cmake --install build --prefix "$install_prefix" >/dev/null
fi
