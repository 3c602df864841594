"""The HTML report in a real browser: headless Chromium renders it to a PNG screenshot.

Chromium is driven through the DevTools protocol over a pipe (``--remote-debugging-pipe``:
file descriptors 3 and 4, NUL-separated JSON), so no network port and no extra package are
needed.  The test checks that the page loads, that the console shows no error (a blocked
resource, a Content-Security-Policy violation or a script error would all appear there),
that every figure the report embeds is decoded with a non-zero size, that the untrusted
header cell is shown as text, and that the screenshot is a real, non-blank image.

It skips with a reason only when Chromium is not installed; CI installs Debian's
``chromium`` (see ``.ci/run``).  Set ``FOGTS_SCREENSHOT_DIR`` to keep the screenshot.
"""

from __future__ import annotations

import base64
import io
import json
import os
import select
import shutil
import subprocess
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from fogts.io.reader import read_run
from fogts.report.html import build_report, write_report

CHROMIUM_FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                  "--disable-background-networking", "--disable-component-update",
                  "--disable-sync", "--disable-quic", "--disable-extensions",
                  "--disable-default-apps", "--mute-audio", "--hide-scrollbars")


def _chromium() -> str:
    for name in ("chromium", "chromium-browser", "google-chrome", "chrome"):
        path = shutil.which(name)
        if path:
            return path
    pytest.skip("chromium is not installed (CI installs Debian's 'chromium'; locally: "
                "apt-get install chromium)")


class DevTools:
    """A minimal Chrome DevTools Protocol client over ``--remote-debugging-pipe``."""

    def __init__(self, binary: str, profile: Path, log: Path) -> None:
        to_chrome_r, self._to_chrome = os.pipe()
        self._from_chrome, from_chrome_w = os.pipe()

        def child_fds() -> None:  # runs in the child before exec: the pipe on fds 3 and 4
            a, b = os.dup(to_chrome_r), os.dup(from_chrome_w)
            os.dup2(a, 3)
            os.dup2(b, 4)

        self._log = log.open("wb")
        self.proc = subprocess.Popen(
            [binary, *CHROMIUM_FLAGS, f"--user-data-dir={profile}", "--remote-debugging-pipe",
             "about:blank"],
            stdin=subprocess.DEVNULL, stdout=self._log, stderr=self._log,
            preexec_fn=child_fds, close_fds=False, start_new_session=True)
        os.close(to_chrome_r)
        os.close(from_chrome_w)
        self._buf = b""
        self._id = 0
        self.events: list[dict[str, Any]] = []

    def _recv(self, deadline: float) -> dict[str, Any]:
        while b"\0" not in self._buf:
            left = deadline - time.monotonic()
            ready, _, _ = select.select([self._from_chrome], [], [], max(0.0, left))
            if not ready:
                raise TimeoutError("chromium did not answer in time")
            chunk = os.read(self._from_chrome, 1 << 20)
            if not chunk:
                raise EOFError("chromium closed the DevTools pipe")
            self._buf += chunk
        msg, _, self._buf = self._buf.partition(b"\0")
        return json.loads(msg)  # type: ignore[no-any-return]

    def call(self, method: str, params: dict[str, Any] | None = None,
             session: str | None = None, timeout_s: float = 60.0) -> dict[str, Any]:
        self._id += 1
        msg: dict[str, Any] = {"id": self._id, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        os.write(self._to_chrome, json.dumps(msg).encode() + b"\0")
        deadline = time.monotonic() + timeout_s
        while True:
            reply = self._recv(deadline)
            if reply.get("id") == self._id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})  # type: ignore[no-any-return]
            self.events.append(reply)

    def wait_for(self, method: str, timeout_s: float = 60.0) -> None:
        deadline = time.monotonic() + timeout_s
        while not any(e.get("method") == method for e in self.events):
            self.events.append(self._recv(deadline))

    def close(self) -> None:
        try:
            self.call("Browser.close", timeout_s=10)
        except Exception:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            os.killpg(self.proc.pid, 9)
            self.proc.wait(timeout=10)
        for fd in (self._to_chrome, self._from_chrome):
            try:
                os.close(fd)
            except OSError:
                pass
        self._log.close()


def _console_errors(events: list[dict[str, Any]]) -> list[str]:
    errors = []
    for e in events:
        method, params = e.get("method"), e.get("params", {})
        if method == "Runtime.exceptionThrown":
            errors.append(json.dumps(params.get("exceptionDetails", {}))[:300])
        elif method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
            errors.append(json.dumps(params.get("args", []))[:300])
        elif method == "Log.entryAdded" and params.get("entry", {}).get("level") == "error":
            errors.append(params["entry"].get("text", "")[:300])
    return errors


def _recording(path: Path) -> None:
    """A 10-minute 10 Hz record with a warm-up temperature and an untrusted header cell."""
    rng = np.random.default_rng(11)
    n, fs = 6_000, 10.0
    t = np.arange(n) / fs
    temp = 20.0 + 12.0 * (1.0 - np.exp(-t / 700.0)) + rng.normal(0.0, 0.02, n)
    rate = 0.4 + 0.03 * temp + rng.normal(0.0, 0.3, n) + np.cumsum(rng.normal(0.0, 0.002, n))
    with path.open("w") as fh:
        fh.write("# bench <b>A</b> & unit \"7\"\n")
        fh.write("time,rate,T,<script>alert(1)</script>\n")
        np.savetxt(fh, np.c_[t, rate, temp, np.ones(n)], delimiter=",", fmt="%.6f")


def test_report_renders_in_headless_chromium(tmp_path: Path) -> None:
    binary = _chromium()
    src = tmp_path / "bench.csv"
    _recording(src)
    report = build_report(read_run(src), title="Unit 7 <i>acceptance</i>")
    page = write_report(tmp_path / "report.html", report)
    expected_figures = report.n_figures
    assert expected_figures >= 3, report.summary()

    profile = tmp_path / "profile"
    profile.mkdir()
    dt = DevTools(binary, profile, tmp_path / "chromium.log")
    try:
        target = dt.call("Target.createTarget", {"url": "about:blank"})["targetId"]
        sid = dt.call("Target.attachToTarget", {"targetId": target, "flatten": True})[
            "sessionId"]
        for domain in ("Page.enable", "Runtime.enable", "Log.enable"):
            dt.call(domain, session=sid)
        dt.call("Emulation.setDeviceMetricsOverride", {"width": 1200, "height": 900,
                                                       "deviceScaleFactor": 1,
                                                       "mobile": False}, session=sid)
        dt.call("Page.navigate", {"url": page.resolve().as_uri()}, session=sid)
        dt.wait_for("Page.loadEventFired")
        probe = dt.call("Runtime.evaluate", {"returnByValue": True, "expression": """
            JSON.stringify({
              title: document.title,
              scripts: document.scripts.length,
              text: document.body.innerText,
              figures: [...document.querySelectorAll('figure[data-figure]')].map(f => {
                const img = f.querySelector('img');
                const r = img ? img.getBoundingClientRect() : {width: 0, height: 0};
                return {id: f.dataset.figure, complete: !!img && img.complete,
                        w: img ? img.naturalWidth : 0, h: img ? img.naturalHeight : 0,
                        shownW: r.width, shownH: r.height};
              }),
              height: document.documentElement.scrollHeight
            })"""}, session=sid)
        info = json.loads(probe["result"]["value"])
        metrics = dt.call("Page.getLayoutMetrics", session=sid)
        size = metrics.get("cssContentSize") or metrics["contentSize"]
        shot = dt.call("Page.captureScreenshot", {
            "format": "png", "captureBeyondViewport": True,
            "clip": {"x": 0, "y": 0, "width": 1200, "height": min(size["height"], 16000),
                     "scale": 1}}, session=sid)
        time.sleep(0.2)  # let late console events arrive
        dt.call("Runtime.evaluate", {"expression": "1"}, session=sid)
        events = list(dt.events)
    finally:
        dt.close()

    png = base64.b64decode(shot["data"])
    keep = os.environ.get("FOGTS_SCREENSHOT_DIR")
    if keep:
        Path(keep).mkdir(parents=True, exist_ok=True)
        (Path(keep) / "report.png").write_bytes(png)
    (tmp_path / "report.png").write_bytes(png)

    # loaded, no console errors (a CSP violation, a failed load or a script error)
    assert _console_errors(events) == []
    assert info["title"] == "Unit 7 <i>acceptance</i>"
    # untrusted strings are text: no script element, the header cell is visible as text
    assert info["scripts"] == 0
    assert "<script>alert(1)</script>" in info["text"]
    assert "bench <b>A</b> & unit \"7\"" in info["text"]
    # every figure present, decoded and shown with a non-zero size
    figs = info["figures"]
    assert len(figs) == expected_figures
    for f in figs:
        assert f["complete"] and f["w"] > 50 and f["h"] > 50, f
        assert f["shownW"] > 50 and f["shownH"] > 50, f
    # the screenshot is a real, non-blank page image
    from matplotlib.image import imread

    img = imread(io.BytesIO(png), format="png")
    assert img.shape[1] == 1200 and img.shape[0] >= 900
    assert float(np.std(img[..., :3])) > 0.05
