#!/usr/bin/env bash
# The README's gallery, rendered by the project itself: each picture in docs/gallery/ is
# made by the command written beside it here (and in the README).
#
#   bash scripts/gallery.sh [BINARY]
#
# BINARY: the combustion binary (default: target/debug/combustion, built by `cargo
# build` if missing). The Khronos model (Avocado, CC0) is read from ../shared/data/gltf
# when that folder is beside the workspace, and skipped otherwise; the error view runs
# the viewer under a virtual X server (xvfb-run, which `scripts/dev.sh` installs).
set -euo pipefail
cd "$(dirname "$0")/.."

binary=${1:-target/debug/combustion}
if [ ! -x "$binary" ]; then
  cargo build --locked
  binary=target/debug/combustion
fi
out=docs/gallery
mkdir -p "$out"
size=(--width 640 --height 360)

run() {
  echo "+ combustion $*"
  "$binary" "$@" >/dev/null
}

run render builtin:spheres "${size[@]}" -o "$out/spheres.png"
run render builtin:glass-underwater "${size[@]}" -o "$out/glass-underwater.png"
run render builtin:glass-underwater --path-trace on --samples 1024 "${size[@]}" -o "$out/glass-underwater-path-traced.png"
run render builtin:grid-sun --shadows on "${size[@]}" -o "$out/grid-sun-shadows.png"
run render builtin:normal-mapped "${size[@]}" -o "$out/normal-mapped.png"
run render builtin:resting --environment-occlusion ray-traced --accumulate-until 0.002 "${size[@]}" -o "$out/resting-ray-traced.png"
run render builtin:cornell-box "${size[@]}" -o "$out/cornell-box.png"
run render builtin:cornell-box --path-trace on --accumulate-until 0.03 "${size[@]}" -o "$out/cornell-box-path-traced.png"
run render builtin:room "${size[@]}" -o "$out/room.png"
run render builtin:room --path-trace on --samples 1024 "${size[@]}" -o "$out/room-path-traced.png"
run render builtin:glass "${size[@]}" -o "$out/glass.png"
run render builtin:glass --ray-traced-refraction on "${size[@]}" -o "$out/glass-traced-refraction.png"
run render builtin:glass --path-trace on --samples 1024 "${size[@]}" -o "$out/glass-path-traced.png"
avocado=../shared/data/gltf/Avocado/glTF/Avocado.gltf
if [ -f "$avocado" ]; then
  run render "$avocado" "${size[@]}" -o "$out/avocado-studio.png"
else
  echo "skipped avocado-studio.png: $avocado not found" >&2
fi
# The error view (the viewer's X key): each pixel's relative error against the f64
# reference, on a log scale; a screenshot of the viewer's second frame.
echo "+ combustion view builtin:spheres --error-view --overlay off --frames 2 --screenshot $out/error-view.png"
xvfb-run -a -s "-screen 0 1280x800x24" "$binary" view builtin:spheres "${size[@]}" \
  --error-view --overlay off --frames 2 --vsync off --screenshot "$out/error-view.png" >/dev/null
