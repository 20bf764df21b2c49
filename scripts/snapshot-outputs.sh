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
"$bin" --quiet periodic --json > periodic.json
"$bin" --quiet periodic --gamma 10 --omega 9 --lyapunov --out periodic.csv
"$bin" --quiet continue --param omega=5:10.5:log --gamma 10 --switch --out continue.csv > /dev/null
"$bin" --quiet frequency-response --gamma 30 --omega-range 6:10 --out frequency.csv --plot frequency.svg > /dev/null
"$bin" --quiet physical --frequency-response --hz 80:130 --out physical-frequency.csv > /dev/null
"$bin" --quiet orbit-diagram --param omega=7:9:12 --gamma 10 --discard 50 --record 8 --out diagram.csv > /dev/null
"$bin" --quiet lyapunov-map --param omega=6:9:6 --param delta=10:20:3 --gamma 10 --periods 50 --out lyapunov.csv > /dev/null
"$bin" --quiet sweep --param gamma=0.1:30:12:log --shard 0/2 --out shards.csv > /dev/null
"$bin" --quiet sweep --param gamma=0.1:30:12:log --shard 1/2 --out shards.csv > /dev/null
"$bin" --quiet merge shards.shard-0-of-2.csv shards.shard-1-of-2.csv --out merged.csv > /dev/null
"$bin" --quiet table > table.txt
"$bin" --quiet analyze > analyze.txt
"$bin" --quiet periodic > periodic.txt
"$bin" --quiet physical --drive CSF-20-50 > physical.txt
for kind in xdot-gamma slope transformed-phase; do
  "$bin" --quiet plot "$kind" --out "plot-$kind.svg" > /dev/null
done
"$bin" --help > help.txt
for c in simulate equilibria analyze bifurcation bursts table sweep periodic continue \
  frequency-response orbit-diagram lyapunov-map merge physical plot report serve; do
  "$bin" "$c" --help > "help-$c.txt"
done
"$bin" --quiet report --out report > /dev/null
rm -rf report/figures report/index.html
