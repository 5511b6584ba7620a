#!/usr/bin/env bash
# The speed comparison with what a user would pick instead, measured side by side in one
# run: the Bevy anchor (../shared/anchors/bevy-spheres: Bevy 0.19's deferred renderer on
# the 7×7 sphere grid) and `combustion view` on the same workload — builtin:grid-7x7 and
# the anchor's own scene as glTF (its twin) — and a textured Khronos model both load
# (Avocado from ../shared/data/gltf, given a camera and two lights of its own by
# scripts/anchors/textured_twin.py; Bevy's side is scripts/anchors/bevy-gltf, built beside
# the anchor), each a window of W×H under Xvfb, vsync off, the median wall-clock frame
# time of 100 frames, interleaved ROUNDS times, then the ratio of Bevy's median to
# Combustion's. Run it alone on the machine (nothing compiling beside it): two shared
# cores move such figures by a fifth from run to run.
#
#   bash scripts/side_by_side.sh            # 1280×720, two rounds
#   W=1920 H=1080 ROUNDS=3 bash scripts/side_by_side.sh
#   DEVICE_NAME=RADV bash scripts/side_by_side.sh   # another device than lavapipe
#
# It installs what it needs (Xvfb, the anchor's build packages, numpy for the twin),
# builds the anchor once into $ANCHOR_DIR (default /var/cache/combustion-anchors; 9.6
# minutes on two cores) and Combustion (PROFILE, dev by default). Combustion's window
# draws bloom and FXAA by default; the anchor has neither (Msaa::Off, no Fxaa component),
# so `--bloom off --anti-aliasing none` here: the same work on both sides.
set -euo pipefail
cd "$(dirname "$0")/.."

W=${W:-1280}
H=${H:-720}
ROUNDS=${ROUNDS:-2}
FRAMES=100
ANCHOR_SRC=../shared/anchors/bevy-spheres
ANCHOR_DIR=${ANCHOR_DIR:-/var/cache/combustion-anchors}

if [ ! -d "$ANCHOR_SRC" ]; then
    echo "error: $ANCHOR_SRC is not there (the shared folder beside the workspace)" >&2
    exit 1
fi

# Debian's own Python (python3-numpy is for it, whatever python3 comes first on PATH).
py=/usr/bin/python3
[ -x "$py" ] || py=python3

need=()
command -v Xvfb >/dev/null || need+=(xvfb)
command -v pkg-config >/dev/null || need+=(pkg-config)
for lib in libwayland-dev libxkbcommon-dev libudev-dev libasound2-dev; do
    dpkg -s "$lib" >/dev/null 2>&1 || need+=("$lib")
done
$py -c 'import numpy' 2>/dev/null || need+=(python3-numpy)
if [ ${#need[@]} -gt 0 ]; then
    apt-get update -qq
    apt-get install -y -qq "${need[@]}" >/dev/null
fi

# The anchor, built once from a writable copy (the shared folder is read-only).
mkdir -p "$ANCHOR_DIR"
if [ ! -x "$ANCHOR_DIR/target/release/bevy-spheres" ]; then
    rm -rf "$ANCHOR_DIR/bevy-spheres"
    cp -r "$ANCHOR_SRC" "$ANCHOR_DIR/bevy-spheres"
    chmod -R u+w "$ANCHOR_DIR/bevy-spheres"
    (cd "$ANCHOR_DIR/bevy-spheres" &&
        CARGO_TARGET_DIR="$ANCHOR_DIR/target" cargo build --release --locked -q)
fi
bevy="$ANCHOR_DIR/target/release/bevy-spheres"
twin="$ANCHOR_DIR/twin.gltf"
[ -f "$twin" ] || "$py" "$ANCHOR_SRC/twin/make_twin.py" "$twin" 4 >/dev/null

# Bevy on a glTF file, built beside the anchor with its lock (the same crates, compiled
# once), and the textured model with its own camera and lights.
mkdir -p "$ANCHOR_DIR/bevy-gltf"
cp -r scripts/anchors/bevy-gltf/. "$ANCHOR_DIR/bevy-gltf/"
sed 's/^name = "bevy-spheres"$/name = "bevy-gltf"/' "$ANCHOR_SRC/Cargo.lock" > "$ANCHOR_DIR/bevy-gltf/Cargo.lock"
(cd "$ANCHOR_DIR/bevy-gltf" && CARGO_TARGET_DIR="$ANCHOR_DIR/target" cargo build --release -q)
bevy_gltf="$ANCHOR_DIR/target/release/bevy-gltf"
model=../shared/data/gltf/Avocado/glTF/Avocado.gltf
textured=""
if [ -f "$model" ]; then
    textured=$("$py" scripts/anchors/textured_twin.py "$model" "$ANCHOR_DIR/avocado")
fi

# Combustion as its test command builds it (the dev profile: opt-level 1, its
# dependencies 2); PROFILE=release for the release profile (a first build compiles
# shaderc's glslang again: tens of minutes on two cores).
PROFILE=${PROFILE:-dev}
cargo build --profile "$PROFILE" --locked -q --bin combustion
if [ "$PROFILE" = dev ]; then
    combustion=target/debug/combustion
else
    combustion=target/$PROFILE/combustion
fi

# A display of our own.
display=:$((90 + RANDOM % 100))
Xvfb "$display" -screen 0 1920x1080x24 >/dev/null 2>&1 &
xvfb=$!
trap 'kill "$xvfb" 2>/dev/null || true' EXIT
sleep 1

# The device both use: lavapipe unless DEVICE_NAME names another (scripts/real_gpu.sh),
# by part of its name (Bevy's wgpu reads WGPU_ADAPTER_NAME the same way).
device=${DEVICE_NAME:-llvmpipe}
export DISPLAY=$display COMBUSTION_DEVICE=$device WGPU_ADAPTER_NAME=$device
driver=$("$combustion" devices | grep -m1 -F "$device" || true)
echo "driver: ${driver:-unknown}; Combustion's $PROFILE profile; ${W}x${H}, $FRAMES frames, $ROUNDS rounds interleaved"

# The median frame time (ms) each tool prints. The files are lit by their own lights
# alone on both sides (`--environment none`: Combustion lights a glTF file with the studio
# environment beside its lights by default, the anchors with nothing of the kind).
bevy_ms() { W=$W H=$H "$@" 2>/dev/null | sed -n 's/.*median_ms=\([0-9.]*\).*/\1/p' | tail -1; }
combustion_ms() {
    "$combustion" view "$@" --width "$W" --height "$H" --frames "$FRAMES" --vsync off \
        --overlay off --bloom off --anti-aliasing none 2>/dev/null |
        sed -n 's/.*wall clock per frame median \([0-9.]*\) ms.*/\1/p' | tail -1
}
# Bevy's median over Combustion's, two decimals.
ratio() { "$py" -c "print(f'{$1/$2:.2f}×')" 2>/dev/null || echo "not measured"; }

# Combustion keeps the heap a CPU device's frames free (combustion_vk::HeapTrim: glibc's
# trim threshold at 256 MiB, KEPT_HEAP_TRIM_THRESHOLD); the anchor is measured as it
# ships and, in a column of its own, given the same setting through glibc's environment.
kept_heap=$((256 << 20))
printf '| round | Bevy 0.19 deferred, grid | Bevy, grid, heap kept | combustion builtin:grid-7x7 | combustion twin.gltf | Bevy, Avocado | combustion, Avocado | Bevy ÷ Combustion (grid, twin, Avocado) | Bevy with the heap kept ÷ Combustion, grid |\n'
printf '|---|---|---|---|---|---|---|---|---|\n'
for round in $(seq 1 "$ROUNDS"); do
    b=$(bevy_ms "$bevy")
    bk=$(MALLOC_TRIM_THRESHOLD_=$kept_heap bevy_ms "$bevy")
    g=$(combustion_ms builtin:grid-7x7)
    t=$(combustion_ms "$twin" --environment none)
    ba="" ca=""
    if [ -n "$textured" ]; then
        ba=$(bevy_ms "$bevy_gltf" "$textured")
        ca=$(combustion_ms "$textured" --environment none)
    fi
    printf '| %s | %s ms | %s ms | %s ms | %s ms | %s ms | %s ms | %s, %s, %s | %s |\n' "$round" "${b:-?}" "${bk:-?}" \
        "${g:-?}" "${t:-?}" "${ba:-?}" "${ca:-?}" "$(ratio "$b" "$g")" "$(ratio "$b" "$t")" "$(ratio "$ba" "$ca")" \
        "$(ratio "$bk" "$g")"
done
