#!/usr/bin/env bash
# Median wall time of `scm preprocess --force` over RUNS runs for each robot (release build).
# Usage: scripts/bench-preprocess.sh [RUNS]   (robots from SCM_ROBOTS, default ../shared/robots)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-5}
robots=${SCM_ROBOTS:-../shared/robots}
cargo build --release -q
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for urdf in "$robots/ur5e/ur5e.urdf" "$robots/panda/panda.urdf" "$robots/orca_hand/orcahand_right.urdf" \
            "$robots/b1/b1.urdf" robots/demo_arm/demo_arm.urdf; do
  times=()
  for _ in $(seq "$runs"); do
    start=$(date +%s.%N)
    ./target/release/scm preprocess "$urdf" -o "$out/x" --force -q
    end=$(date +%s.%N)
    times+=("$(awk "BEGIN { print $end - $start }")")
  done
  median=$(printf '%s\n' "${times[@]}" | sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
  printf '%-28s median %.2f s over %d runs\n' "$(basename "$urdf")" "$median" "$runs"
done
