"""Pools several runs into one, so that `wogan report --table` counts distinct failures over all
of them at once (how many a road family holds, against how many one run finds):

    python3 scripts/experiments/pool_runs.py OUT RUN...

RUN are `wogan run` files (OUT is then a run file: the first run's header, every test renumbered
in order, no summary, so the report names it unfinished) or the competition's result folders (OUT
is then a folder of `test.NNNNN.json`, renumbered, with the first folder's summary.json). OUT must
not exist.
"""

import json
import pathlib
import shutil
import sys


def pool_run_files(out: pathlib.Path, runs: list) -> int:
    tests = 0
    with out.open("x", encoding="utf-8") as pooled:
        for index, run in enumerate(runs):
            for line in run.read_text(encoding="utf-8").splitlines():
                record = json.loads(line)
                if record.get("type") == "header" and index == 0:
                    pooled.write(line + "\n")
                elif record.get("type") == "test":
                    tests += 1
                    record["id"] = tests
                    pooled.write(json.dumps(record) + "\n")
    return tests


def pool_folders(out: pathlib.Path, folders: list) -> int:
    out.mkdir()
    tests = 0
    for folder in folders:
        for test in sorted(folder.glob("test.*.json")):
            tests += 1
            record = json.loads(test.read_text(encoding="utf-8"))
            record["id"] = tests
            (out / f"test.{tests:05d}.json").write_text(json.dumps(record), encoding="utf-8")
    shutil.copy(folders[0] / "summary.json", out / "summary.json")
    return tests


def main() -> int:
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    out, runs = pathlib.Path(sys.argv[1]), [pathlib.Path(r) for r in sys.argv[2:]]
    if out.exists():
        print(f"pool_runs.py: {out} exists; give a new path", file=sys.stderr)
        return 2
    folders = [r.is_dir() for r in runs]
    if any(folders) and not all(folders):
        print("pool_runs.py: give run files or result folders, not both", file=sys.stderr)
        return 2
    tests = pool_folders(out, runs) if all(folders) else pool_run_files(out, runs)
    print(f"pool_runs.py: {tests} tests of {len(runs)} runs in {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
