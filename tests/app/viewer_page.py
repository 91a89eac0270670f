"""The viewer's page as the tests read it, in svetlo serve (viewer_test.py) and in the web page
(tests/web/web_test.py), which are the same page: #view's pixels, a render settled, a control
set as a visitor sets it."""
import json
import os
import time

# Under an emulator (make test-arm64: SVETLO_EMULATED=1) svetlo runs tens of times slower.
SLOW = 10 if os.environ.get("SVETLO_EMULATED") == "1" else 1


# The pixels of #view once loaded: a hash, the count of non-black pixels, and its source.
VIEW = """(() => {
  const img = document.getElementById('view');
  if (!img || !/^(blob|data):/.test(img.src) || !img.complete || !img.naturalWidth) return null;
  const c = document.createElement('canvas');
  c.width = img.naturalWidth; c.height = img.naturalHeight;
  const g = c.getContext('2d'); g.drawImage(img, 0, 0);
  const d = g.getImageData(0, 0, c.width, c.height).data;
  let h = 0, lit = 0;
  for (let i = 0; i < d.length; i += 4) {
    h = (Math.imul(h, 31) + d[i] + 7 * d[i + 1] + 13 * d[i + 2]) >>> 0;
    if (d[i] + d[i + 1] + d[i + 2] > 30) lit++;
  }
  return [h, lit, img.src];
})()"""


def wait_view(tab, previous_src=None, seconds=60 * SLOW):
    end = time.time() + seconds
    while time.time() < end:
        v = tab.eval(VIEW)
        if v and v[2] != previous_src and not tab.eval("window.svetloBusy()"):
            return v
        time.sleep(0.1)
    return None


def settle(tab, seconds=60 * SLOW):
    """#view once it has stopped changing: no render due, the same image half a second apart
    (the page sends a JPEG while the view moves, then one PNG)."""
    end = time.time() + seconds
    last = None
    while time.time() < end:
        v = tab.eval(VIEW)
        if v and not tab.eval("window.svetloBusy()") and last and v[2] == last[2]:
            return v
        last = v
        time.sleep(0.5)
    return None


def set_control(tab, element, value, event="change"):
    tab.eval("(() => { const e = document.getElementById(%s); e.value = %s; "
             "e.dispatchEvent(new Event(%s)); })()"
             % (json.dumps(element), json.dumps(value), json.dumps(event)))
