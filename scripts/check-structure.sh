#!/usr/bin/env bash
# Structure rules a reviewer would otherwise check by hand; exits 1 listing each breach:
#   * the README at most 250 lines (a front door; the reference is the guide in docs/);
#   * a file of code over 600 lines says why it is one file, in its module doc (a Rust file's
#     `//! **Why one file.**` paragraph, a Python file's "Why one file:" in its docstring;
#     generated code excepted: the DOP853 stage formulas);
#   * no `json!` in the binary (its JSON documents are typed structs);
#   * no `unsafe` outside the library's one dispatch module and the FMU's C ABI module, and
#     the command and the Python binding forbid it.
set -euo pipefail
cd "$(dirname "$0")/.."
fail=0
readme=$(wc -l < README.md)
if [ "$readme" -gt 250 ]; then echo "README.md: $readme lines (at most 250)"; fail=1; fi
while read -r n f; do
  [ "$f" = total ] && continue
  if [ "$n" -gt 600 ]; then
    case "$f" in
      *.rs) why='^//! \*\*Why one file\.\*\*' ;;
      *.py) why='^Why one file:' ;;
      *) why='Why one file' ;;
    esac
    if ! grep -q "$why" "$f"; then
      echo "$f: $n lines and no word on why it is one file in its module doc"; fail=1
    fi
  fi
done < <(git ls-files '*.rs' '*.py' '*.js' '*.sh' | grep -v '^crates/hdgear/src/integrate/stages.rs$' | xargs wc -l)
if grep -rn 'json!' crates/hdgear-cli/src; then echo "json! in the binary: use a typed struct"; fail=1; fi
if grep -rln '\bunsafe\b' crates/hdgear/src | grep -v '^crates/hdgear/src/simd.rs$'; then
  echo "unsafe outside crates/hdgear/src/simd.rs"; fail=1
fi
if grep -rln '\bunsafe\b' crates/hdgear-fmu/src | grep -v '^crates/hdgear-fmu/src/ffi.rs$'; then
  echo "unsafe outside crates/hdgear-fmu/src/ffi.rs (the FMU's C ABI)"; fail=1
fi
for f in crates/hdgear-cli/src/main.rs crates/hdgear-py/src/lib.rs; do
  grep -q '^#!\[forbid(unsafe_code)\]' "$f" || { echo "$f: no #![forbid(unsafe_code)]"; fail=1; }
done
[ "$fail" = 0 ] && echo "structure: clean"
exit "$fail"
