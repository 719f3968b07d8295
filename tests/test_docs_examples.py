"""The examples of the docs work: their Python blocks run and their commands parse.

Pages: README.md and every page under docs/ (docs/api/ included).

Python blocks. Every fenced ```python block runs, unless the last non-blank line before
it is ``<!-- not run: REASON -->`` with a reason (it needs a cluster, a GPU, minutes):
the comment stays in the page's source, invisible on the site. A page's blocks run in
the page's order, each in a fresh interpreter (a fresh namespace: a block is whole, as a
reader copies it), all in one temporary directory of the page's, so a block may read
what an earlier block of its page wrote (``swim.md``: the swim's ``gait.json``), never
its variables. Each block has ``BLOCK_TIMEOUT`` seconds; a block meant to run should
take a few seconds (a small grid, a short swim, a tiny search), so that all of them
take about a minute on one core.

Commands. Every line that runs ``aquagait`` in an indented code block, in a ```bash,
```sh or ```shell fence, or after a ``$ `` prompt in any other fence that is not
Python (a console transcript: its output lines are not commands), parses with the real
parser, ``aquagait.cli.build_parser()``: no ``SystemExit``. A trailing comment
(``  # ...``) is left out, a line ending in ``\\`` is joined to the next, each command
of ``a && b`` or ``a; b`` is checked, and ``--help`` lines are skipped. Placeholders
(NAME, RUN_DIR, FILE) are parsed as given: where the parser takes any string they
parse, and where it wants a number or one of its choices (``--seed S``) the page must
show a real value instead, one a reader can paste.
"""

import contextlib
import importlib.util
import io
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md"] + sorted((ROOT / "docs").rglob("*.md"))
NOT_RUN = re.compile(r"^<!--\s*not run\b(?P<colon>:?)(?P<reason>.*?)-->[ \t]*$", re.S | re.M)
"""``<!-- not run: REASON -->`` on the last non-blank line before a Python block."""
BLOCK_TIMEOUT = 120
"""Seconds a block may take (the blocks meant to run take a few seconds each)."""
FENCE = re.compile(r"^ {0,3}(?P<fence>`{3,}|~{3,})\s*(?P<lang>[\w+-]*)")
SHELL = {"bash", "sh", "shell", "zsh"}
"""Fences whose every line is a command; other fences' commands follow a ``$`` prompt."""


def name(page: Path) -> str:
    return str(page.relative_to(ROOT))


def python_blocks(text: str):
    """``(line, code, reason)`` of each fenced Python block: ``reason`` is None for a block
    that runs, else what its ``not run`` comment says (empty if it says nothing)."""
    for match in re.finditer(r"^```python[ \t]*\n(.*?)^```", text, re.S | re.M):
        line = text.count("\n", 0, match.start()) + 1
        before = text[: match.start()].rstrip()
        comment = re.search(r"^<!--(?:(?!<!--).)*-->\Z", before, re.S | re.M)
        marker = NOT_RUN.fullmatch(comment.group(0)) if comment else None
        reason = None if marker is None else marker.group("reason").strip()
        if marker is not None and not marker.group("colon"):
            reason = ""  # <!-- not run --> says nothing: the reason follows a colon
        yield line, match.group(1), reason


def runnable_pages():
    return [
        pytest.param(page, id=name(page))
        for page in PAGES
        if any(reason is None for _, _, reason in python_blocks(page.read_text()))
    ]


def test_every_block_not_run_says_why():
    found = []
    for page in PAGES:
        text = page.read_text()
        for line, _, reason in python_blocks(text):
            if reason == "":
                found.append(f"{name(page)}:{line}")
        markers = sum(1 for _ in NOT_RUN.finditer(text))
        marked = sum(reason is not None for _, _, reason in python_blocks(text))
        assert markers == marked, f"{name(page)}: a 'not run' comment is not right before a block"
    assert not found, f"'<!-- not run: REASON -->' needs its reason: {', '.join(found)}"


@pytest.mark.parametrize("page", runnable_pages())
def test_the_python_blocks_of_a_page_run(page, tmp_path):
    has_gymnasium = importlib.util.find_spec("gymnasium") is not None
    ran = 0
    for line, code, reason in python_blocks(page.read_text()):
        if reason is not None or ("gymnasium" in code and not has_gymnasium):
            continue
        try:
            done = subprocess.run(
                [sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True,
                timeout=BLOCK_TIMEOUT,
            )  # fmt: skip
        except subprocess.TimeoutExpired:
            pytest.fail(f"{name(page)}:{line} ran over {BLOCK_TIMEOUT} s: make it smaller, or "
                        "mark it <!-- not run: REASON -->")  # fmt: skip
        assert done.returncode == 0, f"{name(page)}:{line}:\n{code}\n{done.stderr[-4000:]}"
        ran += 1
    if not ran:
        pytest.skip("its blocks need gymnasium (the gym extra)")


def shell_lines(text: str):
    """``(line, command)`` of each line that may run aquagait, as written (module doc)."""
    fence, lang, pending = None, "", None
    for number, raw in enumerate(text.splitlines(), 1):
        opening = FENCE.match(raw)
        if fence is None and opening:
            fence, lang = opening.group("fence"), opening.group("lang").lower()
            continue
        if fence is not None:
            if raw.strip().startswith(fence) and not raw.strip().strip(fence[0]):
                fence = None
                continue
            if lang in ("python", "py", "pycon"):
                continue
            line = raw.strip()
            if lang not in SHELL and not line.startswith("$ "):
                continue
        elif raw.startswith("    ") or (pending and raw.strip()):
            line = raw.strip()
        else:
            pending = None
            continue
        line = line.removeprefix("$ ")
        if pending is not None:
            start, line = pending[0], f"{pending[1]} {line}"
        else:
            start = number
        if line.endswith("\\"):
            pending = (start, line[:-1].rstrip())
            continue
        pending = None
        yield start, line


def aquagait_commands(line: str) -> list[list[str]]:
    """The words of each aquagait command of a shell line: its trailing comment left out,
    split at ``&&``, ``||``, ``|`` and ``;`` outside quotes, leading ``VAR=value`` settings
    dropped.

    Raises:
        ValueError: the line is not whole (a quote left open).
    """
    lexer = shlex.shlex(re.split(r"\s{2,}#|^#", line)[0], posix=True, punctuation_chars=True)
    lexer.whitespace_split, lexer.commenters = True, ""
    commands, words = [], []
    for word in [*lexer, ";"]:
        if word and set(word) <= set("&|;"):
            while words and re.fullmatch(r"[A-Za-z_]\w*=.*", words[0]):
                words.pop(0)
            if words[:1] == ["aquagait"]:
                commands.append(words)
            words = []
        else:
            words.append(word)
    return commands


def test_the_commands_of_the_docs_parse():
    from aquagait.cli import build_parser

    parser, failures, checked = build_parser(), [], 0
    for page in PAGES:
        for line, shell in shell_lines(page.read_text()):
            try:
                commands = aquagait_commands(shell)
            except ValueError as err:
                if re.match(r"([A-Za-z_]\w*=\S*\s+)*aquagait\s", shell):
                    failures.append(f"{name(page)}:{line}: {shell}\n    not one line: {err}")
                continue
            for words in commands:
                if {"--help", "-h"} & set(words):
                    continue
                where = f"{name(page)}:{line}: {shlex.join(words)}"
                errors = io.StringIO()
                try:
                    with contextlib.redirect_stderr(errors):
                        parser.parse_args(words[1:])
                except SystemExit:
                    message = errors.getvalue().strip().splitlines()
                    failures.append(f"{where}\n    {message[-1] if message else 'exit'}")
                checked += 1
    assert checked > 40, f"only {checked} commands found: is the scan broken?"
    listed = "\n".join(failures)
    assert not failures, f"commands in the docs that aquagait refuses:\n{listed}"


def test_the_scan_finds_commands_where_the_docs_write_them():
    text = """Prose: aquagait swim eel2d is not a command.

    aquagait swim eel2d --seconds 4          # a comment
    pip install x && aquagait check fish

```bash
OMP_NUM_THREADS=1 aquagait bench fluid \\
    --out runs/bench
```

```
$ aquagait swim fish --no-video
aquagait swim fish: this is output
```

```python
aquagait = "not a command"
```
"""
    found = [
        (line, shlex.join(words))
        for line, shell in shell_lines(text)
        for words in aquagait_commands(shell)
    ]
    assert found == [
        (3, "aquagait swim eel2d --seconds 4"),
        (4, "aquagait check fish"),
        (7, "aquagait bench fluid --out runs/bench"),
        (12, "aquagait swim fish --no-video"),
    ]
    assert aquagait_commands("aquagait swim \"$(python -c 'a; b')\" && x") == [
        ["aquagait", "swim", "$(python -c 'a; b')"]
    ]
    marked = "<!-- not run: needs a cluster -->\n```python\nx = 1\n```\n"
    assert [reason for *_, reason in python_blocks(marked)] == ["needs a cluster"]
    unexplained = marked.replace(": needs a cluster", "")
    assert [reason for *_, reason in python_blocks(unexplained)] == [""]
