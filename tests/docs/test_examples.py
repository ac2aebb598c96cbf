"""The examples of the README and the user guide (docs/) run, as written.

Run by ctest (Docs.ExamplesRun) with LINKFIT_BUILD the build tree and PYTHONPATH its python/.

Every fenced block in README.md and docs/**/*.md is collected:
- `sh` (`bash`, `shell`) blocks run as a bash script with `set -e -o pipefail`: every command
  must exit 0; `console` blocks run their `$ ` lines the same way;
- `python` blocks run as a script of their own: none may raise;
- blocks in other languages (`json`, `text`, `cpp`, `cmake`, MyST directives) are listings,
  not run;
- a block of a run language that must not run — a synopsis with placeholders, the setup or the
  test suite itself, a benchmark of minutes, a cluster — is marked in the source by a comment
  `<!-- not run: why -->` on the line right before its opening fence (or, where the block must
  open its page, right after its closing fence).

Each runs in a fresh temporary directory holding `data/` (the bundled examples, a link) and
`build/bin/` (the build tree's programs, a link), with that `bin/` first on PATH, so that the
examples' `build/bin/linkfit ...` and `data/...` read as they do from the repository root.

The docstring examples of the Python API (help(linkfit.X), the guide's API page) run too, as
doctests, in such a directory.
"""

import doctest
import json
import os
import pathlib
import re
import subprocess
import sys

import pytest

SOURCE = pathlib.Path(__file__).resolve().parents[2]
BUILD = pathlib.Path(os.environ.get("LINKFIT_BUILD", SOURCE / "build")).resolve()
PAGES = [SOURCE / "README.md"] + sorted((SOURCE / "docs").rglob("*.md"))
SHELL = {"sh", "bash", "shell", "console"}
RUN = SHELL | {"python"}
FENCE = re.compile(r"^(?P<indent>\s*)(?P<fence>`{3,}|~{3,})\s*(?P<info>.*)$")
NOT_RUN = re.compile(r"^\s*<!--\s*not run\b")
# Seconds one block may take (the examples use fast tasks; the whole test takes about 20 s).
TIMEOUT = 120


def blocks(path):
    """(line, language, text, marked) of every fenced block of a Markdown file."""
    lines = path.read_text(encoding="utf-8").split("\n")
    found = []
    i = 0
    while i < len(lines):
        opening = FENCE.match(lines[i])
        if not opening:
            i += 1
            continue
        fence, indent = opening.group("fence"), opening.group("indent")
        closing = re.compile(r"^\s*" + re.escape(fence[0]) + "{%d,}\\s*$" % len(fence))
        end = i + 1
        while end < len(lines) and not closing.match(lines[end]):
            end += 1
        info = opening.group("info").strip()
        language = info.split()[0] if info and not info.startswith("{") else ""
        body = [line[len(indent):] if line.startswith(indent) else line.lstrip()
                for line in lines[i + 1:end]]
        before = lines[i - 1] if i > 0 else ""
        after = lines[end + 1] if end + 1 < len(lines) else ""
        marked = bool(NOT_RUN.match(before) or NOT_RUN.match(after))
        found.append((i + 1, language, "\n".join(body) + "\n", marked))
        i = end + 1
    return found


def examples():
    """pytest params of every block that runs, named page:line."""
    params = []
    for path in PAGES:
        for line, language, text, marked in blocks(path):
            if language in RUN and not marked:
                name = "%s:%d" % (path.relative_to(SOURCE), line)
                params.append(pytest.param(language, text, id=name))
    return params


@pytest.fixture
def workdir(tmp_path):
    """A directory laid out as the repository root for the examples: data/ and build/bin/."""
    (tmp_path / "data").symlink_to(SOURCE / "data", target_is_directory=True)
    (tmp_path / "build").mkdir()
    (tmp_path / "build" / "bin").symlink_to(BUILD / "bin", target_is_directory=True)
    return tmp_path


def environment():
    env = dict(os.environ)
    env["PATH"] = str(BUILD / "bin") + os.pathsep + env.get("PATH", "")
    env["PYTHONPATH"] = str(BUILD / "python") + (
        os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    env["MPLBACKEND"] = "Agg"  # pictures to files, no display
    return env


def shell_script(language, text):
    if language != "console":
        return text
    return "\n".join(line[2:] for line in text.split("\n") if line.startswith("$ ")) + "\n"


@pytest.mark.parametrize("language,text", examples())
def test_example_runs(language, text, workdir):
    if language in SHELL:
        script = workdir / "example.sh"
        script.write_text("set -e -o pipefail\n" + shell_script(language, text))
        command = ["bash", str(script)]
    else:
        script = workdir / "example.py"
        script.write_text(text)
        command = [sys.executable, str(script)]
    completed = subprocess.run(command, cwd=workdir, env=environment(), capture_output=True,
                               text=True, timeout=TIMEOUT, stdin=subprocess.DEVNULL)
    assert completed.returncode == 0, (
        "the example exited %d:\n%s\n--- stdout ---\n%s\n--- stderr ---\n%s"
        % (completed.returncode, text, completed.stdout[-3000:], completed.stderr[-3000:]))


def test_the_examples_are_found():
    """The collection itself: the README's examples and the guide's, the markers honoured."""
    readme = blocks(SOURCE / "README.md")
    assert readme[0][3], "the README's first block (setup and tests) is marked not run"
    run = [b for b in readme if b[1] in RUN and not b[3]]
    assert len([b for b in run if b[1] == "sh"]) >= 9
    assert len([b for b in run if b[1] == "python"]) >= 9
    assert len(examples()) >= 50


def test_docstring_examples_run(workdir, monkeypatch):
    """The examples in the docstrings of linkfit (help() and the API page), as doctests."""
    import linkfit
    import linkfit.drawing
    import numpy

    modules = [linkfit, linkfit.drawing]
    try:  # Debian's python3-dask (scripts/setup.sh); test_dask.py skips without it too
        import linkfit.dask
        modules.append(linkfit.dask)
    except ImportError:
        pass

    monkeypatch.chdir(workdir)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    task = json.loads((SOURCE / "data" / "four_bar_5_poses.json").read_text())
    globs = {"linkfit": linkfit, "json": json, "numpy": numpy, "task": task,
             "result": linkfit.solve(task), "tasks": [task] * 4}
    flags = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
    tried = 0
    for module in modules:
        failed, attempted = doctest.testmod(module, extraglobs=globs, optionflags=flags,
                                            report=True, verbose=False)
        assert failed == 0, module.__name__
        tried += attempted
    assert tried >= 10
