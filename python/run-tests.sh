#!/usr/bin/env bash
# The Python package's tests: a fresh virtual environment (target/pyenv),
# `pip install ./python` (maturin builds the extension with cargo, sharing
# the workspace's target/ so the libraries are not compiled twice), then
# pytest on python/tests against the `shlight` CLI built from the same
# sources (built here when missing), then the guide's notebook
# (docs/guide/guide.ipynb, executed by nbclient in docs/guide, where Jupyter
# starts its kernel; about 5 s). Budgets: 30 min
# to install, 5 min of tests (about 30 s on 2 cores), 2 min for the notebook.
set -euo pipefail
cd "$(dirname "$0")/.."

venv="${SHLIGHT_PYENV:-target/pyenv}"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/target}"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
echo "== pip install ./python pytest dask[distributed] nbclient ipykernel matplotlib"
timeout 1800 "$venv/bin/pip" install --quiet --disable-pip-version-check ./python pytest "dask[distributed]" \
    nbclient nbformat ipykernel matplotlib
if [ ! -x "$CARGO_TARGET_DIR/release/shlight" ]; then
    cargo build --release --bin shlight
fi
echo "== pytest python/tests"
SHLIGHT_CLI="$CARGO_TARGET_DIR/release/shlight" timeout 300 "$venv/bin/pytest" -q python/tests
echo "== docs/guide/guide.ipynb (nbclient, from docs/guide)"
timeout 120 "$venv/bin/python" docs/guide/run-notebook.py docs/guide
