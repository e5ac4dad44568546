#!/usr/bin/env bash
# Coverage-guided fuzzing of every flexbody reader (fuzz/fuzz_targets/)
# with libFuzzer, on the stable toolchain.
#
#   bash scripts/fuzz.sh [SECONDS_PER_TARGET [TARGET...]]
#
# Builds the targets with the flags `cargo fuzz build` passes (sanitizer
# coverage, no sanitizer), makes the seed corpus from examples/ and
# tests/fixtures/ (scripts/fuzz_seeds.py), then runs each target for
# SECONDS_PER_TARGET (default 20) on one core. Limits per input: 1 s
# (-timeout), 2 GiB resident (-rss_limit_mb) and FLEXBODY_FUZZ_MEMORY_MB
# (default 512) of live heap (fuzz/src/alloc_limit.rs). Prints one line per
# target with its runs and runs per second; exits 1 if any target found an
# input that panics, aborts, hangs, allocates past the bound, gives an
# error naming no location or is accepted with a non-finite number, and
# prints that input's path.
#
# Work files (corpus grown by earlier runs, crash inputs, logs) stay in
# FLEXBODY_FUZZ_DIR, default $CARGO_TARGET_DIR/fuzz or target/fuzz.
# FLEXBODY_BIN names a built `flexbody` for the seeds (default: built
# here, in the dev profile).
#
# A long campaign (docs/testing.md): FLEXBODY_FUZZ_RUNS=N stops each target
# after N inputs (SECONDS_PER_TARGET stays the cap), and FLEXBODY_FUZZ_OPT=2
# builds every crate at that optimisation level, for several times the
# inputs per second after a longer build.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds="${1:-20}"
shift || true
all_targets=(deck model_file matrix_market calculix_matrices body_json body_sid body_mtx body_any)
targets=("${@:-${all_targets[@]}}")

# libFuzzer is C++ (built by libfuzzer-sys with the cc crate).
if ! command -v c++ >/dev/null; then
    apt-get update -qq && apt-get install -y -qq g++ >/dev/null
fi

target_dir="${CARGO_TARGET_DIR:-$PWD/target}"
work="${FLEXBODY_FUZZ_DIR:-$target_dir/fuzz}"
triple="$(rustc -vV | sed -n 's/^host: //p')"
mkdir -p "$work"

opt=()
if [ -n "${FLEXBODY_FUZZ_OPT:-}" ]; then
    opt=(--config "profile.release.opt-level=$FLEXBODY_FUZZ_OPT"
        --config "profile.release.package.\"*\".opt-level=$FLEXBODY_FUZZ_OPT")
fi
runs_limit=()
if [ -n "${FLEXBODY_FUZZ_RUNS:-}" ]; then
    runs_limit=(-runs="$FLEXBODY_FUZZ_RUNS")
fi

start=$(date +%s)
# Instrumented as `cargo fuzz build --sanitizer none` would, but only the
# crates the readers run (scripts/fuzz_rustc.sh); --target keeps the
# flags off build scripts and proc macros. The fuzz crate's release profile
# keeps debug assertions and overflow checks.
RUSTC_WRAPPER="$PWD/scripts/fuzz_rustc.sh" \
    cargo build --quiet --release --locked "${opt[@]}" --manifest-path fuzz/Cargo.toml \
    --target "$triple" --target-dir "$target_dir"
# The command writes the body seeds (built by the tests already in CI).
flexbody="${FLEXBODY_BIN:-$target_dir/debug/flexbody}"
if [ -z "${FLEXBODY_BIN:-}" ]; then
    cargo build --quiet --bin flexbody --target-dir "$target_dir"
fi
echo "fuzz: built in $(($(date +%s) - start)) s"

seeds="$work/seeds"
rm -rf "$seeds"
python3 scripts/fuzz_seeds.py "$seeds" "$flexbody"

failed=()
for t in "${targets[@]}"; do
    corpus="$work/corpus/$t"
    artifacts="$work/artifacts/$t"
    log="$work/$t.log"
    mkdir -p "$corpus" "$artifacts"
    cat "fuzz/dict/$t.dict" fuzz/dict/numbers.dict >"$work/$t.dict"
    status=0
    RAYON_NUM_THREADS=1 RUST_BACKTRACE=0 "$target_dir/$triple/release/$t" \
        -max_total_time="$seconds" "${runs_limit[@]}" -timeout=1 -rss_limit_mb=2048 \
        -max_len=65536 -dict="$work/$t.dict" -print_final_stats=1 \
        -artifact_prefix="$artifacts/" "$corpus" "$seeds/$t" >"$log" 2>&1 || status=$?
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
    if [ "$status" -eq 0 ]; then
        echo "fuzz: $t: ${runs:-?} runs (${rate:-?}/s), no finding"
    else
        echo "fuzz: $t: FINDING after ${runs:-?} runs (exit $status); log $log"
        grep -E "panicked at|ERROR: libFuzzer|memory allocation|non-finite|names no" "$log" | head -5 || true
        sed -n "s/.*Test unit written to \(.*\)/fuzz: input: \1/p" "$log"
        failed+=("$t")
    fi
done

if [ "${#failed[@]}" -gt 0 ]; then
    echo "fuzz: findings in: ${failed[*]}"
    exit 1
fi
echo "fuzz: ${#targets[@]} targets, no finding ($(($(date +%s) - start)) s)"
