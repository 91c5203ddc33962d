#!/usr/bin/env bash
# Runs ParaView's processes the way the plugin's tests and demo need them (docs/paraview.md):
#   paraview/run.sh one                   pvbatch paraview/tests/test_one_rank.py
#   paraview/run.sh two                   mpirun -np 2 pvbatch paraview/tests/test_two_ranks.py
#   paraview/run.sh client-server         mpirun -np 2 pvserver + pvpython paraview/tests/test_client_server.py
#   paraview/run.sh gui                   the paraview GUI, plugin from PV_PLUGIN_PATH, paraview/tests/test_gui.py
#   paraview/run.sh demo RANKS [FRAMES]   (mpirun -np RANKS) pvbatch paraview/demo.py
# What every ParaView process gets here, and why:
#   - an X display: Debian's ParaView 5.11 renders through GLX only (no EGL, no OSMesa), so all
#     of it runs inside one Xvfb; the display number is one no other X server on this machine
#     (in any chroot or container: abstract sockets are shared) has taken;
#   - --disable-xdisplay-test: ParaView's start-up display test opens and closes X connections
#     in quick succession, and Xvfb refuses some of those (measured: 1 in 10 to 3), which makes
#     ParaView abort with "bad X server connection";
#   - LD_PRELOAD of libcellfx_expat_fix.so (paraview/expat_fix): without it Debian 12's expat
#     breaks the XML in which ParaView moves data between MPI ranks;
#   - Open MPI as root, without the single-copy mechanism containers lack, yielding when idle;
#     with several ranks, llvmpipe's threads (LP_NUM_THREADS) shared out among them.
# CELLFX_PARAVIEW_BUILD: the build folder (default build-paraview/).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
export CELLFX_PARAVIEW_BUILD="${CELLFX_PARAVIEW_BUILD:-$root/build-paraview}"
preload="$CELLFX_PARAVIEW_BUILD/lib/libcellfx_expat_fix.so"
[ -f "$preload" ] || { echo "paraview/run.sh: no $preload: build first (bash scripts/paraview.sh)" >&2; exit 1; }
export OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# Ranks waiting for each other yield the CPU instead of spinning on it (they share the cores
# with llvmpipe's rendering threads).
export OMPI_MCA_mpi_yield_when_idle=1

free_display() {
  local n
  for n in $(seq 100 999); do
    [ -e "/tmp/.X$n-lock" ] && continue
    grep -q "/tmp/.X11-unix/X$n\$" /proc/net/unix 2>/dev/null && continue
    echo "$n"
    return
  done
  echo "paraview/run.sh: no free X display number" >&2
  exit 1
}

# Runs "$@" inside a fresh Xvfb.
in_xvfb() {
  xvfb-run -n "$(free_display)" -s "-screen 0 1280x1024x24 -nolisten tcp" "$@"
}

pvbatch_on() { # RANKS SCRIPT ARGS...
  local ranks=$1
  shift
  if [ "$ranks" = 1 ]; then
    in_xvfb env LD_PRELOAD="$preload" pvbatch --disable-xdisplay-test "$@"
  else
    # llvmpipe renders with a thread per core in every rank: share the cores out.
    local threads=$(( $(nproc) / ranks ))
    in_xvfb mpirun -np "$ranks" -x LD_PRELOAD="$preload" -x LP_NUM_THREADS="$(( threads > 0 ? threads : 1 ))" \
      pvbatch --disable-xdisplay-test "$@"
  fi
}

mode="${1:-}"
case "$mode" in
  one) pvbatch_on 1 "$root/paraview/tests/test_one_rank.py" ;;
  two) pvbatch_on 2 "$root/paraview/tests/test_two_ranks.py" ;;
  demo) pvbatch_on "${2:-1}" "$root/paraview/demo.py" "${3:-8}" ;;
  gui)
    out="$CELLFX_PARAVIEW_BUILD/paraview-out"
    mkdir -p "$out"
    rm -f "$out/gui_result.txt"
    in_xvfb env PV_PLUGIN_PATH="$CELLFX_PARAVIEW_BUILD/lib/paraview-5.11/plugins/CellfxVolume" \
      CELLFX_PARAVIEW_TESTS="$root/paraview/tests" XDG_RUNTIME_DIR="$(mktemp -d)" paraview --disable-xdisplay-test --script="$root/paraview/tests/test_gui.py" --exit
    cat "$out/gui_result.txt" 2>/dev/null || { echo "FAIL: the GUI wrote no result"; exit 1; }
    grep -q "^ok" "$out/gui_result.txt"
    ;;
  client-server)
    port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
    log="$(mktemp)"
    # One Xvfb for the server's two ranks and the client; the server is stopped on the way out.
    in_xvfb bash -c '
      mpirun -np 2 -x LD_PRELOAD="$1" pvserver --disable-xdisplay-test --server-port="$2" > "$3" 2>&1 &
      server=$!
      trap "kill $server 2>/dev/null; wait $server 2>/dev/null" EXIT
      for _ in $(seq 600); do grep -q "Accepting connection" "$3" && break; sleep 0.1; done
      grep -q "Accepting connection" "$3" || { echo "pvserver did not start:"; cat "$3"; exit 1; }
      LD_PRELOAD="$1" pvpython --disable-xdisplay-test "$4" "$2"
    ' client-server "$preload" "$port" "$log" "$root/paraview/tests/test_client_server.py"
    rm -f "$log"
    ;;
  *)
    echo "usage: paraview/run.sh one | two | client-server | gui | demo RANKS [FRAMES]" >&2
    exit 2
    ;;
esac
