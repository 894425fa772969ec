#!/usr/bin/env bash
# Sets up, builds and runs the main job on the bundled sample: prepare the
# sample dress (MakeHuman CC0, stored in decimetres) and print its report;
# then, from the C example host (dlopen only), bind the trained demo model
# (data/models/demo.pleat, trained on Blender simulations: data/models/demo.md)
# to the dress and the MakeHuman body and write the first second of a walk as
# an OBJ sequence.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
assets="${PLEAT_ASSET_DIR:-$root/../shared/data}"
"$root/scripts/build.sh"
mkdir -p "$root/out"
"$root/build/pleat" prepare "$root/data/garments/female_elegantsuit01.obj" --unit-scale 0.1 \
  -o "$root/out/female_elegantsuit01.pleatg"
"$root/build/plugin_host_example" "$root/build/libpleat.so.0" "$root/out/female_elegantsuit01.pleatg" \
  "$root/data/models/demo.pleat" "$assets/body" "$root/tests/fixtures/motion/12_03_walk_121.bvh" \
  "$root/out/dress_####.obj" 30
