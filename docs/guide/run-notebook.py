"""Executes docs/guide/guide.ipynb with nbclient from the repository root
(each cell at most 120 s) and writes the executed notebook, outputs and
figures included, to target/guide.ipynb; any failing cell (an `assert`
whose number drifted, an error) fails the run. python/run-tests.sh runs it
with a fixed budget."""

import sys
from pathlib import Path

import nbformat
from nbclient import NotebookClient

root = Path(__file__).resolve().parents[2]
notebook = nbformat.read(root / "docs/guide/guide.ipynb", as_version=4)
NotebookClient(
    notebook, timeout=120, kernel_name="python3", resources={"metadata": {"path": str(root)}}
).execute()
out = root / "target" / "guide.ipynb"
out.parent.mkdir(exist_ok=True)
nbformat.write(notebook, out)
print(f"executed {len(notebook.cells)} cells; wrote {out}", file=sys.stderr)
