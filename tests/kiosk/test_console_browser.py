#!/usr/bin/python3
"""The technician's console in a real browser: headless Chromium (Debian's chromium and
chromium-driver), driven by Selenium (python3-selenium), against console_demo (--demo: a KioskLoop
with the console on and a small frame source that steps its relic on NextRelic) or against the
product itself (--kiosk: `holopyramid kiosk --headless` on the simulated museum with an exhibit
playlist of three built-in relics, the first two turning).

It sets the password with `holopyramid console-password`, logs in (after one wrong password),
sees the health and the snapshots change, presses "Next relic" and sees the relic change, logs
out, and checks the API refuses the browser once logged out. Screenshots (PNG) go to
--screenshots; docs/kiosk.md shows them (docs/images/console-*.png).

Never skipped: a missing browser, driver or library is a failure (scripts/install-deps installs
them). Waits are bounded by condition, not by the clock: each condition may take up to
WAIT_S on a loaded CI machine.
"""
import argparse
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import WebDriverWait

PASSWORD = "museum technician 42"
WAIT_S = 60
CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"


def wait_for(driver, what, condition):
    try:
        return WebDriverWait(driver, WAIT_S, poll_frequency=0.2).until(lambda d: condition(d))
    except Exception as e:
        raise AssertionError(f"browser test: timed out waiting for {what}") from e


def image_data(driver, element_id):
    """The picture an <img> shows, as PNG bytes drawn through a canvas (empty until loaded)."""
    return driver.execute_script(
        """const img = document.getElementById(arguments[0]);
           if (!img || !img.complete || img.naturalWidth === 0) return '';
           const c = document.createElement('canvas');
           c.width = img.naturalWidth; c.height = img.naturalHeight;
           c.getContext('2d').drawImage(img, 0, 0);
           return c.toDataURL('image/png');""",
        element_id,
    )


def start_demo(demo_program, work, secret):
    """console_demo on a free port it writes to a file; returns (process, base URL)."""
    port_file = os.path.join(work, "port")
    demo = subprocess.Popen([demo_program, secret, port_file])
    deadline = time.monotonic() + WAIT_S
    while not (os.path.exists(port_file) and open(port_file).read().strip()):
        if demo.poll() is not None:
            sys.exit(f"browser test: console_demo exited with {demo.returncode}")
        if time.monotonic() > deadline:
            sys.exit("browser test: console_demo did not start its console")
        time.sleep(0.05)
    return demo, f"http://127.0.0.1:{open(port_file).read().strip()}"


def start_kiosk(holopyramid, work, secret):
    """The product: `holopyramid kiosk --headless` with the console on, on the simulated museum
    (small cameras, small views: the browser test checks the console, the kiosk's own tests the
    picture) and a playlist whose relics stay until "Next relic" is pressed. Returns (process,
    base URL, the configuration source the page shows)."""
    with socket.socket() as probe:  # a free port for the console's configuration
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    scene = os.path.join(work, "small_museum.yaml")
    with open(scene, "w") as f:
        f.write("base: museum\ncamera: {width: 160, height: 90, fps: 10}\n")
    config = os.path.join(work, "holopyramid.yaml")
    with open(config, "w") as f:
        f.write(f"""kiosk:
  max_fps: 10
  status_interval_s: 0.2
  degradation: {{frame_budget_ms: 1000}}
  health: {{port: -1, file: ""}}
  console: {{enabled: true, port: {port}, secret_file: "{secret}"}}
display:
  output_size: [512, 512]
exhibit:
  relics:
    - {{relic: vase, duration_s: 3600, turntable_deg_per_s: 20}}
    - {{relic: kettle, duration_s: 3600, turntable_deg_per_s: -20, crossfade_s: 0}}
    - {{relic: glass-vase, duration_s: 3600}}
""")
    log = open(os.path.join(work, "kiosk.log"), "w")
    kiosk = subprocess.Popen([holopyramid, "kiosk", "--headless", "--config", config, "--state-dir", "",
                              "--scene", scene, "--view-size", "96"], stdout=log, stderr=subprocess.STDOUT)
    base = f"http://127.0.0.1:{port}"
    deadline = time.monotonic() + 3 * WAIT_S
    while True:
        if kiosk.poll() is not None:
            raise AssertionError(f"browser test: the kiosk exited with {kiosk.returncode}")
        try:
            with urllib.request.urlopen(base + "/", timeout=5):
                break
        except (urllib.error.URLError, ConnectionError, OSError):
            if time.monotonic() > deadline:
                raise AssertionError("browser test: the kiosk's console did not answer")
            time.sleep(0.2)
    return kiosk, base, config


def main():
    parser = argparse.ArgumentParser()
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--demo", help="console_demo's path")
    mode.add_argument("--kiosk", action="store_true", help="the real kiosk (holopyramid kiosk --headless)")
    parser.add_argument("--holopyramid", required=True)
    parser.add_argument("--screenshots", required=True)
    args = parser.parse_args()
    for program in (CHROMIUM, CHROMEDRIVER):
        if not os.access(program, os.X_OK):
            sys.exit(f"browser test: {program} missing (scripts/install-deps installs chromium and chromium-driver)")
    os.makedirs(args.screenshots, exist_ok=True)
    started = time.monotonic()
    work = tempfile.mkdtemp(prefix="holo_console_browser_")
    demo = None
    driver = None
    try:
        secret = os.path.join(work, "console.secret")
        subprocess.run([args.holopyramid, "console-password", "--file", secret], input=PASSWORD + "\n",
                       text=True, check=True)
        assert (os.stat(secret).st_mode & 0o777) == 0o600, oct(os.stat(secret).st_mode)
        if args.kiosk:
            demo, base, expected_config = start_kiosk(args.holopyramid, work, secret)
        else:
            demo, base = start_demo(args.demo, work, secret)
            expected_config = "console demo"

        options = webdriver.ChromeOptions()
        options.binary_location = CHROMIUM
        for flag in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--disable-gpu",
                     "--window-size=1200,1400", "--hide-scrollbars", "--no-first-run",
                     f"--user-data-dir={os.path.join(work, 'profile')}"):
            options.add_argument(flag)
        driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)

        # Without a session the API says 401 (the page shows its JSON).
        driver.get(base + "/api/status")
        assert "log in first" in driver.find_element(By.TAG_NAME, "body").text

        driver.get(base + "/")
        driver.find_element(By.ID, "password").send_keys("not the password")
        driver.find_element(By.ID, "login-button").click()
        wait_for(driver, "the wrong-password message", lambda d: "Wrong password" in d.find_element(By.ID, "message").text)
        driver.find_element(By.ID, "password").send_keys(PASSWORD)
        driver.save_screenshot(os.path.join(args.screenshots, "console-login.png"))
        driver.find_element(By.ID, "login-button").click()

        wait_for(driver, "the status page", lambda d: d.find_elements(By.ID, "relic"))
        wait_for(driver, "the relic's name",
                 lambda d: d.find_element(By.ID, "relic").text not in ("", "\u2013", "(no playlist)"))
        relic = driver.find_element(By.ID, "relic").text
        next_relic = driver.find_element(By.ID, "next-relic").text
        assert next_relic not in ("", "\u2013", relic), (relic, next_relic)
        if not args.kiosk:
            assert (relic, next_relic) == ("Amphora of Knossos", "Bronze helmet"), (relic, next_relic)
        wait_for(driver, "the configuration's source", lambda d: d.find_element(By.ID, "config").text == expected_config)
        wait_for(driver, "the camera table", lambda d: len(d.find_elements(By.CSS_SELECTOR, "#cameras tbody tr")) == 4)
        wait_for(driver, "the log's tail", lambda d: "console: login from" in d.find_element(By.ID, "log").text)

        # The snapshots arrive and change.
        for element in ("face-0", "face-3", "camera-0", "camera-3"):
            wait_for(driver, f"snapshot {element}", lambda d, e=element: image_data(d, e))
        first = {e: image_data(driver, e) for e in ("face-0", "camera-0")}
        for element, picture in first.items():
            wait_for(driver, f"snapshot {element} to change",
                     lambda d, e=element, p=picture: image_data(d, e) not in ("", p))
        # The per-camera frame rate needs two status polls.
        wait_for(driver, "a camera frame rate", lambda d: d.find_element(By.CSS_SELECTOR, "#cameras tbody td:nth-child(3)").text not in ("", "\u2013"))
        driver.save_screenshot(os.path.join(args.screenshots, "console-status.png"))

        driver.find_element(By.ID, "next-relic-button").click()
        wait_for(driver, "the relic to change", lambda d: d.find_element(By.ID, "relic").text == next_relic)
        if not args.kiosk:
            assert driver.find_element(By.ID, "next-relic").text == "Gold mask of Agamemnon"
        assert "asked" in driver.find_element(By.ID, "action-result").text
        # The status says the relic changed before every face's snapshot has been fetched again:
        # each face is waited for until it shows a picture fetched after the switch.
        faces = [f"face-{f}" for f in range(4)]
        at_switch = {e: image_data(driver, e) for e in faces}
        for element in faces:
            wait_for(driver, f"snapshot {element} to show the new relic",
                     lambda d, e=element: image_data(d, e) not in ("", at_switch[e], first.get(e)))
        driver.save_screenshot(os.path.join(args.screenshots, "console-next-relic.png"))

        driver.find_element(By.ID, "logout").click()
        wait_for(driver, "the login page after logging out", lambda d: d.find_elements(By.ID, "password"))
        status = driver.execute_async_script(
            "const done = arguments[arguments.length - 1];"
            "fetch('/api/status').then((r) => done(r.status), () => done(-1));")
        assert status == 401, status
        print(f"browser test: passed in {time.monotonic() - started:.1f} s; screenshots in {args.screenshots}")
    except BaseException:
        kiosk_log = os.path.join(work, "kiosk.log")
        if os.path.exists(kiosk_log):
            print("browser test: the kiosk's log:\n" + open(kiosk_log).read()[-6000:])
        raise
    finally:
        if driver is not None:
            driver.quit()
        if demo is not None and demo.poll() is None:
            demo.send_signal(signal.SIGTERM)
            try:
                demo.wait(timeout=WAIT_S)
            except subprocess.TimeoutExpired:
                demo.kill()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
