#!/usr/bin/env bash
# Builds pleat with AddressSanitizer + UndefinedBehaviorSanitizer into
# build-asan/ and runs every test there. Slower than scripts/test.sh; run it
# before landing changes to parsers, the C boundary or the solvers.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
cmake -S "$root" -B "$root/build-asan" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPLEAT_SANITIZE=ON \
  -DPLEAT_BUILD_BENCH=OFF >/dev/null
cmake --build "$root/build-asan" -j "$(nproc)"
cd "$root/build-asan"
# The Python reference (SciPy) runs as a child process; keep ASan out of it.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --output-on-failure -j "$(nproc)"
