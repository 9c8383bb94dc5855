#!/usr/bin/env python3
"""Pixel checks of screenshots of the web viewer (tests/cli/viewer_test.sh), standard library only.

  viewer_check.py halves SHOT.png [--seams] [--cones] [--highlight]
      Both halves of the picture (the surface left, the texture layout right; the bar at the top
      left out) show the checkerboard: enough pixels off the background, dark (blue) and light
      squares both, and many changes between them along the rows. --seams: orange seam lines in
      the layout; --cones: red cone dots in the layout; --highlight: the hovered face's yellow in
      both halves.
  viewer_check.py differ A.png B.png MIN_LEFT MAX_RIGHT
      At least MIN_LEFT pixels of the left halves differ (by more than 40 in a channel) and at
      most MAX_RIGHT of the right halves.
  viewer_check.py interact PAGE.html CHROMIUM [FLAGS...]
      Drives the page in Chromium through the DevTools protocol (--remote-debugging-pipe) with
      real mouse events: hovering the surface and the layout shows a face whose figures in the
      box are the data block's; dragging turns the surface (left half changes, right does not);
      the wheel zooms the layout; the checker slider rescales both; the colouring menu colours
      by distortion.

Prints one line per failed check and exits 1 when one failed; prints the measures with -v.
"""

import base64
import json
import os
import re
import select
import struct
import subprocess
import sys
import time
import zlib

TOP = 110  # rows of the bar and the panes' labels, left out


def read_png(path):
    """(width, height, rows of (r, g, b) tuples) of an 8-bit RGB or RGBA PNG (no interlace)."""
    with open(path, "rb") as f:
        return decode_png(f.read(), path)


def decode_png(data, path="PNG"):
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    at, idat, header = 8, [], None
    while at < len(data):
        (length,) = struct.unpack(">I", data[at:at + 4])
        kind, body = data[at + 4:at + 8], data[at + 8:at + 8 + length]
        at += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in (2, 6) or interlace != 0:
        raise ValueError(f"{path}: only 8-bit RGB/RGBA without interlace (got {header})")
    channels = 3 if colour == 2 else 4
    raw = zlib.decompress(b"".join(idat))
    stride = width * channels
    previous = bytearray(stride)
    rows = []
    for y in range(height):
        start = y * (stride + 1)
        kind, line = raw[start], bytearray(raw[start + 1:start + 1 + stride])
        for i in range(stride):
            left = line[i - channels] if i >= channels else 0
            up = previous[i]
            corner = previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + left) & 255
            elif kind == 2:
                line[i] = (line[i] + up) & 255
            elif kind == 3:
                line[i] = (line[i] + (left + up) // 2) & 255
            elif kind == 4:
                p = left + up - corner
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - corner)
                nearest = left if pa <= pb and pa <= pc else up if pb <= pc else corner
                line[i] = (line[i] + nearest) & 255
        rows.append([tuple(line[x * channels:x * channels + 3]) for x in range(width)])
        previous = line
    return width, height, rows


def half_measures(rows, x0, x1, background):
    """Counts over the columns [x0, x1) of every other row below the bar (the pane border left
    out)."""
    m = {"pixels": 0, "off_background": 0, "dark": 0, "light": 0, "changes": 0,
         "seam": 0, "cone": 0, "highlight": 0}
    colours = set()
    br, bg, bb = background
    sampled = rows[TOP::2]
    for row in sampled:
        last = None
        for r, g, b in row[x0 + 2:x1 - 2]:
            off = max(abs(r - br), abs(g - bg), abs(b - bb))
            if off > 24:
                m["off_background"] += 1
            # Checker squares, shaded or not: blue ones, and grey ones off the background.
            if b > 110 and b - r > 60:
                kind = "dark"
            elif min(r, g, b) > 120 and max(r, g, b) - min(r, g, b) < 30 and off > 3:
                kind = "light"
            else:
                kind = None
            if kind:
                m[kind] += 1
                if last and kind != last:
                    m["changes"] += 1
                last = kind
            if r > 200 and 70 < g < 150 and b < 80:
                m["seam"] += 1  # orange
            elif r > 170 and g < 90 and b < 90:
                m["cone"] += 1  # red
            elif r > 190 and g > 170 and b < 125 and g - b > 80 and r - g < 50:
                m["highlight"] += 1  # yellow
            colours.add((r >> 3, g >> 3, b >> 3))
    m["pixels"] = len(sampled) * max(x1 - x0 - 4, 0)
    m["colours"] = len(colours)
    return m


def halves(path, flags, verbose):
    width, height, rows = read_png(path)
    problems = []
    for name, x0, x1, background in (("surface (left)", 0, width // 2, (255, 255, 255)),
                                     ("layout (right)", width // 2, width, (247, 247, 245))):
        m = half_measures(rows, x0, x1, background)
        if verbose:
            print(f"{path} {name}: {m}")
        share = lambda key: m[key] / max(m["pixels"], 1)
        if share("off_background") < 0.05:
            problems.append(f"{name}: only {share('off_background'):.1%} off the background")
        for key in ("dark", "light"):
            if share(key) < 0.01:
                problems.append(f"{name}: {key} checker squares on {share(key):.2%} of the pixels")
        if m["changes"] < 20:
            problems.append(f"{name}: {m['changes']} dark/light changes along the rows (no checker)")
        if m["colours"] < 8:
            problems.append(f"{name}: {m['colours']} colours")
        if "--highlight" in flags and m["highlight"] < 2:
            problems.append(f"{name}: no highlighted face ({m['highlight']} yellow pixels)")
        if name.startswith("layout"):
            if "--seams" in flags and m["seam"] < 10:
                problems.append(f"{name}: no seams ({m['seam']} orange pixels)")
            if "--cones" in flags and m["cone"] < 10:
                problems.append(f"{name}: no cone dots ({m['cone']} red pixels)")
    return problems


def differing_pixels(a, b, top=TOP):
    """Pixels below row `top` that differ by more than 40 in a channel: (left, right half)."""
    counts = [0, 0]
    width = len(a[0])
    for y in range(top, len(a)):
        row_a, row_b = a[y], b[y]
        for x in range(width):
            p, q = row_a[x], row_b[x]
            if abs(x - width // 2) <= 2:
                continue  # the pane border, blended with both sides when scaled
            if abs(p[0] - q[0]) > 40 or abs(p[1] - q[1]) > 40 or abs(p[2] - q[2]) > 40:
                counts[0 if x < width // 2 else 1] += 1
    return counts


def differ(path_a, path_b, min_left, max_right, verbose):
    wa, ha, a = read_png(path_a)
    wb, hb, b = read_png(path_b)
    if (wa, ha) != (wb, hb):
        return [f"{path_a} is {wa} x {ha} but {path_b} is {wb} x {hb}"]
    counts = differing_pixels(a, b)
    if verbose:
        print(f"differing pixels: left {counts[0]}, right {counts[1]}")
    problems = []
    if counts[0] < min_left:
        problems.append(f"left halves differ in {counts[0]} pixels, expected at least {min_left}")
    if counts[1] > max_right:
        problems.append(f"right halves differ in {counts[1]} pixels, expected at most {max_right}")
    return problems


class Browser:
    """Chromium driven through the DevTools protocol over --remote-debugging-pipe (JSON messages
    ended by NUL on file descriptors 3 and 4): no WebSocket, no extra package."""

    def __init__(self, chromium, flags):
        to_browser, self.write_end = os.pipe()
        self.read_end, from_browser = os.pipe()

        def descriptors():
            os.dup2(to_browser, 3)
            os.dup2(from_browser, 4)

        self.process = subprocess.Popen(
            [chromium, *flags, "--remote-debugging-pipe", "about:blank"], pass_fds=(3, 4),
            preexec_fn=descriptors, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(to_browser)
        os.close(from_browser)
        self.buffer, self.last_id, self.session = b"", 0, None
        target = self.call("Target.createTarget", {"url": "about:blank"})["targetId"]
        self.session = self.call("Target.attachToTarget",
                                 {"targetId": target, "flatten": True})["sessionId"]

    def call(self, method, params=None, timeout=60):
        self.last_id += 1
        message = {"id": self.last_id, "method": method, "params": params or {}}
        if self.session:
            message["sessionId"] = self.session
        os.write(self.write_end, json.dumps(message).encode() + b"\0")
        deadline = time.time() + timeout
        while True:
            while b"\0" in self.buffer:
                raw, self.buffer = self.buffer.split(b"\0", 1)
                reply = json.loads(raw)
                if reply.get("id") == self.last_id:
                    if "error" in reply:
                        raise RuntimeError(f"{method}: {reply['error']}")
                    return reply["result"]
            if not select.select([self.read_end], [], [], max(deadline - time.time(), 0))[0]:
                raise TimeoutError(f"{method}: no answer in {timeout} s")
            chunk = os.read(self.read_end, 1 << 20)
            if not chunk:
                raise RuntimeError(f"{method}: the browser closed the pipe")
            self.buffer += chunk

    def evaluate(self, expression):
        result = self.call("Runtime.evaluate", {"expression": expression, "returnByValue": True})
        return result["result"].get("value")

    def mouse(self, kind, x, y, **extra):
        self.call("Input.dispatchMouseEvent", {"type": kind, "x": x, "y": y, **extra})

    def screenshot(self, width, height):
        """The window below the bar at half its size (rows of pixels)."""
        clip = {"x": 0, "y": TOP, "width": width, "height": height - TOP, "scale": 0.5}
        reply = self.call("Page.captureScreenshot", {"format": "png", "clip": clip})
        return decode_png(base64.b64decode(reply["data"]))[2]

    def settle(self):
        """Returns once the page has drawn what the last events asked for (two frames)."""
        self.call("Runtime.evaluate", {"expression": "new Promise(function (done) { "
                  "requestAnimationFrame(function () { requestAnimationFrame(done); }); })",
                  "awaitPromise": True})

    def close(self):
        self.process.kill()
        self.process.wait()


def data_block(page_path):
    with open(page_path, encoding="utf-8") as f:
        text = f.read()
    start = text.index('<script id="ricci-data" type="application/json">')
    start = text.index(">", start) + 1
    return json.loads(text[start:text.index("</script>", start)])


def interact(page_path, chromium, flags, verbose):
    data = data_block(page_path)
    angles = struct.unpack(f"<{data['faces']}f", base64.b64decode(data["angle"]))
    log_areas = struct.unpack(f"<{data['faces']}f", base64.b64decode(data["log_area"]))
    problems = []
    browser = Browser(chromium, flags)
    try:
        browser.call("Page.enable")
        browser.call("Page.navigate", {"url": "file://" + os.path.abspath(page_path)})
        for _ in range(300):
            if browser.evaluate("document.documentElement.dataset.status") in ("ok", "error"):
                break
            time.sleep(0.1)
        status = browser.evaluate("document.documentElement.dataset.status")
        if status != "ok":
            return [f"page status {status}: "
                    f"{browser.evaluate('document.documentElement.dataset.error')}"]
        panes = browser.evaluate("""[document.getElementById('surface-pane'),
            document.getElementById('layout-pane')].map(function (pane) {
              var r = pane.getBoundingClientRect();
              return [r.left + r.width / 2, r.top + r.height / 2]; })""")

        # Hover: the surface's and the layout's centres (every test mesh covers both).
        for name, (x, y) in zip(("surface", "layout"), panes):
            browser.mouse("mouseMoved", x, y)
            browser.settle()
            face = browser.evaluate("document.documentElement.dataset.hoverFace")
            box = browser.evaluate("document.getElementById('hover').style.display + '|' + "
                                   "document.getElementById('hover').textContent")
            if verbose:
                print(f"hover {name}: face {face}: {box}")
            if face is None or not box.startswith("block|face " + face):
                problems.append(f"hover over the {name}: no face shown ({face}, {box!r})")
                continue
            f = int(face)
            angle = re.search(r"max/\S+min ([0-9.e+-]+)", box)
            ratio = re.search(r"area ratio ([0-9.e+-]+)", box)
            if not angle or abs(float(angle.group(1)) - angles[f]) > 1e-4 * angles[f]:
                problems.append(f"hover face {f}: angle distortion {angle and angle.group(1)} "
                                f"but the data says {angles[f]}")
            if not ratio or abs(float(ratio.group(1)) - 2.718281828 ** log_areas[f]) > \
                    1e-3 * 2.718281828 ** log_areas[f]:
                problems.append(f"hover face {f}: area ratio {ratio and ratio.group(1)} but the "
                                f"data says ln {log_areas[f]}")
        browser.mouse("mouseMoved", 5, 5)  # off the panes: the box goes
        browser.settle()
        if browser.evaluate("document.getElementById('hover').style.display") != "none":
            problems.append("the hover box stays when the pointer leaves")

        size = browser.evaluate("[window.innerWidth, window.innerHeight]")

        def changes(action, label, left_min, right_min, right_max):
            before = browser.screenshot(*size)
            action()
            browser.settle()
            left, right = differing_pixels(before, browser.screenshot(*size), top=0)
            if verbose:
                print(f"{label}: {left} left and {right} right pixels changed")
            if left < left_min or right < right_min or right > right_max:
                problems.append(f"{label}: {left} pixels changed on the surface, {right} in the "
                                f"layout")

        (sx, sy), (lx, ly) = panes

        def drag():
            browser.mouse("mousePressed", sx, sy, button="left", buttons=1, clickCount=1)
            for step in range(1, 6):
                browser.mouse("mouseMoved", sx + 30 * step, sy + 8 * step, button="left",
                              buttons=1)
            browser.mouse("mouseReleased", sx + 150, sy + 40, button="left", buttons=0,
                          clickCount=1)
            browser.mouse("mouseMoved", 5, 5)

        # Pixel counts at half size: 500 is about 2000 pixels of the window.
        changes(drag, "dragging the surface", 500, 0, 0)
        changes(lambda: browser.mouse("mouseWheel", lx, ly, deltaX=0, deltaY=-400),
                "the wheel over the layout", 0, 500, 10 ** 9)
        changes(lambda: browser.evaluate("""(function () { var s = document.getElementById('checker');
            s.value = Number(s.value) + 1.5; s.dispatchEvent(new Event('input')); })()"""),
                "the checker slider", 500, 500, 10 ** 9)
        changes(lambda: browser.evaluate("""(function () { var s = document.getElementById('colouring');
            s.value = 'angle'; s.dispatchEvent(new Event('change')); })()"""),
                "colouring by angle distortion", 500, 500, 10 ** 9)
        if browser.evaluate("document.documentElement.dataset.status") != "ok":
            problems.append("error after interaction: " +
                            str(browser.evaluate("document.documentElement.dataset.error")))
    finally:
        browser.close()
    return problems


def main(argv):
    verbose = "-v" in argv
    argv = [a for a in argv if a != "-v"]
    if len(argv) >= 2 and argv[0] == "halves":
        problems = halves(argv[1], set(argv[2:]), verbose)
    elif len(argv) == 5 and argv[0] == "differ":
        problems = differ(argv[1], argv[2], int(argv[3]), int(argv[4]), verbose)
    elif len(argv) >= 3 and argv[0] == "interact":
        problems = interact(argv[1], argv[2], argv[3:], verbose)
    else:
        print(__doc__)
        return 2
    for problem in problems:
        print(problem)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
