#!/usr/bin/python3
"""Writes Lobe scene files ($PEERS_SCRATCH/scenes/*.json, default /tmp/lobe-peers/scenes) that do the same work as
the VTK peer's tasks (README.md): same camera, 4 point lights, 1024^2, iso value, transfer functions and step size in
world units (x-voxels).  Paths inside the scenes are relative to the scenes/ folder (Lobe resolves them from the scene
file): the CT is the repository's assets/cthead/cthead.nhdr written relative to scenes/; the other two inputs are
make_sbs_assets.py's ../work/ files.

Unit conversions (volume/transfer_function.h, volume/volume_marcher.h, docs/scene-format.md):
- Lobe's transfer-function opacity is per *reference voxel length* l_ref = cbrt(|det J|) (CThead 1x1x2: 2^(1/3) = 1.26
  world units; GM 1 mm grid x 0.87: 0.87).  The peers give opacity per world unit, so alpha_lobe = 1-(1-alpha)^l_ref.
- Lobe's step is in index-space voxels along the ray: dt = step / |J^-1 d|.  The camera looks horizontally (view dir
  has z = 0) so for CThead a step of 1 voxel is 1 world unit at the image centre (0.974 at the top/bottom edge, where
  rays tilt 15 degrees towards the 2-unit z axis); for the GM grid it is 0.87 world units, so step = sd / 0.87.
- Lights: VTK uses intensity 0.35 without fall-off; Lobe's point lights are W/sr with I/d^2 fall-off: 3e5 at ~560 units
  gives irradiance ~1 per light (as Lobe's skull scenes).  Exposure 1, no backdrop (the peers render on black).
- Colours: the peers' display RGB, sRGB-decoded and converted to Lobe's CIE-RGB bands (clamped at 0).
"""
import json
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import common  # noqa: E402

SCENES = os.path.join(common.SCRATCH, "scenes")
os.makedirs(SCENES, exist_ok=True)
# relative to scenes/, computed here so that any scratch folder works (real paths on both sides, so symlinks are safe)
CT = os.path.relpath(os.path.realpath(os.path.join(common.DATA, "cthead", "cthead.nhdr")), os.path.realpath(SCENES))
CT_CUT = "../work/cthead_cut.nhdr"              # make_sbs_assets.py
GM = "../work/gm_mni_blur8.nii.gz"              # make_sbs_assets.py
L_REF_CT = 2.0 ** (1.0 / 3.0)
L_REF_GM = common.MNI_SCALE

# core/spectrum.cpp: bands (CIE RGB) -> XYZ -> Bradford E->D65 -> linear sRGB
CIE2XYZ = np.array([[0.49, 0.31, 0.20], [0.17697, 0.81240, 0.01063], [0.0, 0.01, 0.99]])
XYZ2SRGB = np.array([[3.2404542, -1.5371385, -0.4985314], [-0.9692660, 1.8760108, 0.0415560],
                     [0.0556434, -0.2040259, 1.0572252]])
BRAD = np.array([[0.8951, 0.2664, -0.1614], [-0.7502, 1.7135, 0.0367], [0.0389, -0.0685, 1.0296]])
cone_e, cone_d65 = BRAD @ np.ones(3), BRAD @ np.array([0.95047, 1.0, 1.08883])
ADAPT = np.linalg.inv(BRAD) @ np.diag(cone_d65 / cone_e) @ BRAD
BANDS2SRGB = XYZ2SRGB @ ADAPT @ CIE2XYZ
SRGB2BANDS = np.linalg.inv(BANDS2SRGB)


def bands(rgb_display):
    c = np.asarray(rgb_display, dtype=float)
    lin = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return [round(float(max(0.0, v)), 6) for v in SRGB2BANDS @ lin]


def per_lref(alpha_per_unit, l_ref):
    return round(1.0 - (1.0 - alpha_per_unit) ** l_ref, 6)


def base(title, spp=1, step=None):
    eye = common.camera_position()
    s = {"title": title,
         "image": {"width": common.RES, "height": common.RES, "samples_per_pixel": spp, "seed": 1, "exposure": 1.0},
         "camera": {"position": [round(float(v), 3) for v in eye], "target": [float(v) for v in common.CENTER],
                    "up": [float(v) for v in common.VIEW_UP], "fov_deg": common.VIEW_ANGLE},
         "lights": [{"position": [round(float(v), 3) for v in p], "intensity": 300000.0}
                    for p in common.light_positions()],
         "backdrop": {"enabled": False},
         "objects": []}
    if step is not None:
        s["volume"] = {"step_voxels": step}
    return s


def skull(method="exact", path=CT):
    # VTK: Phong, colour (0.92, 0.86, 0.74), ambient 0.1, diffuse 0.8, specular 0.4, power 40
    return {"name": "skull", "kind": "isosurface",
            "source": {"path": path, "divide_by": common.CT_NORM, "background": 100},
            "iso": common.ISO, "method": method, "opacity": 1.0,
            "brdf": {"model": "phong", "ks": 0.4, "exponent": 40}, "kd": 0.8, "color": bands((0.92, 0.86, 0.74))}


def ct_volume():
    # VTK ct_volume(): opacity per unit length 0 @0.45 -> 0.2 @0.6 -> 0.2 @1; colour 0 black, 0.45 tan, 0.6 ivory, 1 white
    a = per_lref(0.2, L_REF_CT)
    pts = [(0.0, 0.0, (0, 0, 0)), (0.45, 0.0, (0.75, 0.55, 0.45)), (0.6, a, (1.0, 0.94, 0.84)), (1.0, a, (1, 1, 1))]
    return {"name": "ct", "kind": "volume",
            "source": {"path": CT, "divide_by": common.CT_NORM, "background": 100},
            "transfer_function": {"points": [{"value": v, "opacity": o, "color": bands(c)} for v, o, c in pts]},
            "reconstruction": "trilinear", "gradient": "central",
            "brdf": {"model": "phong", "ks": 0.3, "exponent": 30}, "kd": 0.8}


def gm_volume():
    # VTK gm_volume(): 4 triangular peaks (half-width 0.01), colour constant over each peak
    hw = common.T3_HALFWIDTH
    pts = []
    for c, op, rgb in common.T3_PEAKS:
        col = bands(rgb)
        pts += [(c - hw, 0.0, col), (c, per_lref(op, L_REF_GM), col), (c + hw, 0.0, col)]
    s = common.MNI_SCALE
    return {"name": "gm", "kind": "volume", "source": {"path": GM},
            "transform": {"scale": [s, -s, -s], "translate": [float(v) for v in common.MNI_OFFSET]},
            "transfer_function": {"points": [{"value": round(v, 6), "opacity": o, "color": c} for v, o, c in pts]},
            "reconstruction": "trilinear", "gradient": "central",
            "brdf": {"model": "phong", "ks": 0.2, "exponent": 20}, "kd": 0.75}


def write(name, scene):
    with open(os.path.join(SCENES, name + ".json"), "w") as f:
        json.dump(scene, f, indent=1)


s = base("T1 skull exact iso 0.5"); s["objects"] = [skull("exact")]; write("t1_exact", s)
s = base("T1 skull mesh iso 0.5"); s["objects"] = [skull("mesh")]; write("t1_mesh", s)
s = base("T2 CThead DVR", step=1.0); s["objects"] = [ct_volume()]; write("t2_dvr", s)
# T3: GM step sd (world) = 0.87 * step_voxels; the file's default is sd 0.5 -> 0.5/0.87 voxel; --step overrides
s = base("T3 GM peaks + cut skull (volume cut)", step=round(0.5 / L_REF_GM, 6))
s["objects"] = [skull("exact", CT_CUT), gm_volume()]; write("t3_cut", s)
# T3 with the whole CThead cut by a clip plane (core/clip.h) instead of the cut volume: the same plane as
# make_sbs_assets.py's (through CENTER, keeping the side away from the camera), exact rather than per voxel.
_eye, _fwd, _right, _up = common.camera_frame()
_sk = skull("exact")
_sk["clip"] = [{"plane": {"point": [float(v) for v in common.CENTER], "normal": [float(v) for v in _fwd]}}]
s = base("T3 GM peaks + cut skull (clip plane)", step=round(0.5 / L_REF_GM, 6))
s["objects"] = [_sk, gm_volume()]; write("t3_clip", s)
s = base("T3 GM peaks only", step=round(0.5 / L_REF_GM, 6)); s["objects"] = [gm_volume()]; write("t3_gm", s)
print("T2 alpha per l_ref", per_lref(0.2, L_REF_CT), "GM", [per_lref(op, L_REF_GM) for _, op, _ in common.T3_PEAKS])
print("skull colour bands", bands((0.92, 0.86, 0.74)))
print("scenes in", SCENES, "; CT path in them:", CT)
