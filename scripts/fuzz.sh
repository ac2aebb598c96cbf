#!/usr/bin/env bash
# Fuzzes linkfit with libFuzzer, AddressSanitizer and UBSan: the task parser
# (tests/fuzz/fuzz_task_parser.cc), the whole solve of every task kind (fuzz_solve.cc) and the
# command line's option handling (fuzz_cli.cc), SECONDS each (default 300).
#   scripts/fuzz.sh [SECONDS] [TARGET...]   (targets: parser solve cli; default all three)
# Installs clang and libFuzzer's runtime if missing (Debian packages, as setup.sh does), builds
# the fuzz targets in build-fuzz/ (clang, -DLINKFIT_FUZZ=ON), copies the seeds (data/ and
# tests/fuzz/corpus/ for the parser and the solve, tests/fuzz/cli_corpus/ for the command line)
# into scratch corpora build-fuzz/corpus-<target>/ and runs each fuzzer on its own. A finding
# stops that run with a report and an input build-fuzz/crash-<sha1> (or leak-, timeout-, oom-):
# fix it, then add the input to tests/fuzz/corpus/ (or cli_corpus/) as a regression seed (the
# tests FuzzCorpusReplay, FuzzSolveCorpusReplay and FuzzCliCorpusReplay replay those directories
# in every build). Exit status: 0 when nothing was found.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-300}"
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then targets=(parser solve cli); fi
build=build-fuzz

./scripts/setup.sh --deps-only
# libclang-rt-14-dev holds libclang_rt.fuzzer (and the sanitizer runtimes) for Debian 12's clang.
packages=(clang libclang-rt-14-dev)
./scripts/install_packages.sh "${packages[@]}"

CC=clang CXX=clang++ cmake -S . -B "$build" -DLINKFIT_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  >/dev/null

status=0
for target in "${targets[@]}"; do
  case "$target" in
    parser) binary=fuzz_task_parser seeds=("$PWD/data" "$PWD/tests/fuzz/corpus")
      dict=tests/fuzz/task.dict max_len=65536 timeout=20 ;;
    # The solve's seeds are the small tasks of the corpus (data/'s twelve-point tasks take more
    # than a minute at balanced under the sanitizers).
    solve) binary=fuzz_solve seeds=("$PWD/tests/fuzz/corpus") dict=tests/fuzz/task.dict
      max_len=8192 timeout=90 ;;
    # Absolute paths: the target works in a scratch directory of its own.
    cli) binary=fuzz_cli seeds=("$PWD/tests/fuzz/cli_corpus") dict=tests/fuzz/cli.dict
      max_len=1024 timeout=20 ;;
    *) echo "fuzz.sh: unknown target $target (parser, solve or cli)" >&2; exit 2 ;;
  esac
  cmake --build "$build" -j2 --target "$binary"
  corpus="$PWD/$build/corpus-$target"
  mkdir -p "$corpus"
  for seed in "${seeds[@]}"; do cp "$seed"/* "$corpus/"; done
  echo "== $binary, $seconds s"
  # -timeout: an input that takes far longer than its kind should (a quadratic path) is a
  # finding too.
  "$build/bin/$binary" -max_total_time="$seconds" -max_len="$max_len" -rss_limit_mb=2048 \
    -timeout="$timeout" -dict="$PWD/$dict" -artifact_prefix="$PWD/$build/" \
    -print_final_stats=1 "$corpus" "${seeds[@]}" || status=1
done
exit $status
