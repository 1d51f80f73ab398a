#!/usr/bin/env bash
# Fetches the bundled environment maps into this directory.
#
# Downloads the npm package @pmndrs/assets (a fixed version, verified by npm
# against the registry's integrity hash), takes a few of its hdri/*.exr.js
# modules (each a base64 data URL of a DWAB-compressed OpenEXR file, 512x256,
# from Poly Haven, CC0), decodes them to envmaps/NAME.exr, copies the default
# one to envmaps/default.exr, prints each file's header, and checks the
# results against envmaps/SHA256SUMS.
#
# Needs: bash, npm and node, tar, sha256sum. Run from anywhere:
#   envmaps/fetch.sh
set -euo pipefail

PACKAGE="@pmndrs/assets"
VERSION="1.7.0"
# name in envmaps/ = module in the package's hdri/ folder
MAPS=(
    "park=park"     # outdoor, sunny: sun in a clear sky over a meadow
    "city=city"     # outdoor, overcast: city square under a grey sky
    "sky=sky"       # sky only: partly cloudy sky with the sun, above a horizon
    "studio=studio" # indoor: photo studio with softbox lights
)
DEFAULT="park"

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

echo "downloading $PACKAGE@$VERSION with npm"
(cd "$work" && npm pack --silent "$PACKAGE@$VERSION" >/dev/null)
tar -xzf "$work"/pmndrs-assets-"$VERSION".tgz -C "$work"

# Decode each module's base64 data URL and print the EXR header.
node - "$work/package/hdri" "$here" "${MAPS[@]}" <<'NODE'
const fs = require('fs');
const path = require('path');
const [srcDir, outDir, ...maps] = process.argv.slice(2);
const COMPRESSION = ['none', 'RLE', 'ZIPS', 'ZIP', 'PIZ', 'PXR24', 'B44', 'B44A', 'DWAA', 'DWAB'];
const SAMPLE = ['uint', 'half', 'float'];

function header(buf) {
  if (buf.readUInt32LE(0) !== 20000630) throw new Error('not an OpenEXR file');
  const attrs = {};
  let p = 8;
  const cstr = () => { const e = buf.indexOf(0, p); const s = buf.toString('latin1', p, e); p = e + 1; return s; };
  while (buf[p] !== 0) {
    const name = cstr(); const type = cstr();
    const size = buf.readInt32LE(p); p += 4;
    attrs[name] = { type, data: buf.subarray(p, p + size) }; p += size;
  }
  const dw = attrs.dataWindow.data;
  const [x0, y0, x1, y1] = [0, 4, 8, 12].map((o) => dw.readInt32LE(o));
  const channels = [];
  const ch = attrs.channels.data;
  for (let q = 0; ch[q] !== 0;) {
    const e = ch.indexOf(0, q); const n = ch.toString('latin1', q, e); q = e + 1;
    channels.push(`${n}:${SAMPLE[ch.readInt32LE(q)]}`); q += 16;
  }
  return {
    size: `${x1 - x0 + 1}x${y1 - y0 + 1}`,
    dataWindow: `(${x0},${y0})-(${x1},${y1})`,
    channels: channels.join(' '),
    compression: COMPRESSION[attrs.compression.data[0]] ?? `code ${attrs.compression.data[0]}`,
  };
}

for (const map of maps) {
  const [name, module] = map.split('=');
  const file = path.join(srcDir, `${module}.exr.js`);
  const text = fs.readFileSync(file, 'utf8');
  const m = text.match(/data:application\/exr;base64,([A-Za-z0-9+/=]+)/);
  if (!m) throw new Error(`${file}: no base64 EXR data URL`);
  const bytes = Buffer.from(m[1], 'base64');
  const h = header(bytes);
  const out = path.join(outDir, `${name}.exr`);
  const tmp = `${out}.tmp-${process.pid}`;
  fs.writeFileSync(tmp, bytes);
  fs.renameSync(tmp, out);
  console.log(`${name}.exr  from hdri/${module}.exr.js  ${bytes.length} bytes  ` +
    `${h.size}  data window ${h.dataWindow}  channels ${h.channels}  compression ${h.compression}`);
}
NODE

cp "$here/$DEFAULT.exr" "$here/default.exr"
echo "default.exr  copy of $DEFAULT.exr"

(cd "$here" && sha256sum --quiet -c SHA256SUMS) && echo "checksums match envmaps/SHA256SUMS"
