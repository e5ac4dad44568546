#!/usr/bin/env bash
# The Python package's tests: builds python/ into a virtual environment
# (target/python-venv, with the system's site packages, where
# scripts/install_peers.sh puts Exudyn) the way a user installs it,
# `pip install ./python`, and runs its pytest suite (python/tests, which
# also runs python/examples) against the command line's binary.
# The extension is built in the `dev` profile, as `cargo test` builds the
# workspace, so that it reuses those compiled crates; a user's
# `pip install ./python` builds it optimised (release).
# Extra arguments go to pytest.
set -euo pipefail
cd "$(dirname "$0")/.."

venv=target/python-venv
[ -x "$venv/bin/python" ] || python3 -m venv --system-site-packages "$venv"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check pytest numpy scipy pandas
cargo build --quiet --bin flexbody
MATURIN_PEP517_ARGS="--profile dev" "$venv/bin/python" -m pip install --quiet \
    --disable-pip-version-check --root-user-action=ignore ./python
cd python/tests
FLEXBODY_BIN="$PWD/../../target/debug/flexbody" "../../$venv/bin/python" -m pytest -q -p no:cacheprovider "$@"
