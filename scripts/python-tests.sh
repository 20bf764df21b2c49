#!/usr/bin/env bash
# The Python package, built and tested as a user would get it (run by .ci/run; run it yourself
# after `cargo build --release`):
#   1. a virtual environment (target/py-venv) with maturin, numpy, pandas, pytest, matplotlib,
#      dask[distributed], nbclient, ziglang, mujoco and scipy from PyPI;
#   2. one wheel, built the way a user installs from source (`pip wheel ./crates/hdgear-py`: pip
#      runs maturin, release build), as a manylinux2014 wheel linked with zig (abi3: CPython
#      ≥ 3.9), so that one build serves every test below;
#   3. that wheel installed into the venv, then pytest, hdgear.mujoco's tests, `hdgear fit`
#      against scipy (scripts/fit_scipy_check.py), the examples
#      (study figure, Dask LocalCluster map, the notebook run top to bottom) and the overhead
#      benchmark;
#   4. the same wheel installed into fresh environments of two other Python versions (pyenv's
#      3.9 and 3.13) and tested there (without pandas: the plain-dict path).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
export PIP_DISABLE_PIP_VERSION_CHECK=1
bin="$root/target/release/hdgear"
[ -x "$bin" ] || cargo build --release --quiet
export HDGEAR_BIN="$bin"

venv="$root/target/py-venv"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/pip" install -q maturin numpy pandas pytest matplotlib "dask[distributed]" nbclient nbformat ipykernel ziglang "mujoco==4.0.1" scipy
echo "== pip wheel ./crates/hdgear-py: one manylinux2014 wheel, linked with zig"
rm -rf target/wheels
# pip runs maturin (the package's build backend) in an isolated environment; MATURIN_PEP517_ARGS
# passes it the zig options, and maturin finds the `zig` that the venv's ziglang package holds
zig_dir=$("$venv/bin/python" -c 'import os, ziglang; print(os.path.dirname(ziglang.__file__))')
PATH="$zig_dir:$PATH" MATURIN_PEP517_ARGS="--zig --compatibility manylinux2014" \
    "$venv/bin/pip" wheel -q --no-deps -w target/wheels ./crates/hdgear-py
wheel=$(ls target/wheels/hdgear-*.whl)
echo "built $(basename "$wheel")"
case "$wheel" in
    *manylinux2014*abi3* | *abi3*manylinux2014*) ;;
    *) echo "not a manylinux2014 abi3 wheel: $wheel"; exit 1 ;;
esac
echo "== the wheel in $("$venv/bin/python" --version)"
"$venv/bin/pip" install -q --force-reinstall --no-deps "$wheel"
"$venv/bin/python" -m pytest -q crates/hdgear-py/tests
echo "== hdgear.mujoco: the drive between two MuJoCo hinges"
"$venv/bin/python" -m pytest -q crates/hdgear-py/tests_mujoco
echo "== hdgear fit against scipy's least_squares on the same data"
"$venv/bin/python" scripts/fit_scipy_check.py "$bin"
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

echo "== the same wheel on two more Python versions"
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
