#!/usr/bin/env bash
# Packs what scripts/device_bench.sh needs on a bare GPU machine that cannot fetch anything (a
# CUDA image without cellfx's Debian packages): the Release `cellfx` binary, the shared libraries
# it links that such an image lacks, and the GLVND/EGL packages that let libepoxy reach the
# NVIDIA driver's EGL. Run here, in the checkout, after scripts/build.sh:
#   bash scripts/device_pack.sh            # writes .device/ (ignored by git: .git/info/exclude)
# then carry `.device` to the GPU machine and run `bash scripts/device_bench.sh` there
# (docs/performance.md, "On a GPU"). About 8 MB.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
build="${CELLFX_BUILD_DIR:-$root/build}"
cellfx="$build/samples/cellfx"
[ -x "$cellfx" ] || { echo "device_pack.sh: $cellfx not built (bash scripts/build.sh first)" >&2; exit 1; }
if ! grep -q "CMAKE_BUILD_TYPE:STRING=Release" "$build/CMakeCache.txt"; then
  echo "device_pack.sh: $build is not a Release build: its timings would not be worth reporting" >&2
  exit 1
fi

grep -qx '/.device/' .git/info/exclude 2>/dev/null || echo '/.device/' >> .git/info/exclude
rm -rf .device
mkdir -p .device/lib .device/debs
cp "$cellfx" .device/cellfx

# The libraries cellfx links, less the C and C++ runtimes every image has (and that must match
# its own loader) and the GL libraries that come from the packages below.
ldd "$cellfx" | awk '$2 == "=>" { print $1, $3 }' | while read -r name path; do
  case "$name" in
    libc.so.*|libm.so.*|libdl.so.*|libpthread.so.*|librt.so.*|libstdc++.so.*|libgcc_s.so.*) ;;
    libEGL*|libGL*|libOpenGL*|libGLdispatch*|libGLX*) ;;
    *) cp -L "$path" .device/lib/ ;;
  esac
done

# GLVND's dispatch libraries (the NVIDIA driver brings its vendor library and JSON, not these).
(cd .device/debs && apt-get -o APT::Sandbox::User=root download libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2 >/dev/null)
echo "device_pack.sh: .device/ holds $(ls .device/lib | wc -l) libraries and $(ls .device/debs | wc -l) packages," \
     "$(du -sh .device | cut -f1)"
