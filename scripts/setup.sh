#!/usr/bin/env bash
# Installs linkfit's build dependencies from Debian packages (only those missing; safe to run
# twice; Sphinx, MyST and MathJax build the user guide, scripts/docs.sh), builds the project in
# build/ (Release) and installs it (to /usr/local, or $LINKFIT_PREFIX). Run as root or with sudo
# available.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake libeigen3-dev libceres-dev libnlopt-cxx-dev libgtest-dev
          nlohmann-json3-dev libcli11-dev librsvg2-bin libxml2-utils libpng-dev
          python3-dev pybind11-dev python3-numpy python3-pytest python3-dask python3-distributed
          python3-matplotlib libnanoflann-dev python3-sphinx python3-myst-parser
          libjs-mathjax pkgconf libdxflib-dev python3-ezdxf
          libcpp-httplib-dev chromium chromium-driver python3-selenium)
./scripts/install_packages.sh "${packages[@]}"

[ "${1:-}" = "--deps-only" ] && exit 0
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
# The CLI, the libraries, their headers, the CMake package and the Python module, to /usr/local
# (or LINKFIT_PREFIX): `linkfit` on the PATH, find_package(linkfit CONFIG) in any project and
# `import linkfit` in Debian's python3.
install_prefix=${LINKFIT_PREFIX:-/usr/local}
if [ -w "$install_prefix" ] || [ "$(id -u)" = 0 ]; then
  cmake --install build --prefix "$install_prefix" >/dev/null
elif command -v sudo >/dev/null; then
  sudo cmake --install build --prefix "$install_prefix" >/dev/null
else
  echo "setup: $install_prefix is not writable and there is no sudo: not installed" \
       "(set LINKFIT_PREFIX to a writable prefix)" >&2
fi
# The `python3` first on the PATH may be another interpreter than Debian's (pyenv, a virtual
# environment); of the same ABI, it gets a copy of the package too, so `import linkfit` works there.
debian_python=/usr/bin/python3
abi() { "$1" -c 'import sysconfig; print(sysconfig.get_config_var("SOABI"))'; }
where() { "$1" -c 'import os, sys; print(os.path.realpath(sys.executable))'; }
if command -v python3 >/dev/null && [ "$(where python3)" != "$(where $debian_python)" ] &&
   [ "$(abi python3)" = "$(abi $debian_python)" ]; then
  version=$($debian_python -c 'import sys; print("%d.%d" % sys.version_info[:2])')
  purelib=$(python3 -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
  if mkdir -p "$purelib" 2>/dev/null && [ -w "$purelib" ]; then
    rm -rf "$purelib/linkfit"
    cp -r "$install_prefix/lib/python$version/dist-packages/linkfit" "$purelib/"
  fi
fi
