#!/usr/bin/env bash
# The Python package's tests: builds python/ into a virtual environment
# (target/python-venv, with the system's site packages, where
# scripts/install_peers.sh puts Exudyn) the way a user installs it,
# `pip install ./python`, and runs its pytest suite (python/tests, which
# also runs python/examples) against the command line's binary.
# The extension is built in the `dev` profile (a user's `pip install
# ./python` builds it optimised, release); maturin builds it on its own, so
# the workspace's crates compile once more for it.
# The tests run the command line's binary FLEXBODY_BIN; unset, it is built
# here (`cargo build --bin flexbody`). scripts/test.sh sets it to the binary
# `cargo test` has just built for the integration tests, so that the suite
# does not build the workspace's crates a second time.
# Extra arguments go to pytest.
set -euo pipefail
cd "$(dirname "$0")/.."

venv=target/python-venv
[ -x "$venv/bin/python" ] || python3 -m venv --system-site-packages "$venv"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check pytest numpy scipy pandas
if [ -z "${FLEXBODY_BIN:-}" ]; then
    cargo build --quiet --bin flexbody
    FLEXBODY_BIN="$PWD/target/debug/flexbody"
fi
MATURIN_PEP517_ARGS="--profile dev" "$venv/bin/python" -m pip install --quiet \
    --disable-pip-version-check --root-user-action=ignore ./python
cd python/tests
FLEXBODY_BIN="$FLEXBODY_BIN" "../../$venv/bin/python" -m pytest -q -p no:cacheprovider "$@"
