#!/usr/bin/env bash
# Installs the build tree BUILD into a fresh prefix under it, configures and builds the consumer
# project (tests/consumer) against that prefix with find_package(linkfit CONFIG), solves the
# bundled five-pose task with it and checks that the result equals `linkfit solve`'s (the
# installed CLI's), timing fields aside.
# Usage: run.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
source_dir=$1
build_dir=$2
work=$(mktemp -d "$build_dir/consumer.XXXXXX")
trap 'rm -rf "$work"' EXIT
cmake --install "$build_dir" --prefix "$work/prefix" >/dev/null
cmake -S "$source_dir/tests/consumer" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/build" >/dev/null
task="$source_dir/data/four_bar_5_poses.json"
strip_times() { grep -v -E '"[a-z_]*(_ms|_seconds)": '; }
"$work/build/consumer" "$task" | strip_times > "$work/consumer.json"
"$work/prefix/bin/linkfit" solve "$task" | strip_times > "$work/cli.json"
diff "$work/consumer.json" "$work/cli.json"
grep -q '"type": "RR"' "$work/consumer.json"
echo "consumer result equals the installed CLI's"
