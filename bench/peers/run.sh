#!/bin/bash
# Lobe vs VTK 9.1, side by side, on this machine.  See README.md.
#
#   bench/peers/run.sh [options] LOBE_BINARY [t1] [t2] [t3]        (no task: all three)
#
# options:
#   --rounds N         interleaved rounds (Lobe, VTK, Lobe, VTK, ...); default 3
#   --errors           also render each renderer's own step-0.02 reference (slow: ~1-2 min each) and report the
#                      self-convergence error of every stepped row (T2, T3)
#   --t2-steps "LIST"  T2 steps in world units (x-voxels); default "1 0.5 0.05"
#   --t3-steps "LIST"  T3 sample distances in world units; default "0.5 0.05" (Lobe gets LIST/0.87 voxels)
#   --no-warmup        skip the untimed warm-up pass (binary, VTK import, GL start, file cache)
#   --no-install       never run apt-get, only tell what is missing
# environment:
#   PEERS_SCRATCH      where everything generated goes (caches, work/, scenes/, runs/<date>/); default /tmp/lobe-peers.
#                      This folder and the repository are only read.
#
# Needs Debian 12 packages (scripts/setup.sh installs them; so does this script, with apt-get, when run as root):
#   python3-vtk9 xvfb xauth python3-numpy python3-scipy python3-nibabel python3-openimageio
# Python is always /usr/bin/python3 (a python3 on PATH may be a pyenv/venv shim that cannot see Debian's modules).
set -u -o pipefail

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
PY=/usr/bin/python3
PKGS="python3-vtk9 xvfb xauth python3-numpy python3-scipy python3-nibabel python3-openimageio"

usage() { sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//'; exit "${1:-2}"; }
die() { echo "run.sh: $*" >&2; exit 1; }

ROUNDS=3 ERRORS=0 WARMUP=1 INSTALL=1 T2_STEPS="1 0.5 0.05" T3_STEPS="0.5 0.05" LOBE="" TASKS=()
while [ $# -gt 0 ]; do
  case $1 in
    --rounds) ROUNDS=${2:?}; shift ;;
    --rounds=*) ROUNDS=${1#*=} ;;
    --errors) ERRORS=1 ;;
    --t2-steps) T2_STEPS=${2:?}; shift ;;
    --t2-steps=*) T2_STEPS=${1#*=} ;;
    --t3-steps) T3_STEPS=${2:?}; shift ;;
    --t3-steps=*) T3_STEPS=${1#*=} ;;
    --no-warmup) WARMUP=0 ;;
    --no-install) INSTALL=0 ;;
    -h|--help) usage 0 ;;
    -*) echo "run.sh: unknown option $1" >&2; usage ;;
    t1|t2|t3) TASKS+=("$1") ;;
    *) [ -z "$LOBE" ] || { echo "run.sh: unexpected argument $1" >&2; usage; }; LOBE=$1 ;;
  esac
  shift
done
[ -n "$LOBE" ] || usage
[ ${#TASKS[@]} -gt 0 ] || TASKS=(t1 t2 t3)
[[ $ROUNDS =~ ^[1-9][0-9]*$ ]] || die "--rounds needs a positive integer"
for s in $T2_STEPS $T3_STEPS; do [[ $s =~ ^[0-9]*\.?[0-9]+$ ]] || die "bad step '$s'"; done
LOBE_ARG=$LOBE
LOBE=$(readlink -f "$LOBE_ARG") && [ -f "$LOBE" ] && [ -x "$LOBE" ] || die "Lobe binary not found or not executable: $LOBE_ARG"
ASSETS=$(cd "$HERE/../../assets" 2>/dev/null && pwd)
[ -n "$ASSETS" ] && [ -f "$ASSETS/cthead/cthead_256x256x113_int16be.raw.gz" ] \
  && [ -f "$ASSETS/brain/mni_icbm152_gm_tal_nlin_sym_09a_converted.nii.gz" ] \
  || die "data not found in the repository's assets/ (cthead/, brain/); run this script from a checkout"

# ------------------------------------------------------------------ packages
missing=""
for p in $PKGS; do
  dpkg-query -W -f='${Status}\n' "$p" 2>/dev/null | grep -q '^install ok installed$' || missing="$missing $p"
done
if [ -n "$missing" ]; then
  if [ "$INSTALL" = 1 ] && [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    echo "== installing:$missing"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $missing \
      || die "apt-get install failed"
  else
    die "missing Debian packages:$missing
  install them with:  sudo apt-get install -y --no-install-recommends$missing"
  fi
fi
[ -x $PY ] || die "$PY not found"
$PY -c "import numpy, scipy.ndimage, nibabel, vtk, OpenImageIO" 2>/dev/null \
  || die "$PY cannot import numpy, scipy, nibabel, vtk and OpenImageIO (the Debian packages above); check with: $PY -c 'import vtk'"
command -v Xvfb >/dev/null || die "Xvfb not found (package xvfb)"

# ------------------------------------------------------------------ scratch, environment
export PEERS_SCRATCH=${PEERS_SCRATCH:-${TMPDIR:-/tmp}/lobe-peers}
export PYTHONDONTWRITEBYTECODE=1          # no __pycache__ in bench/peers
export LIBGL_ALWAYS_SOFTWARE=1 GALLIUM_DRIVER=llvmpipe   # as in the reference runs (Xvfb's GLX is software anyway)
mkdir -p "$PEERS_SCRATCH" || die "cannot create $PEERS_SCRATCH"
RUN=$PEERS_SCRATCH/runs/$(date +%Y%m%d-%H%M%S)
mkdir -p "$RUN/logs" "$RUN/img"
echo "== run folder: $RUN"

# ------------------------------------------------------------------ Xvfb on a free display, stopped by PID at exit
XVFB_PID=""
cleanup() {
  if [ -n "$XVFB_PID" ] && kill -0 "$XVFB_PID" 2>/dev/null; then
    kill "$XVFB_PID" 2>/dev/null; wait "$XVFB_PID" 2>/dev/null
    echo "== stopped Xvfb (PID $XVFB_PID)"
  fi
}
trap cleanup EXIT
trap 'echo "run.sh: interrupted" >&2; exit 130' INT TERM
DFILE=$RUN/xvfb.display
# -displayfd: the server picks a free display itself and writes its number once it accepts connections
Xvfb -displayfd 3 -screen 0 1280x1280x24 -nolisten tcp 3>"$DFILE" </dev/null >"$RUN/xvfb.log" 2>&1 &
XVFB_PID=$!
export XVFB_PID
for _ in $(seq 1 100); do
  [ -s "$DFILE" ] && break
  kill -0 "$XVFB_PID" 2>/dev/null || die "Xvfb exited at start; see $RUN/xvfb.log"
  sleep 0.1
done
[ -s "$DFILE" ] || die "Xvfb did not report a display within 10 s; see $RUN/xvfb.log"
export DISPLAY=:$(head -1 "$DFILE" | tr -dc 0-9)
echo "== Xvfb PID $XVFB_PID on $DISPLAY"

# ------------------------------------------------------------------ inputs (cached in PEERS_SCRATCH)
if [ ! -f "$PEERS_SCRATCH/work/cthead_cut.nhdr" ] || [ ! -f "$PEERS_SCRATCH/cthead_norm.npy" ] \
   || [ ! -f "$PEERS_SCRATCH/gm_mni.npz" ]; then
  echo "== make_sbs_assets.py (GM blur, cut CThead, caches; once)"
  $PY "$HERE/make_sbs_assets.py" > "$RUN/logs/make_sbs_assets.txt" 2>&1 \
    || { cat "$RUN/logs/make_sbs_assets.txt"; die "make_sbs_assets.py failed"; }
fi
$PY "$HERE/make_scenes.py" > "$RUN/logs/make_scenes.txt" 2>&1 \
  || { cat "$RUN/logs/make_scenes.txt"; die "make_scenes.py failed"; }
SC=$PEERS_SCRATCH/scenes

# ------------------------------------------------------------------ runners
VTK=("$PY" "$HERE/vtk_peer.py")
VTKGM=("$PY" "$HERE/vtk_sbs.py")
run() {  # run NAME CMD...   (timed; the output line shows the main time)
  local name=$1; shift
  echo "$name: $*" >> "$RUN/logs/commands.txt"
  $PY "$HERE/timed.py" "$RUN/logs/$name" -- "$@" || echo "   !! $name failed; see $RUN/logs/$name.log" >&2
  return 0
}
lobe() {  # lobe NAME SCENE [lobe render options]
  local name=$1 scene=$2; shift 2
  run "$name" "$LOBE" render "$SC/$scene.json" --out "$RUN/img/$name" --no-contact-sheets "$@"
}
vtk() {  # vtk NAME [vtk_peer.py options]
  local name=$1; shift
  run "$name" "${VTK[@]}" --out "$RUN/img/$name.png" "$@"
}
vtkgm() {
  local name=$1; shift
  run "$name" "${VTKGM[@]}" --out "$RUN/img/$name.png" "$@"
}
frames() { awk -v s="$1" 'BEGIN{print (s < 0.1 ? 1 : 2)}'; }      # VTK steady frames: 2, or 1 for fine steps
gmstep() { awk -v s="$1" 'BEGIN{printf "%.7g", s / 0.87}'; }      # world units -> Lobe voxels of the GM grid
loadline() { echo "   [$1] $(uptime | sed 's/.*load/load/')"; }

{
  echo "date: $(date -Is)"; echo "host: $(uname -srm), $(nproc) CPUs"
  echo "lobe: $LOBE ($("$LOBE" --version 2>&1 | head -1))"
  echo "vtk: $(dpkg-query -W -f='${Version}' python3-vtk9)"; echo "tasks: ${TASKS[*]}  rounds: $ROUNDS  errors: $ERRORS"
  echo "t2 steps: $T2_STEPS  t3 steps: $T3_STEPS"; uptime
} > "$RUN/info.txt"
cat "$RUN/info.txt"

if [ "$WARMUP" = 1 ]; then
  echo "== warm-up (untimed in the table)"
  lobe warmup_lobe t1_exact --preview
  vtk warmup_vtk --task t1 --frames 0 --res 256
fi

for task in "${TASKS[@]}"; do
  echo "== $task"
  case $task in
  t1)
    for k in $(seq 1 "$ROUNDS"); do
      loadline "t1 round $k"
      lobe lobe_t1_exact.r$k t1_exact --spp 1
      lobe lobe_t1_mesh.r$k t1_mesh --spp 1
      vtk vtk_t1.r$k --task t1 --frames 5
    done ;;
  t2)
    for k in $(seq 1 "$ROUNDS"); do
      for s in $T2_STEPS; do
        loadline "t2 step $s round $k"
        lobe lobe_t2_s$s.r$k t2_dvr --step "$s" --spp 1
        vtk vtk_t2_s$s.r$k --task t2 --sd "$s" --frames "$(frames "$s")"
      done
    done
    if [ "$ERRORS" = 1 ]; then
      loadline "t2 reference step 0.02"
      lobe lobe_t2_s0.02.r1 t2_dvr --step 0.02 --spp 1
      vtk vtk_t2_s0.02.r1 --task t2 --sd 0.02 --frames 0
    fi ;;
  t3)
    for k in $(seq 1 "$ROUNDS"); do
      for s in $T3_STEPS; do
        loadline "t3 sd $s round $k"
        lobe lobe_t3cut_s$s.r$k t3_cut --step "$(gmstep "$s")" --spp 1
        vtk vtk_t3cut_s$s.r$k --task t3 --sd "$s" --frames "$(frames "$s")"
        lobe lobe_t3gm_s$s.r$k t3_gm --step "$(gmstep "$s")" --spp 1
        vtkgm vtk_t3gm_s$s.r$k --sd "$s" --frames "$(frames "$s")"
      done
    done
    if [ "$ERRORS" = 1 ]; then
      loadline "t3 references sd 0.02"
      lobe lobe_t3cut_s0.02.r1 t3_cut --step "$(gmstep 0.02)" --spp 1
      vtk vtk_t3cut_s0.02.r1 --task t3 --sd 0.02 --frames 0
      lobe lobe_t3gm_s0.02.r1 t3_gm --step "$(gmstep 0.02)" --spp 1
      vtkgm vtk_t3gm_s0.02.r1 --sd 0.02 --frames 0
    fi ;;
  esac
done

# keep round 1's images (and the references) for a look; later rounds' EXRs only cost disk
find "$RUN/img" -name '*.exr' ! -path '*.r1/*' -delete 2>/dev/null

echo
echo "== results ($RUN/summary.md; images in $RUN/img, logs in $RUN/logs)"
echo
SUMARGS=("$RUN"); [ "$ERRORS" = 1 ] && SUMARGS+=(--errors)
$PY "$HERE/summarize.py" "${SUMARGS[@]}"
