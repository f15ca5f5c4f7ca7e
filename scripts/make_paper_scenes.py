#!/usr/bin/env python3
"""Writes the scene files of the paper's 24 renderings (Koldenhof 2003, Tables 2-5) and a zoomed
close-up of each into assets/scenes/paper/ and assets/scenes/paper-zoom/, and the skull alone with
each of the nine specular BRDFs (the scene of the paper's Table 7) into assets/scenes/skull/.

The mapping of the paper's scene onto our data is docs/paper-scene.md ("A placement that
works"): world = CThead voxel index x spacing (1, 1, 2); MNI millimetres map into it by
diag(0.87, -0.87, -0.87) . mni + (102, 127.6, 85). The camera sits 560 units from the skull's
centre (110, 131, 116) at 45 degrees azimuth from straight-front (front = -y), up = -z, with a 30
degree vertical field of view; four point lights sit at the camera +-60 units along its right and
up axes ("four omni lights ... behind the camera in each corner").

Settings (docs/separation.md says why and measures them): the 2003 reading used until this
version ("before": lights 60 units off the camera, highlights tinted by the object's colour, the
density maps one DVR object, colour backdrop, clipped display) and the current one ("after":
lights behind the camera towards the corners of the view at the objects' depth, highlights in
the light's colour, each density map its own iso-surface with the paper's per-crossing opacity,
a grey backdrop, a shoulder tone curve).

Run from the repository root:  python3 scripts/make_paper_scenes.py
Write the earlier reading elsewhere (for before/after measurements):
    python3 scripts/make_paper_scenes.py --before DIR
"""
import argparse
import json
import math
import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# Tables 2-5: (CThead, cortex, density maps) per rendering.
A = [("ward", "ashikhmin_shirley", "he_torrance"), ("ward", "he_torrance", "ashikhmin_shirley"),
     ("ashikhmin_shirley", "ward", "he_torrance"), ("ashikhmin_shirley", "he_torrance", "ward"),
     ("he_torrance", "ward", "ashikhmin_shirley"), ("he_torrance", "ashikhmin_shirley", "ward")]
B = [("cook_torrance", "schlick_lewis", "phong"), ("cook_torrance", "phong", "schlick_lewis"),
     ("schlick_lewis", "cook_torrance", "phong"), ("schlick_lewis", "phong", "cook_torrance"),
     ("phong", "schlick_lewis", "cook_torrance"), ("phong", "cook_torrance", "schlick_lewis")]
C = [(m, m, m) for m in ("ward", "ashikhmin_shirley", "he_torrance", "cook_torrance",
                         "schlick_lewis", "phong")]
D = [("ward", "schlick_lewis", "phong"), ("ward", "phong", "schlick_lewis"),
     ("schlick_lewis", "ward", "phong"), ("schlick_lewis", "phong", "ward"),
     ("phong", "ward", "schlick_lewis"), ("phong", "schlick_lewis", "ward")]
RENDERINGS = [("A", c) for c in A] + [("B", c) for c in B] + [("C", c) for c in C] + \
             [("D", c) for c in D]

SHORT = {"ward": "Ward", "ashikhmin_shirley": "Ashikhmin", "he_torrance": "He-Torrance",
         "cook_torrance": "Cook-Torrance", "schlick_lewis": "Schlick-Lewis", "phong": "Phong"}

CENTRE = (110.0, 131.0, 116.0)
DISTANCE = 560.0
AZIMUTH = math.radians(45.0)
UP = (0.0, 0.0, -1.0)
MNI_TO_WORLD = {"scale": [0.87, -0.87, -0.87], "translate": [102.0, 127.6, 85.0]}
LIGHT_INTENSITY = 3.0e5  # irradiance ~1 at the head, 560 units away (I/d^2 = 0.96)


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def unit(a):
    n = math.sqrt(sum(x * x for x in a))
    return tuple(x / n for x in a)


def camera(before=False):
    position = (CENTRE[0] + DISTANCE * math.sin(AZIMUTH), CENTRE[1] - DISTANCE * math.cos(AZIMUTH),
                CENTRE[2])
    forward = unit(sub(CENTRE, position))
    right = unit(cross(forward, UP))
    up = cross(right, forward)
    lights = []
    if before:
        # 2003 reading: the camera +-60 units along its right and up axes (8.6 degrees off axis).
        for sr in (-1, 1):
            for su in (-1, 1):
                p = [position[i] + 60.0 * sr * right[i] + 60.0 * su * up[i] for i in range(3)]
                lights.append({"position": [round(x, 3) for x in p], "intensity": LIGHT_INTENSITY})
        return [round(x, 3) for x in position], lights
    # "Four omni lights ... all behind the camera in each corner": a plane LIGHT_BEHIND units
    # behind the camera, each light at one corner of the view's extent at the objects' depth
    # (half extent DISTANCE tan(fov/2) along right and up), 20 degrees off the view axis; the
    # intensity gives irradiance 1 at the head's centre (I = d^2).
    half = DISTANCE * math.tan(math.radians(FOV_DEG / 2.0))
    for sr in (-1, 1):
        for su in (-1, 1):
            p = [position[i] - LIGHT_BEHIND * forward[i] + half * sr * right[i] + half * su * up[i]
                 for i in range(3)]
            d2 = sum((p[i] - CENTRE[i]) ** 2 for i in range(3))
            lights.append({"position": [round(x, 3) for x in p], "intensity": round(d2, 1)})
    return [round(x, 3) for x in position], lights


def brdf(model):
    return {"model": model}


def scene(number, group, combo, zoom, before=False):
    skull, cortex, density = combo
    position, lights = camera(before)
    cam = {"position": position, "target": list(CENTRE), "up": list(UP), "fov_deg": 30}
    if zoom:
        # The density maps' region, magnified 2.5x: a crop window of the same view (so the
        # backdrop and lighting are those of the full image).
        cam["crop"] = ZOOM_CROP
    objects = [{
        "name": "skull", "kind": "isosurface",
        "source": {"path": "../../cthead/cthead.nhdr", "divide_by": 3272, "background": 100},
        # The close-ups use the level set: it halves the slice terraces that otherwise are the
        # strongest texture over the density maps, and the thin bone it loses is in the face,
        # outside the close-up (docs/performance.md, "The skull without terraces").
        "iso": 0.5, "method": "levelset" if zoom and not before else "exact",
        "opacity": SKULL_OPACITY, "brdf": brdf(skull), "kd": 0.2,
        "tangent_axis": [0, 0, 1]}, {
        "name": "cortex", "kind": "volume",
        "source": {"path": "../../brain/mni_icbm152_t1_tal_nlin_sym_09a_converted.nii.gz",
                   "divide_by": 255},
        "transform": MNI_TO_WORLD, "transfer_function": CORTEX_TF,
        "reconstruction": "bspline", "gradient": "bspline", "brdf": brdf(cortex), "kd": 0.2,
        "tangent_axis": [0, 0, 1]}]
    if before:
        # 2003 reading: the four density maps as one DVR object whose transfer function holds
        # the four ramps (they share one BRDF in every rendering).
        objects.append({
            "name": "density maps", "kind": "volume",
            "source": {"path": "../../brain/grey_icbm151_smooth8mm_FieldMap.nii.gz"},
            "transform": MNI_TO_WORLD,
            "transfer_function": {"preset": "density_maps"},
            "reconstruction": "trilinear", "gradient": "central", "brdf": brdf(density),
            "kd": 0.2, "tangent_axis": [0, 0, 1]})
        for o in objects:
            o["highlight"] = "colour"
    else:
        # Figure 10 calls the maps iso-surfaces with opacities 0.3-0.6: each map its own
        # iso-surface (0.70 / 0.75 / 0.80 / 0.85) with that opacity per crossing, coloured blue /
        # green / yellow / red, so every map shows wherever the data reaches its level (as a DVR
        # ramp the red >= 0.85 map covered 0.1 % of the image).
        for i, (iso, opacity, colour) in enumerate(DENSITY_MAPS):
            objects.append({
                "name": "density map %d" % i, "kind": "isosurface",
                "source": {"path": "../../brain/grey_icbm151_smooth8mm_FieldMap.nii.gz"},
                "transform": MNI_TO_WORLD, "iso": iso, "method": "exact", "opacity": opacity,
                "color": colour, "brdf": brdf(density), "kd": 0.2, "tangent_axis": [0, 0, 1]})
    title = "%d%s: %s / %s / %s" % (number, " zoom" if zoom else "", SHORT[skull], SHORT[cortex],
                                    SHORT[density])
    image = {"width": 1024, "height": 1024, "samples_per_pixel": 8, "seed": 1,
             "exposure": EXPOSURE_BEFORE if before else EXPOSURE}
    backdrop = {"seed": 7, "ambient": 0.2, "diffuse": 0.3}
    if not before:
        image["tone"] = "shoulder"
        backdrop["colours"] = "grey"
    return {
        "title": title, "group": group + ("-zoom" if zoom else ""),
        "image": image, "camera": cam, "lights": lights, "backdrop": backdrop,
        "volume": {"step_voxels": STEP_VOXELS},
        "objects": objects}


SKULL_OPACITY = 0.15
EXPOSURE_BEFORE = 2.0
EXPOSURE = 2.0
FOV_DEG = 30.0
LIGHT_BEHIND = 50.0
# Iso value, opacity per crossing, colour: blue, green, yellow and red as linear sRGB primaries,
# written as the three bands (volume/transfer_function.h linearSrgbToBands, as the DVR preset).
DENSITY_MAPS = [(0.70, 0.3, [0.0, 0.087837, 0.880142]), (0.75, 0.4, [0.240203, 0.818643, 0.103307]),
                (0.80, 0.5, [1.069171, 0.912163, 0.119858]),
                (0.85, 0.6, [0.828969, 0.093519, 0.016551])]
STEP_VOXELS = 0.25
ZOOM_CROP = [0.30, 0.22, 0.70, 0.62]
# The cortex as a translucent shell at the T1 boundary between CSF (~0.30) and grey matter
# (~0.65), 0.47 of the maximum: opacity 0.001 at the edges of the ramp rising to 0.2 at the
# boundary and falling back, so the tissue inside stays clear and the density maps show through.
CORTEX_TF = {"points": [
    {"value": 0.40, "opacity": 0.0, "color": [0.85, 0.72, 0.62]},
    {"value": 0.40, "opacity": 0.001, "color": [0.85, 0.72, 0.62]},
    {"value": 0.47, "opacity": 0.2, "color": [0.85, 0.72, 0.62]},
    {"value": 0.54, "opacity": 0.001, "color": [0.85, 0.72, 0.62]},
    {"value": 0.54, "opacity": 0.0, "color": [0.85, 0.72, 0.62]}]}


SPECULAR = ["phong", "strauss", "schlick_lewis", "ward", "cook_torrance", "poulin_fournier",
            "he_torrance", "lafortune", "ashikhmin_shirley"]


def skull_scene(model):
    """The CThead skull alone, opaque, with one BRDF plus Lambert kd 0.2. Tangent field: the
    head's long axis (object z, vertex to neck) projected onto the surface, world x where the
    surface is perpendicular to it (the top of the skull), so anisotropic highlights run around
    the head like lines of latitude."""
    position, lights = camera()
    return {
        "title": model, "group": "skull",
        "image": {"width": 1024, "height": 1024, "samples_per_pixel": 8, "seed": 1,
                  "exposure": EXPOSURE},
        "camera": {"position": position, "target": list(CENTRE), "up": list(UP), "fov_deg": 30},
        "lights": lights,
        "backdrop": {"seed": 7, "ambient": 0.2, "diffuse": 0.3},
        "objects": [{
            "name": "skull", "kind": "isosurface",
            "source": {"path": "../../cthead/cthead.nhdr", "divide_by": 3272, "background": 100},
            "iso": 0.5, "method": "exact", "opacity": 1.0, "brdf": brdf(model), "kd": 0.2,
            "tangent_axis": [0, 0, 1]}]}


# The paper-shape set (issue 25): the same 24 combinations with the lobes' magnitude controlled —
# every lobe of an object scaled to one albedo at normal incidence (brdf.albedo,
# materials/albedo.h), so the renderings differ by the lobes' shapes only: SHAPE_ALBEDO for the
# cortex and the density maps, SHAPE_SKULL_ALBEDO for the skull; iso-surfaces shaded with the
# B-spline gradient ("normals": "bspline": no facet per 2 mm cell on the density maps); and the
# translucent skull's Lambert term lowered to SHAPE_SKULL_KD so that its many crossings do not
# lay a grey veil over the brain. The skull's lobe is dimmer than the inner objects' because at
# albedo 0.3 its bony detail glitters with sub-pixel glints that change with every sample: two
# seeds of rendering 1 at 256^2 x 2 spp differed by 2.8 grey levels, more than renderings 1 and 2
# (0.8), which differ only inside the skull (docs/separation.md, "The paper-shape set").
SHAPE_ALBEDO = 0.5
SHAPE_SKULL_ALBEDO = 0.05
SHAPE_SKULL_KD = 0.05
# Framing: the full view shows the head on 0.60 x 0.75 of the image (x 0.21-0.82, y 0.13-0.88 at
# 256^2), so most pixels are backdrop that no BRDF changes. The paper-shape full view is the
# square crop window around the head with a margin of about 0.02 (magnified 1.25x: the head
# covers 1.56x the pixels), the camera, lights and backdrop unchanged; the close-ups keep
# ZOOM_CROP of the full view.
SHAPE_CROP = [0.11, 0.11, 0.91, 0.91]


def shape_scene(number, group, combo, zoom):
    sc = scene(number, group, combo, zoom)
    sc["title"] = "%d%s shape: %s" % (number, " zoom" if zoom else "", sc["title"].split(": ", 1)[1])
    sc["group"] = "shape-" + sc["group"]
    for o in sc["objects"]:
        o["brdf"]["albedo"] = SHAPE_SKULL_ALBEDO if o["name"] == "skull" else SHAPE_ALBEDO
        if o["kind"] == "isosurface":
            o["normals"] = "bspline"
        if o["name"] == "skull":
            o["kd"] = SHAPE_SKULL_KD
    if not zoom:
        sc["camera"]["crop"] = SHAPE_CROP
    return sc


def write_before(root):
    """The 24 renderings and close-ups as generated until this version, into root/paper and
    root/paper-zoom, with absolute data paths (into this checkout's assets/)."""
    for folder, zoom in (("paper", False), ("paper-zoom", True)):
        out = os.path.join(root, folder)
        os.makedirs(out, exist_ok=True)
        for number, (group, combo) in enumerate(RENDERINGS, start=1):
            name = "rendering-%02d%s.json" % (number, "-zoom" if zoom else "")
            sc = scene(number, group, combo, zoom, before=True)
            for o in sc["objects"]:
                o["source"]["path"] = os.path.normpath(
                    os.path.join(ROOT, "assets", "scenes", "paper", o["source"]["path"]))
            with open(os.path.join(out, name), "w") as f:
                json.dump(sc, f, indent=1)
                f.write("\n")
    print("wrote 48 scenes (2003 reading) under %s" % root)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--before", metavar="DIR",
                        help="write the earlier reading's 48 scenes under DIR/paper[-zoom] instead")
    args = parser.parse_args()
    if args.before:
        write_before(args.before)
        return
    out = os.path.join(ROOT, "assets", "scenes", "skull")
    os.makedirs(out, exist_ok=True)
    for model in SPECULAR:
        with open(os.path.join(out, "skull-%s.json" % model), "w") as f:
            json.dump(skull_scene(model), f, indent=1)
            f.write("\n")
    for folder, zoom, make in (("paper", False, scene), ("paper-zoom", True, scene),
                               ("paper-shape", False, shape_scene),
                               ("paper-shape-zoom", True, shape_scene)):
        out = os.path.join(ROOT, "assets", "scenes", folder)
        os.makedirs(out, exist_ok=True)
        for number, (group, combo) in enumerate(RENDERINGS, start=1):
            name = "rendering-%02d%s.json" % (number, "-zoom" if zoom else "")
            with open(os.path.join(out, name), "w") as f:
                json.dump(make(number, group, combo, zoom), f, indent=1)
                f.write("\n")
    print("wrote 105 scenes")


if __name__ == "__main__":
    main()
