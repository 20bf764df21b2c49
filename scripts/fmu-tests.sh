#!/usr/bin/env bash
# The drive's FMU checked as its users check FMUs (run by .ci/run; run it yourself after
# `cargo build --release`): FMPy's validation and simulation against hdgear's own answer
# (crates/hdgear-fmu/tests/test_fmu.py), in a virtual environment (target/fmu-venv) with fmpy,
# numpy and pytest from PyPI.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
export PIP_DISABLE_PIP_VERSION_CHECK=1
# the FMU's shared library is built with hdgear (target/release/deps), where it looks for it
export HDGEAR_BIN="$root/target/release/hdgear"
[ -x "$HDGEAR_BIN" ] || cargo build --release --quiet
venv="$root/target/fmu-venv"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/pip" install -q fmpy numpy pytest
echo "== fmpy $("$venv/bin/python" -c 'import fmpy; print(fmpy.__version__)')"
"$venv/bin/python" -m pytest -q crates/hdgear-fmu/tests
