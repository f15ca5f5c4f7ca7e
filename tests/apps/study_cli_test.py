"""`lobe study` and `lobe study analyse` on bad input: one `lobe: error:` line, exit 1, nothing
written or overwritten; the template is compiled in (the page works without the source tree).

usage: study_cli_test.py LOBE SOURCE_DIR WORK_DIR"""
import os
import shutil
import subprocess
import sys

from study_common import build_study, check

lobe, source, work = sys.argv[1:4]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
paper = os.path.join(source, "assets", "scenes", "paper")
one = os.path.join(paper, "rendering-01.json")


def lobe_error(args, expected):
    r = subprocess.run([lobe, *args], capture_output=True, text=True, timeout=300, cwd=work)
    check(r.returncode == 1, "%s: exit %d, expected 1 (stderr %r)" % (args, r.returncode, r.stderr))
    check(r.stderr.startswith("lobe: error: ") and r.stderr.count("\n") == 1 and expected in r.stderr,
          "%s: stderr %r, expected one error line with %r" % (args, r.stderr, expected))


empty = os.path.join(work, "empty")
lobe_error(["study", one, "--out", empty], "a pair study needs at least two scene files")
lobe_error(["study", one, one, "--out", empty, "--task", "rank"], "--task: expected pair, which-object or both")
lobe_error(["study", one, os.path.join(paper, "missing.json"), "--out", empty], "missing.json' does not exist")
lobe_error(["study", one, one, "--out", empty], "are both called 'rendering-01'")
check(not os.path.exists(empty), "a failed `lobe study` created its --out folder")
# A scene whose volume file is corrupt fails after the folder was made: nothing is left behind.
with open(one, encoding="utf-8") as f:
    text = f.read().replace("../../brain/mni_icbm152_t1_tal_nlin_sym_09a_converted.nii.gz", "corrupt.nii.gz")
with open(os.path.join(work, "corrupt.nii.gz"), "wb") as f:
    f.write(b"not a NIfTI file")
with open(os.path.join(work, "rendering-99.json"), "w", encoding="utf-8") as f:
    f.write(text.replace("../../cthead/", os.path.join(source, "assets", "cthead") + "/")
                .replace("../../brain/", os.path.join(source, "assets", "brain") + "/"))
lobe_error(["study", os.path.join(paper, "rendering-08.json"), os.path.join(work, "rendering-99.json"),
            "--out", empty, "--width", "64", "--spp", "1", "--quiet"], "corrupt.nii.gz")
check(not os.path.exists(empty), "a `lobe study` failing in its render left " + str(
    os.listdir(empty) if os.path.exists(empty) else ""))

# An existing study is never overwritten.
folder = os.path.join(work, "study")
study = build_study(lobe, source, folder, task="pair")
with open(os.path.join(folder, "index.html"), encoding="utf-8") as f:
    page = f.read()
check('const STUDY = {' in page and "/*LOBE_STUDY_JSON*/" not in page, "the study is not in the page")
check("http://" not in page and "https://" not in page and "<link rel=\"stylesheet\"" not in page,
      "the page refers to something outside its folder")
before = os.path.getmtime(os.path.join(folder, "study.json"))
lobe_error(["study", one, os.path.join(paper, "rendering-08.json"), "--out", folder, "--width", "64"],
           "already holds a study")
check(os.path.getmtime(os.path.join(folder, "study.json")) == before, "study.json was touched")

# Analyse: a file that is not answers, answers of two studies, an existing result.
bad = os.path.join(work, "bad.json")
with open(bad, "w", encoding="utf-8") as f:
    f.write('{"format": "something else"}')
lobe_error(["study", "analyse", bad, "--out", os.path.join(work, "r0")], "bad.json: not a lobe study answers file")
sims = []
for k, jod in enumerate(["0,1,0.5", "0,0.5,1"]):
    out = os.path.join(work, "sim%d" % k)
    r = subprocess.run([lobe, "study", "simulate", folder, "--jod", jod, "--observers", "3", "--out", out],
                       capture_output=True, text=True, timeout=60)
    check(r.returncode == 0, "simulate: " + r.stderr)
    sims.append(out)
other = os.path.join(work, "other-study")
build_study(lobe, source, other, task="pair", extra=("--order-seed", "2"))
r = subprocess.run([lobe, "study", "simulate", other, "--jod", "0,1,0.5", "--observers", "1", "--out",
                    os.path.join(work, "sim-other")], capture_output=True, text=True, timeout=60)
check(r.returncode == 0, "simulate: " + r.stderr)
os.rename(os.path.join(work, "sim-other", "sim-0.json"), os.path.join(work, "sim-other", "other.json"))
lobe_error(["study", "analyse", sims[0], os.path.join(work, "sim-other", "other.json"), "--out",
            os.path.join(work, "r1")], "answers of another study")
lobe_error(["study", "analyse", sims[0], sims[1], "--out", os.path.join(work, "r2")],
           "appears in two answers files")
lobe_error(["study", "simulate", folder, "--jod", "0,1", "--out", os.path.join(work, "r3")],
           "2 JOD values for 3 conditions")
results = os.path.join(work, "results")
r = subprocess.run([lobe, "study", "analyse", sims[0], "--out", results, "--quiet"], capture_output=True,
                   text=True, timeout=60)
check(r.returncode == 0 and sorted(os.listdir(results)) ==
      ["study-results.csv", "study-results.md", "study-results.png"], "analyse: " + r.stderr)
lobe_error(["study", "analyse", sims[0], "--out", results], "exists: give a new --out folder")
for name in ["r0", "r1", "r2", "r3"]:
    check(not os.path.exists(os.path.join(work, name)), "a failed command wrote " + name)
print("ok")
