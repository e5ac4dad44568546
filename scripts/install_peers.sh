#!/usr/bin/env bash
# Installs the peer programs of flexbody's independent checks, skipping what
# is already there; the one place that installs them (.ci/run calls it):
#   - CalculiX 2.20's ccx (Debian package calculix-ccx), for the element
#     matrices against a live ccx (crates/fem) and the stored fixtures
#     (scripts/calculix_fixtures.sh check);
#   - numpy, scipy and exudyn for python3 (pip), for scripts/exudyn_check.py,
#     run by the test exudyn::exudyn_agrees_with_flexbody, and numpy for
#     scripts/beam_invariants.py, run by the test
#     sid::beam_invariants_equal_an_independent_numpy_integration;
#   - Chromium (Debian package chromium), the browser that renders the HTML
#     report of `study --report` in the test report_html;
#   - meshio for python3 (pip), for scripts/vtu_compare.py, run by the test
#     vtu::binary_vtu_reads_in_meshio_as_the_ascii_one.
# Prints the versions found.
set -euo pipefail

missing=()
command -v ccx >/dev/null 2>&1 || missing+=(calculix-ccx)
command -v chromium >/dev/null 2>&1 || missing+=(chromium)
if [ ${#missing[@]} -gt 0 ]; then
    sudo=""
    [ "$(id -u)" = 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
fi
if ! python3 -c "import numpy, scipy, exudyn" >/dev/null 2>&1; then
    python3 -m pip install --quiet numpy scipy exudyn==1.13.6
fi
if ! python3 -c "import meshio" >/dev/null 2>&1; then
    python3 -m pip install --quiet meshio==5.3.5
fi

# `ccx -v` exits non-zero.
ccx_version="$( (ccx -v 2>&1 || true) | grep -m1 -o 'Version [0-9.]*' || true)"
python_versions="$(python3 -c 'import exudyn, meshio, numpy, scipy; print(f"exudyn {exudyn.__version__}, meshio {meshio.__version__}, numpy {numpy.__version__}, scipy {scipy.__version__}")')"
chromium_version="$(chromium --version 2>/dev/null | head -n1 || true)"
echo "peers: ccx ${ccx_version:-of unknown version}, ${python_versions}, ${chromium_version:-chromium of unknown version}"
