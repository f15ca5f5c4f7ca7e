#!/usr/bin/python3
"""VTK 9.1 peer (Debian python3-vtk9): T1 skull iso-surface (FlyingEdges3D / MarchingCubes + polydata mapper),
T2 DVR of CThead (vtkFixedPointVolumeRayCastMapper, CPU), T3 hybrid GM DVR + cut-away skull mesh.

Runs under Xvfb (X11 GLX, Mesa llvmpipe); the VTK build has no EGL/OSMesa backend.
Prints one `RESULT {json}` line with the timings (seconds), writes a PNG.  run.sh calls it; by hand:

  DISPLAY=:99 /usr/bin/python3 vtk_peer.py --task t1 --frames 5 --out /tmp/vtk_t1.png
  DISPLAY=:99 /usr/bin/python3 vtk_peer.py --task t2 --sd 0.5 --frames 2 --out /tmp/vtk_t2_sd0.5.png
  DISPLAY=:99 /usr/bin/python3 vtk_peer.py --task t3 --sd 0.5 --gm mni --frames 2 --out /tmp/vtk_t3.png

The VTK side of the comparison in README.md; its data comes through common.py.
"""
import argparse
import json
import os
import statistics
import sys
import time

t_start = time.perf_counter()
import numpy as np  # noqa: E402
import vtk  # noqa: E402
from vtk.util import numpy_support as ns  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

t_import = time.perf_counter() - t_start


def image_from_zyx(a, spacing, origin=(0.0, 0.0, 0.0)):
    """numpy (z, y, x) C-order float32 -> vtkImageData (x fastest)."""
    img = vtk.vtkImageData()
    nz, ny, nx = a.shape
    img.SetDimensions(nx, ny, nz)
    img.SetSpacing(*spacing)
    img.SetOrigin(*origin)
    arr = ns.numpy_to_vtk(np.ascontiguousarray(a).ravel(), deep=True, array_type=vtk.VTK_FLOAT)
    arr.SetName("v")
    img.GetPointData().SetScalars(arr)
    return img


def extract_skull(ct_img, method="flyingedges"):
    t0 = time.perf_counter()
    if method == "flyingedges":
        f = vtk.vtkFlyingEdges3D()
    else:
        f = vtk.vtkMarchingCubes()
    f.SetInputData(ct_img)
    f.SetValue(0, common.ISO)
    f.ComputeNormalsOn()
    f.ComputeGradientsOff()
    f.ComputeScalarsOff()
    f.Update()
    dt = time.perf_counter() - t0
    return f.GetOutput(), dt


def cut_away(poly):
    """keep the half of the skull behind the plane through CENTER facing the camera"""
    eye, fwd, right, up = common.camera_frame()
    plane = vtk.vtkPlane()
    plane.SetOrigin(*common.CENTER)
    plane.SetNormal(*fwd)
    c = vtk.vtkClipPolyData()
    c.SetInputData(poly)
    c.SetClipFunction(plane)
    c.Update()
    return c.GetOutput()


def setup_renderer(res):
    ren = vtk.vtkRenderer()
    ren.SetBackground(0.0, 0.0, 0.0)
    ren.AutomaticLightCreationOff()
    for p in common.light_positions():
        L = vtk.vtkLight()
        L.SetLightTypeToSceneLight()
        L.SetPositional(True)
        L.SetConeAngle(180.0)  # point light
        L.SetPosition(*p)
        L.SetFocalPoint(*common.CENTER)
        L.SetIntensity(0.35)
        L.SetAttenuationValues(1, 0, 0)
        ren.AddLight(L)
    cam = ren.GetActiveCamera()
    cam.SetFocalPoint(*common.CENTER)
    cam.SetPosition(*common.camera_position())
    cam.SetViewUp(*common.VIEW_UP)
    cam.SetViewAngle(common.VIEW_ANGLE)
    cam.SetClippingRange(50.0, 2000.0)
    rw = vtk.vtkRenderWindow()
    rw.SetOffScreenRendering(1)
    rw.SetSize(res, res)
    rw.SetMultiSamples(0)
    rw.AddRenderer(ren)
    return ren, rw, cam


def skull_actor(poly):
    m = vtk.vtkPolyDataMapper()
    m.SetInputData(poly)
    m.ScalarVisibilityOff()
    a = vtk.vtkActor()
    a.SetMapper(m)
    p = a.GetProperty()
    p.SetInterpolationToPhong()
    p.SetColor(0.92, 0.86, 0.74)
    p.SetAmbient(0.1)
    p.SetDiffuse(0.8)
    p.SetSpecular(0.4)
    p.SetSpecularPower(40.0)
    return a


def ct_volume(ct_img, sd):
    otf = vtk.vtkPiecewiseFunction()
    for x, y in common.T2_RAMP:
        otf.AddPoint(x, y)
    ctf = vtk.vtkColorTransferFunction()
    ctf.AddRGBPoint(0.0, 0.0, 0.0, 0.0)
    ctf.AddRGBPoint(0.45, 0.75, 0.55, 0.45)
    ctf.AddRGBPoint(0.6, 1.0, 0.94, 0.84)
    ctf.AddRGBPoint(1.0, 1.0, 1.0, 1.0)
    prop = vtk.vtkVolumeProperty()
    prop.SetScalarOpacity(otf)
    prop.SetColor(ctf)
    prop.SetScalarOpacityUnitDistance(1.0)
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOn()
    prop.SetAmbient(0.15)
    prop.SetDiffuse(0.8)
    prop.SetSpecular(0.3)
    prop.SetSpecularPower(30.0)
    m = vtk.vtkFixedPointVolumeRayCastMapper()
    m.SetInputData(ct_img)
    m.SetAutoAdjustSampleDistances(0)
    m.SetSampleDistance(sd)
    m.SetImageSampleDistance(1.0)
    m.SetInteractiveSampleDistance(sd)
    v = vtk.vtkVolume()
    v.SetMapper(m)
    v.SetProperty(prop)
    return v, m


def gm_volume(which, sd):
    a_xyz, sp, org = common.load_gm(which)
    img = image_from_zyx(np.transpose(a_xyz, (2, 1, 0)), sp, org)
    otf = vtk.vtkPiecewiseFunction()
    ctf = vtk.vtkColorTransferFunction()
    otf.AddPoint(0.0, 0.0)
    hw = common.T3_HALFWIDTH
    for c, op, rgb in common.T3_PEAKS:
        otf.AddPoint(c - hw, 0.0)
        otf.AddPoint(c, op)
        otf.AddPoint(c + hw, 0.0)
        ctf.AddRGBPoint(c - 0.02, *rgb)
        ctf.AddRGBPoint(c + 0.02, *rgb)
    otf.AddPoint(1.0, 0.0)
    prop = vtk.vtkVolumeProperty()
    prop.SetScalarOpacity(otf)
    prop.SetColor(ctf)
    prop.SetScalarOpacityUnitDistance(1.0)
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOn()
    prop.SetAmbient(0.25)
    prop.SetDiffuse(0.75)
    prop.SetSpecular(0.2)
    prop.SetSpecularPower(20.0)
    m = vtk.vtkFixedPointVolumeRayCastMapper()
    m.SetInputData(img)
    m.SetAutoAdjustSampleDistances(0)
    m.SetSampleDistance(sd)
    m.SetImageSampleDistance(1.0)
    m.SetInteractiveSampleDistance(sd)
    m.IntermixIntersectingGeometryOn()
    v = vtk.vtkVolume()
    v.SetMapper(m)
    v.SetProperty(prop)
    mat = vtk.vtkMatrix4x4()
    M = common.mni_to_ct_matrix()
    for i in range(4):
        for j in range(4):
            mat.SetElement(i, j, M[i, j])
    v.SetUserMatrix(mat)
    return v, m, a_xyz.shape


def timed_render(rw):
    t0 = time.perf_counter()
    rw.Render()
    if hasattr(rw, "WaitForCompletion"):
        rw.WaitForCompletion()
    return time.perf_counter() - t0


def save_png(rw, path):
    w2i = vtk.vtkWindowToImageFilter()
    w2i.SetInput(rw)
    w2i.SetInputBufferTypeToRGB()
    w2i.ReadFrontBufferOff()
    w2i.ShouldRerenderOff()
    w2i.Update()
    wr = vtk.vtkPNGWriter()
    wr.SetFileName(path)
    wr.SetInputConnection(w2i.GetOutputPort())
    wr.Write()
    arr = ns.vtk_to_numpy(w2i.GetOutput().GetPointData().GetScalars())
    return float((arr.max(axis=1) > 8).mean())  # fraction of non-black pixels


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--task", choices=["t1", "t2", "t3"], required=True)
    ap.add_argument("--sd", type=float, default=0.5, help="volume sample distance (world units = x voxels)")
    ap.add_argument("--frames", type=int, default=10, help="steady-state frames after the first")
    ap.add_argument("--res", type=int, default=common.RES)
    ap.add_argument("--iso-method", default="flyingedges", choices=["flyingedges", "marchingcubes"])
    ap.add_argument("--gm", default="mni", choices=["mni", "spm"])
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    res = {"peer": "vtk-" + vtk.vtkVersion.GetVTKVersion(), "task": args.task, "res": args.res,
           "t_import": t_import}

    t0 = time.perf_counter()
    ct = common.load_cthead()
    ct_img = image_from_zyx(ct, common.CT_SPACING)
    res["t_load_ct"] = time.perf_counter() - t0

    ren, rw, cam = setup_renderer(args.res)
    if args.task in ("t1", "t3"):
        poly, dt = extract_skull(ct_img, args.iso_method)
        res.update(iso_method=args.iso_method, t_extract=dt, n_tris=poly.GetNumberOfPolys(),
                   n_verts=poly.GetNumberOfPoints())
        if args.task == "t3":
            t0 = time.perf_counter()
            poly = cut_away(poly)
            res["t_cutaway"] = time.perf_counter() - t0
            res["n_tris_cut"] = poly.GetNumberOfPolys()
        ren.AddActor(skull_actor(poly))
    if args.task == "t2":
        v, m = ct_volume(ct_img, args.sd)
        ren.AddVolume(v)
        res["sd"] = args.sd
    if args.task == "t3":
        t0 = time.perf_counter()
        v, m, shp = gm_volume(args.gm, args.sd)
        res.update(t_load_gm=time.perf_counter() - t0, gm=args.gm, gm_shape=list(shp), sd=args.sd)
        ren.AddVolume(v)

    res["t_first"] = timed_render(rw)
    res["nonblack_frac"] = save_png(rw, args.out)
    times = []
    for i in range(args.frames):
        cam.Azimuth(0.25 if i % 2 == 0 else -0.25)  # tiny jitter so every frame is a fresh view
        times.append(timed_render(rw))
    res["t_frames"] = times
    res["t_steady_median"] = statistics.median(times) if times else None
    res["gl_renderer"] = rw.ReportCapabilities().split("OpenGL renderer string:")[1].split("\n")[0].strip() \
        if "OpenGL renderer string:" in rw.ReportCapabilities() else "?"
    res["threads"] = vtk.vtkMultiThreader.GetGlobalDefaultNumberOfThreads()
    res["t_total_in_process"] = time.perf_counter() - t_start
    print("RESULT " + json.dumps(res))


if __name__ == "__main__":
    main()
