"""What the tests share: the commands that start this folder's scripts, the binary, reference roads."""

import os
import shlex
import subprocess
import sys
from typing import List

import wogan

HERE = os.path.dirname(os.path.abspath(__file__))


def command(script: str) -> str:
    """`cmd:PYTHON SCRIPT` for wogan's --executor or --oracle: this Python runs a script here."""
    return f"cmd:{shlex.quote(sys.executable)} {shlex.quote(os.path.join(HERE, script))}"


def wogan_cli(*args: str, input: str = "") -> subprocess.CompletedProcess:
    """Runs the binary with `args`, `input` on stdin; its output captured as text."""
    return subprocess.run([wogan.find_binary(), *args], input=input, capture_output=True, text=True, timeout=300)


# Three roads of the competition's form (tests/reference/roads.jsonl's first three).
ROADS: List[List[List[float]]] = [
    [[100.0, 10.0], [100.0, 25.0], [99.911185, 39.999737], [95.487376, 54.332564], [82.844127, 62.40401], [68.283297, 58.800924]],
    [[100.0, 10.0], [100.0, 25.0], [103.021079, 39.69262], [104.712361, 54.596967], [101.081101, 69.150796], [88.731867, 77.665279]],
    [[100.0, 10.0], [100.0, 25.0], [97.000254, 39.69699], [95.097976, 54.575879], [93.754754, 69.515617], [88.801841, 83.674312]],
]
