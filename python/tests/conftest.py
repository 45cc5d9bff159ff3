"""The package's tests run the real binary: the installed one (CI installs the wheel into a fresh
venv and sets WOGAN_TEST_INSTALLED=1), or from a checkout `python/` with $WOGAN_BIN."""

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
if os.environ.get("WOGAN_TEST_INSTALLED") != "1":
    source = os.path.dirname(HERE)
    sys.path.insert(0, source)
    # The executors and controllers these tests start import the package too.
    os.environ["PYTHONPATH"] = os.pathsep.join(filter(None, [source, os.environ.get("PYTHONPATH")]))
