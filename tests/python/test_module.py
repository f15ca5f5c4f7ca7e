"""The Python module `lobe` (python/lobe_module.cpp, docs/python.md) against the command line and
against files: its render is the CLI's EXR bit for bit; a volume from a NumPy array or a nibabel
image renders as the same volume read from a NIfTI file; errors name the key path; Ctrl-C stops a
render within a second; lobe.brdf.eval is `lobe brdf eval`.

Run with Debian's python3 (numpy, nibabel, OpenImageIO) and the module on PYTHONPATH:
    LOBE_EXE=build/apps/lobe PYTHONPATH=build/python /usr/bin/python3 -m unittest test_module
"""
import json
import os
import signal
import subprocess
import sys
import tempfile
import textwrap
import time
import unittest

import nibabel as nib
import numpy as np
import OpenImageIO as oiio

import lobe

LOBE = os.environ["LOBE_EXE"]

# A small synthetic head: a noisy ball (iso-surface) around a denser core (volume), on a 2 mm
# grid with its origin off the centre and the x axis flipped, as an oblique NIfTI affine might be.
AFFINE = np.array([[-2.0, 0.0, 0.0, 31.0],
                   [0.0, 2.0, 0.0, -33.0],
                   [0.0, 0.0, 2.5, -40.0],
                   [0.0, 0.0, 0.0, 1.0]])


def ball(shape=(32, 34, 30), seed=3):
    rng = np.random.default_rng(seed)
    i, j, k = np.meshgrid(*[np.linspace(-1, 1, n) for n in shape], indexing="ij")
    r = np.sqrt(i * i + j * j + k * k)
    return (np.clip(1.2 - r, 0, None) + 0.05 * rng.random(shape)).astype(np.float32)


def core(shape=(32, 34, 30)):
    """int16 values (a CT's type) for the volume object."""
    i, j, k = np.meshgrid(*[np.linspace(-1, 1, n) for n in shape], indexing="ij")
    return (1000 * np.clip(0.7 - np.sqrt(i * i + 1.5 * j * j + k * k), 0, None)).astype(np.int16)


def scene_dict(ball_source, core_source, background="backdrop"):
    return {
        "title": "synthetic",
        "image": {"width": 48, "height": 40, "samples_per_pixel": 2, "seed": 9, "exposure": 1.5},
        "camera": {"position": [40.0, -190.0, 60.0], "target": [0.0, 0.0, 0.0], "up": [0, 0, 1],
                   "fov_deg": 30},
        "lights": [{"position": [120.0, -200.0, 150.0], "intensity": 60000.0},
                   {"position": [-150.0, -180.0, -40.0], "intensity": 30000.0}],
        "background": background,
        "volume": {"step_voxels": 0.5},
        "objects": [
            {"name": "shell", "kind": "isosurface", "source": ball_source, "iso": 0.45,
             "opacity": 0.5, "brdf": {"model": "ward", "alpha_x": 0.2, "alpha_y": 0.3}},
            {"name": "core", "kind": "volume", "source": core_source,
             "transfer_function": {"points": [
                 {"value": 0.1, "opacity": 0.0, "color": [0.9, 0.6, 0.5]},
                 {"value": 0.4, "opacity": 0.3, "color": [0.9, 0.6, 0.5]}]},
             "brdf": {"model": "cook_torrance"}},
        ],
    }


def bits(a):
    """The float32 bit patterns, for comparisons without tolerance (and NaN-safe)."""
    return np.ascontiguousarray(a, dtype=np.float32).view(np.uint32)


def read_exr(path):
    image = oiio.ImageBuf(path)
    spec = image.spec()
    pixels = image.get_pixels(oiio.FLOAT)
    return {name: pixels[:, :, c] for c, name in enumerate(spec.channelnames)}


class Files(unittest.TestCase):
    """The synthetic volumes as NIfTI files in a temporary folder."""

    def setUp(self):
        self.dir = tempfile.TemporaryDirectory(prefix="lobe-python-")
        self.tmp = self.dir.name
        self.ball = ball()
        self.core = core()
        self.ball_path = os.path.join(self.tmp, "ball.nii.gz")
        self.core_path = os.path.join(self.tmp, "core.nii")
        nib.save(nib.Nifti1Image(self.ball, AFFINE), self.ball_path)
        # The core with a file scaling, as scanners write it: stored int16, value = raw * 0.5 + 10
        # (written by hand: nibabel chooses its own scaling when it saves an image).
        header = nib.Nifti1Header()
        header.set_data_shape(self.core.shape)
        header.set_data_dtype(np.int16)
        header.set_sform(AFFINE, code=1)
        header.set_qform(AFFINE, code=1)
        header.set_slope_inter(0.5, 10.0)
        header["vox_offset"] = 352
        with open(self.core_path, "wb") as f:
            header.write_to(f)
            f.write(b"\0" * (352 - f.tell()))
            f.write(self.core.tobytes(order="F"))

    def tearDown(self):
        self.dir.cleanup()

    def file_sources(self):
        return ({"path": self.ball_path},
                {"path": self.core_path, "divide_by": 500, "background": 10})

    def write_scene(self, name, scene):
        path = os.path.join(self.tmp, name + ".json")
        with open(path, "w", encoding="utf-8") as f:
            json.dump(scene, f)
        return path


class RenderEqualsCli(Files):
    def test_beauty_alpha_and_passes_equal_the_exr(self):
        for background in ["backdrop", "none", "#336699"]:
            with self.subTest(background=background):
                path = self.write_scene("scene-" + background.strip("#"),
                                        scene_dict(*self.file_sources(), background=background))
                out = os.path.join(self.tmp, "out")
                subprocess.run([LOBE, "render", path, "--width", "37", "--spp", "3", "--seed", "4",
                                "--aov", "objects,depth,id", "--out", out, "--quiet",
                                "--threads", "2"], check=True)
                exr = read_exr(os.path.join(out, os.path.basename(path)[:-5] + ".exr"))
                result = lobe.Scene.from_file(path).render(
                    width=37, spp=3, seed=4, aov=["objects", "depth", "id"], threads=1)
                beauty = result["beauty"]
                self.assertEqual(beauty.dtype, np.float32)
                self.assertEqual(beauty.shape, (31, 37, 3))  # 37 wide keeps the 48 x 40 aspect
                self.assertGreater(float(beauty.max()), 0.0)
                rgb = np.stack([exr["R"], exr["G"], exr["B"]], axis=-1)
                np.testing.assert_array_equal(bits(beauty), bits(rgb))
                if background == "none":
                    np.testing.assert_array_equal(bits(result["alpha"]), bits(exr["A"]))
                    self.assertGreater(float(result["alpha"].max()), 0.5)
                else:
                    self.assertNotIn("alpha", result)
                for layer in ["shell.lambert", "shell.specular", "core.lambert", "core.specular"]:
                    channels = np.stack([exr[layer + "." + c] for c in "RGB"], axis=-1)
                    np.testing.assert_array_equal(bits(result[layer]), bits(channels))
                np.testing.assert_array_equal(bits(result["depth"]), bits(exr["depth.Z"]))
                np.testing.assert_array_equal(bits(result["id"]), bits(exr["object.id"]))

    def test_progress_callback_counts_every_pixel(self):
        calls = []
        scene = lobe.Scene(scene_dict(*self.file_sources()))
        scene.render(width=20, spp=1, progress=lambda done, total: calls.append((done, total)))
        self.assertTrue(calls)
        self.assertEqual(calls[-1], (20 * 17, 20 * 17))
        self.assertEqual([c for c in calls if c[0] > c[1]], [])

    def test_an_exception_in_the_progress_callback_stops_the_render(self):
        scene = lobe.Scene(scene_dict(*self.file_sources()))
        seen = []

        def progress(done, total):
            seen.append(done)
            raise RuntimeError("enough")

        with self.assertRaisesRegex(RuntimeError, "enough"):
            scene.render(width=1024, spp=64, progress=progress)
        self.assertEqual(len(seen), 1)  # called once, then the render stopped

    def test_passes_are_keyed_by_object_name_and_add_up(self):
        d = scene_dict(*self.file_sources())
        d["objects"][0]["name"] = d["objects"][1]["name"] = "outer shell"
        r = lobe.Scene(d).render(width=24, spp=1, aov="objects,backdrop")
        self.assertEqual(sorted(r), ["backdrop", "beauty", "outer shell.lambert",
                                     "outer shell.specular", "outer_shell_2.lambert",
                                     "outer_shell_2.specular"])
        total = sum(v for k, v in r.items() if k != "beauty").astype(np.float64)
        np.testing.assert_allclose(total, r["beauty"], rtol=1e-5, atol=1e-6)

    def test_separation_equals_the_cli(self):
        path = self.write_scene("sep", scene_dict(*self.file_sources()))
        out = os.path.join(self.tmp, "separation")
        subprocess.run([LOBE, "separation", path, "--width", "40", "--spp", "2", "--out", out,
                        "--quiet"], check=True)
        with open(os.path.join(out, "separation.csv"), encoding="utf-8") as f:
            cli_score = f.read().splitlines()[1].split(",")[1]
        report = lobe.Scene.from_file(path).separation(width=40, spp=2)
        self.assertEqual("%.6g" % report["score"], cli_score)
        self.assertEqual([o["name"] for o in report["objects"]], ["shell", "core"])

    def test_assign_equals_the_cli(self):
        path = self.write_scene("assign", scene_dict(*self.file_sources()))
        best_path = os.path.join(self.tmp, "best.json")
        subprocess.run([LOBE, "assign", path, "--out", best_path, "--width", "32", "--quiet",
                        "--exclude", "he_torrance"], check=True)
        with open(best_path, encoding="utf-8") as f:
            cli = json.load(f)
        with open(os.path.join(self.tmp, "best-assign.md"), encoding="utf-8") as f:
            report = f.read()
        result = lobe.assign(lobe.Scene.from_file(path), width=32, exclude=["he_torrance"])
        self.assertEqual(result["best"]["shell"], cli["objects"][0]["brdf"])
        self.assertEqual(result["best"]["core"], cli["objects"][1]["brdf"])
        # The same candidates not offered, by both rules (specks; glints between two seeds).
        lines = report.split("Not offered", 1)[1].split("\n\n", 1)[0] if "Not offered" in report \
            else ""
        self.assertEqual(sorted(result["not_offered"]),
                         sorted(line[2:] for line in lines.splitlines() if line.startswith("- ")))
        self.assertTrue(result["exhaustive"])
        # The scene's own models may be among the sparkle rule's exclusions (at 32 pixels wide
        # highlights are specks); the best ranks above the scene's own only when they are not.
        own = {o["name"]: o["brdf"]["model"] for o in scene_dict(*self.file_sources())["objects"]}
        if not any(line.startswith("%s: %s " % item) for item in own.items()
                   for line in result["not_offered"]):
            self.assertGreaterEqual(result["ranked"][0]["score"], result["current_score"])


class Arrays(Files):
    """Volumes from memory render as the same volumes read from the NIfTI files."""

    def render(self, ball_source, core_source):
        return lobe.Scene(scene_dict(ball_source, core_source)).render(spp=2)["beauty"]

    def test_numpy_arrays_equal_the_nifti_files(self):
        reference = self.render(*self.file_sources())
        self.assertGreater(float(reference.max()), 0.0)
        raw_core = {"array": self.core, "affine": AFFINE, "divide_by": 500, "background": 10}
        # The file's scaling applied by NumPy in double, as the NIfTI reader applies it.
        scaled = self.core.astype(np.float64) * 0.5 + 10.0
        cases = {
            "float32 and float64": ({"array": self.ball, "affine": AFFINE},
                                    dict(raw_core, array=scaled)),
            "Fortran order": ({"array": np.asfortranarray(self.ball), "affine": AFFINE.tolist()},
                              dict(raw_core, array=np.asfortranarray(scaled))),
            "a strided view, int64": ({"array": np.repeat(self.ball, 2, axis=1)[:, ::2, :],
                                       "affine": AFFINE},
                                      dict(raw_core, array=self.core.astype(np.int64) + 20,
                                           divide_by=1000, background=20)),
            "4-D with one volume": ({"array": self.ball[..., None], "affine": AFFINE},
                                    dict(raw_core, array=scaled[..., None])),
        }
        for name, (b, c) in cases.items():
            with self.subTest(name):
                np.testing.assert_array_equal(bits(self.render(b, c)), bits(reference))

    def test_nibabel_images_equal_the_nifti_files(self):
        reference = self.render(*self.file_sources())
        loaded_ball, loaded_core = nib.load(self.ball_path), nib.load(self.core_path)
        self.assertEqual(loaded_core.dataobj.slope, 0.5)  # the proxy's scaling is applied by Lobe
        cases = {
            "loaded images": (loaded_ball, {"image": loaded_core, "divide_by": 500, "background": 10}),
            "images in memory": (nib.Nifti1Image(self.ball, AFFINE),
                                 {"image": nib.Nifti1Image(self.core.astype(np.float64) * 0.5 + 10.0,
                                                           AFFINE),
                                  "divide_by": 500, "background": 10}),
        }
        for name, (b, c) in cases.items():
            with self.subTest(name):
                np.testing.assert_array_equal(bits(self.render(b, c)), bits(reference))

    def test_divide_by_and_blur_apply_to_arrays(self):
        blurred_file = self.render({"path": self.ball_path, "blur_fwhm_mm": 4.0, "divide_by": "max"},
                                   self.file_sources()[1])
        blurred_array = self.render({"array": self.ball, "affine": AFFINE, "blur_fwhm_mm": 4.0,
                                     "divide_by": "max"}, self.file_sources()[1])
        np.testing.assert_array_equal(bits(blurred_array), bits(blurred_file))
        plain = self.render(*self.file_sources())
        self.assertFalse(np.array_equal(bits(blurred_file), bits(plain)))

    def test_no_file_is_written(self):
        before = set(os.listdir(self.tmp))
        cwd = os.getcwd()
        os.chdir(self.tmp)
        try:
            self.render({"array": self.ball, "affine": AFFINE}, {"array": self.core, "divide_by": 500})
        finally:
            os.chdir(cwd)
        self.assertEqual(set(os.listdir(self.tmp)), before)

    def test_to_dict_gives_the_arrays_back(self):
        scene = lobe.Scene(scene_dict({"array": self.ball, "affine": AFFINE}, self.file_sources()[1]))
        d = scene.to_dict()
        self.assertIs(d["objects"][0]["source"]["array"], self.ball)
        self.assertEqual(d["objects"][1]["source"]["path"], os.path.abspath(self.core_path))
        d["objects"][0]["brdf"] = {"model": "phong", "exponent": 20}
        changed = lobe.Scene(d).render(spp=1)["beauty"]
        self.assertFalse(np.array_equal(bits(changed), bits(scene.render(spp=1)["beauty"])))


def label_map(shape=(30, 32, 28)):
    """A segmentation (int16, as atlases store it): a ball (1), a box (2) and a small ball (5)."""
    i, j, k = np.meshgrid(*[np.arange(n) for n in shape], indexing="ij")
    labels = np.zeros(shape, np.int16)
    labels[(i - 10) ** 2 + (j - 14) ** 2 + (k - 14) ** 2 <= 36] = 1
    labels[18:26, 8:24, 6:20] = 2
    labels[(i - 12) ** 2 + (j - 26) ** 2 + (k - 8) ** 2 <= 9] = 5
    return labels


LABEL_TABLE = {1: "Hippocampus_L", 2: {"name": "Putamen_R", "color": "#ff8800"}, 5: "Vermis"}


def segmentation_scene(source):
    return {
        "image": {"width": 40, "height": 36, "samples_per_pixel": 2, "seed": 4},
        "camera": {"position": [30.0, -150.0, 50.0], "target": [0.0, 0.0, 0.0], "up": [0, 0, 1],
                   "fov_deg": 30},
        "lights": [{"position": [100.0, -160.0, 120.0], "intensity": 50000.0}],
        "objects": [
            {"name": "seg", "kind": "segmentation", "source": source,
             "labels": ["Hippocampus_L", "Putamen_R"], "brdf": {"model": "phong"},
             "overrides": {"Putamen_R": {"brdf": {"model": "ward", "alpha_x": 0.2,
                                                  "alpha_y": 0.2}}}},
            {"name": "vermis", "kind": "isosurface", "source": dict(source, labels=["Vermis"]),
             "brdf": {"model": "lambert"}, "color": [0.3, 0.6, 0.9]},
        ],
    }


class LabelMaps(Files):
    """Label maps from memory (an array with its affine, or a nibabel image) with their table in
    memory render as the same map read from a NIfTI file."""

    def setUp(self):
        super().setUp()
        self.labels = label_map()
        self.labels_path = os.path.join(self.tmp, "labels.nii.gz")
        nib.save(nib.Nifti1Image(self.labels, AFFINE), self.labels_path)
        # The table as a file too, for the file's scene (JSON keys are strings).
        self.file_table = {str(k): v for k, v in LABEL_TABLE.items()}

    def render(self, source):
        out = lobe.Scene(segmentation_scene(source)).render(spp=2, aov=["alpha"])
        return out["beauty"], out["alpha"]

    def test_array_and_image_render_as_the_nifti_file(self):
        beauty, alpha = self.render({"path": self.labels_path, "label_table": self.file_table})
        self.assertGreater(float(alpha.mean()), 0.05)  # the labels are in the picture
        loaded = nib.load(self.labels_path)
        cases = {
            "array and affine": {"array": self.labels, "affine": AFFINE},
            "array as float64, numpy keys": {"array": self.labels.astype(np.float64),
                                             "affine": AFFINE},
            "nibabel image from the file": {"image": loaded},
        }
        for name, source in cases.items():
            with self.subTest(name):
                table = ({np.int64(k): v for k, v in LABEL_TABLE.items()}
                         if "numpy" in name else LABEL_TABLE)
                b, a = self.render(dict(source, label_table=table))
                np.testing.assert_array_equal(bits(b), bits(beauty))
                np.testing.assert_array_equal(bits(a), bits(alpha))
        # The nibabel image itself as the source (no room for a table: labels by number, so the
        # colours differ; the geometry, hence the alpha, is the file's).
        d = segmentation_scene({"image": loaded})
        d["objects"][0]["source"] = loaded
        d["objects"][0]["labels"] = [1, 2]
        d["objects"][0]["overrides"] = {2: d["objects"][0]["overrides"]["Putamen_R"]}
        d["objects"][1]["source"] = {"image": loaded, "labels": [5]}
        out = lobe.Scene(d).render(spp=2, aov=["alpha"])
        np.testing.assert_array_equal(bits(out["alpha"]), bits(alpha))
        self.assertGreater(float(out["beauty"].max()), 0.0)

    def test_names_come_from_the_table_in_memory(self):
        scene = lobe.Scene(segmentation_scene({"array": self.labels, "affine": AFFINE,
                                               "label_table": LABEL_TABLE}))
        passes = scene.render(spp=1, width=16, height=12, aov=["objects"])
        names = sorted({k.rsplit(".", 1)[0] for k in passes if k != "beauty"})
        self.assertEqual(names, ["seg: Hippocampus_L", "seg: Putamen_R", "vermis"])

    def test_label_errors_name_the_key_path(self):
        source = {"array": self.labels, "affine": AFFINE, "label_table": LABEL_TABLE}
        d = segmentation_scene(source)
        d["objects"][0]["labels"] = ["Hippocampus_R"]
        with self.assertRaises(lobe.Error) as caught:
            lobe.Scene(d)
        self.assertIn("objects[0].labels: 'Hippocampus_R' is in no label table", str(caught.exception))
        d = segmentation_scene(dict(source, label_table={1: "a", 2: "b"}))
        with self.assertRaises(lobe.Error) as caught:
            lobe.Scene(d)
        self.assertIn("objects[0].source.label_table", str(caught.exception))
        self.assertIn("does not match the map array", str(caught.exception))
        d = segmentation_scene(dict(source, array=self.labels + np.float32(0.5)))
        with self.assertRaises(lobe.Error) as caught:
            lobe.Scene(d)
        self.assertIn("objects[0].source.array", str(caught.exception))
        self.assertIn("not a label map", str(caught.exception))


class Errors(Files):
    def assertError(self, scene, expected, **kwargs):
        with self.assertRaises(lobe.Error) as caught:
            lobe.Scene(scene, **kwargs)
        self.assertIn(expected, str(caught.exception))
        return str(caught.exception)

    def test_errors_name_the_key_path(self):
        d = scene_dict(*self.file_sources())
        d["objects"][0]["brdf"]["alpha_x"] = 5.0
        message = self.assertError(d, "objects[0].brdf.alpha_x", name="mine")
        self.assertTrue(message.startswith("mine: "), message)
        self.assertTrue(issubclass(lobe.Error, ValueError))
        d = scene_dict(*self.file_sources())
        d["objects"][1]["transfer_function"]["points"][1]["opacity"] = "high"
        self.assertError(d, "objects[1].transfer_function.points[1].opacity")
        d = scene_dict(*self.file_sources())
        d["objects"][1]["brdf"]["colour"] = 1
        self.assertError(d, "objects[1].brdf")
        d = scene_dict(*self.file_sources())
        d["objects"][0]["iso"] = object()
        self.assertError(d, "objects[0].iso: cannot be given as a object")

    def test_array_errors_name_the_key_path(self):
        core = self.file_sources()[1]
        self.assertError(scene_dict({"array": self.ball[0], "affine": AFFINE}, core),
                         "objects[0].source.array: expected a 3-D array")
        self.assertError(scene_dict({"array": self.ball, "affine": np.eye(3)}, core),
                         "objects[0].source.affine: expected a 4 x 4 matrix")
        self.assertError(scene_dict({"array": self.ball.astype(np.complex64)}, core),
                         "objects[0].source.array: expected an array of numbers")
        self.assertError(scene_dict({"array": self.ball, "dims": [1, 2, 3]}, core),
                         "objects[0].source.dims: not with \"array\"")
        self.assertError(scene_dict({"image": self.ball}, core),
                         "objects[0].source.image: expected a nibabel image")
        nan = self.ball.copy()
        nan[3, 4, 5] = np.nan
        self.assertError(scene_dict({"array": nan}, core), "voxel (3, 4, 5) is NaN")

    def test_array_key_in_a_file_is_an_error(self):
        path = self.write_scene("array", scene_dict({"array": "x"}, self.file_sources()[1]))
        with self.assertRaises(lobe.Error) as caught:
            lobe.Scene.from_file(path)
        self.assertIn("objects[0].source.array: arrays in memory are given through the Python module",
                      str(caught.exception))
        r = subprocess.run([LOBE, "render", path, "--check"], capture_output=True, text=True)
        self.assertEqual(r.returncode, 1)
        self.assertIn("objects[0].source.array", r.stderr)

    def test_render_arguments_are_checked(self):
        scene = lobe.Scene(scene_dict(*self.file_sources()))
        for kwargs, expected in [({"width": 0}, "width"), ({"spp": 5000}, "spp"),
                                 ({"aov": ["colour"]}, "aov"), ({"step": float("nan")}, "step")]:
            with self.subTest(kwargs=kwargs):
                with self.assertRaises(lobe.Error) as caught:
                    scene.render(**kwargs)
                self.assertIn(expected, str(caught.exception))


# A render far longer than the bound (2048 x 2048 at 64 spp: minutes on this machine) in a child
# process that reports when it has started, is sent SIGINT, and reports what it stopped at.
CHILD = textwrap.dedent("""
    import sys, time
    import numpy as np
    import lobe
    sys.path.insert(0, sys.argv[1])
    from test_module import AFFINE, ball, core, scene_dict
    scene = lobe.Scene(scene_dict({"array": ball(), "affine": AFFINE},
                                  {"array": core(), "affine": AFFINE, "divide_by": 500}))
    state = {"started": False, "done": 0}
    def progress(done, total):
        state["done"] = done
        if done > 0 and not state["started"]:
            state["started"] = True
            print("started", flush=True)
    try:
        scene.render(width=2048, height=2048, spp=64, threads=2, progress=progress)
        print("finished", flush=True)
    except KeyboardInterrupt:
        print("stopped %d of %d" % (state["done"], 2048 * 2048), flush=True)
    # Nothing half-done: the scene renders again.
    image = scene.render(width=8, spp=1)["beauty"]
    print("again", image.shape, flush=True)
""")


class Interrupt(unittest.TestCase):
    def test_ctrl_c_stops_a_render_within_a_second(self):
        here = os.path.dirname(os.path.abspath(__file__))
        child = subprocess.Popen([sys.executable, "-c", CHILD, here], stdout=subprocess.PIPE,
                                 text=True, env=dict(os.environ, PYTHONUNBUFFERED="1"))
        try:
            self.assertEqual(child.stdout.readline().strip(), "started")
            sent = time.monotonic()
            child.send_signal(signal.SIGINT)
            line = child.stdout.readline().split()
            stopped = time.monotonic() - sent
            self.assertEqual(line[0], "stopped", line)
            done, total = int(line[1]), int(line[3])
            self.assertLess(done, total // 2)  # far from finished
            self.assertLess(stopped, 1.0)
            self.assertEqual(child.stdout.readline().strip(), "again (7, 8, 3)")
        finally:
            child.kill()
            child.wait()
            child.stdout.close()


class Brdf(unittest.TestCase):
    def test_models_are_the_cli_list(self):
        listed = subprocess.run([LOBE, "brdf", "list"], capture_output=True, text=True,
                                check=True).stdout
        names = [line.split()[0] for line in listed.splitlines() if line and not line[0].isspace()]
        self.assertEqual([m["name"] for m in lobe.brdf.models()], names)
        ward = next(m for m in lobe.brdf.models() if m["name"] == "ward")
        self.assertIn("alpha_x", [p["name"] for p in ward["params"]])

    def test_eval_equals_lobe_brdf_eval(self):
        rng = np.random.default_rng(11)
        wi = rng.normal(size=(200, 3))
        wo = rng.normal(size=(200, 3))
        wi[:, 2] = np.abs(wi[:, 2])
        wo[:, 2] = np.abs(wo[:, 2])
        wo[:50, 2] *= -1  # some below the horizon
        wi[50:60] *= 1e-200  # tiny and huge vectors normalise as the CLI normalises them
        wo[60:70] *= 1e200
        lines = "".join("%r,%r,%r,%r,%r,%r\n" % (*a, *b) for a, b in zip(wi, wo))
        cases = [(m["name"], {}, []) for m in lobe.brdf.models()]
        cases.append(("ward", {"alpha_x": 0.1, "rho_s": [0.2, 0.3, 0.4]},
                      ["alpha_x=0.1", "rho_s=0.2,0.3,0.4"]))
        for model, params, settings in cases:
            with self.subTest(model=model, params=params):
                cli = subprocess.run([LOBE, "brdf", "eval", model, *settings], input=lines,
                                     capture_output=True, text=True, check=True).stdout.split()
                values = lobe.brdf.eval(model, params, wi, wo)
                self.assertEqual(values.shape, (200, 3))
                ours = ["%.10g,%.10g,%.10g" % tuple(v) for v in values]
                self.assertEqual(ours, cli)

    def test_eval_broadcasts_and_checks(self):
        wi = np.array([0.0, 0.3, 1.0])
        wo = np.array([[0.1, 0.0, 1.0], [0.5, 0.5, 0.7]])
        values = lobe.brdf.eval("phong", {"exponent": 10}, wi, wo)
        self.assertEqual(values.shape, (2, 3))
        np.testing.assert_array_equal(values[1], lobe.brdf.eval("phong", {"exponent": 10}, wi, wo[1]))
        with self.assertRaises(lobe.Error):
            lobe.brdf.eval("phong", {}, [0, 0, 0], wo)
        with self.assertRaises(lobe.Error) as caught:
            lobe.brdf.eval("phong", {"exponent": -1}, wi, wo)
        self.assertIn("exponent", str(caught.exception))
        with self.assertRaises(lobe.Error):
            lobe.brdf.eval("nonesuch", {}, wi, wo)


if __name__ == "__main__":
    unittest.main()
