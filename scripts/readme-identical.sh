#!/usr/bin/env bash
# Proves that a change leaves every output of every README command
# byte-identical: builds the shlight binary of BASE (default: the merge
# base with origin/main, else HEAD~1) in a git worktree and of the working
# tree, runs the README's commands with each (scripts/readme_outputs.py,
# both with this checkout's README.md), and compares the digests.
#
#   scripts/readme-identical.sh [BASE] [--no-gpu]
#
# Exits 1 if any command's exit status, stdout or files differ. A README
# line the base cannot run (a command added with the change) shows as
# differing; read the list.
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

# The base builds in a target directory of its own: cargo names a
# workspace crate's build by its path relative to the workspace root and
# checks it by its sources' times, so two trees sharing one target
# directory share their crates' artifacts and one tree's build can look
# fresh to the other (the "after" binary would be the base's). The first
# run builds the third-party crates there once; later runs reuse them.
echo "== building $base (before)"
(cd "$tree" && CARGO_TARGET_DIR="$out/target" cargo build --release --quiet)
cp "$out/target/release/shlight" "$out/shlight-before"
echo "== building the working tree (after)"
cargo build --release --quiet

echo "== README commands, before"
python3 scripts/readme_outputs.py run --shlight "$out/shlight-before" $gpu_flag -o "$out/before.json"
echo "== README commands, after"
python3 scripts/readme_outputs.py run --shlight target/release/shlight $gpu_flag -o "$out/after.json"
python3 scripts/readme_outputs.py compare "$out/before.json" "$out/after.json"
