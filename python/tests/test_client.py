"""The client against the real binary: executors and controllers written with the classes drive
runs, a drive that raises answers ERROR, and run and suite files read back."""

import os
import subprocess
import sys

import pytest

import wogan

HERE = os.path.dirname(os.path.abspath(__file__))


def command(script):
    return f"cmd:{sys.executable} {os.path.join(HERE, script)}"


def test_an_executor_written_with_the_class_drives_a_search():
    run = wogan.run(["--max-tests", "20", "--seed", "1", "--executor", command("geometric_executor.py")])
    assert run.header["config"]["executor"].endswith("geometric_executor.py")
    assert len(run.tests) == 20
    assert {t["outcome"] for t in run.tests} <= {"PASS", "FAIL"}
    assert any(t["outcome"] == "FAIL" for t in run.tests)
    assert all(t["sim_time_s"] == 10.0 for t in run.tests)
    assert run.summary["executed"] == 20


def test_a_drive_that_raises_answers_error_and_the_run_goes_on(monkeypatch):
    monkeypatch.setenv("RAISE_AT", "3")
    run = wogan.run(["--max-tests", "20", "--seed", "1", "--executor", command("geometric_executor.py")])
    assert len(run.tests) == 20
    third = run.tests[2]
    assert third["outcome"] == "ERROR"
    assert "ValueError: road 3 refused on purpose" in third["error"]
    assert all(t["outcome"] != "ERROR" for t in run.tests[3:])


def test_the_documented_fifteen_line_executor_drives_a_search():
    with open(os.path.join(HERE, "fifteen_line_executor.py")) as f:
        code = f.read()
    assert len(code.strip().splitlines()) <= 15
    with open(os.path.join(os.path.dirname(HERE), "README.md")) as f:
        assert code.strip() in f.read(), "python/README.md shows this executor as it is"
    run = wogan.run(["--max-tests", "20", "--seed", "2", "--executor", command("fifteen_line_executor.py")])
    assert len(run.tests) == 20 and run.summary is not None


def test_a_controller_written_with_the_class_drives_wogans_car():
    run = wogan.run(["--max-tests", "20", "--seed", "1", "--oracle", command("lane_controller.py")])
    assert run.header["oracle"] == "controller"
    assert len(run.tests) == 20
    assert all(t["outcome"] in ("PASS", "FAIL") for t in run.tests), [t.get("error") for t in run.tests]
    assert any(t["outcome"] == "PASS" for t in run.tests)


def test_runs_suites_and_truncated_files_read_back(tmp_path):
    path = tmp_path / "run.jsonl"
    run = wogan.run(["--max-tests", "12", "--seed", "4", "--out", str(path)])
    assert (len(run.tests), run.summary["executed"]) == (12, 12)
    assert [t["id"] for t in run.tests] == list(range(1, 13))
    suite = tmp_path / "suite.jsonl"
    subprocess.run([wogan.binary(), "suite", "add", str(path), "--to", str(suite)], check=True,
                   capture_output=True)
    read = wogan.read_run(suite)
    assert read.header["format"] == "wogan-suite"
    assert len(read.tests) == len(run.failures) and all("road_points" in r for r in read.tests)
    # A run killed mid-write: its last line cut short.
    text = path.read_text()
    cut = tmp_path / "cut.jsonl"
    cut.write_text(text[: text.rindex("\n", 0, len(text) - 1) + 40])
    kept = wogan.read_run(cut)
    assert kept.truncated and kept.summary is None and len(kept.tests) == 12
    with pytest.raises(wogan.RunFileError, match=r"cut\.jsonl:\d+: not JSON \(cut short"):
        wogan.read_run(cut, allow_truncated=False)


def test_a_bad_line_is_named():
    bad = os.path.join(HERE, "bad_run.jsonl")
    with pytest.raises(wogan.RunFileError, match=r"bad_run\.jsonl:2: not JSON"):
        wogan.read_run(bad)


def test_a_refused_command_raises_with_the_binarys_message():
    with pytest.raises(wogan.WoganError, match="--no-such-option") as raised:
        wogan.run(["--no-such-option"])
    assert raised.value.status == 2
