"""Shared by tests/apps/study_serve_test.py and study_browser_test.py: a tiny study built with the
real `lobe study` (three paper scenes, 64 px wide, 1 sample per pixel) and a `lobe study serve`
started on a free loopback port and stopped by its own process id. Every wait is bounded."""
import json
import os
import select
import shutil
import subprocess
import sys
import time

SCENES = ["rendering-01.json", "rendering-08.json", "rendering-13.json"]


def fail(message):
    print("FAIL: " + message, file=sys.stderr)
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)


def build_study(lobe, source, out, task="both", extra=()):
    """Runs `lobe study` into a fresh `out` and returns its study.json."""
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(os.path.dirname(out), exist_ok=True)
    scenes = [os.path.join(source, "assets", "scenes", "paper", s) for s in SCENES]
    cmd = [lobe, "study", *scenes, "--out", out, "--task", task, "--width", "64", "--spp", "1",
           "--repeats", "1", "--checks", "1", "--quiet", *extra]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    check(r.returncode == 0, "lobe study failed: " + r.stderr)
    with open(os.path.join(out, "study.json"), encoding="utf-8") as f:
        return json.load(f)


class Server:
    """`lobe study serve DIR --port 0`; the address is read from its first line of output."""

    def __init__(self, lobe, folder, timeout=60.0):
        self.proc = subprocess.Popen([lobe, "study", "serve", folder, "--port", "0"],
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        ready, _, _ = select.select([self.proc.stdout], [], [], timeout)
        if not ready:
            self.stop()
            fail("lobe study serve printed no address within %.0f s" % timeout)
        line = self.proc.stdout.readline()
        if not line.startswith("serving http://127.0.0.1:"):
            self.stop()
            fail("unexpected first line of lobe study serve: %r (stderr: %s)" %
                 (line, self.proc.stderr.read()))
        self.origin = line.split()[1].rstrip("/")
        self.port = int(self.origin.rsplit(":", 1)[1])

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()


def wait_for(predicate, timeout, what):
    """Polls `predicate` until true; fails naming `what` after `timeout` seconds."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(0.05)
    fail("timed out after %.0f s waiting for %s" % (timeout, what))
