"""`lobe study serve` (study/study_server.h): binds to loopback only unless --allow-remote; serves
the page and its stimuli and nothing else; refuses '..' paths and posts from other origins;
stores each participant's answers without overwriting. All traffic stays on 127.0.0.1.

usage: study_serve_test.py LOBE SOURCE_DIR WORK_DIR"""
import http.client
import json
import os
import shutil
import subprocess
import sys

from study_common import Server, build_study, check, fail

lobe, source, work = sys.argv[1:4]
shutil.rmtree(work, ignore_errors=True)
folder = os.path.join(work, "study")
study = build_study(lobe, source, folder)

# Non-loopback addresses are refused before anything binds (the command ends at once).
for host in ["0.0.0.0", "::", "192.0.2.1", "example.org"]:
    r = subprocess.run([lobe, "study", "serve", folder, "--host", host, "--port", "0"],
                       capture_output=True, text=True, timeout=60)
    check(r.returncode == 1, "--host %s: exit %d, expected 1" % (host, r.returncode))
    check(r.stderr.startswith("lobe: error: --host %s is not a loopback address" % host)
          and r.stderr.count("\n") == 1, "--host %s: stderr %r" % (host, r.stderr))
    check(r.stdout == "", "--host %s printed %r" % (host, r.stdout))
r = subprocess.run([lobe, "study", "serve", os.path.join(work, "no-such-study")],
                   capture_output=True, text=True, timeout=60)
check(r.returncode == 1 and "holds no study" in r.stderr, "missing folder: " + r.stderr)

# Simulated answers to post (the format the page writes).
sim = os.path.join(work, "sim")
r = subprocess.run([lobe, "study", "simulate", folder, "--jod", "0,1,0.5", "--observers", "1",
                    "--out", sim], capture_output=True, text=True, timeout=60)
check(r.returncode == 0, "simulate: " + r.stderr)
with open(os.path.join(sim, "sim-0.json"), encoding="utf-8") as f:
    answers = f.read()

server = Server(lobe, folder)
try:
    def request(method, path, body=None, headers=None):
        conn = http.client.HTTPConnection("127.0.0.1", server.port, timeout=30)
        conn.request(method, path, body=body, headers=headers or {})
        resp = conn.getresponse()
        data = resp.read()
        conn.close()
        return resp.status, data

    status, page = request("GET", "/")
    check(status == 200 and b"lobe-study-answers-1" in page and study["study"].encode() in page,
          "GET / -> %d" % status)
    status, png = request("GET", "/stimuli/rendering-08.png")
    check(status == 200 and png.startswith(b"\x89PNG"), "GET a stimulus -> %d" % status)
    # Only the page's own requests: not the study file, not other files of the folder.
    for path in ["/study.json", "/answers", "/stimuli/", "/stimuli/rendering-08.exr", "/favicon.ico"]:
        status, _ = request("GET", path)
        check(status == 404, "GET %s -> %d, expected 404" % (path, status))
    # '..' in any form is refused, even where it would stay inside the folder.
    for path in ["/../study.json", "/stimuli/../index.html", "/stimuli/..%2f..%2fetc/passwd",
                 "/%2e%2e/%2e%2e/etc/passwd", "/stimuli/rendering-08.png/.."]:
        status, _ = request("GET", path)
        check(status == 403, "GET %s -> %d, expected 403" % (path, status))
    status, _ = request("DELETE", "/index.html")
    check(status == 405, "DELETE -> %d" % status)

    # Answers: stored under the participant's id, never overwritten.
    json_headers = {"Content-Type": "application/json"}
    status, body = request("POST", "/answers", answers, json_headers)
    check(status == 200 and json.loads(body)["saved"] == "answers/sim-0.json", "POST -> %d %r" % (status, body))
    status, body = request("POST", "/answers", answers.replace('"sim-0"', '"sim-0"'),
                           dict(json_headers, Origin=server.origin))
    check(status == 200 and json.loads(body)["saved"] == "answers/sim-0-2.json",
          "second POST -> %d %r" % (status, body))
    # The page loaded as http://localhost:PORT posts with that origin: accepted.
    localhost = "localhost:%d" % server.port
    status, body = request("POST", "/answers", answers.replace('"sim-0"', '"sim-0"'),
                           dict(json_headers, Host=localhost, Origin="http://" + localhost))
    check(status == 200 and json.loads(body)["saved"] == "answers/sim-0-3.json",
          "POST from localhost -> %d %r" % (status, body))
    with open(os.path.join(folder, "answers", "sim-0.json"), encoding="utf-8") as f:
        check(f.read() == answers, "stored answers differ from the posted ones")
    # Refused: another origin, another study, missing trials, not JSON, a '..' path.
    refused = [
        ("POST", "/answers", answers, dict(json_headers, Origin="http://evil.example"), 403),
        ("POST", "/answers", answers.replace(study["study"], "0000000000000000"), json_headers, 400),
        ("POST", "/answers", json.dumps(dict(json.loads(answers), trials=[])), json_headers, 400),
        ("POST", "/answers", "{not json", json_headers, 400),
        ("POST", "/../answers", answers, json_headers, 403),
        ("POST", "/index.html", answers, json_headers, 405),
        # DNS rebinding: another site's name pointed at 127.0.0.1, its page reading or posting.
        ("GET", "/", None, {"Host": "evil.example:%d" % server.port}, 403),
        ("POST", "/answers", answers, dict(json_headers, Host="evil.example:%d" % server.port,
                                           Origin="http://evil.example:%d" % server.port), 403),
    ]
    for method, path, body, headers, expected in refused:
        status, _ = request(method, path, body, headers)
        check(status == expected, "%s %s -> %d, expected %d" % (method, path, status, expected))
    stored = sorted(os.listdir(os.path.join(folder, "answers")))
    check(stored == ["sim-0-2.json", "sim-0-3.json", "sim-0.json"], "answers folder holds %s" % stored)
finally:
    server.stop()
print("ok")
