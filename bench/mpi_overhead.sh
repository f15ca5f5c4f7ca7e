#!/usr/bin/env bash
# The cost of rendering across processes on one machine: one image on 2 MPI ranks × 1 thread
# against 1 process × 2 threads, alternated ROUNDS times in one run; prints wall and CPU seconds
# of the whole command (scene loading included: every rank loads the scene) and of the render
# alone (from lobe's summary line), then the median ratios.
# Usage: bench/mpi_overhead.sh [LOBE] [SCENE] [ROUNDS] [extra lobe render options…]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
lobe=${1:-$here/build/apps/lobe}
scene=${2:-$here/assets/scenes/paper/rendering-01.json}
rounds=${3:-3}
shift $(( $# < 3 ? $# : 3 ))
extra=("$@")
[[ ${#extra[@]} -eq 0 ]] && extra=(--width 512 --spp 8)
mpi=(mpirun -n 2 --oversubscribe)
[[ $(id -u) -eq 0 ]] && mpi+=(--allow-run-as-root)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

run() {  # run NAME COMMAND… → prints "NAME wall cpu render"
  local name=$1; shift
  /usr/bin/time -f "%e %U %S" -o "$work/time" "$@" --no-contact-sheets --out "$work/$name" \
    2>"$work/log" >/dev/null
  read -r wall user sys <"$work/time"
  render=$(grep -oE ', [0-9]+\.[0-9]+ s( |,)' "$work/log" | head -1 | tr -dc '0-9.')
  echo "$name $wall $(echo "$user + $sys" | bc) $render"
  rm -rf "${work:?}/$name"
}

echo "# what wall_s cpu_s render_s ($scene ${extra[*]})"
for ((i = 0; i < rounds; i++)); do
  run threads "$lobe" render "$scene" "${extra[@]}" --threads 2
  run ranks "${mpi[@]}" "$lobe" render "$scene" "${extra[@]}" --threads 1
done | tee "$work/all"
python3 - "$work/all" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1]) if not l.startswith("#")]
def med(name, col): return statistics.median(float(r[col]) for r in rows if r[0] == name)
for col, what in ((1, "wall"), (2, "CPU"), (3, "render")):
    a, b = med("threads", col), med("ranks", col)
    print(f"{what}: 1 process × 2 threads {a:.2f} s, 2 ranks × 1 thread {b:.2f} s, ratio {b / a:.3f}")
PY
