#!/usr/bin/python3
"""Loads an HTML page in headless Chromium and reports what went wrong (scripts/check_report.sh).

  check_report.py CHROMIUM PAGE.html SCREENSHOT.png PROFILE_DIR

Drives Chromium over the DevTools protocol on --remote-debugging-pipe (file
descriptors 3 and 4, NUL-terminated JSON: no websocket library needed), so
every failure is reported as an event, not guessed from log text:
  * console messages of level warning/error, uncaught exceptions, browser log
    entries of level error (e.g. "Failed to load resource: net::ERR_FILE_NOT_FOUND");
  * failed resource loads (Network.loadingFailed);
  * images that did not decode (naturalWidth 0): lazy images are made eager
    first, so the images below the first screen are checked too;
and writes a 1280x2000 screenshot of the page's top. Exit 1 when anything
failed, 2 when the browser could not be driven.
"""
import base64
import fcntl
import json
import os
import select
import subprocess
import sys
import time
from pathlib import Path

TIMEOUT = 90  # seconds for the whole check


class Browser:
    def __init__(self, chromium, profile):
        to_child_r, to_child_w = os.pipe()
        from_child_r, from_child_w = os.pipe()
        # Out of the way of 3 and 4, which the child gets.
        hi = [fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10) for fd in (to_child_r, from_child_w)]
        for fd in (to_child_r, from_child_w):
            os.close(fd)

        def child_fds():
            os.dup2(hi[0], 3)  # Chromium reads commands on 3
            os.dup2(hi[1], 4)  # and writes replies and events on 4

        self.proc = subprocess.Popen(
            [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--no-first-run",
             "--no-default-browser-check", "--remote-debugging-pipe", f"--user-data-dir={profile}",
             "--window-size=1280,2000", "about:blank"],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=open(Path(profile).with_suffix(".log"), "w"),
            preexec_fn=child_fds, close_fds=False)
        for fd in hi:
            os.close(fd)
        self.w, self.r = to_child_w, from_child_r
        self.buf = b""
        self.next_id = 0
        self.events = []
        self.deadline = time.monotonic() + TIMEOUT

    def _read_message(self, wait):
        while b"\0" not in self.buf:
            left = min(wait, self.deadline - time.monotonic())
            if left <= 0 or not select.select([self.r], [], [], left)[0]:
                return None
            chunk = os.read(self.r, 1 << 20)
            if not chunk:
                raise RuntimeError("chromium closed the DevTools pipe (crashed or refused --remote-debugging-pipe)")
            self.buf += chunk
        msg, self.buf = self.buf.split(b"\0", 1)
        return json.loads(msg)

    def send(self, method, params=None, session=None):
        self.next_id += 1
        msg = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        os.write(self.w, json.dumps(msg).encode() + b"\0")
        while True:
            reply = self._read_message(self.deadline - time.monotonic())
            if reply is None:
                raise RuntimeError(f"no reply to {method} from chromium in time")
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            self.events.append(reply)

    def pump(self, seconds, until=None):
        """Collects events for `seconds`, or until one satisfies `until`."""
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            msg = self._read_message(end - time.monotonic())
            if msg is None:
                return False
            self.events.append(msg)
            if until and until(msg):
                return True
        return False

    def close(self):
        try:
            self.send("Browser.close")
        except Exception:
            pass
        try:
            self.proc.wait(10)
        except subprocess.TimeoutExpired:
            self.proc.kill()


def problems_in(events, url_of_request):
    out = []
    for e in events:
        m, p = e.get("method"), e.get("params", {})
        if m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "warning", "assert"):
            text = " ".join(str(a.get("value", a.get("description", ""))) for a in p.get("args", []))
            out.append(f"console.{p['type']}: {text}")
        elif m == "Runtime.exceptionThrown":
            d = p.get("exceptionDetails", {})
            out.append(f"uncaught exception: {d.get('exception', {}).get('description') or d.get('text')}")
        elif m == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
            entry = p["entry"]
            out.append(f"console error: {entry.get('text')} {entry.get('url', '')}".rstrip())
        elif m == "Network.loadingFailed" and not p.get("canceled"):
            out.append(f"failed load: {url_of_request.get(p.get('requestId'), '?')}: {p.get('errorText')}")
    return out


def main():
    if len(sys.argv) != 5:
        print(__doc__, file=sys.stderr)
        return 2
    chromium, page, shot, profile = sys.argv[1:]
    url = Path(page).resolve().as_uri()
    b = Browser(chromium, profile)
    try:
        target = b.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        s = b.send("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        for domain in ("Page", "Runtime", "Log", "Network"):
            b.send(f"{domain}.enable", session=s)
        b.send("Emulation.setDeviceMetricsOverride",
               {"width": 1280, "height": 2000, "deviceScaleFactor": 1, "mobile": False}, session=s)
        nav = b.send("Page.navigate", {"url": url}, session=s)
        if nav.get("errorText"):
            print(f"check_report: cannot open {url}: {nav['errorText']}", file=sys.stderr)
            return 1
        if not b.pump(30, lambda m: m.get("method") == "Page.loadEventFired" and m.get("sessionId") == s):
            print("check_report: the page did not finish loading in 30 s", file=sys.stderr)
            return 1
        # Lazy images below the first screen: load them all, then wait for them.
        b.send("Runtime.evaluate", {"expression": "document.querySelectorAll('img').forEach(i => i.loading = 'eager')"},
               session=s)
        b.send("Runtime.evaluate", {"awaitPromise": True, "expression": (
            "Promise.all(Array.from(document.images).map(i => i.decode().catch(() => null)))")}, session=s)
        b.pump(0.5)
        images = b.send("Runtime.evaluate", {"returnByValue": True, "expression": (
            "Array.from(document.images).map(i => [i.getAttribute('src'), i.complete, i.naturalWidth])")},
            session=s)["result"]["value"]
        counts = b.send("Runtime.evaluate", {"returnByValue": True, "expression": (
            "[document.querySelectorAll('svg').length, document.querySelectorAll('table').length,"
            " document.querySelectorAll('script').length, document.title]")}, session=s)["result"]["value"]
        b.send("Runtime.evaluate", {"expression": "window.scrollTo(0, 0)"}, session=s)
        png = b.send("Page.captureScreenshot", {"format": "png"}, session=s)["data"]
        Path(shot).write_bytes(base64.b64decode(png))
    except RuntimeError as e:
        print(f"check_report: {e}", file=sys.stderr)
        return 2
    finally:
        b.close()

    url_of_request = {e["params"]["requestId"]: e["params"]["request"]["url"]
                      for e in b.events if e.get("method") == "Network.requestWillBeSent"}
    problems = problems_in(b.events, url_of_request)
    problems += [f"image not shown: {src}" for src, complete, width in images if not (complete and width > 0)]
    svgs, tables, scripts, title = counts
    print(f"check_report: loaded '{title}': {len(images)} images, {svgs} SVG charts, {tables} tables, "
          f"{scripts} scripts, {len(url_of_request)} requests")
    for p in dict.fromkeys(problems):
        print(f"check_report: {p}", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
