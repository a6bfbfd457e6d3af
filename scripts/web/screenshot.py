#!/usr/bin/env python3
"""Screenshots of the browser page (`sss view`) for the README: serves SITE, opens each scene in
headless Chromium with WebGPU (SwiftShader), waits until the page has drawn and saves a PNG.

    sss view skin1 --scene sphere --scene fin --scene bust.obj --out site
    python3 scripts/web/screenshot.py site docs/images/web_{scene}.png sphere fin bust

Needs Debian's chromium and websocket-client (pip install websocket-client)."""

import base64
import functools
import http.server
import json
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

import websocket


class Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


def serve(root):
    handler = functools.partial(Quiet, directory=root)
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server.server_address[1]


def main():
    site, pattern, scenes = sys.argv[1], sys.argv[2], sys.argv[3:]
    port = serve(site)
    profile = tempfile.mkdtemp()
    browser = subprocess.Popen([
        "chromium", "--headless=new", "--no-sandbox", "--enable-unsafe-webgpu",
        "--enable-features=Vulkan", "--use-vulkan=native", "--ignore-gpu-blocklist",
        "--remote-debugging-port=9333", f"--user-data-dir={profile}", "--window-size=1100,800",
        "about:blank"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        for _ in range(100):
            try:
                pages = json.load(urllib.request.urlopen("http://127.0.0.1:9333/json"))
                break
            except OSError:
                time.sleep(0.1)
        page = next(p for p in pages if p["type"] == "page")
        ws = websocket.create_connection(page["webSocketDebuggerUrl"])
        ids = iter(range(1, 10**6))

        def call(method, **params):
            i = next(ids)
            ws.send(json.dumps({"id": i, "method": method, "params": params}))
            while True:
                m = json.loads(ws.recv())
                if m.get("id") == i:
                    return m.get("result", {})

        for scene in scenes:
            call("Page.navigate", url=f"http://127.0.0.1:{port}/index.html?scene={scene}")
            for _ in range(600):
                r = call("Runtime.evaluate", expression="document.body && document.body.dataset.drawn")
                if r.get("result", {}).get("value") == "1":
                    break
                time.sleep(0.1)
            else:
                sys.exit(f"{scene}: the page did not draw")
            shot = call("Page.captureScreenshot", format="png")
            out = pattern.format(scene=scene)
            with open(out, "wb") as f:
                f.write(base64.b64decode(shot["data"]))
            print(f"wrote {out}")
    finally:
        browser.kill()


if __name__ == "__main__":
    main()
