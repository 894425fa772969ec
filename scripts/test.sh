#!/usr/bin/env bash
# Sets up, builds and runs every test. This is what CI runs (.ci/run).
# After the Release tests, the model-file fuzz test runs again in the
# sanitizer build (build-asan/, ASan + UBSan), which builds only that target.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/build.sh"
cd "$root/build"
ctest --output-on-failure -j "$(nproc)"
"$root/scripts/sanitize.sh" test_model_fuzz
