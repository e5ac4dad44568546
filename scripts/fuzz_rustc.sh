#!/usr/bin/env bash
# RUSTC_WRAPPER of the fuzz build (scripts/fuzz.sh): adds libFuzzer's
# coverage instrumentation (the flags `cargo fuzz build --sanitizer none`
# passes) to the crates whose code the readers run - flexbody's own, the
# fuzz targets, the TOML and JSON parsers - and leaves the rest (faer,
# rayon, ...) plain, which keeps the build shorter. Crates built for the
# host (build scripts, proc macros: no --target) are never instrumented.
rustc="$1"
shift
crate=""
for_target=0
prev=""
for arg in "$@"; do
    [ "$prev" = "--crate-name" ] && crate="$arg"
    [ "$prev" = "--target" ] && for_target=1
    prev="$arg"
done
if [ "$for_target" = 1 ]; then
    case "$crate" in
    flexbody* | deck | model_file | matrix_market | calculix_matrices | body_* | toml | toml_edit | winnow | serde_json)
        exec "$rustc" "$@" -Cpasses=sancov-module \
            -Cllvm-args=-sanitizer-coverage-level=4 \
            -Cllvm-args=-sanitizer-coverage-inline-8bit-counters \
            -Cllvm-args=-sanitizer-coverage-pc-table \
            -Cllvm-args=-sanitizer-coverage-trace-compares
        ;;
    esac
fi
exec "$rustc" "$@"
