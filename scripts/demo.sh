#!/usr/bin/env bash
# Sets up, builds and runs the main job on the bundled sample: prepare the
# sample dress (MakeHuman CC0, stored in decimetres) and print its report.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/build.sh"
mkdir -p "$root/out"
"$root/build/pleat" prepare "$root/data/garments/female_elegantsuit01.obj" --unit-scale 0.1 \
  -o "$root/out/female_elegantsuit01.pleatg"
"$root/build/plugin_host_example" "$root/build/libpleat.so.0" "$root/out/female_elegantsuit01.pleatg"
