#!/usr/bin/env bash
# The Python package, built and tested as a user would get it (run by .ci/run; run it yourself
# after `cargo build --release`):
#   1. a virtual environment (target/py-venv) with maturin, numpy, pandas, pytest, matplotlib,
#      dask[distributed], nbclient and ziglang from PyPI;
#   2. `pip install ./crates/hdgear-py` (maturin, release build), then pytest, the examples
#      (study figure, Dask LocalCluster map, the notebook run top to bottom) and the overhead
#      benchmark;
#   3. one manylinux2014 wheel built with `maturin build --zig` (abi3: CPython ≥ 3.9), installed
#      into fresh environments of two other Python versions (pyenv's 3.9 and 3.13) and tested there
#      (without pandas: the plain-dict path).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
export PIP_DISABLE_PIP_VERSION_CHECK=1
bin="$root/target/release/hdgear"
[ -x "$bin" ] || cargo build --release --quiet
export HDGEAR_BIN="$bin"

venv="$root/target/py-venv"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/pip" install -q maturin numpy pandas pytest matplotlib "dask[distributed]" nbclient nbformat ipykernel ziglang
echo "== pip install ./crates/hdgear-py ($("$venv/bin/python" --version))"
"$venv/bin/pip" install -q --force-reinstall --no-deps ./crates/hdgear-py
"$venv/bin/python" -m pytest -q crates/hdgear-py/tests
echo "== examples"
"$venv/bin/python" examples/python/study.py target/py-examples
"$venv/bin/python" examples/python/dask_sweep.py
"$venv/bin/python" - <<'PY'
import nbformat, nbclient
nb = nbformat.read("examples/python/explore.ipynb", as_version=4)
nbclient.NotebookClient(nb, timeout=300, kernel_name="python3").execute()
print("examples/python/explore.ipynb ran top to bottom")
PY
echo "== the Python overhead benchmark"
"$venv/bin/python" bench/python_overhead.py "$bin"

echo "== a manylinux2014 wheel built with zig, tested on two more Python versions"
rm -rf target/wheels
# maturin finds zig through `python3 -m ziglang` on PATH: the venv's
PATH="$venv/bin:$PATH" "$venv/bin/maturin" build --release --zig --compatibility manylinux2014 \
    -m crates/hdgear-py/Cargo.toml -o target/wheels -i "$venv/bin/python" --quiet
wheel=$(ls target/wheels/hdgear-*.whl)
echo "built $(basename "$wheel")"
pyroot=$(pyenv root 2>/dev/null || echo "$HOME/.pyenv")
tested=0
for v in 3.9 3.13; do
    py=$(ls -d "$pyroot"/versions/"$v".*/bin/python3 2>/dev/null | sort -V | tail -n 1 || true)
    if [ -z "$py" ]; then
        echo "no Python $v under $pyroot"
        continue
    fi
    env="$root/target/py-$v"
    rm -rf "$env"
    "$py" -m venv "$env"
    "$env/bin/pip" install -q "$wheel" pytest
    echo "-- $("$env/bin/python" --version): $(basename "$wheel")"
    (cd /tmp && "$env/bin/python" -m pytest -q "$root/crates/hdgear-py/tests")
    tested=$((tested + 1))
done
if [ "$tested" -lt 2 ]; then
    echo "the wheel was tested on $tested other Python version(s), not 2"
    [ "${CI:-}" = true ] && exit 1
fi
