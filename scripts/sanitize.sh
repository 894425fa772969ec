#!/usr/bin/env bash
# Builds pleat with clang, AddressSanitizer + UndefinedBehaviorSanitizer and
# libFuzzer's coverage instrumentation into build-asan/ and runs the tests
# there. Slower than a Release build; run it whole before landing changes to
# parsers, the C boundary or the solvers.
#
#   scripts/sanitize.sh                  every test, and each fuzz target for a few seconds
#   scripts/sanitize.sh test_a test_b    only these test programs
#   scripts/sanitize.sh fuzz_targets     every fuzz target, 3,000 inputs each
#   scripts/sanitize.sh --build-only     builds everything, runs nothing (scripts/fuzz.sh)
#   scripts/sanitize.sh --thread test_a  ThreadSanitizer instead, in build-tsan/ (the
#                                        threaded tests: test_capi_model, test_runtime_golden)
# CI runs `scripts/sanitize.sh test_model_fuzz test_capi_fault_injection test_capi_stress test_mesh_caches
# test_gltf_scene test_capi_body_collision fuzz_targets`
# and `scripts/sanitize.sh --thread test_capi_model test_runtime_golden`.
# The trainer is left out: libtorch itself is not built with the sanitizers.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
build_only=0
tree=build-asan
sanitizers=(-DPLEAT_SANITIZE=ON -DPLEAT_FUZZ=ON)
case "${1:-}" in
  --build-only) build_only=1; shift ;;
  --thread) tree=build-tsan; sanitizers=(-DPLEAT_TSAN=ON); shift ;;
esac
# CI builds this tree from scratch on every run, so it is built for build
# time: -O1 and line tables only (enough for the sanitizers' stack traces) and
# unity batches, which parse Eigen's headers once per batch instead of once
# per file (870 -> 591 CPU s for CI's ASan targets; docs/benchmarks.md,
# 2026-12-06).
# Unity batches share one scope: a file-local name must be unique within its
# library (kDenseKind, not kKind).
CC=clang CXX=clang++ cmake -S "$root" -B "$root/$tree" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "${sanitizers[@]}" \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1" \
  -DCMAKE_UNITY_BUILD=ON -DPLEAT_BUILD_BENCH=OFF -DPLEAT_BUILD_TRAINING=OFF >/dev/null
cmake --build "$root/$tree" -j "$(nproc)" ${1:+--target "$@"}
[ $build_only -eq 1 ] && exit 0
cd "$root/$tree"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$root/tests/tsan.supp"
if [ $# -gt 0 ]; then
  tests=("${@/#fuzz_targets/fuzz_.*}")
  ctest --output-on-failure -j "$(nproc)" -R "^($(IFS='|'; echo "${tests[*]}"))\$"
else
  ctest --output-on-failure -j "$(nproc)"
fi
