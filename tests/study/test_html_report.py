"""``report.html``: self-contained, and checked in a real browser (headless Chromium over the DevTools
protocol on a pipe, no Python dependency): no console errors, every plot drawn, nothing wider than the
viewport, sortable tables, and readable with JavaScript off. Skipped with the reason where no Chromium
is installed (CI installs Debian's ``chromium``)."""

from __future__ import annotations

import base64
import fcntl
import json
import os
import re
import select
import shutil
import struct
import subprocess
import time
from pathlib import Path
from typing import Any

import pytest

from ddgsa.cli import main
from ddgsa.report.html import write_html

RESULTS = Path(__file__).parents[2] / "results"
BROWSERS = ("chromium", "chromium-browser", "google-chrome", "chrome")
BROWSER = next((shutil.which(b) for b in BROWSERS if shutil.which(b)), None)
needs_browser = pytest.mark.skipif(BROWSER is None, reason="no Chromium on PATH (tried: " + ", ".join(BROWSERS)
                                   + "); install Debian's `chromium` to run the browser test")
FOLDERS = {   # committed results that together carry every kind of chart the page draws
    "paper_a_faults": {"bars", "scatter", "pod", "png"},
    "paper_c_structural_published": {"bars", "heatmap", "scatter"},
    "paper_a_structural": {"bars", "heatmap", "scatter"},
    "seed003_bearing_stiffness_sweep": {"sweep"},
    "hss_rig_campbell": {"campbell"},
    "accuracy_cost": {"convergence", "png"},
    "direct_drive_spectrum": {"signal", "convergence"},
    "direct_drive_groups": {"bars"},
}
LARGE = {"paper_a_structural"}
"""Folders whose page is checked in the slow run only: paper_a_structural's 2.8 MB page (27 parameters, many
panels) took 19 s in Chromium; paper_c_structural_published carries the same chart kinds in the default run."""


def _report(tmp_path: Path, name: str) -> Path:
    folder = tmp_path / name
    shutil.copytree(RESULTS / name, folder)
    return write_html(folder)


class Chromium:
    """Headless Chromium driven over ``--remote-debugging-pipe`` (fd 3: commands in, fd 4: replies out;
    each message a JSON object ended by a NUL byte)."""

    def __init__(self, profile: Path, width: int = 1280, height: int = 900) -> None:
        to_child, self._w = os.pipe()
        self._r, from_child = os.pipe()
        cin, cout = (fcntl.fcntl(fd, fcntl.F_DUPFD, 10) for fd in (to_child, from_child))

        def fds() -> None:
            os.dup2(cin, 3)
            os.dup2(cout, 4)

        args = [BROWSER, "--headless=new", "--remote-debugging-pipe", "--disable-gpu", "--no-first-run",
                "--no-default-browser-check", "--disable-extensions", "--allow-file-access-from-files",
                f"--user-data-dir={profile}", f"--window-size={width},{height}", "about:blank"]
        if os.geteuid() == 0:
            args.insert(1, "--no-sandbox")      # Chromium refuses to sandbox as root (CI containers)
        self.proc = subprocess.Popen(args, pass_fds=(3, 4), preexec_fn=fds, stdout=subprocess.DEVNULL,
                                     stderr=subprocess.DEVNULL)
        for fd in (to_child, from_child, cin, cout):
            os.close(fd)
        self._buf, self._id, self.events = b"", 0, []
        target = self.send("Target.createTarget", url="about:blank")["targetId"]
        self.session = self.send("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]
        for domain in ("Page", "Runtime", "Log"):
            self.call(f"{domain}.enable")
        self.call("Emulation.setDeviceMetricsOverride", width=width, height=height, deviceScaleFactor=1, mobile=False)

    def send(self, method: str, session: str | None = None, **params: Any) -> dict[str, Any]:
        self._id += 1
        msg: dict[str, Any] = {"id": self._id, "method": method, "params": params}
        if session:
            msg["sessionId"] = session
        os.write(self._w, json.dumps(msg).encode() + b"\0")
        while True:
            reply = self._next(30.0)
            if reply.get("id") == self._id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            self.events.append(reply)

    def call(self, method: str, **params: Any) -> dict[str, Any]:
        return self.send(method, self.session, **params)

    def _next(self, timeout: float) -> dict[str, Any]:
        end = time.monotonic() + timeout
        while b"\0" not in self._buf:
            ready, _, _ = select.select([self._r], [], [], max(end - time.monotonic(), 0.0))
            chunk = os.read(self._r, 1 << 20) if ready else b""
            if not chunk:
                raise TimeoutError("no reply from Chromium")
            self._buf += chunk
        msg, self._buf = self._buf.split(b"\0", 1)
        return json.loads(msg)

    def open(self, url: str) -> None:
        """Navigate and wait for the load event."""
        self.events.clear()
        self.call("Page.navigate", url=url)
        end = time.monotonic() + 30.0
        while not any(e.get("method") == "Page.loadEventFired" for e in self.events):
            self.events.append(self._next(end - time.monotonic()))

    def js(self, expression: str) -> Any:
        res = self.call("Runtime.evaluate", expression=expression, returnByValue=True, awaitPromise=True)
        if "exceptionDetails" in res:
            raise RuntimeError(res["exceptionDetails"])
        return res["result"].get("value")

    def errors(self) -> list[str]:
        """Console errors and warnings, uncaught exceptions and browser log errors since the last :meth:`open`."""
        out = []
        for e in self.events:
            m, p = e.get("method"), e.get("params", {})
            if m == "Runtime.exceptionThrown":
                out.append(json.dumps(p["exceptionDetails"])[:300])
            elif m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "warning", "assert"):
                out.append(f"console.{p['type']}: {p.get('args')}")
            elif m == "Log.entryAdded" and p["entry"].get("level") in ("error", "warning"):
                out.append(f"log {p['entry']['level']}: {p['entry'].get('text')} {p['entry'].get('url', '')}")
        return out

    def close(self) -> None:
        try:
            self.send("Browser.close")
        except (OSError, RuntimeError, TimeoutError):
            pass
        try:
            self.proc.wait(10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait(10)
        os.close(self._w)
        os.close(self._r)


@pytest.fixture
def browser(tmp_path: Path) -> Any:
    b = Chromium(tmp_path / "profile")
    yield b
    b.close()


PLOTS_DRAWN = """[...document.querySelectorAll('figure.plot')].map(f => {
  const svg = f.querySelector(':scope > svg'), img = f.querySelector(':scope > img');
  const r = (svg || img).getBoundingClientRect();
  return {kind: f.dataset.kind, w: r.width, h: r.height,
          marks: svg ? [...svg.querySelectorAll('.series, .mark')].filter(g => g.querySelector('path, use, image'))
                           .length
                     : (img.complete ? img.naturalWidth : 0)};
})"""
LEGEND_TOGGLE = """(() => {   // a click on a chart's first legend entry hides its series, a second shows it again
  const item = document.querySelector('svg .legend-item[data-series]');
  if (!item) { return null; }
  const marks = () => [...item.ownerSVGElement.querySelectorAll(`.series[data-series="${item.dataset.series}"]`)];
  const shown = () => marks().length > 0 && marks().every(g => getComputedStyle(g).display !== 'none');
  const before = shown();
  item.dispatchEvent(new MouseEvent('click', {bubbles: true}));
  const hidden = marks().every(g => getComputedStyle(g).display === 'none');
  item.dispatchEvent(new MouseEvent('click', {bubbles: true}));
  return {before, hidden, after: shown()};
})()"""
WIDEST = """({scroll: document.documentElement.scrollWidth, inner: document.documentElement.clientWidth,
  outside: [...document.querySelectorAll('body *')].filter(e => !e.closest('.scroll, svg') &&
           e.getBoundingClientRect().right > window.innerWidth + 1).map(e => e.tagName + '.' + e.className).slice(0, 5)})"""


def _png_size(path: Path) -> tuple[int, int]:
    head = path.read_bytes()[:24]
    assert head[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", head[16:24])


@needs_browser
@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n in LARGE else n for n in sorted(FOLDERS)])
def test_report_opens_offline_in_chromium_with_every_plot_drawn(browser: Chromium, tmp_path: Path,
                                                                 name: str) -> None:
    html = _report(tmp_path, name)
    browser.open(html.as_uri())
    assert browser.errors() == []
    plots = browser.js(PLOTS_DRAWN)
    assert {p["kind"] for p in plots} >= FOLDERS[name]
    empty = [p for p in plots if not (p["w"] > 50 and p["h"] > 20 and p["marks"] > 0)]
    assert plots and not empty, empty
    toggled = browser.js(LEGEND_TOGGLE)
    assert toggled is None or toggled == {"before": True, "hidden": True, "after": True}, toggled
    for width in (1280, 400):     # a laptop and a phone
        browser.call("Emulation.setDeviceMetricsOverride", width=width, height=900, deviceScaleFactor=1, mobile=False)
        wide = browser.js(WIDEST)
        assert wide["scroll"] <= wide["inner"] and not wide["outside"], (width, wide)
        shot = tmp_path / f"screenshot_{width}.png"
        shot.write_bytes(base64.b64decode(browser.call("Page.captureScreenshot", format="png")["data"]))
        assert _png_size(shot) == (width, 900)
    from PIL import Image

    with Image.open(shot) as im:          # the phone screenshot shows a page, not a blank
        assert len(im.convert("L").getcolors(1 << 16) or []) > 20


@needs_browser
def test_index_table_sorts_on_click_and_reads_without_javascript(browser: Chromium, tmp_path: Path) -> None:
    html = _report(tmp_path, "quickstart")
    browser.open(html.as_uri())
    col = browser.js("[...document.querySelectorAll('#t-indices th')].findIndex(th => th.textContent === 'ST')")
    # rows without a value (given_data_s1 gives no ST) sort after the numbers either way; the numbers are compared
    values = (f"[...document.querySelectorAll('#t-indices tbody tr')].map(r => r.cells[{col}].textContent.trim())"
              ".filter(t => t !== '' && t.toLowerCase() !== 'nan').map(Number)")
    before = browser.js(values)
    browser.js(f"document.querySelectorAll('#t-indices th')[{col}].click()")
    asc = browser.js(values)
    browser.js(f"document.querySelectorAll('#t-indices th')[{col}].click()")
    assert asc == sorted(before) and browser.js(values) == sorted(before, reverse=True) and before != asc
    browser.js("const f = document.querySelector('input.filter[data-table=t-indices]');"
               "f.value = 'k_rear_z'; f.dispatchEvent(new Event('input'))")
    shown = browser.js("[...document.querySelectorAll('#t-indices tbody tr')].filter(r => !r.hidden).length")
    assert shown == sum("k_rear_z" in line for line in (tmp_path / "quickstart" / "indices.csv").open())
    browser.call("Emulation.setScriptExecutionDisabled", value=True)
    browser.open(html.as_uri())
    state = browser.js(
        "({js: document.documentElement.classList.contains('js'),"
        " filters: [...document.querySelectorAll('input.filter')].filter(i => i.offsetWidth > 0).length,"
        " drawn: [...document.querySelectorAll('figure.plot > svg, figure.plot > img')].filter(e =>"
        "        e.getBoundingClientRect().width > 50).length, total: document.querySelectorAll('figure.plot').length})")
    assert not state["js"] and state["filters"] == 0 and state["drawn"] == state["total"] > 0   # the page's script did not run


def test_report_is_self_contained_with_units_on_every_axis(tmp_path: Path) -> None:
    """No reference leaves the file (no http(s), no relative src/href/url()), and the Campbell diagram's and
    the sweep's axes carry the units of what they plot (rpm, Hz; bearing stiffness N/m, frequency Hz)."""
    for name in ("hss_rig_campbell", "seed003_bearing_stiffness_sweep", "paper_a_faults"):
        text = _report(tmp_path, name).read_text()
        loads = re.findall(r'\b(?:src|srcset|data|poster)="([^"]*)"|url\(([^)]*)\)|@import', text)
        assert all(b.startswith("#") if b else a.startswith("data:image/png;base64,") for a, b in loads)  # url(#clip)
        assert not re.search(r"<(link|iframe|object|embed)\b|<script[^>]+src=", text)
        assert all(h.startswith("#") for h in re.findall(r'href="([^"]*)"', text))
    campbell = (tmp_path / "hss_rig_campbell" / "report.html").read_text()
    assert ">rotor speed [rpm]<" in campbell and ">frequency [Hz]<" in campbell
    sweep = (tmp_path / "seed003_bearing_stiffness_sweep" / "report.html").read_text()
    assert ">bearing_stiffness [N/m]<" in sweep and ">bearing_frequency_hz [Hz]<" in sweep
    faults = (tmp_path / "paper_a_faults" / "report.html").read_text()
    assert ">probability of detection [-]<" in faults and "[?]" not in faults


def test_cli_html_rebuilds_committed_folders_and_refuses_a_file(tmp_path: Path, capsys: Any) -> None:
    for name in ("quickstart", "seed003_frequencies"):
        shutil.copytree(RESULTS / name, tmp_path / name)
    assert main(["html", str(tmp_path / "quickstart"), str(tmp_path / "seed003_frequencies")]) == 0
    assert (tmp_path / "quickstart" / "report.html").stat().st_size > 10_000
    assert main(["html", str(tmp_path / "quickstart" / "summary.md")]) == 2
    assert "not a folder" in capsys.readouterr().err
    stray = tmp_path / "notes"
    stray.mkdir()
    (stray / "notes.txt").write_text("nothing a report shows\n")
    assert main(["html", str(stray)]) == 2                      # not a results folder: refused, nothing written
    assert "not a results folder" in capsys.readouterr().err
    assert not (stray / "report.html").exists()


def test_model_options_are_named_in_summary_and_provenance(tmp_path: Path) -> None:
    """A variant chosen by model options (seed 000's printed readings) shows in the summary's model
    line and the page's provenance, not only in study.yaml."""
    from ddgsa.report.sections.provenance import model_words

    assert model_words({"name": "direct_drive", "fidelity": "rigid", "options": {}}) == "rigid"
    assert model_words({"fidelity": "linear", "options": {"bending_rayleigh": "printed", "deflection": "frame"}}) \
        == "linear; bending_rayleigh=printed; deflection=frame"
    page = _report(tmp_path, "paper_c_structural_published").read_text()
    line = page.split("<dt>model</dt><dd>", 1)[1].split("<", 1)[0]
    assert line.startswith("direct_drive (linear; ")
    assert "bearing_damping=stiffness_proportional;" in line and "bending_rayleigh=printed;" in line



def test_the_verdicts_section_says_what_the_confirm_escalation_spent_and_why_it_stopped(tmp_path: Path) -> None:
    """Newcomer trial (#48): a time budget's escalation ran 981 runs and stopped on the budget; only the console
    and provenance.json said so. The page's Verdicts section now says it, from provenance.json."""
    (tmp_path / "confirmation.csv").write_text(
        "scene,output,verdict,method,runs,std,resolution,ranking,next_step,next_runs,next_seconds\n"
        "0,y,unconfirmed,mdrm,24,1.0,0,,add saltelli,7168,500\n")
    stop = "stopped by the time budget (120 s): the next stage's 7168 runs would take ~366 s, 61.7 s were left"
    (tmp_path / "provenance.json").write_text(json.dumps(
        {"study": "c", "confirm": [{"scene": 0, "budget": None, "time_s": 120.0, "spent": 981, "log": ["...", stop]}]}))
    (tmp_path / "study.yaml").write_text("scenes: {realisations: 2}\n")
    page = write_html(tmp_path).read_text()
    verdicts = page.split('<section id="confirmation">')[1].split("</section>")[0]
    assert "escalation, scene 0: 1962 runs spent (budget: 120 s of wall time); last: " + stop in verdicts
