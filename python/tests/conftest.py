"""The package's tests run the real binary. From a checkout they import `python/wogan` and run
$WOGAN_BIN (default: the checkout's target/release/wogan); the executors and controllers they
start (small scripts here, run with this Python) import the package from there too. With
WOGAN_TEST_INSTALLED=1 (CI, after installing the wheel into a fresh venv) they use the installed
package and binary."""

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
PYTHON_DIR = os.path.dirname(HERE)
REPO = os.path.dirname(PYTHON_DIR)

if os.environ.get("WOGAN_TEST_INSTALLED") != "1":
    sys.path.insert(0, PYTHON_DIR)
    os.environ["PYTHONPATH"] = os.pathsep.join(filter(None, [PYTHON_DIR, os.environ.get("PYTHONPATH")]))
    built = os.path.join(REPO, "target", "release", "wogan")
    if not os.environ.get("WOGAN_BIN") and os.path.exists(built):
        os.environ["WOGAN_BIN"] = built
