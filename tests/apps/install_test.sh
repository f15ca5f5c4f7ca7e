#!/usr/bin/env bash
# Installs the build into a fresh prefix and runs the installed `lobe demo` from an unrelated
# working directory: the binary must find its data relative to itself (apps/data_dir.h) and carry
# no build-tree path. Then the README's paper scene from the installed assets (the scenes' relative
# data paths must hold there), the user guide installed beside it (README.md, docs/), and the
# Python module imported from the prefix.
# Usage: install_test.sh CMAKE BUILD_DIR WORK_DIR
set -euo pipefail
cmake_bin=$1 build=$2 work=$3
rm -rf "$work"
mkdir -p "$work/elsewhere"
"$cmake_bin" --install "$build" --prefix "$work/prefix" >/dev/null
test -x "$work/prefix/bin/lobe"
test -f "$work/prefix/share/lobe/assets/scenes/paper/rendering-01.json"
if strings "$work/prefix/bin/lobe" | grep -F -q "$build"; then
  echo "the installed binary contains the build path $build" >&2
  exit 1
fi
cd "$work/elsewhere"
"$work/prefix/bin/lobe" demo --size 16 --spp 1 --quiet --out out
for f in rendering-01.png rendering-01.exr gallery.png gallery.exr; do
  test -s "out/$f" || { echo "missing out/$f" >&2; exit 1; }
done
"$work/prefix/bin/lobe" render "$work/prefix/share/lobe/assets/scenes/paper/rendering-01.json" \
  --width 16 --spp 1 --no-contact-sheets --out paper >/dev/null 2>&1
test -s paper/rendering-01.png || { echo "the installed paper scene did not render" >&2; exit 1; }
for f in README.md docs/models.md docs/architecture.md docs/scene-format.md docs/images/gallery.jpg; do
  test -s "$work/prefix/share/doc/lobe/$f" || { echo "not installed: share/doc/lobe/$f" >&2; exit 1; }
done
# The Python module, when it was built: importable from the prefix's Python path as docs/python.md
# sets it, from this unrelated folder, by Debian's python3 (the one it was built for).
if compgen -G "$build/python/lobe*.so" >/dev/null; then
  site=$(/usr/bin/python3 -c 'import sys; print("lib/python%d.%d/dist-packages" % sys.version_info[:2])')
  compgen -G "$work/prefix/$site/lobe*.so" >/dev/null || { echo "not installed: $site/lobe*.so" >&2; exit 1; }
  PYTHONPATH="$work/prefix/$site" /usr/bin/python3 -c "import lobe, lobe.brdf; assert lobe.__file__.startswith('$work/prefix/'), lobe.__file__; lobe.brdf.models()"
fi
echo "install test: ok"
