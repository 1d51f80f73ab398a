#!/usr/bin/env bash
# basis.sh L M [R,G,B]: a shlight coefficient file (JSON, radiance, lmax L,
# z-up (+Z the pole), real orthonormal SH with the Condon-Shortley phase) holding the one
# basis function Y_L^M: colour R,G,B on coefficient L(L+1)+M, zero elsewhere.
# The default colour 1,0,-1 draws the positive lobes red and the negative
# lobes blue when `shlight render` writes a PNG (negative values clamp to 0).
set -euo pipefail
if [ $# -lt 2 ] || [ "$2" -gt "$1" ] || [ "$2" -lt "-$1" ]; then
    echo "usage: basis.sh L M [R,G,B] with -L <= M <= L" >&2
    exit 2
fi
l=$1 m=$2 colour=${3:-1,0,-1}
index=$((l * (l + 1) + m))
rows=""
for ((i = 0; i < (l + 1) * (l + 1); i++)); do
    if [ "$i" -eq "$index" ]; then row="[$colour]"; else row="[0,0,0]"; fi
    rows="$rows${rows:+,}$row"
done
cat <<JSON
{"format": "shlight-sh", "format_version": 1,
 "basis": {"kind": "real-orthonormal", "condon_shortley_phase": true, "index": "l*(l+1)+m"},
 "lmax": $l, "frame": "z-up", "mirror": false, "quantity": "radiance", "color_space": "linear-rec709",
 "provenance": {"tool": "docs/guide/basis.sh", "input": "Y_${l}^${m}", "width": 0, "height": 0,
                "layout": "equirect", "method": "convert", "window": "none"},
 "coefficients": [$rows]}
JSON
