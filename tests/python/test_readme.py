"""The Python samples of the README run as written (pydantic-core's ``test_docstrings.py``
habit): each fenced ``python`` block is executed with the installed package, warnings as
errors (``pytest.ini``)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[2] / "README.md"


def python_blocks() -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", README.read_text(encoding="utf-8"), flags=re.S | re.M)


def test_the_readme_has_a_python_sample() -> None:
    assert python_blocks(), f"no ```python block in {README}"


@pytest.mark.parametrize("index", range(len(python_blocks())))
def test_readme_python_sample_runs(index: int) -> None:
    code = python_blocks()[index]
    exec(compile(code, f"{README}:python block {index}", "exec"), {"__name__": "readme"})
