#!/usr/bin/env bash
# Fuzzes the task parser (tests/fuzz/fuzz_task_parser.cc) with libFuzzer, AddressSanitizer and
# UBSan for SECONDS (default 300). Installs clang and libFuzzer's runtime if missing (Debian
# packages, as setup.sh does), builds only the fuzz target in build-fuzz/ (clang,
# -DLINKFIT_FUZZ=ON), copies the seeds (data/, tests/fuzz/corpus/) into the scratch corpus
# build-fuzz/corpus/ and runs the fuzzer on it. A finding stops the run with a report and an
# input build-fuzz/crash-<sha1> (or leak-, timeout-, oom-): fix it, then add the input to
# tests/fuzz/corpus/ as a regression seed (the test FuzzCorpusReplay replays that directory
# in every build). Exit status: 0 when nothing was found.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-300}"
build=build-fuzz

./scripts/setup.sh --deps-only
# libclang-rt-14-dev holds libclang_rt.fuzzer (and the sanitizer runtimes) for Debian 12's clang.
packages=(clang libclang-rt-14-dev)
./scripts/install_packages.sh "${packages[@]}"

CC=clang CXX=clang++ cmake -S . -B "$build" -DLINKFIT_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  >/dev/null
cmake --build "$build" -j2 --target fuzz_task_parser

mkdir -p "$build/corpus"
cp data/* tests/fuzz/corpus/* "$build/corpus/"
# -timeout: an input that takes seconds (a quadratic path) is a finding too.
"$build/bin/fuzz_task_parser" -max_total_time="$seconds" -max_len=65536 -rss_limit_mb=2048 \
  -timeout=10 -dict=tests/fuzz/task.dict -artifact_prefix="$build/" -print_final_stats=1 \
  "$build/corpus" data tests/fuzz/corpus
