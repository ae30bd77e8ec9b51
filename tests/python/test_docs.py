"""docs/python.md: its Python code blocks, run in order in one namespace from the source
tree, as a reader would paste them."""

import os
import re

from conftest import SOURCE_DIR


def test_the_python_tutorial_runs(tmp_path, capsys):
    text = (SOURCE_DIR / "docs/python.md").read_text()
    blocks = re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)
    assert len(blocks) >= 3
    os.chdir(SOURCE_DIR)
    namespace = {"__name__": "__tutorial__"}
    for block in blocks:
        exec(compile(block, "docs/python.md", "exec"), namespace)
    assert "camopt" in namespace
