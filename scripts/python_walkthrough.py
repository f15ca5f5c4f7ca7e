#!/usr/bin/python3
"""The walk-through of docs/python.md, run as a script: the same code cells in order, writing the
page's pictures to docs/images/python-*.jpg. From the repository root, after `make`:

    PYTHONPATH=build/python /usr/bin/python3 scripts/python_walkthrough.py
"""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import nibabel as nib  # noqa: E402
import numpy as np  # noqa: E402

import lobe  # noqa: E402

OUT = "docs/images/"


def save(fig, name):
    fig.savefig(OUT + name, dpi=100, bbox_inches="tight", pil_kwargs={"quality": 85})
    plt.close(fig)


# --- cell: load NIfTI images with nibabel ---
t1 = nib.load("assets/brain/mni_icbm152_t1_tal_nlin_sym_09a_converted.nii.gz")
gm = nib.load("assets/brain/grey_icbm151_smooth8mm_FieldMap.nii.gz")
print(t1.shape, gm.shape)

# A mask made in NumPy (here: where the grey-matter map is high), never written to a file.
mask = (gm.get_fdata() > 0.85).astype(np.float32)

# --- cell: a scene as a dict: the JSON of a scene file, with the images in place of paths ---
description = {
    "image": {"width": 320, "height": 320, "samples_per_pixel": 4, "exposure": 2.0},
    "camera": {"fit": {"view": "left", "objects": ["cortex"]}, "fov_deg": 30},
    "lights": {"rig": "paper"},
    "backdrop": {"colours": "grey"},
    "volume": {"step_voxels": 0.5},
    "objects": [
        {"name": "cortex", "kind": "volume",
         "source": {"image": t1, "divide_by": 255, "background": 20},
         "transfer_function": {"preset": "cortex_shell"},
         "brdf": {"model": "ashikhmin_shirley"}},
        {"name": "grey matter", "kind": "isosurface", "source": gm,
         "iso": 0.75, "opacity": 0.5, "color": [1.07, 0.91, 0.12],
         "brdf": {"model": "he_torrance"}},
        {"name": "mask", "kind": "isosurface",
         "source": {"array": mask, "affine": gm.affine, "blur_fwhm_mm": 3},
         "iso": 0.5, "opacity": 0.8, "color": [0.9, 0.1, 0.05],
         "brdf": {"model": "ward", "alpha_x": 0.2, "alpha_y": 0.2}},
    ],
}
scene = lobe.Scene(description)
print(scene.objects)

# --- cell: render and show ---
image = scene.render(progress=lambda done, total: None)
beauty = image["beauty"]  # 320 x 320 x 3 float32, linear: the floats `lobe render` puts in the EXR


def display(linear):
    """Linear sRGB to what a screen shows: clipped to [0, 1], sRGB-encoded (IEC 61966-2-1)."""
    x = np.clip(linear, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)


fig, ax = plt.subplots(figsize=(4, 4))
ax.imshow(display(beauty))
ax.set_axis_off()
save(fig, "python-render.jpg")

# --- cell: change a BRDF and compare ---
changed = scene.to_dict()
changed["objects"][1]["brdf"] = {"model": "phong", "exponent": 40}
phong = lobe.Scene(changed).render()["beauty"]

fig, axes = plt.subplots(1, 2, figsize=(8, 4))
for ax, img, title in zip(axes, [beauty, phong], ["grey matter: He-Torrance", "grey matter: Phong exponent 40"]):
    ax.imshow(display(img))
    ax.set_title(title)
    ax.set_axis_off()
save(fig, "python-brdf.jpg")

# --- cell: per-object passes ---
passes = scene.render(aov=["objects"], width=200)
fig, axes = plt.subplots(1, 3, figsize=(9, 3.2))
for ax, name in zip(axes, scene.objects):
    ax.imshow(display(4 * passes[name + ".specular"]))
    ax.set_title(name + ": specular x 4")
    ax.set_axis_off()
save(fig, "python-passes.jpg")

# --- cell: separation score and BRDF assignment ---
print(scene.separation(width=200)["score"])
result = lobe.assign(scene, keep=["cortex"])
print(result["ranked"][0])
assigned = scene.to_dict()
for o in assigned["objects"]:
    if o["name"] in result["best"]:
        o["brdf"] = result["best"][o["name"]]
best = lobe.Scene(assigned).render()["beauty"]
fig, axes = plt.subplots(1, 2, figsize=(8, 4))
labels = ", ".join("%s: %s" % kv for kv in result["ranked"][0]["brdfs"].items() if kv[0] != "cortex")
for ax, img, title in zip(axes, [beauty, best], ["as given", "assigned (" + labels + ")"]):
    ax.imshow(display(img))
    ax.set_title(title, fontsize=8)
    ax.set_axis_off()
save(fig, "python-assign.jpg")

# --- cell: the BRDFs themselves ---
theta = np.radians(np.linspace(-89, 89, 357))
wo = np.stack([np.sin(theta), np.zeros_like(theta), np.cos(theta)], axis=-1)
wi = [np.sin(np.radians(45)), 0.0, np.cos(np.radians(45))]
fig, ax = plt.subplots(figsize=(5, 3.2))
for model, params in [("phong", {"exponent": 40}), ("ward", {"alpha_x": 0.2, "alpha_y": 0.2}),
                      ("he_torrance", {})]:
    f = lobe.brdf.eval(model, params, wi, wo)  # (357, 3): the three bands
    ax.plot(np.degrees(theta), f[:, 1] * np.cos(theta), label=model)
ax.set_xlabel("outgoing angle (deg); light at +45 in the same plane")
ax.set_ylabel("f_s cos(theta_o), 546.1 nm")
ax.legend()
save(fig, "python-lobes.jpg")
