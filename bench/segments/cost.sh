#!/usr/bin/env bash
# Cost of a segmented body against its number of segments (issue 35):
# scenes/spin_up_gravity.toml cut to t_end = 2 s (2000 steps of dt 1e-3),
# N = 1, 2, 4, 8, 16 segments of 2 beam3 elements each (E = 2N elements),
# the minimum of REPS (default 3) `ffr run`s each; writes
# bench/segments/cost.csv with the run summary's CPU time (the
# simulation's thread CPU time, as `ffr run` prints it),
# steps, Newton iterations and iteration matrices, and prints the
# least-squares exponent p of CPU ∝ N^p over N = 2…16.
#
#   bench/segments/cost.sh                 # uses target/release/ffr (cargo build --release first)
#   FFR=/path/to/ffr bench/segments/cost.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
FFR=${FFR:-${CARGO_TARGET_DIR:-target}/release/ffr}
REPS=${REPS:-3}
test -x "$FFR" || { echo "no ffr binary at $FFR (cargo build --release, or set FFR)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=bench/segments/cost.csv
echo "segments,elements,steps,newton_iterations,iteration_matrices,cpu_s,cpu_ms_per_step" > "$out"
for n in 1 2 4 8 16; do
  e=$((2 * n))
  sed -e "s/^elements = 16$/elements = $e\nsegments = $n/" -e 's/^t_end = 20.0$/t_end = 2.0/' \
    scenes/spin_up_gravity.toml > "$tmp/s$n.toml"
  grep -q "^segments = $n$" "$tmp/s$n.toml" && grep -q '^t_end = 2.0$' "$tmp/s$n.toml" \
    || { echo "scenes/spin_up_gravity.toml changed: the edits did not apply" >&2; exit 1; }
  cpu=
  for _ in $(seq "$REPS"); do
    line=$("$FFR" run "$tmp/s$n.toml" --csv "$tmp/s$n.csv" 2>&1 | grep '^steps:')
    # steps: 2000 of dt = 0.001 s, N Newton iterations, M iteration matrices, …, CPU time X s
    steps=$(sed -E 's/^steps: ([0-9]+) .*/\1/' <<<"$line")
    newton=$(sed -E 's/.* ([0-9]+) Newton iterations.*/\1/' <<<"$line")
    mats=$(sed -E 's/.* ([0-9]+) iteration matrices.*/\1/' <<<"$line")
    c=$(sed -E 's/.*CPU time ([0-9.eE+-]+) s.*/\1/' <<<"$line")
    cpu=$(awk -v a="$cpu" -v b="$c" 'BEGIN { print (a == "" || b + 0 < a + 0) ? b : a }')
  done
  per=$(awk -v c="$cpu" -v s="$steps" 'BEGIN { printf "%.4g", 1000 * c / s }')
  echo "$n,$e,$steps,$newton,$mats,$cpu,$per" | tee -a "$out"
done
awk -F, 'NR > 1 && $1 >= 2 { x = log($1); y = log($6); n++; sx += x; sy += y; sxx += x * x; sxy += x * y }
  END { printf "CPU ~ N^%.2f over N = 2..16 (least squares, %d runs)\n", (n * sxy - sx * sy) / (n * sxx - sx * sx), n }' "$out"
