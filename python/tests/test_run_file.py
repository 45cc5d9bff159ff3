"""wogan.read_run: a run and a suite made by the binary, files cut short, bad lines."""

import json
import tracemalloc

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


@pytest.mark.parametrize("value, says", [
    ("NaN", "NaN is not JSON"), ("Infinity", "Infinity is not JSON"), ("-Infinity", "-Infinity is not JSON"),
    ("1e400", "the number 1e400 is beyond a float's range"), ("-1E+400", "the number -1E\\+400 is beyond"),
    ("1" + "0" * 400, "the number 1000.* is beyond a float's range"),
    ("9" * 5000, r"the number 9999.*\(5000 characters\) is beyond"),
])
def test_numbers_the_binary_refuses_are_named(tmp_path, value, says):
    bad = tmp_path / "bad.jsonl"
    bad.write_text('{"type":"header"}\n{"type":"test","id":1,"oob":{"x":[' + value + ']}}\n')
    with pytest.raises(wogan.RunFileError, match=rf"bad\.jsonl:2: not JSON: {says}"):
        wogan.read_run(bad)


def test_numbers_a_float_holds_are_read_as_before(tmp_path):
    values = ["1e308", "-1.7976931348623157e308", "5e-324", "-0.0", "123456789012345678901234567890", "7"]
    good = tmp_path / "good.jsonl"
    good.write_text('{"type":"header"}\n{"type":"test","values":[' + ", ".join(values) + "]}\n")
    assert wogan.read_run(good).tests[0]["values"] == [json.loads(v) for v in values]
    assert [type(v) for v in wogan.read_run(good).tests[0]["values"][-2:]] == [int, int]


def test_deep_nesting_is_named_not_a_recursion_error(tmp_path):
    deep = tmp_path / "deep.jsonl"
    deep.write_text('{"type":"header"}\n' + "[" * 100000 + "]" * 100000 + "\n")
    with pytest.raises(wogan.RunFileError, match=r"deep\.jsonl:2: not JSON: nested too deeply"):
        wogan.read_run(deep)


def test_lines_are_bounded_and_a_longer_one_is_named_without_being_held(tmp_path):
    bound = wogan.run_file.MAX_LINE_BYTES
    assert bound == 16 * 1024 * 1024
    opening = '{"type":"test","pad":"'
    # A line of exactly the bound (its newline not counted) is read.
    longest = tmp_path / "longest.jsonl"
    longest.write_text('{"type":"header"}\n' + opening + "a" * (bound - len(opening) - 2) + '"}\n')
    assert len(wogan.read_run(longest).tests[0]["pad"]) == bound - len(opening) - 2
    # One byte more is refused, naming its line, with or without a newline, whatever follows.
    for ending in ("\n", "", '\n{"type":"summary"}\n'):
        longer = tmp_path / "longer.jsonl"
        longer.write_text('{"type":"header"}\n\n' + opening + "a" * (bound - len(opening) - 1) + '"}' + ending)
        with pytest.raises(wogan.RunFileError, match=r"longer\.jsonl:3: a line longer than 16777216 bytes"):
            wogan.read_run(longer, allow_truncated=True)
    # A line four times the bound is refused, holding little more than the bound.
    huge = tmp_path / "huge.jsonl"
    with open(huge, "w") as f:
        f.write('{"type":"header"}\n' + opening)
        for _ in range(4):
            f.write("a" * bound)
    tracemalloc.start()
    try:
        with pytest.raises(wogan.RunFileError, match=r"huge\.jsonl:2: a line longer"):
            wogan.read_run(huge)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < bound + 2 * 1024 * 1024, peak  # the bound, a piece read, and a little
