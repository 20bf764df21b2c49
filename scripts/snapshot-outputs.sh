#!/usr/bin/env bash
# Writes every command's output on the study's defaults (JSON and CSV) and the report's data/
# into DIR, so two builds can be compared byte for byte:
#   scripts/snapshot-outputs.sh OLD_BINARY /tmp/before
#   scripts/snapshot-outputs.sh target/release/hdgear /tmp/after
#   diff -r /tmp/before /tmp/after
set -euo pipefail
bin=$(realpath "$1")
out=$2
rm -rf "$out"
mkdir -p "$out"
cd "$out"
for ext in json csv; do
  "$bin" --quiet simulate --out "simulate.$ext"
  "$bin" --quiet equilibria --out "equilibria.$ext"
  "$bin" --quiet bifurcation --gamma-min 0.001 --out "bifurcation.$ext"
  "$bin" --quiet bursts --out "bursts.$ext"
  "$bin" --quiet sweep --param gamma=0.1:30:40:log --out "sweep.$ext" > /dev/null
  "$bin" --quiet physical --drive CSF-20-50 --simulate --t-end 0.5 --out "physical-sim.$ext"
done
"$bin" --quiet simulate --summary > simulate-summary.json
"$bin" --quiet analyze --json > analyze.json
"$bin" --quiet table --json > table.json
"$bin" --quiet physical --drive CSF-20-50 --json > physical.json
"$bin" --quiet physical --drive CSF-20-50 --design --json > design-check.json
"$bin" --quiet physical --drive CSF-20-50 --simulate --t-end 0.5 --summary > physical-summary.json
"$bin" --quiet report --out report > /dev/null
rm -rf report/figures report/index.html
