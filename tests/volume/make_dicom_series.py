#!/usr/bin/python3
"""Writes the DICOM series the DICOM loader tests read (tests/volume/test_dicom.cpp), and for each
good series the same volume as a NIfTI-1 file, from an independent path:

  * synthetic series: the NIfTI is written from the *generating* parameters (the true world
    position of every voxel and its Hounsfield value), not from the DICOM files;
  * pydicom's shipped CT series (Debian python3-pydicom test data): the NIfTI is built from the
    files by pydicom, with the geometry written out here from the standard.

Geometry (DICOM PS3.3 C.7.6.2.1.1): voxel (i = column, j = row) of the slice at
ImagePositionPatient S sits at S + i*dc*X + j*dr*Y (LPS mm), X, Y = ImageOrientationPatient,
(dr, dc) = PixelSpacing. NIfTI's sform is RAS (nifti1.h), so x and y are negated. Values: stored
value * RescaleSlope + RescaleIntercept (C.11.1.1.2). The NIfTI files store the slices in the
opposite order (last slice first), so their affine differs from the DICOM reader's and the tests
compare by world position.

Usage: make_dicom_series.py OUTDIR   (needs only pydicom, no numpy)
"""
import math
import os
import struct
import sys

import pydicom
from pydicom.dataset import FileDataset, FileMetaDataset
from pydicom.uid import ExplicitVRLittleEndian, generate_uid

CT_IMAGE_STORAGE = "1.2.840.10008.5.1.4.1.1.2"


def write_nifti(path, dims, affine, values):
    """NIfTI-1 single file, float32, sform_code 1 with `affine` (3 rows of 4), qform_code 0.
    `values` x fastest. Field offsets from nifti1.h."""
    hdr = bytearray(348)
    struct.pack_into("<i", hdr, 0, 348)
    struct.pack_into("<8h", hdr, 40, 3, dims[0], dims[1], dims[2], 1, 1, 1, 1)
    struct.pack_into("<hh", hdr, 70, 16, 32)  # datatype FLOAT32, bitpix
    pix = [math.sqrt(sum(affine[r][c] ** 2 for r in range(3))) for c in range(3)]
    struct.pack_into("<8f", hdr, 76, 1.0, pix[0], pix[1], pix[2], 1, 1, 1, 1)
    struct.pack_into("<f", hdr, 108, 352.0)  # vox_offset
    struct.pack_into("<ff", hdr, 112, 1.0, 0.0)  # scl_slope, scl_inter
    struct.pack_into("<hh", hdr, 252, 0, 1)  # qform_code, sform_code
    for r in range(3):
        struct.pack_into("<4f", hdr, 280 + 16 * r, *affine[r])
    hdr[344:348] = b"n+1\0"
    with open(path, "wb") as f:
        f.write(hdr)
        f.write(b"\0\0\0\0")
        f.write(struct.pack("<%df" % len(values), *values))


def nifti_reversed_k(dims, lps_origin, x_step, y_step, k_step, hu):
    """The RAS affine and values of a volume stored last slice first: NIfTI index k' = K-1-k."""
    K = dims[2]
    origin = [lps_origin[a] + (K - 1) * k_step[a] for a in range(3)]
    cols = [x_step, y_step, [-v for v in k_step], origin]
    affine = [[(-1 if r < 2 else 1) * cols[c][r] for c in range(4)] for r in range(3)]
    per = dims[0] * dims[1]
    values = []
    for kk in range(K):
        k = K - 1 - kk
        values.extend(hu[k * per:(k + 1) * per])
    return affine, values


def ct_slice(path, series_uid, study_uid, description, position, orientation, spacing, rows, cols,
             stored, slope, intercept, instance, signed=True, transfer_syntax=ExplicitVRLittleEndian,
             pixel_data=None, native_pixel_data=None):
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = CT_IMAGE_STORAGE
    meta.MediaStorageSOPInstanceUID = generate_uid()
    meta.TransferSyntaxUID = transfer_syntax
    ds = FileDataset(path, {}, file_meta=meta, preamble=b"\0" * 128)
    ds.is_little_endian = True
    ds.is_implicit_VR = False
    ds.SOPClassUID = CT_IMAGE_STORAGE
    ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
    ds.Modality = "CT"
    ds.PatientName = "Test^Lobe"
    ds.PatientID = "LOBE-TEST"
    ds.StudyInstanceUID = study_uid
    ds.SeriesInstanceUID = series_uid
    ds.SeriesDescription = description
    ds.SeriesNumber = 1
    ds.InstanceNumber = instance
    ds.ImagePositionPatient = ["%.6f" % v for v in position]
    ds.ImageOrientationPatient = ["%.8f" % v for v in orientation]
    ds.PixelSpacing = ["%.6f" % v for v in spacing]
    ds.SliceThickness = "2.5"
    ds.SamplesPerPixel = 1
    ds.PhotometricInterpretation = "MONOCHROME2"
    ds.Rows = rows
    ds.Columns = cols
    ds.BitsAllocated = 16
    ds.BitsStored = 16
    ds.HighBit = 15
    ds.PixelRepresentation = 1 if signed else 0
    ds.RescaleSlope = "%g" % slope
    ds.RescaleIntercept = "%g" % intercept
    if native_pixel_data is not None:
        ds.PixelData = native_pixel_data
    elif pixel_data is None:
        ds.PixelData = struct.pack("<%d%s" % (len(stored), "h" if signed else "H"), *stored)
    else:
        ds.PixelData = pixel_data
        ds["PixelData"].VR = "OB"
        ds["PixelData"].is_undefined_length = True
    ds.save_as(path, write_like_original=False)


def oblique_orientation():
    """Row and column directions: the axial frame turned 20 degrees about LPS z, then 10 about x."""
    a, b = math.radians(20), math.radians(10)
    rz = [[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]]
    rx = [[1, 0, 0], [0, math.cos(b), -math.sin(b)], [0, math.sin(b), math.cos(b)]]
    m = [[sum(rx[r][t] * rz[t][c] for t in range(3)) for c in range(3)] for r in range(3)]
    row = [m[r][0] for r in range(3)]
    col = [m[r][1] for r in range(3)]
    return row, col


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def synthetic(out):
    """ct/: 5 columns x 4 rows x 6 slices, oblique, PixelSpacing 0.8 (rows) \\ 0.6 (columns),
    slices 2.5 mm apart, int16 with slope 2 and intercept -1024; files named so their order is
    not the slice order; a README that is not DICOM. Also ct.nii from the generating numbers."""
    cols, rows, K = 5, 4, 6
    row_dir, col_dir = oblique_orientation()
    normal = cross(row_dir, col_dir)
    dr, dc, dz = 0.8, 0.6, 2.5
    origin = [-40.0, 25.0, 110.0]  # LPS of voxel (0, 0, 0)
    slope, intercept = 2.0, -1024.0
    folder = os.path.join(out, "ct")
    os.makedirs(folder, exist_ok=True)
    study, series = generate_uid(), generate_uid()
    hu_all = []
    order = [3, 0, 5, 1, 4, 2]  # file n holds slice order[n]
    stored_by_k = {}
    for k in range(K):
        # Stored values from -300 to +1100 or so: negative stored values (signed) and HU from
        # -1624 up; voxel (i, j, k) holds 37 i - 53 j + 211 k - 300 + (i j k mod 7).
        stored = [37 * i - 53 * j + 211 * k - 300 + (i * j * k) % 7 for j in range(rows) for i in range(cols)]
        stored_by_k[k] = stored
        hu_all.extend(v * slope + intercept for v in stored)
    for n, k in enumerate(order):
        pos = [origin[a] + k * dz * normal[a] for a in range(3)]
        ct_slice(os.path.join(folder, "IM%04d" % (n + 1)), series, study, "synthetic oblique CT", pos,
                 row_dir + col_dir, [dr, dc], rows, cols, stored_by_k[k], slope, intercept, n + 1)
    with open(os.path.join(folder, "README.txt"), "w") as f:
        f.write("not a DICOM file: the reader skips it\n")
    x_step = [row_dir[a] * dc for a in range(3)]
    y_step = [col_dir[a] * dr for a in range(3)]
    k_step = [normal[a] * dz for a in range(3)]
    affine, values = nifti_reversed_k([cols, rows, K], origin, x_step, y_step, k_step, hu_all)
    write_nifti(os.path.join(out, "ct.nii"), [cols, rows, K], affine, values)

    # Error series: axial 3x2 slices at the given z positions (LPS), one folder each.
    def axial(name, zs, orientations=None, uid=None, description="axial", start=1):
        folder = os.path.join(out, name)
        os.makedirs(folder, exist_ok=True)
        s_uid = uid or generate_uid()
        for n, z in enumerate(zs):
            o = orientations[n] if orientations else [1, 0, 0, 0, 1, 0]
            ct_slice(os.path.join(folder, "%s_%02d.dcm" % (description.replace(" ", "_"), n + start)),
                     s_uid, study, description, [0.0, 0.0, z], o, [1.0, 1.0], 2, 3,
                     [n] * 6, 1.0, -1024.0, n + 1)
        return s_uid

    axial("gap", [0.0, 2.5, 5.0, 10.0, 12.5])          # the slice at 7.5 is missing
    axial("uneven", [0.0, 2.5, 5.0, 8.0, 10.5])        # 2.5 and 3 mm apart
    axial("duplicate", [0.0, 2.5, 2.5, 5.0])           # two slices at 2.5
    axial("mixed", [0.0, 2.5, 5.0],
          orientations=[[1, 0, 0, 0, 1, 0], [1, 0, 0, 0, 1, 0], [1, 0, 0, 0, 0, -1]])
    a = axial("two_series", [0.0, 2.5, 5.0], uid="1.2.826.0.1.3680043.8.498.1111", description="first series")
    b = axial("two_series", [0.0, 1.0, 2.0, 3.0], uid="1.2.826.0.1.3680043.8.498.2222",
              description="second series")
    assert a and b
    # A series whose pixel data is MPEG-2 video (PS3.5 A.4.5), which GDCM does not decode.
    folder = os.path.join(out, "compressed")
    os.makedirs(folder, exist_ok=True)
    from pydicom.encaps import encapsulate
    ct_slice(os.path.join(folder, "mpeg2.dcm"), generate_uid(), study, "mpeg2", [0, 0, 0],
             [1, 0, 0, 0, 1, 0], [1, 1], 2, 3, None, 1.0, 0.0, 1,
             transfer_syntax="1.2.840.10008.1.2.4.100",
             pixel_data=encapsulate([b"\x00\x00\x01\xb3" + b"\x00" * 12]))


def damaged(out):
    """Series with damaged pixel data, each of 3 axial 64x64 slices whose second file is hurt:
    short_pixels/ (its PixelData element 2 bytes short of Rows x Columns x 2), cut_file/ (the
    file cut 1000 bytes short, as a copy interrupted). good64/ is the same series undamaged (the
    JPEG-lossless damage in tests/volume/test_dicom.cpp starts from it)."""
    study = generate_uid()
    n = 64
    for name in ("good64", "short_pixels", "cut_file"):
        folder = os.path.join(out, name)
        os.makedirs(folder, exist_ok=True)
        series = generate_uid()
        for k in range(3):
            stored = [(7 * i + 13 * j + 101 * k) % 2000 - 1000 for j in range(n) for i in range(n)]
            path = os.path.join(folder, "slice_%02d.dcm" % (k + 1))
            data = None
            if name == "short_pixels" and k == 1:
                data = struct.pack("<%dh" % len(stored), *stored)[:-2]
            ct_slice(path, series, study, name, [0.0, 0.0, 2.5 * k], [1, 0, 0, 0, 1, 0], [1.0, 1.0],
                     n, n, stored, 1.0, 0.0, k + 1, native_pixel_data=data)
            if name == "cut_file" and k == 1:
                with open(path, "rb") as f:
                    whole = f.read()
                with open(path, "wb") as f:
                    f.write(whole[:-1000])


def from_pydicom_files(folder, nifti_path):
    """The NIfTI of a shipped series, built by pydicom from its files (sorted along the normal)."""
    slices = []
    for name in sorted(os.listdir(folder)):
        ds = pydicom.dcmread(os.path.join(folder, name))
        slices.append(ds)
    row = [float(v) for v in slices[0].ImageOrientationPatient[:3]]
    col = [float(v) for v in slices[0].ImageOrientationPatient[3:]]
    normal = cross(row, col)
    slices.sort(key=lambda ds: sum(float(ds.ImagePositionPatient[a]) * normal[a] for a in range(3)))
    rows, cols, K = int(slices[0].Rows), int(slices[0].Columns), len(slices)
    dr, dc = (float(v) for v in slices[0].PixelSpacing)
    first = [float(v) for v in slices[0].ImagePositionPatient]
    last = [float(v) for v in slices[-1].ImagePositionPatient]
    k_step = [(last[a] - first[a]) / (K - 1) for a in range(3)]
    hu = []
    for ds in slices:
        assert ds.BitsAllocated == 16
        fmt = "<%d%s" % (rows * cols, "h" if ds.PixelRepresentation == 1 else "H")
        stored = struct.unpack(fmt, ds.PixelData)
        m, b = float(ds.get("RescaleSlope", 1)), float(ds.get("RescaleIntercept", 0))
        hu.extend(v * m + b for v in stored)
    affine, values = nifti_reversed_k([cols, rows, K], first, [row[a] * dc for a in range(3)],
                                      [col[a] * dr for a in range(3)], k_step, hu)
    write_nifti(nifti_path, [cols, rows, K], affine, values)


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    synthetic(out)
    damaged(out)
    shipped = os.path.join(os.path.dirname(pydicom.__file__), "data", "test_files", "dicomdirtests",
                           "98892001", "CT5N")
    if os.path.isdir(shipped):
        from_pydicom_files(shipped, os.path.join(out, "ct5n.nii"))


if __name__ == "__main__":
    main()
