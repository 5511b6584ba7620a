#!/usr/bin/env bash
# The cold build's cost, as a new user pays it: a clean clone of HEAD built into an empty
# target folder with `cargo build --timings` (what `bash scripts/dev.sh render` builds),
# then the total and the ten longest units from cargo's timing report. Run it on an
# otherwise idle machine (the figures in the README's "Build cost" came from it).
#
#   bash scripts/cold-build-time.sh            # the render build
#   bash scripts/cold-build-time.sh --tests    # then the test build on top of it
#
# Needs the system packages of scripts/dev.sh (run `bash scripts/dev.sh render` once) and
# about 4 GiB (the render build; 15 GiB more with --tests) in $TMPDIR.
set -euo pipefail
cd "$(dirname "$0")/.."
with_tests=0
[ "${1:-}" = "--tests" ] && with_tests=1
work=$(mktemp -d "${TMPDIR:-/tmp}/combustion-cold-build.XXXXXX")
trap 'rm -rf "$work"' EXIT
git clone -q --no-hardlinks . "$work/clone"
cd "$work/clone"
export CARGO_TARGET_DIR="$work/target"

report() { # $1: what was built; the newest timing report's units
  python3 - "$1" "$(ls -t "$CARGO_TARGET_DIR"/cargo-timings/cargo-timing-*.html | head -1)" <<'EOF'
import json, re, sys
what, path = sys.argv[1], sys.argv[2]
units = json.loads(re.search(r"const UNIT_DATA = (\[.*?\]);\n", open(path).read(), re.S).group(1))
wall = max(u["start"] + u["duration"] for u in units)
busy = sum(u["duration"] for u in units)
print(f"{what}: {wall:.0f} s wall, {len(units)} units, {busy:.0f} s of unit time "
      f"(parallelism {busy / wall:.2f})")
for u in sorted(units, key=lambda u: -u["duration"])[:10]:
    kind = u["target"].strip() or "lib"
    print(f"  {u['name']} {u['version']} ({kind}): {u['duration']:.0f} s, "
          f"from {u['start']:.0f} s")
EOF
}

start=$(date +%s)
cargo build --locked --timings >/dev/null 2>"$work/build.log" || { cat "$work/build.log" >&2; exit 1; }
echo "cargo build (the render command's build): $(( $(date +%s) - start )) s on $(nproc) cores, $(date -u +%F)"
report "render build"
if ((with_tests)); then
  start=$(date +%s)
  cargo test --locked --workspace --no-run --timings >/dev/null 2>"$work/build.log" || { cat "$work/build.log" >&2; exit 1; }
  echo "cargo test --no-run after it: $(( $(date +%s) - start )) s"
  report "test build"
fi
