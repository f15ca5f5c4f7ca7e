#!/usr/bin/env bash
# `lobe render` under mpirun equals the single-process render: the same pixels in every EXR
# channel and PNG (idiff with no tolerance; the files differ in OpenImageIO's DateTime and in the
# command line of their provenance), contact sheets included, for 2 processes × all threads and
# 3 processes × 1 thread. A rank that fails ends the run with its message and no output; bad input
# is one message. The same in bands of rows (--band-rows, figure/figure_output.h).
# Usage: mpi_test.sh LOBE MPIRUN SOURCE_DIR WORK_DIR
set -euo pipefail
lobe=$1 mpirun_bin=$2 src=$3 work=$4
rm -rf "$work"
mkdir -p "$work"
cd "$work"
mpi=("$mpirun_bin" --oversubscribe)
[[ $(id -u) -eq 0 ]] && mpi+=(--allow-run-as-root)
scenes=("$src/assets/scenes/paper/rendering-01.json" "$src/assets/scenes/paper/rendering-13.json")
settings=(--width 64 --spp 2 --aov all --quiet)
fail() { echo "mpi test: $*" >&2; exit 1; }

"$lobe" render "${scenes[@]}" "${settings[@]}" --out ref
"${mpi[@]}" -n 2 "$lobe" render "${scenes[@]}" "${settings[@]}" --out n2
"${mpi[@]}" -n 3 "$lobe" render "${scenes[@]}" "${settings[@]}" --threads 1 --out n3
# In bands of 5 rows (a poster's way: each band's tiles shared and gathered, then written).
"${mpi[@]}" -n 2 "$lobe" render "${scenes[@]}" "${settings[@]}" --band-rows 5 --out n2-bands
for run in n2 n3 n2-bands; do
  for f in ref/*; do
    name=$(basename "$f")
    [[ -f "$run/$name" ]] || fail "$run/$name missing"
    case "$name" in
      # Images by pixels: their provenance (figure/figure_output.h) names their own command
      # lines, contact sheets' too; anything else byte for byte.
      *.exr|*.png) idiff -a -fail 0 -failpercent 0 -warn 0 "$f" "$run/$name" >/dev/null ||
               fail "$run/$name: pixels differ from the single-process render" ;;
      *) cmp -s "$f" "$run/$name" || fail "$run/$name differs from the single-process render" ;;
    esac
  done
  [[ $(ls "$run" | wc -l) -eq $(ls ref | wc -l) ]] || fail "$run holds other files than ref"
done

# A process that fails while rendering ends every process: exit non-zero, its message, no files.
if LOBE_FAULT_RANK=1 "${mpi[@]}" -n 2 "$lobe" render "${scenes[0]}" "${settings[@]}" \
     --out fault 2>fault.err; then
  fail "a failing rank left exit status 0"
fi
grep -q "lobe: error on rank 1 of 2: fault injected on rank 1" fault.err ||
  fail "no message from the failing rank: $(cat fault.err)"
[[ -z $(ls -A fault 2>/dev/null) ]] || fail "a failed run left files: $(ls -A fault)"

# Bad input is found before any rank renders and reported once.
if "${mpi[@]}" -n 3 "$lobe" render missing.json --out bad 2>bad.err; then
  fail "a missing scene left exit status 0"
fi
[[ $(grep -c "^lobe: error: scene file 'missing.json' does not exist" bad.err) -eq 1 ]] ||
  fail "expected one message for a missing scene: $(cat bad.err)"
[[ ! -e bad ]] || fail "a refused run created its output folder"
# Node-local copies of a volume that differ between ranks (same scene text, other voxels) are
# found before rendering by the volumes' content hashes and named by rank and file; a file that
# is missing on one rank only is named by rank too.
for r in 0 1 2; do
  mkdir -p "node$r"
  cat > "node$r/ball.json" <<'SCENE'
{"image": {"width": 16, "height": 16, "samples_per_pixel": 1},
 "camera": {"position": [40, 30, 35], "target": [7.5, 7.5, 7.5], "up": [0, 0, 1], "fov_deg": 40},
 "lights": [{"position": [40, 30, 35], "intensity": 3000}],
 "objects": [{"name": "ball", "kind": "isosurface",
   "source": {"path": "ball.raw", "dims": [16, 16, 16], "type": "uint8"},
   "iso": 100, "opacity": 1.0, "brdf": {"model": "ward"}}]}
SCENE
done
{ head -c 2048 /dev/zero; head -c 2048 /dev/zero | tr '\0' '\310'; } > node0/ball.raw
{ head -c 1024 /dev/zero; head -c 3072 /dev/zero | tr '\0' '\310'; } > node1/ball.raw
per_rank=(bash -c 'exec "$0" render "node$OMPI_COMM_WORLD_RANK/ball.json" --quiet --out "$1"')
if "${mpi[@]}" -n 2 "${per_rank[@]}" "$lobe" mixed 2>mixed.err; then
  fail "ranks with different volume data left exit status 0"
fi
grep -q "^lobe: error: on rank 1 of 2 only: node1/ball.json: this rank loaded other volume data than rank 0: node1/ball.raw (content hash " mixed.err ||
  fail "no message naming the rank and the file: $(cat mixed.err)"
[[ $(grep -c "^lobe:" mixed.err) -eq 1 ]] || fail "more than one line of Lobe's: $(cat mixed.err)"
[[ -z $(ls -A mixed 2>/dev/null) ]] || fail "ranks with different data wrote: $(ls -A mixed)"
cp node0/ball.raw node1/ball.raw
"${mpi[@]}" -n 2 "${per_rank[@]}" "$lobe" same || fail "ranks with the same data failed"
if "${mpi[@]}" -n 3 "${per_rank[@]}" "$lobe" lost 2>lost.err; then
  fail "a volume missing on rank 2 left exit status 0"
fi
grep -q "^lobe: error: on rank 2 of 3 only: node2/ball.json: .*ball.raw" lost.err ||
  fail "a file missing on one rank is not named by rank: $(cat lost.err)"
echo "mpi test: ok"
