#!/usr/bin/env bash
# The two commands of the README:
#   bash scripts/dev.sh render   install what is missing, render builtin:spheres to spheres.png
#   bash scripts/dev.sh test     install what is missing, run fmt, clippy, rustdoc and the whole test suite
# Both first install the system packages Combustion needs on Debian/Ubuntu (lavapipe,
# the Vulkan loader, the validation layers, and what building shaderc from source needs).
set -euo pipefail
cd "$(dirname "$0")/.."

# Debian/Ubuntu packages: lavapipe (CPU Vulkan driver), the loader, the validation layers,
# and shaderc's build-from-source needs (cmake, python3, a C++ compiler, git for its sources
# is not needed: the crate ships them); for `combustion view` and its test, the X libraries
# winit loads at run time and a virtual X server (Xvfb; xauth for xvfb-run; xdotool and
# x11-utils' xprop to drive and minimise its window as a window manager would); a headless
# Wayland compositor (weston) for the viewer's Wayland test (it brings libwayland-client,
# which winit loads at run time on Wayland); coreutils for mkfifo in the output-path tests
# (Essential on Debian, listed so a slimmed image says so); tar and xz-utils to unpack the
# fuzz corpora the replay tests read (fuzz/seeds/*.tar.xz).
PACKAGES=(mesa-vulkan-drivers libvulkan1 vulkan-validationlayers cmake make python3 g++ pkg-config coreutils
  xvfb xauth xdotool x11-utils procps libx11-6 libx11-xcb1 libxcursor1 libxrandr2 libxi6 libxkbcommon-x11-0
  weston libwayland-client0 libxkbcommon0 tar xz-utils)

# Lavapipe has ray queries (VK_KHR_ray_query, acceleration structures) from Mesa 24.1: the
# exact-visibility paths are tested on it. Debian 12 ships Mesa 22.3; its own
# bookworm-backports suite has 25.0 (with the libdrm it needs). Elsewhere: a Mesa of 24.1 or
# later from the distribution (Debian 13, Ubuntu 24.10 and later; Fedora 40 and later).
mesa_with_ray_queries() {
  local sudo=()
  [ "$(id -u)" -eq 0 ] || sudo=(sudo)
  local codename version
  codename=$(. /etc/os-release 2>/dev/null && echo "${VERSION_CODENAME:-}")
  version=$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true)
  if [ -n "$version" ] && dpkg --compare-versions "$version" ge 24.1; then
    return
  fi
  if [ "$codename" = bookworm ]; then
    echo "installing mesa-vulkan-drivers from bookworm-backports (lavapipe with ray queries)"
    local list=/etc/apt/sources.list.d/bookworm-backports.sources
    if ! grep -rqs "bookworm-backports" /etc/apt/sources.list /etc/apt/sources.list.d/; then
      printf 'Types: deb\nURIs: http://deb.debian.org/debian\nSuites: bookworm-backports\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' |
        "${sudo[@]}" tee "$list" >/dev/null
    fi
    "${sudo[@]}" apt-get update -qq
    DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq -t bookworm-backports \
      mesa-vulkan-drivers libdrm2 libdrm-amdgpu1
  else
    echo "warning: mesa-vulkan-drivers ${version:-(none)} is older than 24.1: lavapipe has no ray queries, and the tests of the exact-visibility paths fail (install Mesa 24.1 or later)" >&2
  fi
}

install_packages() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]})); then
    echo "installing: ${missing[*]}"
    local sudo=()
    [ "$(id -u)" -eq 0 ] || sudo=(sudo)
    "${sudo[@]}" apt-get update -qq
    DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq "${missing[@]}"
  fi
  mesa_with_ray_queries
  # A cold build and the test binaries take about 15 GiB of target/ (docs/build.md, "Build
  # cost"); a full disk shows up as a compiler crash deep in the build, so say it first.
  local free_kib
  free_kib=$(df -Pk . | awk 'NR == 2 { print $4 }')
  if [ -n "$free_kib" ] && [ "$free_kib" -lt $((16 * 1024 * 1024)) ]; then
    echo "warning: $((free_kib / 1024 / 1024)) GiB free here; a cold build and the tests need about 16 GiB" >&2
  fi
  if ! command -v cargo >/dev/null; then
    echo "error: cargo not found; install Rust (https://rustup.rs), then run this again" >&2
    exit 1
  fi
}

case "${1:-}" in
  render)
    install_packages
    shift
    cargo run --locked -- render --scene builtin:spheres --width 1280 --height 720 \
      -o spheres.png --hdr spheres.exr "$@"
    ;;
  test)
    install_packages
    start=$(date +%s)
    cargo fmt --all -- --check
    # --profile test: clippy then shares the test build's build-script outputs, so the
    # shaderc C++ build (the bulk of a cold build) runs once, not twice.
    cargo clippy --locked --workspace --all-targets --profile test -- -D warnings
    # The public API's documentation: every public item documented (missing_docs, denied
    # by clippy above) and every intra-doc link resolving.
    RUSTDOCFLAGS="-D warnings" cargo doc --locked --workspace --no-deps
    # glibc gives a heap's free top back to the kernel once it passes 128 KiB (dynamically
    # more); lavapipe's draws allocate and free such blocks every frame, so each frame
    # faulted its pages in and zeroed them again: a third of the CPU time of a test that
    # renders many small frames went to the kernel. Keeping freed memory in the test
    # processes (no trim below 4 GiB) changes no result (docs/build.md, "Build cost"). Fixing the
    # trim threshold also fixes the mmap threshold, which would otherwise grow with the
    # blocks freed; it is set to its largest (32 MiB), so blocks below it come from the
    # heap and are reused instead of mapped and unmapped each time.
    export GLIBC_TUNABLES="${GLIBC_TUNABLES:+$GLIBC_TUNABLES:}glibc.malloc.trim_threshold=4294967296:glibc.malloc.mmap_threshold=33554432"
    # nextest runs a test per core, so lavapipe's own rasteriser threads (one per core in
    # each test process) add only hand-offs between threads: each process rasterises in
    # its own thread instead (the same pixels; docs/build.md, "Build cost"). A value already
    # set is kept.
    export LP_NUM_THREADS="${LP_NUM_THREADS:-0}"
    if cargo nextest --version >/dev/null 2>&1; then
      # What the tests run, not the examples: clippy above checks them (--all-targets),
      # and the two a test runs (examples/host, examples/guide_engine.rs) are built
      # into it; building the nine examples took about 10 s of the test build's unit
      # time (2 s of its wall time on 2 cores).
      cargo nextest run --locked --workspace --lib --bins --tests --no-fail-fast
    else
      cargo test --locked --workspace --no-fail-fast
    fi
    echo "test command took $(( $(date +%s) - start )) s"
    ;;
  *)
    echo "usage: bash scripts/dev.sh render|test" >&2
    exit 2
    ;;
esac
