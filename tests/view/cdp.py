"""A small Chrome DevTools Protocol driver for headless Chromium (Debian's chromium and
python3-websocket), used by hunav_view's page tests."""
import json
import os
import re
import shutil
import signal
import subprocess
import tempfile
import time
import urllib.request

import websocket

# The bound of every wait here, in s: a condition is polled until it holds, so a loaded machine (CI's
# two cores running two tests) makes a test slower, never fail, and a passing test waits only as long as
# the condition takes. (A fixed 20 s for the page to load failed view_page_replay under load.)
GENEROUS = 120.0


class Browser:
    def __init__(self, width=1280, height=800, timeout=GENEROUS):
        self.profile = tempfile.mkdtemp(prefix="hunav_view_chromium.")
        self.log_path = os.path.join(self.profile, "chromium.log")
        self.log = open(self.log_path, "w")
        exe = shutil.which("chromium") or "/usr/bin/chromium"
        self.proc = subprocess.Popen(
            [exe, "--headless=new", "--no-sandbox", "--disable-gpu", "--no-first-run", "--no-default-browser-check",
             "--disable-extensions", "--remote-debugging-port=0", "--remote-allow-origins=*",
             "--user-data-dir=" + self.profile, "--window-size=%d,%d" % (width, height), "about:blank"],
            stdout=self.log, stderr=subprocess.STDOUT,
            # Chromium's own org.chromium.Chromium.* folders go with the profile, not into /tmp; its
            # own process group, to end its helpers with it (close()).
            env=dict(os.environ, TMPDIR=self.profile), start_new_session=True)
        port = None
        deadline = time.time() + timeout
        while port is None:
            if time.time() > deadline or self.proc.poll() is not None:
                raise RuntimeError("chromium did not start: " + open(self.log_path).read()[-2000:])
            time.sleep(0.1)
            m = re.search(r"DevTools listening on ws://[^:]+:(\d+)/", open(self.log_path).read())
            if m:
                port = int(m.group(1))
        targets = json.load(urllib.request.urlopen("http://127.0.0.1:%d/json" % port, timeout=GENEROUS))
        page = next(t for t in targets if t.get("type") == "page")
        self.ws = websocket.create_connection(page["webSocketDebuggerUrl"], timeout=timeout)
        self.next_id = 0
        self.exceptions = []
        self.console_errors = []
        self.call("Runtime.enable")
        self.call("Page.enable")
        self.call("Log.enable")

    def _event(self, msg):
        method = msg.get("method")
        if method == "Runtime.exceptionThrown":
            d = msg["params"]["exceptionDetails"]
            self.exceptions.append(d.get("exception", {}).get("description") or d.get("text"))
        elif method == "Runtime.consoleAPICalled" and msg["params"].get("type") == "error":
            args = msg["params"]["args"]
            self.console_errors.append(" ".join(str(a.get("value", a.get("description"))) for a in args))
        elif method == "Log.entryAdded" and msg["params"]["entry"].get("level") == "error":
            self.console_errors.append(msg["params"]["entry"].get("text"))

    def call(self, method, **params):
        self.next_id += 1
        my_id = self.next_id
        self.ws.send(json.dumps({"id": my_id, "method": method, "params": params}))
        while True:
            msg = json.loads(self.ws.recv())
            if msg.get("id") == my_id:
                if "error" in msg:
                    raise RuntimeError("%s: %s" % (method, msg["error"]))
                return msg.get("result", {})
            self._event(msg)

    def pump(self, seconds):
        """Reads events for a while (exceptions arrive as events)."""
        end = time.time() + seconds
        self.ws.settimeout(0.1)
        try:
            while time.time() < end:
                try:
                    self._event(json.loads(self.ws.recv()))
                except websocket.WebSocketTimeoutException:
                    pass
        finally:
            self.ws.settimeout(GENEROUS)

    def goto(self, url):
        self.call("Page.navigate", url=url)
        self.wait_for("window.hunavView && window.hunavView.ready === true")

    def eval(self, expr, await_promise=False):
        r = self.call("Runtime.evaluate", expression=expr, returnByValue=True, awaitPromise=await_promise)
        if "exceptionDetails" in r:
            raise RuntimeError("JavaScript error in %r: %s" % (expr[:80], r["exceptionDetails"]))
        return r["result"].get("value")

    def wait_for(self, expr, timeout=GENEROUS):
        end = time.time() + timeout
        while time.time() < end:
            if self.eval("!!(%s)" % expr):
                return
            self.pump(0.1)
        raise AssertionError("timed out waiting for: " + expr)

    def mouse(self, kind, x, y, buttons=1):
        self.call("Input.dispatchMouseEvent", type=kind, x=x, y=y, button="left", buttons=buttons, clickCount=1)

    def drag(self, x0, y0, x1, y1, steps=8):
        self.mouse("mousePressed", x0, y0)
        for k in range(1, steps + 1):
            self.mouse("mouseMoved", x0 + (x1 - x0) * k / steps, y0 + (y1 - y0) * k / steps)
        self.mouse("mouseReleased", x1, y1, buttons=0)

    def screenshot(self, path):
        import base64
        data = self.call("Page.captureScreenshot", format="png")["data"]
        with open(path, "wb") as f:
            f.write(base64.b64decode(data))

    def js_errors(self):
        page_errors = self.eval("window.hunavView ? window.hunavView.errors : []") or []
        return self.exceptions + self.console_errors + page_errors

    def close(self):
        try:
            self.ws.close()
        except Exception:
            pass
        self.proc.terminate()
        try:
            self.proc.wait(10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        # Chromium's helpers (zygote, renderers) can outlive the browser and write into the profile
        # after it is removed: end what is left of its process group first.
        try:
            os.killpg(self.proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        deadline = time.time() + 10
        while time.time() < deadline:
            try:
                os.killpg(self.proc.pid, 0)
            except ProcessLookupError:
                break
            time.sleep(0.05)
        self.log.close()
        shutil.rmtree(self.profile, ignore_errors=True)


def states_at(states_csv, t, tol=1e-9):
    """Rows of states.csv at time t: {'robot': (x, y), id: (x, y, behavior)}."""
    import csv
    out = {}
    with open(states_csv) as f:
        for row in csv.DictReader(f):
            if abs(float(row["t"]) - t) > tol:
                continue
            if row["kind"] == "robot":
                out["robot"] = (float(row["x"]), float(row["y"]))
            else:
                out[int(row["id"])] = (float(row["x"]), float(row["y"]), int(row["behavior"]))
    return out


def hex_rgb(color):
    return tuple(int(color[i:i + 2], 16) for i in (1, 3, 5))
