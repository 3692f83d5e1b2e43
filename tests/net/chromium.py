"""A headless Debian chromium driven over the DevTools protocol (a websocket), for the browser tests."""

from __future__ import annotations

import base64
import json
import shutil
import socket
import subprocess
import tempfile
import time
import urllib.request


class _Detached(RuntimeError):
    """The page's DevTools session is between two documents (a navigation is committing)."""


def chromium_path() -> str | None:
    for name in ("chromium", "chromium-browser"):
        path = shutil.which(name)
        if path:
            return path
    return None


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Chromium:
    """One headless chromium with one page; WebGL through SwiftShader (no GPU needed). Use as a context
    manager: the browser and its profile directory are removed on exit."""

    def __init__(self, width: int = 1280, height: int = 800, timeout_s: float = 30.0) -> None:
        from websockets.sync.client import connect

        self.width, self.height = width, height
        self.port = _free_port()
        self.profile = tempfile.mkdtemp(prefix="vessel-gym-chromium-")
        args = [
            chromium_path() or "chromium",
            "--headless",
            "--no-sandbox",  # tests run as root in CI
            "--disable-gpu",
            "--enable-unsafe-swiftshader",
            "--use-angle=swiftshader",
            f"--window-size={width},{height}",
            "--remote-debugging-address=127.0.0.1",
            f"--remote-debugging-port={self.port}",
            f"--user-data-dir={self.profile}",
            "--no-first-run",
            "--no-default-browser-check",
            "about:blank",
        ]
        self.proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self.events: list[dict] = []
        self._id = 0
        try:
            deadline = time.monotonic() + timeout_s
            while True:
                try:
                    url = f"http://127.0.0.1:{self.port}/json/list"
                    with urllib.request.urlopen(url, timeout=2) as r:
                        tabs = json.load(r)
                    page = next(t for t in tabs if t.get("type") == "page")
                    break
                except (OSError, StopIteration, ValueError):
                    if time.monotonic() > deadline or self.proc.poll() is not None:
                        raise RuntimeError("chromium did not start its DevTools endpoint") from None
                    time.sleep(0.2)
            self.ws = connect(page["webSocketDebuggerUrl"], max_size=None, open_timeout=10)
            for method in ("Page.enable", "Runtime.enable", "Log.enable"):
                self.call(method)
            self.call(
                "Emulation.setDeviceMetricsOverride",
                width=width,
                height=height,
                deviceScaleFactor=1,
                mobile=False,
            )
        except BaseException:
            self.close()
            raise

    def call(self, method: str, timeout_s: float = 60.0, **params: object) -> dict:
        # While a navigation commits, the page's session briefly answers "Not attached to an active page".
        for _ in range(50):
            try:
                return self._call(method, timeout_s, **params)
            except _Detached:
                self.pump(0.1)
        return self._call(method, timeout_s, **params)

    def _call(self, method: str, timeout_s: float, **params: object) -> dict:
        self._id += 1
        mid = self._id
        self.ws.send(json.dumps({"id": mid, "method": method, "params": params}))
        deadline = time.monotonic() + timeout_s
        while True:
            msg = json.loads(self.ws.recv(timeout=max(0.05, deadline - time.monotonic())))
            if msg.get("id") == mid:
                if "error" in msg:
                    if "Not attached to an active page" in str(msg["error"].get("message")):
                        raise _Detached(method)
                    raise RuntimeError(f"{method}: {msg['error']}")
                return msg.get("result", {})
            self.events.append(msg)

    def pump(self, seconds: float) -> None:
        """Collect events (console messages, exceptions) for ``seconds``."""
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            try:
                self.events.append(json.loads(self.ws.recv(timeout=max(0.01, end - time.monotonic()))))
            except TimeoutError:
                pass

    def press(self, key: str, code: str, key_code: int) -> None:
        """Press and release one key on the page (as a person at the keyboard)."""
        for kind in ("keyDown", "keyUp"):
            self.call("Input.dispatchKeyEvent", type=kind, key=key, code=code, windowsVirtualKeyCode=key_code)

    def text(self) -> str:
        """The page's visible text."""
        result = self.call("Runtime.evaluate", expression="document.body.innerText", returnByValue=True)
        return str(result.get("result", {}).get("value", ""))

    def screenshot(self, path: str) -> bytes:
        data = base64.b64decode(self.call("Page.captureScreenshot", format="png")["data"])
        with open(path, "wb") as f:
            f.write(data)
        return data

    def errors(self) -> list[str]:
        """Uncaught exceptions, console.error calls and error log entries seen so far."""
        out = []
        for e in self.events:
            method, p = e.get("method"), e.get("params", {})
            if method == "Runtime.exceptionThrown":
                d = p.get("exceptionDetails", {})
                out.append(f"{d.get('text', '')} {d.get('exception', {}).get('description', '')}")
            elif method == "Runtime.consoleAPICalled" and p.get("type") == "error":
                out.append(" ".join(str(a.get("value", a.get("description", ""))) for a in p.get("args", [])))
            elif method == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
                out.append(p["entry"].get("text", ""))
        return out

    def close(self) -> None:
        ws = getattr(self, "ws", None)
        if ws is not None:
            try:
                ws.close()
            except Exception:  # noqa: BLE001 - the browser may be gone already
                pass
        self.proc.terminate()
        try:
            self.proc.wait(10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        shutil.rmtree(self.profile, ignore_errors=True)

    def __enter__(self) -> Chromium:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
