#!/usr/bin/env bash
# A contact sheet of the Khronos sample models in ../shared/data/gltf: each model rendered
# by Combustion beside the authors' own screenshot, to look at.
#
#   bash scripts/contact-sheet.sh OUT [BINARY] [-- RENDER OPTIONS...]
#
# OUT: a folder (created) that receives one NAME.png render per model and
# contact-sheet-N.png pages of 12 models each (render | screenshot). BINARY: the
# combustion binary (default: target/debug/combustion, built by `cargo build` if
# missing). RENDER OPTIONS are passed to every `combustion render` (e.g. --environment
# none). Needs ImageMagick's montage (Debian: apt-get install imagemagick); a model that
# fails to render is shown as a grey tile with its error in the log, and the script goes
# on.
set -euo pipefail
cd "$(dirname "$0")/.."

if [ $# -lt 1 ]; then
  echo "usage: bash scripts/contact-sheet.sh OUT [BINARY] [-- RENDER OPTIONS...]" >&2
  exit 2
fi
out=$1
shift
binary=target/debug/combustion
if [ $# -gt 0 ] && [ "$1" != "--" ]; then
  binary=$1
  shift
fi
if [ $# -gt 0 ] && [ "$1" = "--" ]; then
  shift
fi
extra=("$@")
samples=../shared/data/gltf
size=${CONTACT_SHEET_SIZE:-256}

if ! command -v montage >/dev/null; then
  echo "error: montage not found; install ImageMagick (Debian: apt-get install imagemagick)" >&2
  exit 1
fi
if [ ! -d "$samples" ]; then
  echo "error: $samples not found (the sample models live beside the workspace)" >&2
  exit 1
fi
if [ ! -x "$binary" ]; then
  cargo build --locked
fi
mkdir -p "$out"

tiles=()
for dir in "$samples"/*/; do
  name=$(basename "$dir")
  [ "$name" = "_LICENSES" ] && continue
  file=$( (find "$dir/glTF" "$dir/glTF-Binary" -maxdepth 1 \( -name '*.gltf' -o -name '*.glb' \) 2>/dev/null || true) | sort | head -n 1)
  [ -n "$file" ] || continue
  render="$out/$name.png"
  if ! "$binary" render --scene "$file" --width "$size" --height "$size" -o "$render" \
    "${extra[@]}" >"$out/$name.log" 2>&1; then
    echo "$name: render failed (see $out/$name.log)" >&2
    convert -size "${size}x${size}" xc:grey50 "$render"
  fi
  shot=$( (find "$dir/screenshot" -maxdepth 1 \( -name 'screenshot.png' -o -name 'screenshot.jpg' -o -name 'screenshot.gif' \) 2>/dev/null || true) | sort | head -n 1)
  if [ "${shot##*.}" = gif ]; then
    # An animation's first frame.
    convert "$shot[0]" "$out/$name-screenshot.png"
    shot="$out/$name-screenshot.png"
  elif [ -z "$shot" ]; then
    shot="$out/$name-no-screenshot.png"
    convert -size "${size}x${size}" xc:grey20 "$shot"
  fi
  tiles+=("$render" "$shot")
done

# 12 models (24 tiles) a page: render and screenshot side by side, two models a row.
page=0
for ((i = 0; i < ${#tiles[@]}; i += 24)); do
  page=$((page + 1))
  args=()
  for tile in "${tiles[@]:i:24}"; do
    case "$tile" in
      *-screenshot.png | *-no-screenshot.png) label="$(basename "$tile" .png)" ;;
      "$out"/*) label="$(basename "$tile" .png) (Combustion)" ;;
      *) label="$(basename "$(dirname "$(dirname "$tile")")") screenshot" ;;
    esac
    args+=(-label "$label" "$tile")
  done
  montage "${args[@]}" -tile 4x -geometry "${size}x${size}+4+4" -background grey15 \
    -fill white -pointsize 12 "$out/contact-sheet-$page.png"
  echo "$out/contact-sheet-$page.png"
done
