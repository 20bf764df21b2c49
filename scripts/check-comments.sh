#!/usr/bin/env bash
# Code comments say what and why: no measurement (a number with a time unit), no CPU model, no
# reference to documents outside the repository ("SPEC §n"). Benchmarks (bench/, benches/) are
# exempt: timing is their job. Exits 1 listing every offending line.
set -euo pipefail
cd "$(dirname "$0")/.."
files=$(git ls-files '*.rs' '*.py' '*.js' '*.sh' '*.pyi' | grep -v -e '^bench/' -e '/benches/' -e '^scripts/check-comments.sh$')
# comment lines: Rust //, ///, //! and Python/shell # (after optional code)
pattern='(//|#).*([0-9](\.[0-9]+)? ?(ms|µs|us|ns|s)\b|Xeon|EPYC|Zen ?[0-9]|Ryzen|Core i[3579]|SPEC §|SPEC\.md)'
if hits=$(grep -nE "$pattern" $files | grep -vE '^[^:]+:[0-9]+:\s*(let|const|pub|assert|fn|if|for|#\[)'); then
  echo "comments with measurements, CPU names or outside references:"
  echo "$hits"
  exit 1
fi
echo "comments: clean"
