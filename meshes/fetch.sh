#!/usr/bin/env bash
# Fetches the bundled meshes into this directory as Wavefront OBJ.
#
# Downloads the npm packages `bunny` and `teapot` (fixed versions, verified by
# npm against the registry's integrity hash), each a CommonJS module exporting
# `positions` ([x, y, z] arrays) and `cells` (triangles as 0-based vertex
# indices), and writes them as OBJ: one `v` line per position in the
# module's order, one `f` line per cell (1-based), nothing else. Then checks
# the results against meshes/SHA256SUMS.
#
# Needs: bash, npm and node, tar, sha256sum. Run from anywhere:
#   meshes/fetch.sh
set -euo pipefail

PACKAGES=(
    "bunny@1.0.1=index.js=bunny.obj"
    "teapot@1.0.0=teapot.js=teapot.obj"
)

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

for entry in "${PACKAGES[@]}"; do
    IFS='=' read -r spec module out <<<"$entry"
    name="${spec%@*}"
    version="${spec#*@}"
    echo "downloading $spec with npm"
    (cd "$work" && npm pack --silent "$spec" >/dev/null)
    mkdir -p "$work/$name"
    tar -xzf "$work/$name-$version.tgz" -C "$work/$name"
    node - "$work/$name/package/$module" "$here/$out" "$spec" <<'NODE'
const fs = require('fs');
const [modulePath, outPath, spec] = process.argv.slice(2);
const { positions, cells } = require(modulePath);
const lines = [`# ${spec} (npm): ${positions.length} vertices, ${cells.length} triangles`];
for (const p of positions) lines.push(`v ${p[0]} ${p[1]} ${p[2]}`);
for (const c of cells) lines.push(`f ${c[0] + 1} ${c[1] + 1} ${c[2] + 1}`);
fs.writeFileSync(outPath, lines.join('\n') + '\n');
console.log(`${outPath}: ${positions.length} vertices, ${cells.length} triangles`);
NODE
done

cd "$here"
sha256sum -c SHA256SUMS
