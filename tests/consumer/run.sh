#!/usr/bin/env bash
# Installs the build tree BUILD into a fresh prefix under it, configures and builds the consumer
# project (tests/consumer) against that prefix with find_package(linkfit CONFIG), solves the
# bundled five-pose task with it and checks that the result equals `linkfit solve`'s (the
# installed CLI's), timing fields aside; and that PYTHON imports the installed Python module from
# the prefix's dist-packages and solves the task the same.
# Usage: run.sh SOURCE_DIR BUILD_DIR PYTHON
set -euo pipefail
source_dir=$1
build_dir=$2
python=$3
work=$(mktemp -d "$build_dir/consumer.XXXXXX")
trap 'rm -rf "$work"' EXIT
cmake --install "$build_dir" --prefix "$work/prefix" >/dev/null
cmake -S "$source_dir/tests/consumer" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/build" >/dev/null
task="$source_dir/data/four_bar_5_poses.json"
strip_times() { grep -v -E '"[a-z_]*(_ms|_seconds)": '; }
"$work/build/consumer" "$task" | strip_times > "$work/consumer.json"
"$work/prefix/bin/linkfit" solve "$task" > "$work/cli_raw.json"
strip_times < "$work/cli_raw.json" > "$work/cli.json"
diff "$work/consumer.json" "$work/cli.json"
grep -q '"type": "RR"' "$work/consumer.json"
version=$("$python" -c 'import sys; print("%d.%d" % sys.version_info[:2])')
PYTHONPATH="$work/prefix/lib/python$version/dist-packages:$source_dir/tests/python" \
PYTHONDONTWRITEBYTECODE=1 "$python" - "$task" "$work/cli_raw.json" "$work/prefix" <<'PY'
import json, sys
import linkfit
from test_linkfit import untimed
assert linkfit.__file__.startswith(sys.argv[3]), linkfit.__file__  # the installed one
result = linkfit.solve(json.load(open(sys.argv[1])))
cli = json.loads(open(sys.argv[2]).read())
assert untimed(result) == untimed(cli), "python result differs from the CLI's"
PY
echo "consumer and Python results equal the installed CLI's"
