#!/usr/bin/env bash
# Builds pleat and runs the benchmarks; prints the machine, the date and the
# medians that docs/benchmarks.md records (bench_nn, the kernels alone, runs
# separately). Benchmarks are not tests: run them
# on a quiet machine. Arguments go to bench_spectral (e.g. --quick).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/build.sh" >/dev/null
echo "date: $(date -u +%Y-%m-%d)"
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(free -g | awk '/Mem:/ {print $2}') GiB"
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
garments="$root/../shared/data/garments"
"$root/build/bench/bench_spectral" "$@" \
  "$garments/female_casualsuit02/female_casualsuit02.obj" "$garments/male_elegantsuit01/male_elegantsuit01.obj"
"$root/build/bench/bench_metrics"
"$root/build/bench/bench_runtime" "$root/../shared/data"
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
