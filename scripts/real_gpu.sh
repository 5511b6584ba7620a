#!/usr/bin/env bash
# The measurements lavapipe cannot stand in for, ready for a machine with a GPU: the
# report's floors (is the G-buffer pass bound by its geometry or its fragment work, the
# lighting pass by its fetches or its arithmetic, on real hardware?) and the side by side
# with the Bevy anchor, both on the first device that is not a CPU (or DEVICE=NAME).
#
#   bash scripts/real_gpu.sh                  # writes target/real-gpu/<device>/
#   DEVICE=RADV bash scripts/real_gpu.sh      # a device by part of its name
#   SCENES="builtin:grid-7x7 builtin:spheres" bash scripts/real_gpu.sh
#
# On lavapipe the frame's floors are the CPU's (docs/performance.md, "Where the frame's
# time goes"): its G-buffer pass is bound by rasterising small triangles in 4×4 blocks,
# its lighting pass by the surfaces' fetches and the BRDF's arithmetic (a 4×4 block of
# background costs it nothing but its depth test). A
# GPU's are its memory bandwidth (the G-buffer's 24 bytes a pixel written and read) and
# its ALU (the BRDF's per-light work): which bounds each pass there is what this run
# says. It refuses to run on a CPU device unless ALLOW_CPU=1 (to try the script itself).
set -euo pipefail
cd "$(dirname "$0")/.."

W=${W:-1280}
H=${H:-720}
FRAMES=${FRAMES:-30}
SCENES=${SCENES:-"builtin:grid-7x7 builtin:spheres"}

cargo build --locked -q --bin combustion
combustion=target/debug/combustion

# `combustion devices`: "INDEX: NAME (TYPE, Vulkan …, driver)".
devices=$("$combustion" devices)
if [ -n "${DEVICE:-}" ]; then
    line=$(grep -m1 -F "$DEVICE" <<<"$devices" || true)
else
    line=$(grep -v -m1 '(CPU,' <<<"$devices" || true)
    if [ -z "$line" ] && [ "${ALLOW_CPU:-0}" = 1 ]; then
        line=$(head -n1 <<<"$devices")
    fi
fi
if [ -z "$line" ]; then
    echo "error: no GPU among the Vulkan devices (DEVICE=NAME picks one by name):" >&2
    echo "$devices" >&2
    exit 1
fi
if grep -q '(CPU,' <<<"$line" && [ "${ALLOW_CPU:-0}" != 1 ]; then
    echo "error: '$line' is a CPU device: its figures are docs/performance.md's (ALLOW_CPU=1 to run anyway)" >&2
    exit 1
fi
name=$(sed 's/^[0-9]*: \(.*\) ([^()]*, Vulkan .*/\1/' <<<"$line")
export COMBUSTION_DEVICE="$name"
out=target/real-gpu/$(printf '%s' "$name" | tr -c 'A-Za-z0-9._-' '_')
mkdir -p "$out"
echo "device: $line"
echo "writing $out"

# Pass times and the floors of each scene (report.md, report.csv, floors.csv, …).
for scene in $SCENES; do
    dir="$out/$(printf '%s' "$scene" | tr -c 'A-Za-z0-9._-' '_')"
    "$combustion" bench "$scene" --width "$W" --height "$H" --frames "$FRAMES" | tee "$dir.bench.txt"
    "$combustion" bench --report "$dir" --scene "$scene" --width "$W" --height "$H" --frames "$FRAMES"
done

# Side by side with Bevy on the same device (Bevy picks the GPU by itself; on a machine
# with a display the windows present through it, under Xvfb through a CPU copy).
DEVICE_NAME="$name" bash scripts/side_by_side.sh | tee "$out/side-by-side.md"
