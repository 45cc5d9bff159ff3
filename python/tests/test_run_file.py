"""wogan.read_run: a run and a suite made by the binary, files cut short, bad lines."""

import json

import pytest
from helpers import command, wogan_cli

import wogan


@pytest.fixture(scope="module")
def run_path(tmp_path_factory):
    """A real run, written by the binary itself, with failing roads (the geometric executor)."""
    path = tmp_path_factory.mktemp("run") / "smoke.jsonl"
    done = wogan_cli("run", "--max-tests", "15", "--seed", "4", "--quiet", "--executor",
                     command("geometric_executor.py"), "--out", str(path))
    assert done.returncode == 0, done.stderr
    return path


def test_a_run_reads_into_its_header_tests_and_summary(run_path):
    records = [json.loads(line) for line in run_path.read_text().splitlines()]
    run = wogan.read_run(run_path)
    assert (run.kind, run.truncated, run.path, run.status) == ("run", False, str(run_path), None)
    assert run.header == records[0] and run.header["seed"] == 4
    assert run.tests == [r for r in records if r["type"] == "test"]
    assert [t["id"] for t in run.tests] == list(range(1, 16))
    assert run.summary == records[-1] and run.summary["executed"] == 15
    assert run.records == records and any(r["type"] == "train" for r in run.records)
    assert len(run.failures) == run.summary["failed"] > 0
    assert str(run_path) == wogan.read_run(str(run_path)).path  # a str path reads the same


def test_a_suite_reads_into_the_same_shape(run_path, tmp_path):
    suite_path = tmp_path / "suite.jsonl"
    done = wogan_cli("suite", "add", str(run_path), "--to", str(suite_path))
    assert done.returncode == 0, done.stderr
    suite = wogan.read_run(suite_path)
    run = wogan.read_run(run_path)
    assert suite.kind == "suite" and suite.header["format"] == "wogan-suite" and suite.summary is None
    assert [r["road_points"] for r in suite.tests] == [t["road_points"] for t in run.failures]
    assert all(r["type"] == "road" and r["name"].startswith("smoke#") for r in suite.tests)
    assert suite.failures == suite.tests  # every road went in failing


def test_a_run_cut_short_mid_line_is_dropped_or_refused(run_path, tmp_path):
    text = run_path.read_text()
    lines = text.splitlines(keepends=True)
    cut = tmp_path / "cut.jsonl"
    # Killed while writing its 10th line: 9 whole lines, then half of the 10th.
    cut.write_text("".join(lines[:9]) + lines[9][: len(lines[9]) // 2])
    kept = wogan.read_run(cut)
    whole = [json.loads(line) for line in lines[:9]]
    assert kept.truncated and kept.summary is None
    assert kept.records == whole and kept.tests == [r for r in whole if r["type"] == "test"]
    with pytest.raises(wogan.RunFileError, match=r"cut\.jsonl:10: not JSON \(the file ends inside it"):
        wogan.read_run(cut, allow_truncated=False)
    # Cut between two lines: nothing was cut short, the run has no summary yet.
    between = tmp_path / "between.jsonl"
    between.write_text("".join(lines[:9]))
    read = wogan.read_run(between, allow_truncated=False)
    assert not read.truncated and read.summary is None and read.records == whole
    # A last line whole but for its newline is a record.
    last = tmp_path / "last.jsonl"
    last.write_text(text.rstrip("\n"))
    assert wogan.read_run(last, allow_truncated=False).summary == json.loads(lines[-1])


@pytest.mark.parametrize("lines, says", [
    (['{"type":"header"}', '{"type":"test", oops', '{"type":"summary"}'], r"bad\.jsonl:2: not JSON: "),
    (['{"type":"header"}', '', '[1, 2]'], r"bad\.jsonl:3: not a record"),
    (['{"type":"header"}', '{"id": 1}'], r"bad\.jsonl:2: not a record"),
    (['{"type":"test","id":1}'], r"bad\.jsonl:1: not a run or suite file: its first record is a 'test'"),
    (['{"type":"header"}', '{"type":"header"}'], r"bad\.jsonl:2: a second header"),
    (['{"type":"suite","format":"wogan-suite","version":1}', '{"type":"test"}'],
     r"bad\.jsonl:2: a 'test' record in a suite file"),
    ([], r"bad\.jsonl: empty"),
])
def test_a_bad_line_is_named(tmp_path, lines, says):
    bad = tmp_path / "bad.jsonl"
    bad.write_text("".join(line + "\n" for line in lines))
    with pytest.raises(wogan.RunFileError, match=says):
        wogan.read_run(bad)


def test_text_that_is_not_utf8_is_named(tmp_path):
    bad = tmp_path / "bad.jsonl"
    bad.write_bytes(b'{"type":"header"}\n{"type":"test","name":"\xff"}\n')
    with pytest.raises(wogan.RunFileError, match=r"bad\.jsonl:2: not UTF-8"):
        wogan.read_run(bad)
