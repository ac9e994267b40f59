#!/usr/bin/env bash
# The build cost of a user crate with one #[flex_body] attribute, measured
# side by side with a crate that depends on nalgebra alone (README, "Build
# cost"). Each build is cold (its own fresh target directory), the two crates
# alternate, and the wall times go to stdout as CSV:
#   pair,profile,crate,seconds
# Usage: bench/build-cost/run.sh [PAIRS] [debug|release]   (default: 5 debug)
# Run it on an otherwise idle machine; it takes about a minute per pair.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
pairs="${1:-5}"
profile="${2:-debug}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

mkdir -p "$work/nalgebra-only/src" "$work/one-attribute/src"
cat > "$work/nalgebra-only/Cargo.toml" <<TOML
[package]
name = "nalgebra-only"
version = "0.1.0"
edition = "2021"
[dependencies]
nalgebra = "0.33"
[workspace]
TOML
cat > "$work/nalgebra-only/src/main.rs" <<'RS'
fn main() {
    let m = nalgebra::Matrix3::<f64>::identity();
    println!("{}", m.determinant());
}
RS
cat > "$work/one-attribute/Cargo.toml" <<TOML
[package]
name = "one-attribute"
version = "0.1.0"
edition = "2021"
[dependencies]
ffr = { path = "$repo" }
[workspace]
TOML
cat > "$work/one-attribute/src/main.rs" <<'RS'
use ffr::prelude::*;

#[flex_body(shape = "beam3", elements = 4)]
struct Beam { length: f64, rho: f64, area: f64, iy: f64, iz: f64, e: f64, g: f64, j: f64 }

fn main() {
    let b = Beam { length: 1.0, rho: 7800.0, area: 1e-4, iy: 1e-9, iz: 1e-9, e: 2e11, g: 8e10, j: 2e-9 };
    let body = KernelBody::compiled(&b).expect("a valid beam");
    println!("{}", body.layout().nf);
}
RS
# Fetch once so that downloads are not timed.
for c in nalgebra-only one-attribute; do
    (cd "$work/$c" && cargo fetch --quiet)
done
flag=""
[ "$profile" = release ] && flag="--release"
echo "pair,profile,crate,seconds"
for p in $(seq 1 "$pairs"); do
    for c in nalgebra-only one-attribute; do
        rm -rf "$work/$c/target"
        start=$(date +%s.%N)
        (cd "$work/$c" && cargo build --quiet $flag)
        end=$(date +%s.%N)
        echo "$p,$profile,$c,$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }')"
    done
done
