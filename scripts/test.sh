#!/usr/bin/env bash
# Sets up, builds and runs every test. This is what CI runs (.ci/run).
# After the Release tests, the sanitizer build (build-asan/: clang, ASan +
# UBSan) runs the model-file mutation test, the fault injection, the stress
# catalogue, the glTF/USD cache readers and writers, pleat's glTF scene
# reader, the body-collision post-pass and every libFuzzer target briefly; then a ThreadSanitizer build
# (build-tsan/) runs the concurrency tests. Each builds only those targets.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/build.sh"
cd "$root/build"
ctest --output-on-failure -j "$(nproc)"
"$root/scripts/sanitize.sh" test_model_fuzz test_capi_fault_injection test_capi_stress test_mesh_caches \
  test_gltf_scene test_capi_body_collision fuzz_targets
"$root/scripts/sanitize.sh" --thread test_capi_model test_runtime_golden
