"""The panel in a real browser (Debian's Chromium, headless, driven by
Selenium through chromedriver) against edsp-web beside a live sim group:
the page and its libraries load with the token of its URL alone, the 3-D
view draws the platform from EDSP_CONFIG where the legs' encoders put it
(checked at a tilted pose, where a wrong angle order or frame would be
centimetres off), an operator moves, halts and re-arms from the page and
reads the answers (the planner's whole-path check shown as the form is
edited), the plots hold what the tables showed, and a viewer's page offers
no live control.

The drawn legs are held to the encoders within 0.5 mm: the encoders carry
the passive-rotation correction (tens of µm at these angles) and the page
draws the joint centres; an angle order swapped or a frame mixed up moves a
leg by centimetres at 3°."""
import math
import os
import shutil
import signal
import subprocess
import time

import pytest
from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys

import live_group  # tests/python
import served_web

CHROMIUM = shutil.which("chromium")
CHROMEDRIVER = shutil.which("chromedriver")
# Not a skip: a suite that cannot run its browser tests must say so (deploy/edsp deps installs both).
assert CHROMIUM and CHROMEDRIVER, "chromium and chromedriver are needed (Debian: chromium chromium-driver)"
TILT = [12.0, -8.0, None, 3.0, -2.0, 4.0]  # x, y mm; z kept; roll, pitch, yaw deg


@pytest.fixture(scope="module")
def served(tmp_path_factory):
    with served_web.serve(tmp_path_factory.mktemp("web")) as server:
        yield server


def _browser(tmp_path, extra_args=()):
    """Chromium at the lowest nice level: in the test it shares the
    machine's cores with the group's 1 kHz loops, as a rig's controller
    never shares them with an operator's browser (a page loading at normal
    priority on two cores stalls the loops until the bridge latches a
    hold); not SCHED_IDLE, where it would share only what the suite's
    idle-priority compiles leave (a page redrawing seconds late)."""
    tmp_path.mkdir(parents=True, exist_ok=True)
    idle = tmp_path / "chromium-nice"
    idle.write_text(f'#!/bin/sh\nexec nice -n 19 {CHROMIUM} "$@"\n')
    idle.chmod(0o755)
    options = webdriver.ChromeOptions()
    options.binary_location = str(idle)
    for arg in ["--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1400,1000",
                "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--no-first-run",
                f"--user-data-dir={tmp_path}", *extra_args]:
        options.add_argument(arg)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)


def _following(group):
    """The group's bridge following its commands at a test's start. The
    tests share one group: a hold a stall of the machine left during an
    earlier test (the drives silent past their timeout: what the fault-matrix
    tests measure) is re-armed here, and said, so that each test sees what
    it tests, never what the machine did before it."""
    rig = live_group.connect(group)
    if rig.status()["state"] == "fault":
        print(f"re-armed before the test: {rig.status()['reason']}: {rig.arm()}")
        deadline = time.monotonic() + 30
        while rig.status()["state"] == "fault" and time.monotonic() < deadline:
            time.sleep(0.05)


@pytest.fixture
def page(served, tmp_path):
    """A function that opens the panel with a token and returns the driver."""
    _following(served["group"])
    drivers = []

    def open_panel(token):
        driver = _browser(tmp_path / f"profile{len(drivers)}")
        drivers.append(driver)
        driver.get(f"http://127.0.0.1:{served['port']}/?token={token}")
        return driver

    yield open_panel
    for driver in drivers:
        driver.quit()


def _until(driver, seconds, script, what):
    """The first truthy value of `script` (JavaScript returning a value)."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        value = driver.execute_script(script)
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError(f"{what} within {seconds} s; page says: " +
                         driver.find_element(By.TAG_NAME, "body").text[:2000])


def _severe_console(driver):
    return [e["message"] for e in driver.get_log("browser") if e["level"] == "SEVERE"]


def _encoder_lengths_mm(driver):
    _until(driver, 10, "return document.querySelectorAll('#legs tr').length === 7", "the legs' table")
    rows = driver.find_elements(By.CSS_SELECTOR, "#legs tr")[1:]
    return [float(r.find_elements(By.TAG_NAME, "td")[1].text) for r in rows]


def _drawn(driver):
    """Share of the canvas's pixels that are not its background, and of
    those, how many are the legs' greens (a leg mid-stroke)."""
    return driver.execute_script("""
        const canvas = document.getElementById('view');
        const copy = document.createElement('canvas');
        copy.width = canvas.width; copy.height = canvas.height;
        const ctx = copy.getContext('2d');
        ctx.drawImage(canvas, 0, 0);
        const px = ctx.getImageData(0, 0, copy.width, copy.height).data;
        let drawn = 0, green = 0;
        for (let i = 0; i < px.length; i += 4) {
          const [r, g, b] = [px[i], px[i + 1], px[i + 2]];
          if (Math.abs(r - 0xf4) + Math.abs(g - 0xf5) + Math.abs(b - 0xf7) > 24) drawn++;
          if (g > r + 40 && g > b + 40) green++;
        }
        return [drawn / (px.length / 4), green / (px.length / 4)];""")


def _fill_goal(driver, goal, relative=False):
    for i, value in enumerate(goal):
        if value is None:
            continue
        field = driver.find_element(By.ID, f"goal-{i}")
        field.clear()
        field.send_keys(str(value))
    box = driver.find_element(By.ID, "goal-relative")
    if box.is_selected() != relative:
        box.click()


def _move_from_page(driver, goal, relative=False):
    _fill_goal(driver, goal, relative)
    driver.find_element(By.ID, "move").click()


def _reply(driver, seconds, prefix, line="control-reply"):
    return _until(driver, seconds, f"""
        const t = document.getElementById('{line}').textContent;
        return t.startsWith('{prefix}') && !t.endsWith(': sent') ? t : null;""", f"an answer to '{prefix}'")


def test_an_operator_tilts_the_platform_from_the_page_and_the_view_draws_it_where_the_encoders_are(page, served):
    driver = page(served["operator"])
    _until(driver, 30, "return typeof view3d !== 'undefined' && view3d.rendered()", "a rendered 3-D view")
    drawn, green = _drawn(driver)
    assert drawn > 0.02 and green > 0.0005, (drawn, green)
    assert driver.find_element(By.ID, "control-role").text.startswith("operator (Esc halts"), driver.find_element(By.ID, "control-role").text
    # the form starts at the held target: z is the home height
    z = float(_until(driver, 10, "return document.getElementById('goal-2').value", "a prefilled form"))
    assert 1400 < z < 1600, z
    # the planner's whole-path check answers as the form is edited, before any move is sent
    _fill_goal(driver, TILT)
    checked = _until(driver, 20, """const t = document.getElementById('check-reply').textContent;
        return t.includes('(0.012000, -0.008000, ') ? t : null;""", "the check of the whole form")
    assert checked.startswith("path check: accepted, "), checked
    assert float(checked.split(", ")[1].split(" s")[0]) > 0, checked
    driver.find_element(By.ID, "move").click()
    assert _reply(driver, 20, "move to").startswith("move to: accepted"), driver.find_element(By.ID, "control-reply").text
    _until(driver, 60, "const m = document.getElementById('motion');"
                       "return m.dataset.state === 'holding' && m.dataset.onTarget === '1'", "the move on target")
    # the view drawn at the settled pose: once the page has redrawn it (a busy browser redraws
    # seconds late), its legs are the encoders'
    deadline = time.monotonic() + 30
    while True:
        drawn_mm = [leg["length_m"] * 1e3 for leg in driver.execute_script("return view3d.legs()")]
        encoders = _encoder_lengths_mm(driver)
        agree = len(encoders) == 6 and max(abs(a - b) for a, b in zip(drawn_mm, encoders)) < 0.5
        if agree or time.monotonic() > deadline:
            break
        time.sleep(0.1)
    assert agree, (drawn_mm, encoders)
    # the tilt is real: the legs differ by more than the tolerance from each other and from home
    assert max(encoders) - min(encoders) > 5.0, encoders
    pose_text = [float(driver.find_element(By.ID, f"pose-{i}").text) for i in range(6)]
    for i in (0, 1, 3, 4, 5):
        # on target: within 10 µm and 50 µrad (config [motion]), shown to 1 µm and 0.0001°
        assert math.isclose(pose_text[i], TILT[i], abs_tol=0.011 if i < 3 else 0.0030), (pose_text, TILT)
    # the plots hold what the tables showed: once the plot has drawn the settled pose (a busy browser
    # redraws late, and the CSV is what the plot shows), the CSV's last legs are the encoders'
    _until(driver, 10, "return plots.rows('legs') > 10 && plots.rows('tracking') > 10", "plotted rows")
    _until(driver, 30, "return plots.lag('legs') < 0.3", "the plot drawn up to its newest rows")
    rows = [line for line in driver.execute_script("return plots.csv('legs')").splitlines() if not line.startswith("#")]
    assert rows[0].startswith('"t (s)","leg 1"') and len(rows) > 10, rows[:3]
    last = [float(v) for v in rows[-1].split(",")[1:]]
    assert max(abs(a - b) for a, b in zip(last, _encoder_lengths_mm(driver))) < 0.05, (last, encoders)
    assert not _severe_console(driver)


def test_a_pose_out_of_reach_is_refused_on_the_page_with_the_planners_reason_and_nothing_moves(page, served):
    driver = page(served["operator"])
    _until(driver, 30, "return typeof view3d !== 'undefined' && view3d.rendered()", "a rendered 3-D view")
    before = _encoder_lengths_mm(driver)
    _fill_goal(driver, [0, 0, 800, 0, 0, 0], relative=True)
    driver.find_element(By.ID, "check").click()  # after the whole form: the answer shown is this one's
    checked = _reply(driver, 20, "path check", line="check-reply")
    assert checked.startswith("path check: refused: ") and len(checked) > 30, checked
    driver.find_element(By.ID, "move").click()
    refused = _reply(driver, 20, "move by")
    assert refused.startswith("move by: refused: "), refused
    assert refused.split("refused: ", 1)[1] == checked.split("refused: ", 1)[1], (refused, checked)
    time.sleep(1.0)
    after = _encoder_lengths_mm(driver)
    # held: the legs keep still to the jitter of a held pose (a move would be millimetres)
    assert max(abs(a - b) for a, b in zip(before, after)) < 0.05, (before, after)
    assert not _severe_console(driver)


def test_escape_on_the_page_halts_a_move_short_and_re_arm_is_answered(page, served):
    driver = page(served["operator"])
    _until(driver, 30, "return typeof view3d !== 'undefined' && view3d.rendered()", "a rendered 3-D view")
    _move_from_page(driver, [0, 0, 300, 0, 0, 0], relative=True)  # 3 s or more: time to see it move
    assert _reply(driver, 20, "move by").startswith("move by: accepted")
    _until(driver, 20, "return document.getElementById('motion').dataset.state === 'moving'", "the move under way")
    ActionChains(driver).send_keys(Keys.ESCAPE).perform()  # the key the Halt button also has
    assert _reply(driver, 20, "halt").startswith("halt: accepted")
    motion = _until(driver, 30, "const m = document.getElementById('motion');"
                                "return m.dataset.state === 'holding' ? m.textContent : null", "holding after the halt")
    assert "last motion halted" in motion, motion
    driver.find_element(By.ID, "rearm").click()
    answer = _reply(driver, 20, "re-arm")
    assert answer.startswith("re-arm: accepted") or answer.startswith("re-arm: refused: "), answer
    assert len(answer) > len("re-arm: refused: "), answer  # the bridge says what it did, or why not
    assert not _severe_console(driver)


def test_a_killed_kinematics_node_shows_the_bridges_hold_and_re_arm_from_the_page_resumes(page, served):
    """The bridge holds when its commands stop; the page shows the fault
    state and the bridge's fault; the launcher restarts the node, and the
    operator's re-arm from the page lets a move through again. How soon the
    page showed the hold is printed (the issue's target is 1 s; a test of a
    shared, possibly slow machine asserts only that it was shown)."""
    driver = page(served["operator"])
    _until(driver, 30, "return typeof view3d !== 'undefined' && view3d.rendered()", "a rendered 3-D view")
    kinematics = subprocess.check_output(["pgrep", "-f", f"edsp-kinematics .*--group {served['group']}"], text=True)
    killed = time.monotonic()
    os.kill(int(kinematics.split()[0]), signal.SIGKILL)
    _until(driver, 20, "return document.getElementById('motion').dataset.state === 'fault'", "the hold shown")
    print(f"the page showed the bridge's hold {time.monotonic() - killed:.3f} s after the kill")
    faults = driver.find_element(By.ID, "faults").text
    assert "actuator_bridge" in faults, faults
    deadline = time.monotonic() + 60
    while True:  # refused (with its reason) until the restarted node's commands flow again
        driver.find_element(By.ID, "rearm").click()
        answer = _reply(driver, 20, "re-arm")
        if answer.startswith("re-arm: accepted"):
            break
        assert answer.startswith("re-arm: refused: ") and time.monotonic() < deadline, answer
        time.sleep(1.0)
    _until(driver, 20, "return document.getElementById('motion').dataset.state !== 'fault'", "the hold lifted")
    _fill_goal(driver, [0, 0, 2, 0, 0, 0], relative=True)
    driver.find_element(By.ID, "move").click()
    assert _reply(driver, 20, "move by").startswith("move by: accepted"), driver.find_element(By.ID, "control-reply").text
    assert not _severe_console(driver)


def test_a_viewers_page_shows_the_rig_and_offers_no_control(page, served):
    driver = page(served["viewer"])
    _until(driver, 30, "return typeof view3d !== 'undefined' && view3d.rendered()", "a rendered 3-D view")
    _until(driver, 10, "return document.getElementById('control-role').textContent === 'viewer: read-only'",
           "the viewer's role shown")
    for button in ("move", "check", "halt", "stop", "rearm"):
        assert not driver.find_element(By.ID, button).is_enabled(), button
    assert not _severe_console(driver)


def test_over_tls_the_page_draws_and_its_websocket_is_wss(served, tmp_path):
    """--tls-cert/--tls-key: the page at https, its scripts, and the
    WebSocket the page opens (wss, from the page's scheme). The browser is
    told to accept the test's self-signed certificate."""
    cert, key = served_web.certificate(tmp_path)
    with served_web.server(tmp_path / "tls.err", served["group"], served["tokens"],
                           ["--tls-cert", cert, "--tls-key", key]) as (port, _):
        driver = _browser(tmp_path / "profile", ["--ignore-certificate-errors"])
        try:
            driver.get(f"https://127.0.0.1:{port}/?token={served['viewer']}")
            _until(driver, 30, "return typeof view3d !== 'undefined' && view3d.rendered()", "a rendered 3-D view")
            assert driver.execute_script("return panel.ws.url").startswith(f"wss://127.0.0.1:{port}/")
            assert not _severe_console(driver)
        finally:
            driver.quit()


def test_with_a_wrong_token_the_page_is_refused_and_no_script_runs(page, served):
    driver = page("wrong")
    assert "unknown token" in driver.find_element(By.TAG_NAME, "body").text
    assert driver.execute_script("return typeof view3d") == "undefined"
