#!/usr/bin/env bash
# Two scm builds against each other in alternating rounds: per robot and round, `scm sample --force`
# (100,000 samples, all six types, defaults) with OLD, then with NEW, back to back, so that a machine
# whose speed drifts slows both alike; prints each run, the per-round ratios NEW / OLD and the medians.
# Usage: scripts/bench-compare.sh OLD_SCM NEW_SCM [ROUNDS] [ROBOT_FOLDER...]
# (robots from SCM_ROBOTS, default ../shared/robots; default robots: ur5e panda). Build the two
# binaries first, e.g. from two worktrees with `cargo build --release`, and copy them aside.
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { echo "usage: $0 OLD_SCM NEW_SCM [ROUNDS] [ROBOT_FOLDER...]" >&2; exit 2; }
old=$1
new=$2
shift 2
rounds=${1:-3}
shift || true
robots=${SCM_ROBOTS:-../shared/robots}
names=("$@")
[ ${#names[@]} -gt 0 ] || names=(ur5e panda)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
seconds() {
  local start end
  start=$(date +%s.%N)
  "$1" sample "$2" --force -q
  end=$(date +%s.%N)
  awk "BEGIN { printf \"%.2f\", $end - $start }"
}
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
for name in "${names[@]}"; do
  urdf=$(ls "$robots/$name"/*.urdf | grep -v '\.original\.urdf$' | head -n 1)
  "$new" preprocess "$urdf" -o "$out/$name" -q
  olds=() news=()
  for r in $(seq "$rounds"); do
    a=$(seconds "$old" "$out/$name")
    b=$(seconds "$new" "$out/$name")
    olds+=("$a")
    news+=("$b")
    printf '%-12s round %d  old %7.2f s  new %7.2f s  new/old %.2f\n' "$name" "$r" "$a" "$b" \
      "$(awk "BEGIN { print $b / $a }")"
  done
  printf '%-12s median   old %7.2f s  new %7.2f s\n' "$name" \
    "$(printf '%s\n' "${olds[@]}" | median)" "$(printf '%s\n' "${news[@]}" | median)"
done
