#!/usr/bin/env python3
"""Every output of every README command, as digests, and two runs compared.

    scripts/readme_outputs.py run --shlight BIN [--readme README.md] -o RUN.json
    scripts/readme_outputs.py compare BEFORE.json AFTER.json

`run` reads the `cargo run --release -- ...` lines of README.md's ```sh
blocks as tests/readme.rs does (continuations joined, `# needs: window`
lines skipped, `# needs: gpu` lines run unless --no-gpu), runs each with
BIN in order in one fresh directory holding links to the bundled envmaps/
and meshes/, and records per command its exit status, the SHA-256 of its
standard output, and the SHA-256 of every file it created or changed.
Standard error is not compared: it holds timings.

`compare` prints every command whose status, stdout or files differ, and
exits 1 if any does. scripts/readme-identical.sh builds two revisions and
runs both; it is how a refactor proves the README's outputs unchanged.
Python 3 standard library only.
"""

import argparse
import hashlib
import json
import os
import subprocess
import sys
import tempfile

PREFIX = "cargo run --release -- "


def commands(readme):
    """(command, needs) for each README command line, in order."""
    out, in_sh, pending = [], False, ""
    for raw in readme.splitlines():
        trimmed = raw.strip()
        if trimmed.startswith("```"):
            in_sh = (not in_sh) and trimmed == "```sh"
            continue
        if not in_sh:
            continue
        if trimmed.endswith("\\"):
            pending += trimmed[:-1].rstrip() + " "
            continue
        full, pending = pending + trimmed, ""
        if not full.startswith(PREFIX):
            continue
        rest = full[len(PREFIX):]
        needs = None
        if "# needs:" in rest:
            rest, need = rest.split("# needs:", 1)
            needs = need.strip()
        out.append((rest.strip(), needs))
    return out


def snapshot(root):
    """path -> (size, mtime_ns) of every regular file under root, links not followed."""
    files = {}
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames[:] = [d for d in dirnames if not os.path.islink(os.path.join(dirpath, d))]
        for name in filenames:
            path = os.path.join(dirpath, name)
            if os.path.islink(path):
                continue
            st = os.stat(path)
            files[os.path.relpath(path, root)] = (st.st_size, st.st_mtime_ns)
    return files


def sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def run(args):
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    readme = args.readme or os.path.join(repo, "README.md")
    with open(readme, encoding="utf-8") as f:
        lines = commands(f.read())
    exe = os.path.abspath(args.shlight)
    results = []
    with tempfile.TemporaryDirectory(prefix="shlight-readme-") as work:
        for bundled in ("envmaps", "meshes"):
            os.symlink(os.path.join(repo, bundled), os.path.join(work, bundled))
        before = snapshot(work)
        for command, needs in lines:
            if needs == "window" or (needs == "gpu" and args.no_gpu):
                results.append({"command": command, "skipped": needs})
                continue
            proc = subprocess.run(
                ["sh", "-c", f'"$SHLIGHT" {command}'],
                cwd=work,
                env={**os.environ, "SHLIGHT": exe},
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
            )
            after = snapshot(work)
            changed = sorted(p for p, s in after.items() if before.get(p) != s)
            before = after
            results.append({
                "command": command,
                "status": proc.returncode,
                "stdout": hashlib.sha256(proc.stdout).hexdigest(),
                "files": {p: sha256(os.path.join(work, p)) for p in changed},
                "stderr_tail": proc.stderr.decode(errors="replace")[-400:] if proc.returncode else "",
            })
            mark = "ok" if proc.returncode == 0 else f"exit {proc.returncode}"
            print(f"[{mark}] {command} ({len(changed)} files)", file=sys.stderr)
    with open(args.output, "w", encoding="utf-8") as f:
        json.dump({"shlight": exe, "commands": results}, f, indent=1)
    return 0


def compare(args):
    with open(args.before, encoding="utf-8") as f:
        before = {r["command"]: r for r in json.load(f)["commands"]}
    with open(args.after, encoding="utf-8") as f:
        after = json.load(f)["commands"]
    differ = 0
    new = 0
    same_files = 0
    for r in after:
        b = before.get(r["command"])
        if "skipped" in r or (b is not None and "skipped" in b):
            print(f"skipped: {r['command']}")
            continue
        if b is None:
            print(f"new (no earlier run): {r['command']}")
            new += 1
            continue
        problems = []
        if b["status"] != r["status"]:
            problems.append(f"exit status {b['status']} -> {r['status']} {r['stderr_tail']!r}")
        if b["stdout"] != r["stdout"]:
            problems.append("stdout differs")
        for path in sorted(set(b["files"]) | set(r["files"])):
            if b["files"].get(path) != r["files"].get(path):
                problems.append(f"{path}: " + (
                    "only before" if path not in r["files"] else
                    "only after" if path not in b["files"] else "bytes differ"))
            else:
                same_files += 1
        if problems:
            differ += 1
            print(f"DIFFERS: {r['command']}")
            for p in problems:
                print(f"    {p}")
    total = sum(1 for r in after if "skipped" not in r) - new
    print(f"{total - differ} of {total} commands identical ({same_files} files byte-identical); {differ} differ; {new} new")
    return 1 if differ else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="verb", required=True)
    r = sub.add_parser("run", help="run the README's commands with one binary")
    r.add_argument("--shlight", required=True, help="the shlight binary")
    r.add_argument("--readme", help="README.md to read the commands from (default: this checkout's)")
    r.add_argument("--no-gpu", action="store_true", help="skip the `# needs: gpu` lines")
    r.add_argument("-o", "--output", required=True, help="where the digests go (JSON)")
    c = sub.add_parser("compare", help="compare two runs")
    c.add_argument("before")
    c.add_argument("after")
    args = parser.parse_args()
    sys.exit(run(args) if args.verb == "run" else compare(args))


if __name__ == "__main__":
    main()
