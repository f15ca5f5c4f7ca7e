#!/usr/bin/python3
"""Shadow cost and the cache's error (docs/performance.md, "Shadows, clipping and masks").

Usage: bench/shadow_timing.py LOBE OUTDIR [--rounds 2] [--width 256] [--spp 4] [--scene PATH]...

Writes copies of each scene (default: rendering 1 and its close-up) with "shadows" set to off,
cached (surface shadows from the cache, the default), cachedN (the same at "cache_voxels" N),
cached-sharp ("surfaces": "exact") and exact (--modes chooses), renders them ALTERNATELY round after round (a shared machine: the configurations see the
same load), and prints CPU seconds (user + system, from os.wait4) per render, the ratio to off,
and each cached variant's error against the exact render: mean |cached − exact| over the linear
EXR bands as a fraction of the shadows' own effect mean |exact − off|, and of the mean radiance.
"""
import argparse, json, os, subprocess, sys
import numpy as np
import OpenImageIO as oiio

MODES = {"off": "off", "exact": "exact", "cached": "cached",
         "cached-sharp": {"mode": "cached", "surfaces": "exact"}}
for n in (1, 2, 4, 8):  # cachedN: the cache at cache_voxels N
    MODES[f"cached{n}"] = {"mode": "cached", "cache_voxels": n}

def scene_copy(path, mode, out):
    s = json.load(open(path))
    base = os.path.dirname(os.path.abspath(path))
    for o in s["objects"]:
        for src in (o.get("source"), (o.get("mask") or {}).get("source")):
            if src and "path" in src:
                src["path"] = os.path.normpath(os.path.join(base, src["path"]))
    s["shadows"] = MODES[mode]
    name = os.path.splitext(os.path.basename(path))[0] + "-" + mode
    p = os.path.join(out, name + ".json")
    json.dump(s, open(p, "w"), indent=1)
    return name, p

def cpu_run(cmd):
    pid = os.fork()
    if pid == 0:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, 1)
        os.execv(cmd[0], cmd)
    _, status, ru = os.wait4(pid, 0)
    if status != 0:
        sys.exit(f"failed: {' '.join(cmd)}")
    return ru.ru_utime + ru.ru_stime

def load(p):
    return oiio.ImageBuf(p).get_pixels(oiio.FLOAT)[..., :3].astype(np.float64)

def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("lobe"); ap.add_argument("out")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--width", type=int, default=256)
    ap.add_argument("--spp", type=int, default=4)
    ap.add_argument("--modes", default="off,cached,cached-sharp,exact")
    ap.add_argument("--scene", action="append")
    a = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    scenes = a.scene or [os.path.join(root, "assets/scenes/paper/rendering-01.json"),
                         os.path.join(root, "assets/scenes/paper-zoom/rendering-01-zoom.json")]
    modes = a.modes.split(",")
    os.makedirs(a.out, exist_ok=True)
    times = {}
    for r in range(a.rounds):
        for sc in scenes:
            for m in modes:
                name, p = scene_copy(sc, m, a.out)
                d = os.path.join(a.out, f"r{r}")
                t = cpu_run([a.lobe, "render", p, "--width", str(a.width), "--spp", str(a.spp),
                             "--no-contact-sheets", "--quiet", "--out", d])
                times.setdefault((sc, m), []).append(t)
                print(f"round {r} {name}: {t:.2f} CPU s", flush=True)
    for sc in scenes:
        stem = os.path.splitext(os.path.basename(sc))[0]
        print(f"\n{stem}, {a.width} px, {a.spp} spp")
        off = times.get((sc, "off"))
        for m in modes:
            t = times[(sc, m)]
            ratio = f"{np.mean(t) / np.mean(off):.2f}x off" if off else ""
            print(f"  {m:13s} " + " ".join(f"{x:6.2f}" for x in t) + f"  {ratio}")
        if "exact" in modes and "off" in modes:
            d = os.path.join(a.out, "r0")
            ex, of = load(f"{d}/{stem}-exact.exr"), load(f"{d}/{stem}-off.exr")
            effect = np.abs(ex - of).mean()
            print(f"  shadows' effect mean |exact - off| = {effect:.4g} (mean radiance {ex.mean():.4g})")
            for m in modes:
                if not m.startswith("cached"):
                    continue
                c = load(f"{d}/{stem}-{m}.exr")
                e = np.abs(c - ex)
                lum = lambda x: x.mean(axis=2)
                rel = np.abs(lum(c) - lum(ex)) / np.maximum(lum(ex), 1e-3 * lum(ex).max())
                print(f"  {m}: mean |cached - exact| = {e.mean():.4g} = {e.mean() / effect:.3f} of "
                      f"the effect, {e.mean() / ex.mean():.4f} of the radiance; 99th pct rel. "
                      f"luminance error {np.percentile(rel, 99):.3f}, max {e.max():.3g}")

main()
