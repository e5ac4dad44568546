#!/usr/bin/env bash
# CalculiX fixtures of tests/flexbody/calculix.rs: small decks (one per solid
# element type), ccx's K and M (*FREQUENCY, SOLVER=MATRIXSTORAGE) and its
# lowest natural frequencies, in tests/fixtures/calculix/<name>/.
#
#   scripts/calculix_fixtures.sh write   regenerate the fixtures in place
#   scripts/calculix_fixtures.sh check   (default) regenerate into a temporary
#                                        directory and compare with the stored
#                                        fixtures: matrix indices and DOFs
#                                        exactly, matrix values entry by entry
#                                        (1e-12 of the entry + 1e-13 of
#                                        sqrt(d_i d_j), d the diagonal),
#                                        frequencies to 1e-9
#
# Needs ccx (CalculiX 2.20; Debian: apt-get install -y calculix-ccx) and
# python3 (standard library only); the work is in calculix_fixtures.py. ccx
# runs single-threaded, `OMP_NUM_THREADS=1 ccx -i <name>`: with two threads
# SPOOLES changes the round-off from run to run and ccx's frequencies move by
# ~5e-7, more than the check allows.
set -euo pipefail
cd "$(dirname "$0")/.."

mode="${1:-check}"
stored="tests/fixtures/calculix"
generator="scripts/calculix_fixtures.py"

if ! command -v ccx >/dev/null 2>&1; then
    echo "calculix_fixtures.sh: ccx (CalculiX) is not installed; on Debian: apt-get install -y calculix-ccx" >&2
    exit 1
fi
if ! command -v python3 >/dev/null 2>&1; then
    echo "calculix_fixtures.sh: python3 is not installed" >&2
    exit 1
fi

case "$mode" in
    write)
        fresh="$(mktemp -d)"
        trap 'rm -rf "$fresh"' EXIT
        python3 "$generator" generate "$fresh"
        rm -rf "$stored"
        mkdir -p "$(dirname "$stored")"
        cp -r "$fresh" "$stored"
        chmod -R u+rwX,go+rX "$stored"
        echo "wrote $stored ($(du -sk "$stored" | cut -f1) KB)"
        ;;
    check)
        fresh="$(mktemp -d)"
        trap 'rm -rf "$fresh"' EXIT
        python3 "$generator" generate "$fresh"
        python3 "$generator" compare "$stored" "$fresh"
        ;;
    *)
        echo "usage: scripts/calculix_fixtures.sh [write|check]" >&2
        exit 2
        ;;
esac
