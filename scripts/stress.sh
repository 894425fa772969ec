#!/usr/bin/env bash
# The stress catalogue at length (docs/reliability.md): the Release build's
# test_capi_stress with ten times the frames (1,000,000 frames evaluated in
# chunks, no allocation, no drift; about 5 minutes), then the catalogue and
# the concurrency tests under ASan + UBSan and under ThreadSanitizer.
#
#   scripts/stress.sh [scale]    scale: frames x 100,000 (default 10)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
scale="${1:-10}"
"$root/scripts/build.sh"
(cd "$root/build" && PLEAT_STRESS_SCALE="$scale" ctest --output-on-failure --timeout 3600 -R '^test_capi_stress$')
"$root/scripts/sanitize.sh" test_capi_stress test_capi_model test_capi_fault_injection
"$root/scripts/sanitize.sh" --thread test_capi_model test_runtime_golden
