"""Names the peers' runs that a generator's exception ended, and whose crash each is (dev-time).

    python3 scripts/peers/crashes.py target/peers/beamng-ai-proxy.*       # every crashed run
    python3 scripts/peers/crashes.py --quiet FOLDER                        # nothing if it did not crash

run_peer.py writes the exception's last line into the run's summary.json (`crashed`). A crash is
the tool's own behaviour in its competition only when KNOWN says so (each entry says why); any
other crash is the harness's defect (a library that changed under the tool, an executor that
answered what the pipeline does not expect), not a result, and makes the exit status 1.
scripts/results/ imports `classify` to mark the tool's own crashes in the field's table and to
refuse a run that ended in a harness defect. Standard library only.
"""
import json
import os
import re
import sys

# tool (the generator's class in summary.json) -> [(pattern of the exception line, why it is the
# tool's own)].
KNOWN = {
    "RandomTestGenerator": [
        (re.compile(r"^ValueError: Invalid inputs\.$"),
         "the pipeline's random generator can draw the same point twice in a road, which the "
         "pipeline's spline fit (splprep in tests_generation._interpolate) refuses; it did so "
         "beside BeamNG too"),
    ],
}


def crash_of(folder):
    """(generator class, exception line) of a crashed run, None for a run that did not crash."""
    with open(os.path.join(folder, "summary.json")) as f:
        summary = json.load(f)
    crashed = summary.get("crashed")
    if not crashed:
        return None
    return summary.get("generator", "?").rsplit(".", 1)[-1], crashed


def classify(folder):
    """None when the run did not crash; else (is the tool's own, what to say of it)."""
    crash = crash_of(folder)
    if crash is None:
        return None
    tool, line = crash
    for pattern, why in KNOWN.get(tool, []):
        if pattern.search(line):
            return True, f"{tool} crashed as in its competition ({why}): {line}"
    return False, f"HARNESS DEFECT: {tool} crashed where it did not in its competition: {line}"


def main(argv):
    quiet = "--quiet" in argv
    # A glob of target/peers/ also names the campaign's FOLDER.log files: only folders count.
    folders = [a for a in argv if a != "--quiet" and os.path.isdir(a)]
    if not folders:
        sys.exit(__doc__.strip().splitlines()[2].strip())
    own = defects = 0
    for folder in folders:
        verdict = classify(folder)
        if verdict is None:
            continue
        is_own, text = verdict
        own += is_own
        defects += not is_own
        print(f"crashes.py: {folder}: {text}", file=sys.stderr)
    if not quiet:
        print(f"crashes.py: {len(folders)} runs, {own} ended by their tool's own crash, "
              f"{defects} by a harness defect", file=sys.stderr)
    return 1 if defects else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
