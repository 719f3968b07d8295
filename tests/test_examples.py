"""Every example runs headless in a few seconds with ``--steps 2`` (docs/development.md)."""

import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = sorted((Path(__file__).resolve().parents[1] / "examples").glob("[0-9][0-9]_*.py"))


@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.stem)
def test_example_runs(script):
    header = script.read_text().split('"""')[1]
    assert header.strip(), f"{script.name} needs a header docstring saying what it shows"
    result = subprocess.run(
        [sys.executable, str(script), "--steps", "2"], capture_output=True, text=True, timeout=60
    )
    assert result.returncode == 0, result.stderr
