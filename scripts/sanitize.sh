#!/usr/bin/env bash
# Builds pleat with AddressSanitizer + UndefinedBehaviorSanitizer into
# build-asan/ and runs the tests there. Slower than a Release build; run it
# whole before landing changes to parsers, the C boundary or the solvers.
#
#   scripts/sanitize.sh                  every test
#   scripts/sanitize.sh test_a test_b    only these test programs (CI runs the
#                                        file-loader fuzz tests this way)
# The trainer is left out: libtorch itself is not built with the sanitizers.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
# -O1 and line tables only: enough for ASan's stack traces, and CI builds
# this tree from scratch on every run.
cmake -S "$root" -B "$root/build-asan" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPLEAT_SANITIZE=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1" \
  -DPLEAT_BUILD_BENCH=OFF -DPLEAT_BUILD_TRAINING=OFF >/dev/null
cmake --build "$root/build-asan" -j "$(nproc)" ${1:+--target "$@"}
cd "$root/build-asan"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
if [ $# -gt 0 ]; then
  ctest --output-on-failure -j "$(nproc)" -R "^($(IFS='|'; echo "$*"))\$"
else
  ctest --output-on-failure -j "$(nproc)"
fi
