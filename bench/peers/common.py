"""Data loading and scene constants shared by the VTK peer and Lobe's scenes of the comparison (README.md).

All peers use the same world frame: CThead voxel index (x, y, z) * spacing (1, 1, 2), i.e. world units are
"x-voxels" (1 unit = 1 CThead in-plane voxel).  Orientation of CThead (assets/cthead/README.md): row 0 (y=0) is
anterior, slice 1 (z=0) is the top of the head, so superior = -z and anterior = -y.

The MNI/SPM grey-matter map (RAS mm) is placed inside the skull with a fixed similarity transform
MNI_TO_CT (flip y and z, scale, translate), estimated once from the CThead brain-cavity bounding box
(docs/paper-scene.md, "A placement that works").
"""
import gzip
import math
import os
import tempfile

import numpy as np

# this file lives in bench/peers/, the data in the repository's assets/
DATA = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "assets"))
CT_RAW = os.path.join(DATA, "cthead/cthead_256x256x113_int16be.raw.gz")
CT_SHAPE = (113, 256, 256)  # numpy order (z, y, x)
CT_SPACING = (1.0, 1.0, 2.0)  # world spacing for (x, y, z)
CT_NORM = 3272.0
MNI_GM = os.path.join(DATA, "brain/mni_icbm152_gm_tal_nlin_sym_09a_converted.nii.gz")
SPM_GM = os.path.join(DATA, "brain/grey_icbm151_smooth8mm_FieldMap.nii.gz")
# everything generated (caches, work/, scenes/, runs/) goes here, never into the repository (run.sh exports the same default)
SCRATCH = os.environ.get("PEERS_SCRATCH") or os.path.join(tempfile.gettempdir(), "lobe-peers")
os.makedirs(SCRATCH, exist_ok=True)

RES = 1024
ISO = 0.5
# T2 ramp: opacity (per unit length) 0 at <=0.45, 0.2 at >=0.6 (normalised CT)
T2_RAMP = [(0.0, 0.0), (0.45, 0.0), (0.6, 0.2), (1.0, 0.2)]
# T3 peaks: (centre, opacity per unit length, rgb)
T3_PEAKS = [(0.70, 0.3, (0.0, 0.0, 1.0)), (0.75, 0.4, (0.0, 1.0, 0.0)),
            (0.80, 0.5, (1.0, 1.0, 0.0)), (0.85, 0.6, (1.0, 0.0, 0.0))]
T3_HALFWIDTH = 0.01  # triangular peak, zero at centre +- 0.01

# ---------------------------------------------------------------- camera / lights (world units)
CENTER = np.array([110.0, 131.0, 116.0])  # centre of the skull bbox (bone x 28..193, y 25..237, z 8..224)
VIEW_UP = np.array([0.0, 0.0, -1.0])      # superior is -z
VIEW_ANGLE = 30.0                         # vertical field of view, degrees
CAM_DIST = 560.0
AZIMUTH = 45.0                            # 0 = straight from the front (camera at -y)


def camera_position(azimuth=AZIMUTH, dist=CAM_DIST):
    a = math.radians(azimuth)
    d = np.array([math.sin(a), -math.cos(a), 0.0])  # from centre towards camera
    return CENTER + dist * d


def camera_frame():
    eye = camera_position()
    fwd = CENTER - eye
    fwd /= np.linalg.norm(fwd)
    right = np.cross(fwd, VIEW_UP)
    right /= np.linalg.norm(right)
    up = np.cross(right, fwd)
    return eye, fwd, right, up


def light_positions(offset=60.0):
    """4 point lights near the camera: at the camera +- offset along right/up."""
    eye, fwd, right, up = camera_frame()
    return [eye + sx * offset * right + sy * offset * up for sx, sy in ((-1, 1), (1, 1), (-1, -1), (1, -1))]


# ---------------------------------------------------------------- data
def load_cthead():
    """float32 array (z, y, x) normalised by 3272."""
    cache = os.path.join(SCRATCH, "cthead_norm.npy")
    if os.path.exists(cache):
        return np.load(cache)
    with gzip.open(CT_RAW, "rb") as f:
        raw = np.frombuffer(f.read(), dtype=">i2").reshape(CT_SHAPE)
    a = (raw.astype(np.float32) / CT_NORM)
    with open(cache + ".tmp", "wb") as fh:  # write, then rename: a reader never sees half a cache
        np.save(fh, a)
    os.replace(cache + ".tmp", cache)
    return a


def load_gm(which="mni"):
    """Grey-matter probability in RAS order (i=x right, j=y anterior, k=z superior), float32.
    Returns (array[x, y, z], spacing_mm, origin_mm).
    which='mni': ICBM2009a GM/255 blurred with 8 mm FWHM Gaussian (1 mm grid, 197x233x189).
    which='spm': SPM12 FieldMap grey (already 8 mm smoothed, 2 mm grid), x flipped LAS->RAS."""
    import nibabel as nib
    cache = os.path.join(SCRATCH, f"gm_{which}.npz")
    if os.path.exists(cache):
        z = np.load(cache)
        return z["a"], tuple(z["sp"]), tuple(z["org"])
    if which == "mni":
        from scipy.ndimage import gaussian_filter
        img = nib.load(MNI_GM)
        a = np.asarray(img.dataobj).astype(np.float32) / 255.0
        sigma = 8.0 / (2.0 * math.sqrt(2.0 * math.log(2.0)))  # FWHM 8 mm at 1 mm voxels
        a = gaussian_filter(a, sigma).astype(np.float32)
        aff = img.get_sform()
        sp = (1.0, 1.0, 1.0)
        org = tuple(aff[:3, 3])
    else:
        img = nib.load(SPM_GM)
        a = np.asarray(img.get_fdata(dtype=np.float32))  # applies scl_slope
        aff = img.affine
        assert aff[0, 0] < 0
        a = a[::-1, :, :].copy()  # LAS -> RAS
        n = a.shape[0]
        sp = (2.0, 2.0, 2.0)
        org = (aff[0, 3] + aff[0, 0] * (n - 1), aff[1, 3], aff[2, 3])
    a = np.ascontiguousarray(a, dtype=np.float32)
    with open(cache + ".tmp", "wb") as fh:
        np.savez(fh, a=a, sp=np.array(sp), org=np.array(org))
    os.replace(cache + ".tmp", cache)
    return a, sp, org


# MNI (RAS mm) -> CThead world.  CT x ~ MNI x (left/right undocumented), CT y = -MNI y (posterior),
# CT z = -MNI z (inferior).  Scale and offset fitted to the CThead brain cavity
# (once, by fit_mni_to_ct.py of the original peer set; not needed here).
# cavity (slices 10-36): x 37..167, y 64..219; MNI GM>0.2 bbox x -74..74, y -107..75, z -72..82 mm
MNI_SCALE = 0.87
MNI_OFFSET = np.array([102.0, 127.6, 85.0])


def mni_to_ct_matrix(scale=None, offset=None):
    s = MNI_SCALE if scale is None else scale
    t = MNI_OFFSET if offset is None else offset
    m = np.eye(4)
    m[0, 0], m[1, 1], m[2, 2] = s, -s, -s
    m[:3, 3] = t
    return m
