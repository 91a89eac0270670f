"""Debian's headless chromium, driven through its DevTools protocol with Debian's
python3-websocket: what the viewer's test (viewer_test.py) and the web page's test
(tests/web/web_test.py) share. `import devtools` exits 77 (CTest's skip) when chromium or
websocket is missing."""
import json
import re
import shutil
import subprocess
import sys
import time
import urllib.request

try:
    import websocket
except ImportError:
    print("python3-websocket is missing: skipped")
    sys.exit(77)

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
if not CHROMIUM:
    print("chromium is missing: skipped")
    sys.exit(77)

failures = []


def check(name, ok, detail=""):
    print(("ok   " if ok else "FAIL ") + name + ("" if ok else ": " + str(detail)), flush=True)
    if not ok:
        failures.append(name)


def start_chromium(profile, url, window="1000,600", seconds=30):
    """Headless chromium on `url` with a fresh profile: (the process, its DevTools port or
    None)."""
    browser = subprocess.Popen(
        [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--remote-debugging-port=0", "--user-data-dir=" + profile, "--window-size=" + window,
         url], stderr=subprocess.PIPE, text=True)
    end = time.time() + seconds
    while time.time() < end:
        m = re.search(r"DevTools listening on ws://127\.0\.0\.1:(\d+)/", browser.stderr.readline())
        if m:
            return browser, int(m.group(1))
    return browser, None


def first_page(port, timeout=30):
    """The DevTools address of the browser's first page."""
    for _ in range(50):
        with urllib.request.urlopen("http://127.0.0.1:%d/json/list" % port, timeout=timeout) as r:
            pages = [t for t in json.loads(r.read()) if t["type"] == "page"]
        if pages:
            return pages[0]["webSocketDebuggerUrl"]
        time.sleep(0.1)
    return None


class Tab:
    """One page of the browser: its errors, console and requests, its workers' too."""

    def __init__(self, ws_url, timeout=60):
        self.ws = websocket.create_connection(ws_url, timeout=timeout, suppress_origin=True)
        self.next_id = 0
        self.errors = []
        self.console = []
        self.requests = []
        for domain in ("Runtime.enable", "Log.enable", "Network.enable"):
            self.call(domain)
        self.call("Target.setAutoAttach", autoAttach=True, waitForDebuggerOnStart=False,
                  flatten=True)

    def call(self, method, **params):
        self.next_id += 1
        own = self.next_id  # (event() may send commands of its own meanwhile)
        self.ws.send(json.dumps({"id": own, "method": method, "params": params}))
        while True:
            message = json.loads(self.ws.recv())
            if message.get("id") == own and "sessionId" not in message:
                return message.get("result", {})
            self.event(message)

    def send(self, method, session, **params):
        """A command to an attached worker, its answer not awaited."""
        self.next_id += 1
        self.ws.send(json.dumps({"id": self.next_id, "method": method, "params": params,
                                 "sessionId": session}))

    def event(self, message):
        method = message.get("method", "")
        p = message.get("params", {})
        if method == "Target.attachedToTarget":
            session = p["sessionId"]
            for domain in ("Runtime.enable", "Network.enable"):
                self.send(domain, session)
            self.send("Target.setAutoAttach", session, autoAttach=True,
                      waitForDebuggerOnStart=False, flatten=True)
        elif method == "Runtime.exceptionThrown":
            d = p["exceptionDetails"]
            self.errors.append(d.get("text", "exception") + " " +
                               str(d.get("exception", {}).get("description", "")))
        elif method == "Runtime.consoleAPICalled":
            text = " ".join(str(a.get("value", a.get("description", "")))
                            for a in p.get("args", []))
            self.console.append(text)
            if p.get("type") == "error":
                self.errors.append(text)
        elif method == "Log.entryAdded" and p["entry"].get("level") == "error":
            self.errors.append(p["entry"].get("text"))
        elif method == "Network.requestWillBeSent":
            self.requests.append(p["request"]["url"])

    def eval(self, expression):
        r = self.call("Runtime.evaluate", expression=expression, returnByValue=True,
                      awaitPromise=True)
        return None if "exceptionDetails" in r else r.get("result", {}).get("value")
