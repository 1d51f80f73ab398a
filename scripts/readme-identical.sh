#!/usr/bin/env bash
# Proves that a change leaves every output of every README command
# byte-identical: builds the shlight binary of BASE (default: the merge
# base with origin/main, else HEAD~1) in a git worktree and of the working
# tree, runs the README's commands with each (scripts/readme_outputs.py,
# both with this checkout's README.md), and compares the digests.
#
#   scripts/readme-identical.sh [BASE] [--no-gpu]
#
# Exits 1 if any command's exit status, stdout or files differ. Both builds
# share target/: only shlight's own crates are compiled twice.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
base=""
gpu_flag=""
for arg in "$@"; do
    case "$arg" in
        --no-gpu) gpu_flag="--no-gpu" ;;
        *) base=$arg ;;
    esac
done
if [ -z "$base" ]; then
    base=$(git merge-base HEAD origin/main 2>/dev/null || git rev-parse HEAD~1)
fi
base=$(git rev-parse --verify "$base^{commit}")
out=$root/target/readme-identical
mkdir -p "$out"
tree=$out/base-tree
if [ -d "$tree" ]; then
    git worktree remove --force "$tree" >/dev/null 2>&1 || rm -rf "$tree"
fi
git worktree prune
git worktree add --detach "$tree" "$base" >/dev/null
trap 'git worktree remove --force "$tree" >/dev/null 2>&1 || true' EXIT

# Cargo names a workspace crate's build by its path relative to the
# workspace root and checks it by its sources' times, so the two trees'
# crates share their artifacts and one tree's build can look fresh to the
# other (the "after" binary would be the base's): each build starts with
# its workspace's own crates cleaned; third-party crates stay built.
clean_workspace() {
    local packages
    packages=$(cargo metadata --no-deps --format-version 1 | python3 -c \
        'import json, sys; print(" ".join("-p " + p["name"] for p in json.load(sys.stdin)["packages"]))')
    # shellcheck disable=SC2086
    cargo clean --release --quiet $packages
}
echo "== building $base (before)"
(cd "$tree" && export CARGO_TARGET_DIR="$root/target" && clean_workspace && cargo build --release --quiet)
cp target/release/shlight "$out/shlight-before"
echo "== building the working tree (after)"
clean_workspace
cargo build --release --quiet

echo "== README commands, before"
python3 scripts/readme_outputs.py run --shlight "$out/shlight-before" $gpu_flag -o "$out/before.json"
echo "== README commands, after"
python3 scripts/readme_outputs.py run --shlight target/release/shlight $gpu_flag -o "$out/after.json"
python3 scripts/readme_outputs.py compare "$out/before.json" "$out/after.json"
