#!/usr/bin/env bash
# Runs one fuzz target for a fixed time on the checked-in seeds:
#
#     fuzz/run.sh TARGET SECONDS [libFuzzer options...]
#
# TARGET is one of fuzz/fuzz_targets/*.rs (exr, hdr, png_jpeg, obj, mtl,
# ply, off, gltf, coefficients, shprt, shvol). The seeds are
# fuzz/corpus/TARGET and the regression inputs the crate's tests check
# (tests/fuzz_regressions/TARGET); both are only read: what the fuzzer
# adds goes to fuzz/target/corpus/TARGET, kept between runs. A crash, hang
# or out-of-memory input is written to fuzz/artifacts/TARGET/ and the
# script fails.
#
# The limits are docs/limits.md's: 2048 MiB of memory (-rss_limit_mb, also
# the largest single allocation) and 10 s an input (-timeout).
#
# Toolchain: cargo-fuzz needs nightly-only rustc flags; on a stable
# toolchain RUSTC_BOOTSTRAP=1 allows them (set below, harmless on
# nightly). AddressSanitizer is used where the toolchain ships its runtime
# (rustup's x86_64 Linux toolchains do, stable included); elsewhere the
# targets are built with `--sanitizer none`, which still finds panics,
# hangs and out-of-memory, but not memory errors in unsafe code.
# FUZZ_SANITIZER=none (or address) overrides the choice.
set -euo pipefail
cd "$(dirname "$0")"
# cargo-fuzz builds in fuzz/target; a CARGO_TARGET_DIR set for the root
# workspace would make it rebuild everything elsewhere.
unset CARGO_TARGET_DIR

if [ $# -lt 2 ]; then
    echo "usage: fuzz/run.sh TARGET SECONDS [libFuzzer options...]" >&2
    echo "targets: $(cd fuzz_targets && ls *.rs | sed 's/\.rs$//' | tr '\n' ' ')" >&2
    exit 2
fi
target=$1
seconds=$2
shift 2
if [ ! -f "fuzz_targets/$target.rs" ]; then
    echo "fuzz/run.sh: no target \"$target\" (see fuzz/fuzz_targets/)" >&2
    exit 2
fi

# The limits docs/limits.md promises (keep the two in step).
rss_limit_mb=2048
timeout_s=10

export RUSTC_BOOTSTRAP=1
host=$(rustc -vV | sed -n 's/^host: //p')
sysroot=$(rustc --print sysroot)
sanitizer=${FUZZ_SANITIZER:-}
if [ -z "$sanitizer" ]; then
    if ls "$sysroot/lib/rustlib/$host/lib/"librustc-*_rt.asan.a >/dev/null 2>&1; then
        sanitizer=address
    else
        sanitizer=none
        echo "fuzz/run.sh: no AddressSanitizer runtime in $sysroot; building with --sanitizer none" >&2
    fi
fi

case $target in
    exr | hdr | png_jpeg) crate=shlight-io ;;
    obj | mtl | ply | off | gltf) crate=shlight-mesh ;;
    *) crate=shlight-format ;;
esac
dirs=("target/corpus/$target" "corpus/$target")
regressions="../crates/$crate/tests/fuzz_regressions/$target"
if [ -d "$regressions" ]; then
    dirs+=("$regressions")
fi
mkdir -p "target/corpus/$target" "artifacts/$target"

# -detect_leaks=0: LeakSanitizer reports glibc's per-thread destructor
# list (32 bytes, __cxa_thread_atexit_impl) of the OpenEXR decoder's
# short-lived threads as a leak; a leak is not what the targets look for
# (memory is bounded by -rss_limit_mb).
# -a: debug assertions and overflow checks, so that arithmetic overflow on
# a hostile header is found rather than wrapped. They are on in the
# dependencies too, where a decoder may rely on wrapping (exr's B44 does,
# as the C code it follows): such a panic inside a reader's guard is
# allowed (fuzz/src/lib.rs, abort_on_shlight_panics).
cargo fuzz run --sanitizer "$sanitizer" -a "$target" "${dirs[@]}" -- \
    -max_total_time="$seconds" \
    -rss_limit_mb="$rss_limit_mb" \
    -malloc_limit_mb="$rss_limit_mb" \
    -timeout="$timeout_s" \
    -print_final_stats=1 \
    -detect_leaks=0 \
    "$@"
