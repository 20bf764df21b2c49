"""Drives `hdgear serve` in a real Chromium (Debian's, through Playwright; no browser download).

    python explorer.py URL CHROMIUM OUTDIR [MODEL_URL]

Loads the page at γ = 30, checks the verdict says "not bursting", drags the γ slider with the
mouse from 30 down to 0.1 (a storm of input events), checks the verdict turns to "bursting", the
equilibrium curve was redrawn (its path changed), the quick button γ = 0.1 gives the study's
numbers, the permalink reproduces the view, a bad value shows the server's one-line message, and
no console error or page error occurred; with MODEL_URL (a server of a scenario with smooth
friction), that the model's parameters are sliders and its friction level changes the view.
Screenshots at 1400 and 800 px wide go to OUTDIR.
Prints one JSON line of what it measured; exits 1 on the first failed check.
"""
import json
import math
import sys
import time

from playwright.sync_api import sync_playwright

URL, CHROMIUM, OUT = sys.argv[1], sys.argv[2], sys.argv[3]
MODEL_URL = sys.argv[4] if len(sys.argv) > 4 else None
ARGS = ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def check(cond, what):
    if not cond:
        print(f"FAILED: {what}", file=sys.stderr)
        sys.exit(1)


def verdict(page):
    return page.locator("#verdict-word").inner_text(timeout=10_000)


def settle(page):
    """Waits until no request is in flight and the view is current."""
    page.wait_for_function("!document.body.classList.contains('stale')", timeout=10_000)


def slider_x(box, value):
    lo, hi = math.log10(1e-3), math.log10(100)
    f = (math.log10(value) - lo) / (hi - lo)
    # the thumb's centre travels between half a thumb from either end (about 8 px)
    return box["x"] + 8 + f * (box["width"] - 16)


with sync_playwright() as p:
    browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
    page = browser.new_page(viewport={"width": 1400, "height": 1000})
    errors = []
    page.on("console", lambda m: errors.append(f"console {m.type}: {m.text}") if m.type == "error" else None)
    page.on("pageerror", lambda e: errors.append(f"page error: {e}"))
    page.goto(URL + "?gamma=30")
    check(verdict(page) == "not bursting", "γ = 30 is not bursting")
    settle(page)
    curve_30 = page.locator("#curve-stable").get_attribute("d")
    page.screenshot(path=f"{OUT}/explorer-g30-1400.png", full_page=True)

    # drag the γ thumb from 30 to 0.1
    box = page.locator("#s-gamma").bounding_box()
    y = box["y"] + box["height"] / 2
    page.mouse.move(slider_x(box, 30), y)
    page.mouse.down()
    t0 = time.time()
    for k in range(1, 41):
        v = 30 * (0.1 / 30) ** (k / 40)
        page.mouse.move(slider_x(box, v), y)
        page.wait_for_timeout(15)
    page.mouse.up()
    settle(page)
    drag_s = time.time() - t0
    g = float(page.locator("#n-gamma").input_value())
    check(abs(math.log10(g / 0.1)) < 0.02, f"the slider ended near γ = 0.1 (at {g})")
    check(verdict(page) == "bursting", f"γ ≈ 0.1 is bursting (verdict: {verdict(page)})")
    curve_01 = page.locator("#curve-stable").get_attribute("d")
    check(curve_01 != curve_30 and len(curve_01) > 100, "the curve was redrawn")

    # the study's point exactly, and how long one update takes
    t0 = time.time()
    page.click("button[data-gamma='0.1']")
    settle(page)
    update_ms = (time.time() - t0) * 1000
    check("gamma=0.1" in page.url, f"the permalink follows the parameters ({page.url})")
    text = page.locator("#verdict").inner_text()
    check("pronounced-bursting" in text and "overshoot, ringing" in text, f"study point verdict: {text}")
    bursts = page.locator("#trace rect").count()
    check(bursts >= 1, "bursts are shaded in the x'(τ) view")
    page.screenshot(path=f"{OUT}/explorer-g0.1-1400.png", full_page=True)
    full = page.locator("#curve-stable").get_attribute("d")
    page.click("#zoom")
    check(page.locator("#curve-stable").get_attribute("d") != full, "zoom redraws the phase portrait")
    page.locator(".views").screenshot(path=f"{OUT}/explorer-g0.1-zoom.png")
    page.click("#zoom")

    # hover shows values
    pbox = page.locator("#phase").bounding_box()
    page.mouse.move(pbox["x"] + pbox["width"] * 0.5, pbox["y"] + pbox["height"] * 0.5)
    tip = page.locator("#tip").inner_text()
    check("x* =" in tip and "dx/da" in tip, f"hover shows curve values ({tip!r})")

    # downloads: the JSON of what is shown, the trajectory CSV, an SVG of a view
    with page.expect_download() as d:
        page.click("#dl-json")
    shown = json.loads(open(d.value.path()).read())
    check(shown["params"]["gamma"] == 0.1 and shown["classification"]["bursting"], "JSON download")
    with page.expect_download() as d:
        page.click("#dl-csv")
    rows = open(d.value.path()).read().splitlines()
    check(rows[0] == "t,a,x,xdot" and len(rows) > 1000, f"CSV download ({rows[:2]})")
    with page.expect_download() as d:
        page.click("button.svg-dl[data-view='slope']")
    svg = open(d.value.path()).read()
    check(svg.startswith("<svg") and "slope-path" in svg, "SVG download")

    # the boundaries located by simulation, on demand
    page.click("#simulate-b")
    page.wait_for_function("document.getElementById('simulated').textContent.startsWith('γ')", timeout=60_000)
    located = page.locator("#simulated").inner_text()

    # burst control: virtual damping assessed at k_d = 3 removes the study point's bursts, and
    # tuned (no gain) it reports its least gain
    page.click("#control summary")
    page.select_option("#law", "vdamping")
    page.fill("#gain", "3")
    page.click("#run-control")
    page.wait_for_function("document.getElementById('control-out').querySelector('table')", timeout=30_000)
    assessed = page.locator("#control-out").inner_text()
    check("no-bursts" in assessed and "overshoot" in assessed, f"k_d = 3 removes the bursts ({assessed!r})")
    page.fill("#gain", "")
    page.click("#run-control")
    page.wait_for_function("document.getElementById('control-out').innerText.includes('least gain that removes')",
                           timeout=60_000)
    tuned = page.locator("#control-out").inner_text()
    check("no-bursts" in tuned, f"the tuned law removes the bursts ({tuned!r})")

    # a catalogue drive: its reduced parameters (α·ε = 1) replace the sliders
    page.click("#physical summary")
    page.select_option("#drive", "CSF-32-50")
    page.click("#use-drive")
    page.wait_for_function("document.getElementById('drive-info').textContent.includes('α·ε = 1')", timeout=10_000)
    settle(page)
    check(abs(float(page.locator("#n-alpha").input_value()) * float(page.locator("#n-eps").input_value()) - 1) < 1e-5,
          "the drive's α·ε = 1 is in the fields")
    check("not 1" not in page.locator("#verdict").inner_text(), "no α·ε warning for a physical drive")
    drive_verdict = verdict(page)
    page.screenshot(path=f"{OUT}/explorer-drive-1400.png", full_page=True)
    mu_pos = int(page.locator("#s-mu").input_value())
    check(0 < mu_pos < 1000, f"the μ slider's range grew to hold the drive's μ (at {mu_pos})")
    page.click("#reset")
    settle(page)

    # a permalink reproduces the view in a fresh page
    link = page.url
    check("gamma=0.1" in link and "alpha=16" in link, f"permalink {link}")
    other = browser.new_page(viewport={"width": 800, "height": 1400})
    other.on("console", lambda m: errors.append(f"console {m.type}: {m.text}") if m.type == "error" else None)
    other.on("pageerror", lambda e: errors.append(f"page error: {e}"))
    other.goto(link)
    check(verdict(other) == "bursting", "the permalink reproduces the verdict")
    settle(other)
    other.screenshot(path=f"{OUT}/explorer-g0.1-800.png", full_page=True)

    # a bad value: the server's message, no crash
    page.fill("#n-omega", "-1")
    page.press("#n-omega", "Enter")
    page.wait_for_selector("#verdict .err", timeout=10_000)
    err = page.locator("#verdict .err").inner_text()
    check("invalid parameter omega" in err, f"a bad ω shows the server's message ({err!r})")

    # a scenario's model (MODEL_URL, served with --config: friction f_c tanh(x'/v_s) at γ = 0.1):
    # its friction level is a slider, and raising it changes the view
    model = {}
    if MODEL_URL:
        mp = browser.new_page(viewport={"width": 1400, "height": 1000})
        mp.on("console", lambda m: errors.append(f"console {m.type}: {m.text}") if m.type == "error" else None)
        mp.on("pageerror", lambda e: errors.append(f"page error: {e}"))
        mp.goto(MODEL_URL)
        verdict(mp)
        settle(mp)
        keys = mp.eval_on_selector_all("#sliders input[type=range]", "els => els.map(e => e.getAttribute('aria-label'))")
        check(keys == ["alpha", "gamma", "eps", "mu", "delta", "omega", "fc", "vs"], f"the model's sliders ({keys})")
        text = mp.locator("#verdict").inner_text()
        check("damping at rest" in text, f"the verdict shows the model's curve ({text!r})")
        check("tanh" in mp.locator("#equation").inner_text(), "the page names the model's equation")
        peak = mp.locator("#trace-path").get_attribute("d")
        mp.fill("#n-fc", "0.5")
        mp.press("#n-fc", "Enter")
        settle(mp)
        check(mp.locator("#trace-path").get_attribute("d") != peak, "f_c = 0.5 redraws the response")
        check("damping at rest\n11" in mp.locator("#verdict").inner_text(), "1 + f_c/v_s = 11 at rest")
        check("fc=0.5" in mp.url, f"the permalink holds f_c ({mp.url})")
        mp.screenshot(path=f"{OUT}/explorer-model-1400.png", full_page=True)
        model = {"model_verdict": verdict(mp)}
    # console errors from the 400 response itself are the browser's network log, not the page's
    errors = [e for e in errors if "status of 400" not in e]
    check(not errors, f"no console errors: {errors}")
    browser.close()
    print(json.dumps({"drag_seconds": round(drag_s, 2), "update_ms": round(update_ms),
                      "bursts_shaded": bursts, "gamma_after_drag": g, "located": located,
                      "csf_32_50": drive_verdict, **model}))
