#!/usr/bin/python3
"""Inputs that Lobe needs to do the same work as the peers, written to $PEERS_SCRATCH/work/ (default
/tmp/lobe-peers/work; never into the repository).  Also fills the loaders' caches ($PEERS_SCRATCH/cthead_norm.npy,
gm_mni.npz), so that no timed VTK run pays for them:
  gm_mni_blur8.nii.gz  the exact array the VTK/Blender T3 peers render (common.load_gm('mni'): ICBM2009a GM/255,
                       scipy Gaussian 8 mm FWHM on the 1 mm grid), float32, with the original sform (RAS mm)
  cthead_cut.nhdr/.raw.gz  CThead with every voxel on the camera side of the plane through common.CENTER facing the
                       camera set to 0 (air): Lobe has no clip plane, so this is its closest equivalent of the peers'
                       cut-away skull mesh (vtkClipPolyData with the same plane).  Same int16 big-endian layout and
                       spacing 1 1 2 as assets/cthead.
"""
import gzip
import os
import sys

import numpy as np
import nibabel as nib

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import common  # noqa: E402

WORK = os.path.join(common.SCRATCH, "work")
os.makedirs(WORK, exist_ok=True)
if os.path.exists(os.path.join(WORK, "cthead_cut.nhdr")):  # the completion marker goes first, is written last
    os.remove(os.path.join(WORK, "cthead_cut.nhdr"))
common.load_cthead()  # fills the CT cache that vtk_peer.py reads

# --- GM density, identical array to the peers
a, sp, org = common.load_gm("mni")
src = nib.load(common.MNI_GM)
aff = src.get_sform()
assert np.allclose(np.diag(aff)[:3], sp) and np.allclose(aff[:3, 3], org), (aff, sp, org)
img = nib.Nifti1Image(np.asarray(a, dtype=np.float32), aff)
img.set_sform(aff, code=2)
img.set_qform(aff, code=2)
img.header["scl_slope"] = 1.0
img.header["scl_inter"] = 0.0
nib.save(img, os.path.join(WORK, "gm_mni_blur8.nii.gz"))
print("gm", a.shape, float(a.min()), float(a.max()))

# --- cut-away CThead
with gzip.open(common.CT_RAW, "rb") as f:
    raw = np.frombuffer(f.read(), dtype=">i2").reshape(common.CT_SHAPE).copy()  # (z, y, x)
eye, fwd, right, up = common.camera_frame()
z, y, x = np.meshgrid(np.arange(raw.shape[0]) * common.CT_SPACING[2], np.arange(raw.shape[1]) * common.CT_SPACING[1],
                      np.arange(raw.shape[2]) * common.CT_SPACING[0], indexing="ij")
side = (x - common.CENTER[0]) * fwd[0] + (y - common.CENTER[1]) * fwd[1] + (z - common.CENTER[2]) * fwd[2]
cut = side < 0.0  # camera side of the plane: removed (vtkClipPolyData keeps value > 0)
raw[cut] = 0
with gzip.open(os.path.join(WORK, "cthead_cut.raw.gz.tmp"), "wb", compresslevel=1) as f:
    f.write(raw.astype(">i2").tobytes())
os.replace(os.path.join(WORK, "cthead_cut.raw.gz.tmp"), os.path.join(WORK, "cthead_cut.raw.gz"))
with open(os.path.join(WORK, "cthead_cut.nhdr"), "w") as f:  # written last: run.sh takes it as "assets complete"
    f.write("NRRD0004\n# CThead (assets/cthead) with the camera-side half (plane through CENTER facing the camera)"
            " set to 0, written by bench/peers/make_sbs_assets.py\ntype: short\ndimension: 3\nsizes: 256 256 113\n"
            "spacings: 1 1 2\nendian: big\nencoding: gzip\ndata file: cthead_cut.raw.gz\n")
print("cut voxels", int(cut.sum()), "of", cut.size)
