#!/usr/bin/python3
"""Writes FreeSurfer .mgh/.mgz files with nibabel (an independent implementation of the format)
for tests/volume/test_label_files.cpp, and beside each FILE.txt what nibabel reads from it: the
shape, the 4x4 vox2ras affine (row by row) and every voxel value in x-fastest order.
Usage: make_mgh_files.py OUTPUT_DIR"""
import os
import sys

import nibabel as nib
import numpy as np

out = sys.argv[1]
os.makedirs(out, exist_ok=True)
rng = np.random.default_rng(26)


def write(name, data, affine):
    img = nib.MGHImage(data, affine)
    path = os.path.join(out, name)
    nib.save(img, path)
    back = nib.load(path)  # what nibabel reads: the reference
    values = np.asanyarray(back.dataobj)
    with open(path + ".txt", "w") as f:
        f.write(" ".join(str(s) for s in values.shape) + "\n")
        for row in back.affine:
            f.write(" ".join(repr(float(x)) for x in row) + "\n")
        f.write(" ".join(repr(float(x)) for x in values.flatten(order="F")) + "\n")


# An oblique affine: a rotation about z by 20 degrees, voxels 1.2 x 0.9 x 2.5 mm, an offset.
c, s = np.cos(np.radians(20)), np.sin(np.radians(20))
oblique = np.array([[c * 1.2, -s * 0.9, 0, -30.5],
                    [s * 1.2, c * 0.9, 0, 12.25],
                    [0, 0, 2.5, -7.0],
                    [0, 0, 0, 1]])
labels = rng.integers(0, 40, size=(7, 5, 6)).astype(np.int32)
write("labels.mgz", labels, oblique)
write("labels_uint8.mgh", labels.astype(np.uint8), np.diag([-1.0, 1.0, 1.0, 1.0]))
write("short.mgz", (labels * 100 - 900).astype(np.int16), oblique)
write("float.mgz", rng.normal(size=(4, 6, 5)).astype(np.float32), oblique)
