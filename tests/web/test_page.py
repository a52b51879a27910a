"""The explorer's page in a real browser (headless Chromium through ChromeDriver): it loads and
draws the lobes of the starting case, redraws them when an input changes, checks and simulates
a clicked point, switches examples, and logs no console error. Skipped when Chromium,
ChromeDriver or Selenium is missing (./run installs them)."""

import os
import shutil

import pytest

webdriver = pytest.importorskip("selenium.webdriver")
from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.common.keys import Keys  # noqa: E402
from selenium.webdriver.support.ui import Select, WebDriverWait  # noqa: E402

from conftest import run_cli  # noqa: E402

CHROMIUM = shutil.which("chromium")
CHROMEDRIVER = shutil.which("chromedriver")
pytestmark = pytest.mark.skipif(not (CHROMIUM and CHROMEDRIVER),
                                reason="needs chromium and chromium-driver")


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--no-proxy-server",
                "--disable-dev-shm-usage", "--window-size=1280,900",
                f"--user-data-dir={tmp_path_factory.mktemp('chromium')}"):
        options.add_argument(arg)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    service = webdriver.ChromeService(executable_path=CHROMEDRIVER) \
        if hasattr(webdriver, "ChromeService") else \
        __import__("selenium.webdriver.chrome.service", fromlist=["Service"]).Service(CHROMEDRIVER)
    driver = webdriver.Chrome(service=service, options=options)
    yield driver
    driver.quit()


def wait(driver, condition, seconds=30):
    return WebDriverWait(driver, seconds).until(lambda d: condition(d))


def boundary(driver):
    """The drawn boundary: the points of its polylines (read in one script, so that a redraw
    between finding and reading them cannot get in the way)."""
    return driver.execute_script(
        "return [...document.querySelectorAll('#lobes-plot polyline.boundary')]"
        ".map((e) => e.getAttribute('points'));")


def console_errors(driver):
    return [e for e in driver.get_log("browser") if e["level"] == "SEVERE"]


def test_the_page_draws_changes_checks_and_simulates(server, browser):
    browser.get(server.url + "/")
    wait(browser, lambda d: boundary(d))
    first = boundary(browser)
    caption = browser.find_element(By.ID, "lobes-caption").text
    lowest = server.request("/api/lobes", body=server.request("/api/case")[1]["case"])[1]["lowest"]
    assert f"{lowest['critical_depth_mm']:.4g}" in caption, caption
    assert browser.find_elements(By.CSS_SELECTOR, "#lobes-plot polygon.stable")

    # An input, named after its case-file key: a stiffer tool raises the lobes.
    stiffness = browser.find_element(By.CSS_SELECTOR, '[data-key="modes[0].stiffness_n_per_m"]')
    value = float(stiffness.get_attribute("value"))
    # Typed over the selected text, not after clear(): an empty stiffness for longer than the
    # page's 120 ms pause (a loaded machine) is a case without one, which the server refuses
    # (400 in the console).
    stiffness.send_keys(Keys.CONTROL, "a")
    stiffness.send_keys(str(2 * value))
    wait(browser, lambda d: boundary(d) and boundary(d) != first)
    assert boundary(browser) != first

    # The method select redraws too.
    Select(browser.find_element(By.ID, "method")).select_by_value("zero-order")
    wait(browser, lambda d: "zero-order" in d.find_element(By.ID, "lobes-caption").text)

    # A click on the diagram: the verdict, then the simulated trace and its spectrum.
    plot = browser.find_element(By.CSS_SELECTOR, "#lobes-plot svg")
    webdriver.ActionChains(browser).move_to_element_with_offset(plot, 60, 80).click().perform()
    wait(browser, lambda d: "Simulated" in d.find_element(By.ID, "verdict").text, 60)
    verdict = browser.find_element(By.ID, "verdict").text
    assert "stable" in verdict or "chatter" in verdict
    assert browser.find_elements(By.CSS_SELECTOR, "#trace-plot polyline.series")
    assert browser.find_elements(By.CSS_SELECTOR, "#spectrum-plot polyline.series")
    assert browser.find_elements(By.CSS_SELECTOR, "#lobes-plot circle.point")
    shot = os.environ.get("CUTDYN_SCREENSHOT")
    if shot:
        browser.save_screenshot(shot)

    assert console_errors(browser) == []
    # A bad input: the server's message is shown, nothing breaks. (The browser logs the 400 of
    # that request as a network error; the log is read, so emptied, before and after.)
    damping = browser.find_element(By.CSS_SELECTOR, '[data-key="modes[0].damping_ratio"]')
    damping.clear()
    damping.send_keys("-1")
    wait(browser, lambda d: d.find_element(By.ID, "error").is_displayed())
    assert "damping_ratio" in browser.find_element(By.ID, "error").text
    damping.clear()
    damping.send_keys("0.02")
    wait(browser, lambda d: not d.find_element(By.ID, "error").is_displayed())
    assert all("status of 400" in e["message"] for e in console_errors(browser))

    # The busy note: hidden once the lobes are drawn; while a computation runs it appears after
    # half a second with the seconds spent, and goes when it ends.
    assert not browser.find_element(By.ID, "busy").is_displayed()
    browser.execute_script("setBusy(true);")
    wait(browser, lambda d: d.find_element(By.ID, "busy").is_displayed(), 5)
    assert "Computing the lobes" in browser.find_element(By.ID, "busy").text
    browser.execute_script("setBusy(false);")
    assert not browser.find_element(By.ID, "busy").is_displayed()

    # Another example: a turning case with vibration draws its conventional lobes too.
    Select(browser.find_element(By.ID, "example")).select_by_value("turning-ultrasonic")
    wait(browser, lambda d: "turning-ultrasonic" in d.find_element(By.ID, "lobes-caption").text, 60)
    assert console_errors(browser) == []


def test_the_page_fits_a_phone(server, browser):
    browser.set_window_size(390, 844)
    try:
        browser.get(server.url + "/")
        wait(browser, lambda d: boundary(d))
        width = browser.execute_script("return document.documentElement.scrollWidth")
        assert width <= 390 + 1, width  # no sideways scrolling
        assert console_errors(browser) == []
    finally:
        browser.set_window_size(1280, 900)


def test_the_downloads_are_the_command_lines_files(server, tmp_path_factory):
    # The two buttons, in a browser that saves downloads to a folder: the TOML is a case file
    # the command line reads back to the same case, the CSV is `cutdyn lobes --out` of it.
    folder = tmp_path_factory.mktemp("downloads")
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--no-proxy-server",
                "--disable-dev-shm-usage", f"--user-data-dir={tmp_path_factory.mktemp('c2')}"):
        options.add_argument(arg)
    options.add_experimental_option("prefs", {"download.default_directory": str(folder),
                                              "download.prompt_for_download": False})
    service = __import__("selenium.webdriver.chrome.service", fromlist=["Service"]) \
        .Service(CHROMEDRIVER)
    driver = webdriver.Chrome(service=service, options=options)
    try:
        driver.get(server.url + "/")
        wait(driver, lambda d: boundary(d))
        driver.find_element(By.ID, "download-toml").click()
        wait(driver, lambda d: (folder / "case.toml").exists())
        driver.find_element(By.ID, "download-csv").click()
        wait(driver, lambda d: (folder / "lobes.csv").exists() and
             (folder / "lobes.csv").stat().st_size > 0)
    finally:
        driver.quit()
    code, out, err = run_cli("lobes", str(folder / "case.toml"), "--out", str(folder / "cli.csv"))
    assert code == 0, err
    assert (folder / "lobes.csv").read_text() == (folder / "cli.csv").read_text()
