"""Executes docs/guide/guide.ipynb with nbclient as Jupyter runs it: the
kernel's working directory is docs/guide, the notebook's own folder (each
cell at most 120 s), or the folder given as the one argument (the
repository root, say). Writes the executed notebook, outputs and figures
included, to target/guide.ipynb; any failing cell (an `assert` whose number
drifted, an error) fails the run. python/run-tests.sh runs it with a fixed
budget."""

import sys
from pathlib import Path

import nbformat
from nbclient import NotebookClient

root = Path(__file__).resolve().parents[2]
guide = root / "docs/guide"
cwd = Path(sys.argv[1]).resolve() if len(sys.argv) > 1 else guide
notebook = nbformat.read(guide / "guide.ipynb", as_version=4)
NotebookClient(
    notebook, timeout=120, kernel_name="python3", resources={"metadata": {"path": str(cwd)}}
).execute()
out = root / "target" / "guide.ipynb"
out.parent.mkdir(exist_ok=True)
nbformat.write(notebook, out)
print(f"executed {len(notebook.cells)} cells in {cwd}; wrote {out}", file=sys.stderr)
