#!/usr/bin/env bash
# Issue 21's speed goals, measured side by side: a modal body (4 normal
# modes plus static modes) against the full body it reduces, on the planar
# spin-up (16 and 64 beam2 elements, fourth-order stiffening, `ffr spin-up
# --dt 0.01 --t-end 100`), on the spatial spin-up under gravity
# (scenes/spin_up_gravity.toml: 16 beam3, `modes = 4` and `modes = 8`), and
# without stiffening (8 vs 64 elements, ω_s = 0.5 rad/s so the linear model
# stays valid). The runs alternate; each figure is the least of REPS
# (default 5) simulation CPU times that the commands print (this thread's
# CPU time of the run alone, construction excluded), which other load on
# the machine inflates less than wall time.
#
#   bench/modal_cost.sh [REPS]
set -euo pipefail
cd "$(dirname "$0")/.."
reps=${1:-5}
cargo build --release -q -p ffr-cli
ffr=target/release/ffr
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for m in 4 8; do
    sed "s/^stiffening = true$/stiffening = true\nmodes = $m/" scenes/spin_up_gravity.toml >"$tmp/m$m.toml"
    grep -q "^modes = $m$" "$tmp/m$m.toml"
done
wall() { "$@" --csv "$tmp/out.csv" 2>&1 | sed -n 's/.*CPU time \([0-9.]*\) s.*/\1/p' | head -1; }
declare -A best
note() {
    local key=$1 t=$2
    [[ -n $t ]] || { echo "no wall time for $key" >&2; exit 1; }
    best[$key]=$(python3 -c "print(min(${best[$key]:-1e9}, $t))")
}
for _ in $(seq "$reps"); do
    for n in 16 64; do
        note "planar-$n-full" "$(wall $ffr spin-up --dt 0.01 --t-end 100 --elements $n)"
        note "planar-$n-modal" "$(wall $ffr spin-up --dt 0.01 --t-end 100 --elements $n --modes 4)"
    done
    for n in 8 64; do
        note "linear-$n-modal" "$(wall $ffr spin-up --dt 0.01 --t-end 100 --elements $n --modes 4 --stiffening off --omega 0.5)"
    done
    note "spatial-full" "$(wall $ffr run scenes/spin_up_gravity.toml)"
    note "spatial-m4" "$(wall $ffr run "$tmp/m4.toml")"
    note "spatial-m8" "$(wall $ffr run "$tmp/m8.toml")"
done
r() { python3 -c "print(f'{${best[$2]} / ${best[$3]}:.2f}')"; }
echo "least of $reps runs, simulation CPU time (s); load average: $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-44s %8s %8s %6s %s\n' case modal full ratio goal
printf '%-44s %8s %8s %6s %s\n' "planar, 16 beam2, 4 modes + static" "${best[planar-16-modal]}" "${best[planar-16-full]}" "$(r x planar-16-modal planar-16-full)" "<= 1.0"
printf '%-44s %8s %8s %6s %s\n' "planar, 64 beam2, 4 modes + static" "${best[planar-64-modal]}" "${best[planar-64-full]}" "$(r x planar-64-modal planar-64-full)" "<= 0.33"
printf '%-44s %8s %8s %6s %s\n' "spatial, 16 beam3, modes = 4" "${best[spatial-m4]}" "${best[spatial-full]}" "$(r x spatial-m4 spatial-full)" "<= 1.0"
printf '%-44s %8s %8s %6s %s\n' "spatial, 16 beam3, modes = 8" "${best[spatial-m8]}" "${best[spatial-full]}" "$(r x spatial-m8 spatial-full)" "<= 1.5"
printf '%-44s %8s %8s %6s %s\n' "no stiffening, modal 64 vs 8 elements" "${best[linear-64-modal]}" "${best[linear-8-modal]}" "$(r x linear-64-modal linear-8-modal)" "<= 1.2"
