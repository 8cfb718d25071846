#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, AddressSanitizer + UndefinedBehaviorSanitizer) into build-fuzz/ and runs them.
# Installs clang, libfuzzer-14-dev and libclang-rt-14-dev with apt-get when missing. Every input a target fails on is kept as
# build-fuzz/failures/<target>-*; make it a regression test (tests/native/test_bad_input.cpp shows how).
#
# Usage: scripts/fuzz.sh [--seconds N] [--target fuzz_obj|fuzz_plan|fuzz_cli|fuzz_tessellation] [--build-only]
#                       [--run-only]
#   default: build, then run every target for 60 s (the test suite runs them too; longer runs: --seconds 3600)
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=60 targets=(fuzz_obj fuzz_plan fuzz_cli fuzz_tessellation) build=1 run=1
while (($#)); do
  case "$1" in
    --seconds) seconds="${2:?--seconds needs a number}"; shift 2 ;;
    --target) targets=("${2:?--target needs a name}"); shift 2 ;;
    --build-only) run=0; shift ;;
    --run-only) build=0; shift ;;
    *) echo "fuzz: unknown argument '$1'" >&2; exit 2 ;;
  esac
done

if ((build)); then
  source scripts/packages.sh
  install_packages clang libfuzzer-14-dev libclang-rt-14-dev  # the last: the sanitizers' and libFuzzer's runtime
  cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLOOPSUB_FUZZ=ON \
    -DLOOPSUB_TESTS=OFF -DLOOPSUB_BENCH=OFF -DLOOPSUB_PYTHON=OFF -DLOOPSUB_BLENDER= >/dev/null
  cmake --build build-fuzz -j"$(nproc)" --target "${targets[@]}"
fi
((run)) || exit 0

shapes=../shared/peer/opensubdiv-loop-shapes
status=0
for target in "${targets[@]}"; do
  corpus=build-fuzz/corpus/$target
  mkdir -p "$corpus" build-fuzz/failures
  # The OBJ target starts from OpenSubdiv's shapes; the raw-bytes target finds its own way from nothing.
  if [ "$target" = fuzz_obj ] && [ -d "$shapes" ]; then cp -n "$shapes"/*.obj "$corpus"/ 2>/dev/null || true; fi
  log=build-fuzz/$target.log
  if build-fuzz/"$target" -max_total_time="$seconds" -rss_limit_mb=2048 -print_final_stats=1 \
       -artifact_prefix=build-fuzz/failures/"$target"- "$corpus" >"$log" 2>&1; then
    echo "fuzz: $target: $(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$') inputs in ${seconds} s, no failure"
  else
    echo "fuzz: $target FAILED; the input is in build-fuzz/failures/, the report:" >&2
    grep -E -A12 'runtime error|ERROR: |deadly signal' "$log" | head -40 >&2
    status=1
  fi
done
exit "$status"
