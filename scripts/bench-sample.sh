#!/usr/bin/env bash
# Median wall time of `scm sample --force` (100,000 samples, all six types, default settings) over RUNS
# runs per robot, release build. Usage: scripts/bench-sample.sh [RUNS] [ROBOT_FOLDER...]
# (robots from SCM_ROBOTS, default ../shared/robots; default robots: ur5e panda).
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-3}
shift || true
robots=${SCM_ROBOTS:-../shared/robots}
names=("$@")
[ ${#names[@]} -gt 0 ] || names=(ur5e panda)
cargo build --release -q
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for name in "${names[@]}"; do
  urdf=$(ls "$robots/$name"/*.urdf | grep -v '\.original\.urdf$' | head -n 1)
  ./target/release/scm preprocess "$urdf" -o "$out/$name" -q
  times=()
  for _ in $(seq "$runs"); do
    start=$(date +%s.%N)
    ./target/release/scm sample "$out/$name" --force -q
    end=$(date +%s.%N)
    times+=("$(awk "BEGIN { print $end - $start }")")
  done
  median=$(printf '%s\n' "${times[@]}" | sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
  printf '%-12s median %.1f s over %d runs\n' "$name" "$median" "$runs"
done
