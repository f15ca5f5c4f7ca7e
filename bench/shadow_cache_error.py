#!/usr/bin/python3
"""Error of the shadow cache against exact shadow rays (docs/performance.md, "Shadows, clipping and
masks"): given the round number r, reads /tmp/r1out-{off,exact,cached2,cached4}-r/r1-*.exr, the
renders of rendering 1 with "shadows" off / exact / cached (cache_voxels 2 and 4) written by
`lobe render r1-MODE.json --out /tmp/r1out-MODE-r`, and prints mean |cached - exact| against the
shadows' own effect mean |exact - off|."""
import sys
import OpenImageIO as oiio, numpy as np
def load(p):
    b = oiio.ImageBuf(p)
    return b.get_pixels(oiio.FLOAT)[..., :3].astype(np.float64)
r = sys.argv[1]
off, exact = load(f"/tmp/r1out-off-{r}/r1-off.exr"), load(f"/tmp/r1out-exact-{r}/r1-exact.exr")
effect = np.abs(exact - off).mean()
print(f"mean |exact - off| (the shadows' effect) = {effect:.4g}, mean exact = {exact.mean():.4g}")
import os
for m in ("cached2", "cached4"):
    if not os.path.exists(f"/tmp/r1out-{m}-{r}/r1-{m}.exr"):
        continue
    c = load(f"/tmp/r1out-{m}-{r}/r1-{m}.exr")
    d = np.abs(c - exact)
    lum = lambda x: x.mean(axis=2)
    rel = np.abs(lum(c) - lum(exact)) / np.maximum(lum(exact), 1e-3 * lum(exact).max())
    print(f"{m}: mean |cached - exact| = {d.mean():.4g} ({d.mean() / effect:.3f} of the effect, "
          f"{d.mean() / exact.mean():.4f} of the mean), 99th pct rel. luminance error {np.percentile(rel, 99):.3f}, "
          f"max abs {d.max():.4g} (max exact {exact.max():.4g})")
