#!/usr/bin/env bash
# The cold build's cost, as a new user pays it: a clean clone of HEAD built into an empty
# target folder with `cargo build --timings` (what `bash scripts/dev.sh render` builds),
# then the total and the ten longest units from cargo's timing report. Run it on an
# otherwise idle machine (the figures in the docs/build.md's "Build cost" came from it).
#
#   bash scripts/cold-build-time.sh             # the render build
#   bash scripts/cold-build-time.sh --tests     # then the test build on top of it
#   bash scripts/cold-build-time.sh --commands  # the README's two commands, as timed there
#
# --commands runs `bash scripts/dev.sh render`, then `bash scripts/dev.sh test`, in the
# clean clone with an empty target folder and empty caches (the SPIR-V cache, the
# environment bakes' cubes, Mesa's shader cache: XDG_CACHE_HOME is a new folder),
# ../shared beside the clone when it is beside this one, and prints each command's wall
# time; a failing command fails it. Each
# command's output is kept in $TMPDIR/combustion-cold-render.log and -test.log.
#
# Needs the system packages of scripts/dev.sh (run `bash scripts/dev.sh render` once) and
# about 4 GiB (the render build; 4 GiB more with --tests or --commands) in $TMPDIR.
set -euo pipefail
cd "$(dirname "$0")/.."
mode=${1:-}
case "$mode" in
  "" | --tests | --commands) ;;
  *) echo "usage: bash scripts/cold-build-time.sh [--tests | --commands]" >&2; exit 2 ;;
esac
work=$(mktemp -d "${TMPDIR:-/tmp}/combustion-cold-build.XXXXXX")
trap 'rm -rf "$work"' EXIT
git clone -q --no-hardlinks . "$work/clone"
[ -d ../shared ] && ln -s "$(cd ../shared && pwd)" "$work/shared"
cd "$work/clone"
export CARGO_TARGET_DIR="$work/target"

if [ "$mode" = --commands ]; then
  mkdir "$work/cache"
  export XDG_CACHE_HOME="$work/cache"
  for command in render test; do
    start=$(date +%s)
    log="${TMPDIR:-/tmp}/combustion-cold-$command.log"
    bash scripts/dev.sh "$command" >"$log" 2>&1 || {
      tail -40 "$log" >&2
      echo "bash scripts/dev.sh $command failed after $(( $(date +%s) - start )) s" >&2
      exit 1
    }
    echo "bash scripts/dev.sh $command: $(( $(date +%s) - start )) s on $(nproc) cores, $(date -u +%F)"
    grep -E "^ +Summary|Finished" "$log" | sed 's/^ */  /'
  done
  exit 0
fi

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
if [ "$mode" = --tests ]; then
  start=$(date +%s)
  cargo test --locked --workspace --no-run --timings >/dev/null 2>"$work/build.log" || { cat "$work/build.log" >&2; exit 1; }
  echo "cargo test --no-run after it: $(( $(date +%s) - start )) s"
  report "test build"
fi
