#!/usr/bin/env bash
# Times web/shlight-three.js's loadLightProbeGrid in headless Chromium on
# the three.js export of a 32x16x32 volume (the Cornell box), half and f32,
# and prints the times in milliseconds (benches/web/load.html says what is
# timed).
#
#   benches/web_load.sh
#
# Needs chromium and three.js in target/web-deps (.ci/run installs both),
# python3 for the local server. SHLIGHT names the binary (default: built
# here in release). Work files go to target/web-bench.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
shlight=${SHLIGHT:-${CARGO_TARGET_DIR:-target}/release/shlight}
three=target/web-deps/node_modules/three
[ -f "$three/examples/jsm/lighting/LightProbeGridWebGL.js" ] || {
    echo "three.js is not at $three (npm install --prefix target/web-deps three@0.187.0)" >&2
    exit 1
}
dir=target/web-bench
rm -rf "$dir"
mkdir -p "$dir/site/node_modules"
ln -s "$PWD/$three" "$dir/site/node_modules/three"
cp web/shlight-three.js benches/web/load.html "$dir/site/"
"$shlight" volume meshes/cornell_box.obj --env envmaps/park.exr --resolution 32x16x32 \
    --samples 64 --surface-samples 64 --bounces 1 -q -o "$dir/big.shvol"
"$shlight" convert "$dir/big.shvol" --format threejs -o "$dir/site/grid-half.json" 2>/dev/null
"$shlight" convert "$dir/big.shvol" --format threejs --precision f32 -o "$dir/site/grid-f32.json" 2>/dev/null
ls -l "$dir/site/"grid-*.json

cat >"$dir/server.py" <<'PY'
import functools, http.server, sys
class Handler(http.server.SimpleHTTPRequestHandler):
    def do_POST(self):
        body = self.rfile.read(int(self.headers["Content-Length"]))
        print(body.decode(), flush=True)
        self.send_response(204)
        self.end_headers()
    def log_message(self, *args):
        pass
server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(Handler, directory=sys.argv[1]))
print(server.server_address[1], flush=True)
server.serve_forever()
PY
python3 "$dir/server.py" "$dir/site" >"$dir/server.out" &
server=$!
chrome=""
cleanup() {
    [ -n "$chrome" ] && kill "$chrome" 2>/dev/null
    kill "$server" 2>/dev/null
}
trap cleanup EXIT
for _ in $(seq 50); do [ -s "$dir/server.out" ] && break; sleep 0.1; done
port=$(head -n 1 "$dir/server.out")
chromium --headless=new --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader \
    --no-first-run --disable-background-networking --disable-component-update --disable-sync \
    --disable-quic --user-data-dir="$dir/profile" "http://127.0.0.1:$port/load.html" \
    >"$dir/chromium.log" 2>&1 &
chrome=$!
for _ in $(seq 600); do
    [ "$(wc -l <"$dir/server.out")" -ge 2 ] && break
    sleep 0.1
done
sed -n 2p "$dir/server.out"
