"""The study page in a real browser (Debian chromium + chromium-driver + python3-selenium): a
scripted participant answers every trial of a tiny study (64 px, 1 spp, both tasks), twice —
served by `lobe study serve` (answers POSTed and stored) and opened as a file (answers
downloaded) — and the answers parse with the right trial count and analyse. Chromium's
performance log must show no request outside the page's own origin (or its folder, for the
file). Every wait is on page state, bounded; no sleep decides anything.

usage: study_browser_test.py LOBE SOURCE_DIR WORK_DIR"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import WebDriverWait

from study_common import Server, build_study, check, fail, wait_for

lobe, source, work = sys.argv[1:4]
shutil.rmtree(work, ignore_errors=True)
folder = os.path.join(work, "study")
study = build_study(lobe, source, folder, extra=("--orbit", "2"))
trial_count = len(study["trials"])
kinds = {t["kind"] for t in study["trials"]}
check(kinds == {"pair", "marker", "attention"}, "study trial kinds %s" % kinds)
check(all(len(c["frames"]) == 2 for c in study["conditions"]), "orbit frames missing")
WAIT = 60  # seconds: an upper bound on any one page state change, never a correctness condition


def browser(downloads):
    options = webdriver.ChromeOptions()
    options.binary_location = "/usr/bin/chromium"
    for arg in ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                "--disable-background-networking", "--disable-component-update", "--disable-sync",
                "--no-first-run", "--no-default-browser-check", "--disable-extensions",
                "--disable-features=Translate,OptimizationHints,MediaRouter",
                "--user-data-dir=" + tempfile.mkdtemp(prefix="profile-", dir=work),
                "--window-size=800,600"]:
        options.add_argument(arg)
    options.add_experimental_option("prefs", {"download.default_directory": downloads,
                                              "download.prompt_for_download": False})
    options.set_capability("goog:loggingPrefs", {"performance": "ALL"})
    driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
    # The browser's own start-up page (chrome:// resources) is not the study's: its log entries
    # are read and dropped before the study is opened; every request after this is checked.
    driver.get("about:blank")
    driver.get_log("performance")
    return driver


def state(driver):
    return driver.find_element(By.TAG_NAME, "body").get_attribute("data-state")


def participate(driver, url):
    """Answers every trial: the instructed answer at attention checks, else the first choice."""
    driver.get(url)
    WebDriverWait(driver, WAIT).until(lambda d: state(d) == "intro")
    driver.find_element(By.ID, "start").click()
    for k in range(trial_count):
        WebDriverWait(driver, WAIT).until(
            lambda d: state(d) == "trial" and
            d.find_element(By.TAG_NAME, "body").get_attribute("data-trial") == str(k))
        prompt = driver.find_element(By.ID, "prompt").text
        buttons = driver.find_elements(By.CSS_SELECTOR, "#choices button")
        check(len(buttons) >= 2, "trial %d shows %d choices" % (k, len(buttons)))
        images = driver.find_elements(By.CSS_SELECTOR, "#stimuli img")
        for img in images:  # the fixed stimulus size, and the image decoded
            check(img.get_attribute("width") == "64", "stimulus width %s" % img.get_attribute("width"))
            WebDriverWait(driver, WAIT).until(
                lambda d, img=img: d.execute_script("return arguments[0].complete && "
                                                    "arguments[0].naturalWidth > 0", img))
        choice = buttons[0]
        if prompt.startswith("Attention check"):
            named = [b for b in buttons if "\u201c" + b.text + "\u201d" in prompt]
            check(len(named) == 1, "attention check %r: %d buttons named" % (prompt, len(named)))
            choice = named[0]
        choice.click()
    WebDriverWait(driver, WAIT).until(lambda d: state(d) == "done")


def own_requests_only(driver, allowed):
    """Every request Chromium's network domain saw starts with one of `allowed` (or is data:/blob:)."""
    urls = []
    for entry in driver.get_log("performance"):
        message = json.loads(entry["message"])["message"]
        if message["method"] == "Network.requestWillBeSent":
            urls.append(message["params"]["request"]["url"])
    check(urls, "the performance log recorded no request at all")
    outside = [u for u in urls if not (u.startswith(allowed) or u.startswith(("data:", "blob:")))]
    check(not outside, "requests outside the page's origin: %s" % outside)
    return urls


def check_answers(path, participant):
    with open(path, encoding="utf-8") as f:
        answers = json.load(f)
    check(answers["format"] == "lobe-study-answers-1", "format " + str(answers.get("format")))
    check(answers["study"] == study["study"], "study fingerprint")
    check(answers["participant"] == participant, "participant " + answers["participant"])
    check(len(answers["trials"]) == trial_count,
          "%d answered trials, the study has %d" % (len(answers["trials"]), trial_count))
    positions = sorted(t["position"] for t in answers["trials"])
    check(positions == list(range(trial_count)), "trial positions %s" % positions)
    for t in answers["trials"]:
        if t["kind"] == "attention":
            check(t["answer"] == t["instructed"], "attention check answered %r" % t)


# 1. Served: answers POSTed to the server and stored in DIR/answers.
server = Server(lobe, folder)
driver = None
try:
    driver = browser(os.path.join(work, "downloads-served"))
    participate(driver, server.origin + "/?participant=browser-1")
    WebDriverWait(driver, WAIT).until(
        lambda d: d.find_element(By.TAG_NAME, "body").get_attribute("data-posted") in ("yes", "failed"))
    check(driver.find_element(By.TAG_NAME, "body").get_attribute("data-posted") == "yes",
          "posting failed: " + driver.find_element(By.ID, "status").text)
    urls = own_requests_only(driver, server.origin + "/")
    check(any(u.endswith("/answers") for u in urls), "no POST /answers in the log")
    check_answers(os.path.join(folder, "answers", "browser-1.json"), "browser-1")
finally:
    if driver:
        driver.quit()
    server.stop()

# 2. Opened as a file: the answers downloaded.
downloads = os.path.join(work, "downloads-file")
os.makedirs(downloads)
driver = browser(downloads)
try:
    participate(driver, "file://" + os.path.abspath(folder) + "/index.html?participant=browser-2")
    check(driver.find_element(By.TAG_NAME, "body").get_attribute("data-posted") == "no",
          "a file page tried to post")
    driver.find_element(By.ID, "download").click()
    saved = os.path.join(downloads, "answers-browser-2.json")
    wait_for(lambda: os.path.exists(saved), WAIT, "the downloaded answers " + saved)
    own_requests_only(driver, "file://" + os.path.abspath(folder) + "/")
finally:
    driver.quit()
check_answers(saved, "browser-2")

# 3. Both answers files analyse.
r = subprocess.run([lobe, "study", "analyse", os.path.join(folder, "answers", "browser-1.json"), saved,
                    "--out", os.path.join(work, "results"), "--bootstrap", "50", "--quiet"],
                   capture_output=True, text=True, timeout=120)
check(r.returncode == 0, "analyse: " + r.stderr)
with open(os.path.join(work, "results", "study-results.md"), encoding="utf-8") as f:
    check("2 participants analysed, 0 excluded" in f.read(), "analysis of the browser's answers")
print("ok: %d trials answered in the browser, served and from a file" % trial_count)
