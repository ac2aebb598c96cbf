#!/usr/bin/env bash
# Builds the user guide (docs/: Sphinx with MyST Markdown) into build/docs/html, every warning an
# error (a broken link or cross-reference included). The API page is generated from the Python
# module of the build tree, so build first (./scripts/setup.sh, or cmake --build build).
#   LINKFIT_BUILD  the build directory (default build/)
#   LINKFIT_DOCS   where the guide goes (default <build>/docs; the pages in its html/)
#   LINKFIT_PYTHON the interpreter with Sphinx (default Debian's /usr/bin/python3)
# Needs Debian's python3-sphinx and python3-myst-parser (scripts/setup.sh installs them).
set -euo pipefail
cd "$(dirname "$0")/.."
build=$(realpath -m "${LINKFIT_BUILD:-build}")
out=$(realpath -m "${LINKFIT_DOCS:-$build/docs}")
python=${LINKFIT_PYTHON:-/usr/bin/python3}
if [ ! -f "$build/python/linkfit/__init__.py" ]; then
  echo "docs: no Python module in $build/python: build linkfit first" >&2
  exit 2
fi
# -E -a: read and write every page each time, so that every warning is seen again; -n: every
# cross-reference must resolve; -W --keep-going: report all warnings, then fail.
PYTHONPATH="$build/python${PYTHONPATH:+:$PYTHONPATH}" PYTHONDONTWRITEBYTECODE=1 \
  "$python" -m sphinx -b html -E -a -n -W --keep-going -q -d "$out/doctrees" docs "$out/html"
echo "docs: $out/html/index.html"
