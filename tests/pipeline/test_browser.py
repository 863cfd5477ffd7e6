"""The smoke report opens in headless Chromium, renders, and every image loads."""

from __future__ import annotations

import os
import re
import shutil
import subprocess

import pytest

from .conftest import ROOT

pytestmark = [pytest.mark.pipeline, pytest.mark.browser]

CHECK = """
<script>
window.addEventListener('load', function () {
  var imgs = Array.from(document.images);
  var ok = imgs.filter(function (i) { return i.complete && i.naturalWidth > 0; }).length;
  var d = document.createElement('div');
  d.id = 'imgcheck';
  d.textContent = 'IMAGES ' + ok + '/' + imgs.length + ' H2 ' +
                  document.querySelectorAll('h2').length;
  document.body.appendChild(d);
});
</script>
"""

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--virtual-time-budget=5000"]


def _chromium() -> str:
    path = shutil.which("chromium") or shutil.which("chromium-browser")
    if path is None:
        if os.environ.get("CI"):
            pytest.fail("chromium is not installed (make test installs Debian's chromium)")
        pytest.skip("chromium not installed here; `make chromium` installs it")
    return path


def test_report_renders_and_all_images_load(smoke_run, tmp_path):
    chromium = _chromium()
    index = ROOT / "reports" / "smoke" / "index.html"
    page = index.read_text().replace("</body>", CHECK + "</body>")
    probe = tmp_path / "index.html"
    probe.write_text(page)
    profile_dir = tmp_path / "profile"
    dom = subprocess.run([chromium, *FLAGS, f"--user-data-dir={profile_dir}", "--dump-dom",
                          probe.as_uri()], capture_output=True, text=True, timeout=120)
    m = re.search(r"IMAGES (\d+)/(\d+) H2 (\d+)", dom.stdout)
    assert m, f"page did not finish loading:\n{dom.stderr[-2000:]}"
    ok, total, h2 = map(int, m.groups())
    assert ok == total
    assert total == page.count("<img ")
    assert h2 >= 7  # six chapters and the claims
    shot = tmp_path / "shot.png"
    subprocess.run([chromium, *FLAGS, f"--user-data-dir={profile_dir}",
                    f"--screenshot={shot}", "--window-size=1200,2000", index.as_uri()],
                   capture_output=True, timeout=120)
    assert shot.exists() and shot.stat().st_size > 10_000
