"""wogan.run, wogan.find_binary and wogan.Simulator against the real binary."""

import os
import sys

import pytest
from helpers import ROADS, command

import wogan


def test_run_reads_the_run_it_made_and_keeps_a_given_out(tmp_path):
    out = tmp_path / "run.jsonl"
    run = wogan.run(["run", "--max-tests", "5", "--seed", "3", "--algorithm", "random"], out=out)
    assert run.path == str(out) and out.exists()
    assert (run.status, run.header["algorithm"], run.header["seed"], len(run.tests)) == (0, "random", 3, 5)
    again = wogan.run(["--max-tests", "5", "--seed", "3", "--algorithm", "random", f"--out={tmp_path / 'again.jsonl'}"])
    assert [t["road_points"] for t in again.tests] == [t["road_points"] for t in run.tests]
    with pytest.raises(ValueError, match="give one"):
        wogan.run(["--out", "a.jsonl"], out=tmp_path / "b.jsonl")


def test_a_refused_command_raises_with_the_binarys_message():
    with pytest.raises(wogan.WoganError, match="--no-such-option") as raised:
        wogan.run(["--no-such-option"])
    assert raised.value.status == 2
    assert "status 2" in str(raised.value) and "--no-such-option" in raised.value.stderr
    assert isinstance(raised.value, RuntimeError)


def test_a_verdict_exit_status_is_an_error_unless_accepted():
    args = ["--max-tests", "20", "--seed", "1", "--executor", command("geometric_executor.py"), "--fail-on", "failure"]
    with pytest.raises(wogan.WoganError, match="status 1"):
        wogan.run(args)
    run = wogan.run(args, ok_statuses=(0, 1))
    assert run.status == 1 and run.failures
    assert wogan.run(args, check=False).status == 1


def test_the_binary_is_found_from_wogan_bin(monkeypatch, tmp_path):
    if os.environ.get("WOGAN_TEST_INSTALLED") == "1":
        assert os.path.basename(wogan.find_binary()) == "wogan"
        return
    assert wogan.find_binary() == os.environ["WOGAN_BIN"]
    monkeypatch.setenv("WOGAN_BIN", str(tmp_path / "missing"))
    with pytest.raises(FileNotFoundError, match="WOGAN_BIN="):
        wogan.find_binary()


def test_the_simulator_drives_one_road_at_a_time():
    with wogan.Simulator(["--execution-data"]) as simulator:
        pid = simulator.process.pid
        first = simulator.drive(ROADS[0], id=41)
        second = simulator.drive([(80, 20), (100, 60), (120, 20)])  # too sharp: not driven
        assert simulator.process.pid == pid and simulator.process.poll() is None
    assert (first["type"], first["line"], first["id"], first["outcome"]) == ("result", 1, 41, "PASS")
    assert len(first["execution_data"]) > 10 and first["sim_time_s"] > 0
    assert (second["line"], second["outcome"]) == (2, "INVALID")
    assert simulator.process.returncode == 0


def test_a_simulator_that_dies_or_answers_junk_raises_naming_the_road():
    dead = wogan.Simulator(binary=[sys.executable, "-c", "import sys; sys.stdin.readline()"])
    with pytest.raises(wogan.WoganError, match="ended before answering test 7"):
        dead.drive(ROADS[0], label="test 7")
    dead.close()
    junk = wogan.Simulator(binary=[sys.executable, "-c", "import sys\nfor _ in sys.stdin: print('{\"no\": 1}', flush=True)"])
    with pytest.raises(wogan.WoganError, match="answered road 1 with garbage"):
        junk.drive(ROADS[0])
    assert junk.close() == 0
