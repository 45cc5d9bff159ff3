"""The examples of python/README.md work as written: its executor (15 lines) drives a search, its
controller drives another."""

import os
import re
import shlex
import sys

import pytest

import wogan

README = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "README.md")


def readme_example(section):
    """The first Python block under the README's heading `section`."""
    with open(README, encoding="utf-8") as f:
        text = f.read()
    part = text[text.index(f"## {section}"):]
    return re.search(r"```python\n(.*?)```", part, re.S).group(1)


def as_command(code, tmp_path, name):
    script = tmp_path / name
    script.write_text(code)
    return f"cmd:{shlex.quote(sys.executable)} {shlex.quote(str(script))}"


@pytest.fixture
def bends():
    return readme_example("An executor")


def test_the_readme_executor_has_15_lines_and_drives_a_search(bends, tmp_path):
    assert len(bends.strip().splitlines()) <= 15, bends
    run = wogan.run(["--max-tests", "20", "--seed", "2", "--executor", as_command(bends, tmp_path, "bends.py")])
    assert len(run.tests) == 20 and run.summary["executed"] == 20
    assert all(t["sim_time_s"] == 10.0 for t in run.tests)
    assert {t["outcome"] for t in run.tests} == {"PASS", "FAIL"}


def test_the_readme_controller_drives_a_search(tmp_path):
    keeper = readme_example("A controller")
    run = wogan.run(["--max-tests", "10", "--seed", "2", "--oracle", as_command(keeper, tmp_path, "keeper.py")])
    assert len(run.tests) == 10
    assert all(t["outcome"] in ("PASS", "FAIL") for t in run.tests), [t.get("error") for t in run.tests]
    assert sum(t["outcome"] == "PASS" for t in run.tests) >= 7
