"""The example of docs/python.md runs and prints what the page shows."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

from conftest import ROOT


def test_the_example_prints_what_the_page_shows(tmp_path: Path, monkeypatch):
    page = (ROOT / "docs" / "python.md").read_text()
    m = re.search(r"## Example\n\n```python\n(.*?)```\n\n```\n(.*?)```", page, re.S)
    assert m, "docs/python.md: no example with its output"
    code, shown = m.group(1), m.group(2)
    assert len(code.strip().splitlines()) <= 25, "the example is meant to be about 20 lines"
    monkeypatch.chdir(ROOT)
    code = code.replace('"vcd_out"', repr(str(tmp_path)))
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, "docs/python.md", "exec"), {})
    assert out.getvalue() == shown.replace("vcd_out/fig15a.vcd", f"{tmp_path}/fig15a.vcd")
    assert (tmp_path / "fig15a.vcd").exists()


def test_the_hdl_guide_links_this_page():
    assert "(python.md)" in (ROOT / "docs" / "hdl-guide.md").read_text()
