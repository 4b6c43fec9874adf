#!/usr/bin/env python3
"""The built guide opens in a real browser: headless Chromium (Debian's), driven over its
DevTools protocol on a pipe-free loopback port, loads the front page and a chapter from disk,
and for each: no console error or uncaught exception, every image loaded (complete, with a
width), a title; a screenshot of each is written next to the site (OUT_DIR). No traffic
leaves the machine: the pages are files, and the browser runs with networking to anything but
127.0.0.1 refused by its own proxy setting.

Usage: guide_browser.py HTML_DIR OUT_DIR
"""
import base64
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

import websocket


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Browser:
    def __init__(self):
        self.profile = tempfile.mkdtemp(prefix="spectralize_chromium_")
        self.port = free_port()
        exe = shutil.which("chromium") or shutil.which("chromium-browser")
        if not exe:
            raise SystemExit("chromium not found")
        self.proc = subprocess.Popen(
            [exe, "--headless=new", "--no-sandbox", "--disable-gpu", "--no-first-run",
             "--disable-extensions", "--disable-background-networking", "--disable-sync",
             "--no-default-browser-check", "--proxy-server=127.0.0.1:9",
             "--proxy-bypass-list=<-loopback>", "--remote-allow-origins=*",
             f"--remote-debugging-address=127.0.0.1", f"--remote-debugging-port={self.port}",
             f"--user-data-dir={self.profile}", "--window-size=1280,900", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = time.time() + 30
        while True:
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{self.port}/json/list",
                                            timeout=2) as r:
                    targets = [t for t in json.load(r) if t.get("type") == "page"]
                if targets:
                    break
            except OSError:
                pass
            if time.time() > deadline:
                raise SystemExit("chromium did not start its DevTools endpoint")
            time.sleep(0.2)
        self.ws = websocket.create_connection(targets[0]["webSocketDebuggerUrl"], timeout=30)
        self.next_id, self.events = 0, []

    def call(self, method, **params):
        self.next_id += 1
        self.ws.send(json.dumps({"id": self.next_id, "method": method, "params": params}))
        while True:
            msg = json.loads(self.ws.recv())
            if msg.get("id") == self.next_id:
                if "error" in msg:
                    raise RuntimeError(f"{method}: {msg['error']}")
                return msg.get("result", {})
            self.events.append(msg)

    def wait_for(self, method, timeout=30):
        deadline = time.time() + timeout
        while time.time() < deadline:
            for i, e in enumerate(self.events):
                if e.get("method") == method:
                    return self.events.pop(i)
            self.ws.settimeout(max(0.1, deadline - time.time()))
            try:
                self.events.append(json.loads(self.ws.recv()))
            except websocket.WebSocketTimeoutException:
                break
        raise RuntimeError(f"no {method} within {timeout} s")

    def close(self):
        try:
            self.ws.close()
        finally:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
            shutil.rmtree(self.profile, ignore_errors=True)


def check_page(b, path, shot):
    b.events.clear()
    b.call("Page.navigate", url="file://" + path)
    b.wait_for("Page.loadEventFired")
    time.sleep(0.5)  # late console messages
    problems = []
    for e in b.events:
        m = e.get("method")
        if m == "Runtime.exceptionThrown":
            problems.append("exception: " + e["params"]["exceptionDetails"].get("text", ""))
        elif m == "Runtime.consoleAPICalled" and e["params"]["type"] in ("error", "assert"):
            problems.append("console error: " + json.dumps(e["params"]["args"])[:300])
        elif m == "Log.entryAdded" and e["params"]["entry"]["level"] == "error":
            problems.append("log error: " + e["params"]["entry"]["text"][:300])
    images = b.call("Runtime.evaluate", returnByValue=True, expression=(
        "JSON.stringify(Array.from(document.images).map(i => [i.getAttribute('src'), "
        "i.complete && i.naturalWidth > 0]))"))["result"]["value"]
    images = json.loads(images)
    problems += [f"image not loaded: {src}" for src, ok in images if not ok]
    title = b.call("Runtime.evaluate", expression="document.title",
                   returnByValue=True)["result"]["value"]
    if not title:
        problems.append("no title")
    png = base64.b64decode(b.call("Page.captureScreenshot", format="png")["data"])
    with open(shot, "wb") as f:
        f.write(png)
    if len(png) < 10000:
        problems.append(f"screenshot of {len(png)} bytes: a blank page?")
    print(f"{os.path.basename(path)}: '{title}', {len(images)} images, screenshot {shot} "
          f"({len(png)} bytes), {len(problems)} problems")
    return problems


def main():
    html, out = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    os.makedirs(out, exist_ok=True)
    pages = [("index.html", "front_page.png"), ("guide/accuracy.html", "chapter_accuracy.png")]
    b = Browser()
    problems = []
    try:
        b.call("Page.enable")
        b.call("Runtime.enable")
        b.call("Log.enable")
        for page, shot in pages:
            problems += [f"{page}: {p}" for p in check_page(b, os.path.join(html, page),
                                                            os.path.join(out, shot))]
    finally:
        b.close()
    for p in problems:
        print("PROBLEM:", p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
