"""Load a page in headless Chromium over the DevTools protocol: check it, photograph it.

Used by tests/test_documents.py (every HTML document is checked in a real browser)
and to make the README's screenshot:

    python tools/browser.py --screenshot docs/derivation.png examples/seed_disk_wall.mom

Standard library only: a tiny WebSocket client speaks the DevTools protocol to the
OS's Chromium (`/usr/bin/chromium`, or $CHROMIUM); nothing is downloaded.
"""
from __future__ import annotations

import base64
import json
import os
import re
import shutil
import socket
import struct
import subprocess
import sys
import tempfile
import time
import zlib
from pathlib import Path
from urllib.parse import urlparse

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--hide-scrollbars", "--remote-debugging-port=0"]


def find_chromium() -> str | None:
    """The Chromium to use: $CHROMIUM, else the OS package's, else one on PATH."""
    for c in (os.environ.get("CHROMIUM"), "/usr/bin/chromium", shutil.which("chromium"),
              shutil.which("chromium-browser"), shutil.which("google-chrome")):
        if c and os.path.isfile(c) and os.access(c, os.X_OK):
            return c
    return None


class BrowserError(Exception):
    """Chromium did not start, or the protocol answered with an error."""


# ---- a minimal WebSocket client (RFC 6455: text frames, client-side masking) ------------
class _WebSocket:
    def __init__(self, url: str, timeout: float):
        u = urlparse(url)
        self.sock = socket.create_connection((u.hostname, u.port), timeout=timeout)
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall((f"GET {u.path} HTTP/1.1\r\nHost: {u.hostname}:{u.port}\r\n"
                           "Upgrade: websocket\r\nConnection: Upgrade\r\n"
                           f"Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n")
                          .encode())
        head = b""
        while b"\r\n\r\n" not in head:
            chunk = self.sock.recv(4096)
            if not chunk:
                raise BrowserError("the DevTools socket closed during the handshake")
            head += chunk
        status, _, rest = head.partition(b"\r\n\r\n")
        if b" 101 " not in status.split(b"\r\n")[0]:
            raise BrowserError(f"DevTools handshake refused: {status[:80]!r}")
        self.buf = rest

    def send(self, text: str) -> None:
        data = text.encode()
        head = bytes([0x81])
        n = len(data)
        if n < 126:
            head += bytes([0x80 | n])
        elif n < 65536:
            head += bytes([0x80 | 126]) + struct.pack(">H", n)
        else:
            head += bytes([0x80 | 127]) + struct.pack(">Q", n)
        mask = os.urandom(4)
        body = bytes(b ^ mask[i % 4] for i, b in enumerate(data))
        self.sock.sendall(head + mask + body)

    def _read(self, n: int) -> bytes:
        while len(self.buf) < n:
            chunk = self.sock.recv(1 << 16)
            if not chunk:
                raise BrowserError("the DevTools socket closed")
            self.buf += chunk
        out, self.buf = self.buf[:n], self.buf[n:]
        return out

    def recv(self) -> str:
        parts = []
        while True:
            b0, b1 = self._read(2)
            n = b1 & 0x7F
            if n == 126:
                n = struct.unpack(">H", self._read(2))[0]
            elif n == 127:
                n = struct.unpack(">Q", self._read(8))[0]
            payload = self._read(n)
            op = b0 & 0x0F
            if op == 0x8:
                raise BrowserError("the DevTools socket was closed by the browser")
            if op in (0x9, 0xA):  # ping / pong: no answer needed by Chromium
                continue
            parts.append(payload)
            if b0 & 0x80:
                return b"".join(parts).decode()

    def close(self) -> None:
        try:
            self.sock.close()
        except OSError:
            pass


# ---- the browser --------------------------------------------------------------------------
class Chromium:
    """A headless Chromium with its own empty profile, driven over DevTools."""

    def __init__(self, executable: str | None = None, timeout: float = 60.0):
        self.executable = executable or find_chromium()
        if self.executable is None:
            raise BrowserError("no Chromium found (set $CHROMIUM or install the chromium "
                               "package)")
        self.timeout = timeout
        self.profile = tempfile.mkdtemp(prefix="momentum-chromium-")
        self.proc = subprocess.Popen([self.executable, *FLAGS,
                                      f"--user-data-dir={self.profile}", "about:blank"],
                                     stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        url = self._devtools_url()
        self.ws = _WebSocket(url, timeout)
        self.next_id = 0
        self.events: list[dict] = []
        target = self.call("Target.createTarget", url="about:blank")["targetId"]
        self.session = self.call("Target.attachToTarget", targetId=target,
                                 flatten=True)["sessionId"]

    def _devtools_url(self) -> str:
        deadline = time.monotonic() + self.timeout
        seen = b""
        while time.monotonic() < deadline:
            line = self.proc.stderr.readline()
            if not line:
                break
            seen += line
            m = re.search(rb"DevTools listening on (ws://\S+)", line)
            if m:
                return m.group(1).decode()
        self.close()
        raise BrowserError("Chromium did not start: " + seen.decode(errors="replace")[-400:])

    def call(self, method: str, session: bool = False, **params) -> dict:
        """One DevTools command; its result (events meanwhile are kept in `events`)."""
        self.next_id += 1
        msg = {"id": self.next_id, "method": method, "params": params}
        if session:
            msg["sessionId"] = self.session
        self.ws.send(json.dumps(msg))
        while True:
            reply = json.loads(self.ws.recv())
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise BrowserError(f"{method}: {reply['error'].get('message')}")
                return reply.get("result", {})
            if "method" in reply:
                self.events.append(reply)

    def page(self, method: str, **params) -> dict:
        return self.call(method, session=True, **params)

    def wait_for(self, event: str) -> dict:
        """The next `event` of the page (or one already received)."""
        for i, e in enumerate(self.events):
            if e.get("method") == event:
                return self.events.pop(i)
        deadline = time.monotonic() + self.timeout
        while time.monotonic() < deadline:
            reply = json.loads(self.ws.recv())
            if reply.get("method") == event:
                return reply
            if "method" in reply:
                self.events.append(reply)
        raise BrowserError(f"timed out waiting for {event}")

    def close(self) -> None:
        ws = getattr(self, "ws", None)
        if ws is not None:
            ws.close()
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        if self.proc.stderr is not None:
            self.proc.stderr.close()
        shutil.rmtree(self.profile, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


# what a page holds, measured in the page itself
PROBE = """(() => {
  const maths = [...document.querySelectorAll('math')];
  const svgs = [...document.querySelectorAll('svg')];
  const box = e => { const r = e.getBoundingClientRect(); return [r.width, r.height]; };
  return JSON.stringify({
    title: document.title,
    math: maths.length,
    math_empty: maths.filter(m => !m.textContent.trim()).length,
    math_unrendered: maths.filter(m => { const [w, h] = box(m); return !(w > 0 && h > 0); }).length,
    math_display: maths.filter(m => m.getAttribute('displaystyle') === 'true').length,
    svg: svgs.length,
    svg_empty: svgs.filter(s => !s.children.length || (() => { const [w, h] = box(s);
      return !(w > 0 && h > 0); })()).length,
    scripts: document.scripts.length,
    text: document.body.innerText.length,
    height: document.documentElement.scrollHeight,
  });
})()"""


def load(browser: Chromium, path: str | Path, width: int = 1000) -> dict:
    """Open a file in the page; returns what PROBE measured and the page's errors
    (console errors, uncaught exceptions, log entries of level error: a blocked
    request or a CSP violation is one)."""
    browser.events.clear()
    browser.page("Page.enable")
    browser.page("Runtime.enable")
    browser.page("Log.enable")
    browser.page("Emulation.setDeviceMetricsOverride", width=width, height=800,
                 deviceScaleFactor=1, mobile=False)
    browser.page("Page.navigate", url=Path(path).resolve().as_uri())
    browser.wait_for("Page.loadEventFired")
    res = browser.page("Runtime.evaluate", expression=PROBE, returnByValue=True)
    info = json.loads(res["result"]["value"])
    errors = []
    for e in browser.events:
        m, p = e.get("method"), e.get("params", {})
        if m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
            errors.append("console: " + " ".join(str(a.get("value", a.get("description", "")))
                                                 for a in p.get("args", [])))
        elif m == "Runtime.exceptionThrown":
            errors.append("exception: " + p.get("exceptionDetails", {}).get("text", ""))
        elif m == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
            errors.append("log: " + p["entry"].get("text", ""))
    info["errors"] = errors
    return info


def screenshot(browser: Chromium, png: str | Path, height: int | None = None,
               width: int = 1000, scale: float = 1.0) -> bytes:
    """The loaded page as PNG (its whole height, or the top `height` pixels), at
    `scale` (a small one is enough to tell a drawn page from a blank one)."""
    full = browser.page("Page.getLayoutMetrics")["cssContentSize"]
    h = min(full["height"], height) if height else full["height"]
    shot = browser.page("Page.captureScreenshot", format="png", captureBeyondViewport=True,
                        clip=dict(x=0, y=0, width=width, height=h, scale=scale))
    data = base64.b64decode(shot["data"])
    Path(png).write_bytes(data)
    return data


def print_pdf(browser: Chromium, pdf: str | Path) -> bytes:
    """The loaded page printed (A4, with its print styles) to PDF."""
    res = browser.page("Page.printToPDF", paperWidth=8.27, paperHeight=11.69,
                       printBackground=True, preferCSSPageSize=True)
    data = base64.b64decode(res["data"])
    Path(pdf).write_bytes(data)
    return data


# ---- PNG: enough decoding to count colours ---------------------------------------------
def png_colours(data: bytes, limit: int = 16) -> int:
    """Distinct pixel values of an 8-bit RGB/RGBA/grey PNG (counting stops at `limit`)."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        chunk = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", chunk[:10])
            if depth != 8 or ctype not in (0, 2, 4, 6):
                raise ValueError(f"PNG colour type {ctype}, depth {depth} not supported")
            bpp = {0: 1, 2: 3, 4: 2, 6: 4}[ctype]
        elif kind == b"IDAT":
            idat += chunk
        pos += 12 + n
    raw = zlib.decompress(idat)
    stride = w * bpp
    prev = bytearray(stride)
    seen: set[bytes] = set()
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        for x in range(0, stride, bpp * 7):  # a sample of each row is plenty
            seen.add(bytes(line[x:x + bpp]))
        if len(seen) >= limit:
            return len(seen)
        prev = line
    return len(seen)


# ---- the README's screenshot --------------------------------------------------------------
def main(argv: list[str]) -> int:
    import argparse

    ap = argparse.ArgumentParser(description="Render a problem's HTML derivation and "
                                 "photograph it in headless Chromium.")
    ap.add_argument("problem", help="a .mom file")
    ap.add_argument("--screenshot", required=True, metavar="PNG")
    ap.add_argument("--height", type=int, default=1800, help="pixels from the top (0: all)")
    ap.add_argument("--width", type=int, default=1000)
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        html = os.path.join(tmp, "page.html")
        subprocess.run([sys.executable, "-m", "momentum_cli", "solve", "--format", "html",
                        "--output", html, args.problem], check=True)
        with Chromium() as browser:
            info = load(browser, html, args.width)
            if info["errors"]:
                print("\n".join(info["errors"]), file=sys.stderr)
                return 1
            screenshot(browser, args.screenshot, args.height or None, args.width)
    print(f"wrote {args.screenshot} ({info['math']} MathML, {info['svg']} SVG elements)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
