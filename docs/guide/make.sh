#!/usr/bin/env bash
# make.sh [--quick]: regenerates every figure (docs/guide/img/) and prints
# every number of the guide by running the ```sh blocks of the chapters
# (docs/guide/0*.md), in page order, from the repository root, with the
# freshly built `shlight` first on PATH. Each block's output is printed
# under it, to paste into the page's ```text block that follows it.
# --quick skips the blocks marked `<!-- guide: slow -->`; --list prints
# the blocks of every page (each followed by a NUL byte) and runs nothing.
# tests/guide.rs runs the quick version and checks the printed numbers.
set -euo pipefail
cd "$(dirname "$0")/../.."
quick=0 list=0
case "${1:-}" in
    --quick) quick=1 ;;
    --list) list=1 ;;
    "") ;;
    *) echo "usage: docs/guide/make.sh [--quick | --list]" >&2; exit 2 ;;
esac

# The ```sh blocks of page $1 (without the slow ones when $2 is 1), each
# followed by a NUL byte.
blocks() {
    awk -v quick="$2" '
        /^<!-- guide: slow -->/ { slow = 1; next }
        /^```sh$/ { inblock = 1; block = ""; next }
        inblock && /^```$/ {
            inblock = 0
            if (!(quick && slow)) printf "%s%c", block, 0
            slow = 0
            next
        }
        inblock { block = block $0 "\n"; next }
        /^```/ { slow = 0 }
    ' "$1"
}

if [ "$list" = 1 ]; then
    for page in docs/guide/0*.md; do blocks "$page" 0; done
    exit 0
fi
cargo build --release --bin shlight
export PATH="$PWD/target/release:$PATH"
rm -rf guide-out
mkdir -p guide-out docs/guide/img
for page in docs/guide/0*.md; do
    echo "=== $page"
    blocks "$page" "$quick" | while IFS= read -r -d '' block; do
        printf '$ %s' "$block"
        start=$(date +%s%N)
        bash -euo pipefail -c "$block"
        echo "($(( ($(date +%s%N) - start) / 1000000 )) ms)" >&2
    done
done
rm -rf guide-out
du -ch docs/guide/img/* | tail -1 >&2
