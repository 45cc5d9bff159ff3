"""The protocols' JSON Schemas (docs/protocols/, written from wogan's Rust message types and checked
against them there) hold both ends: every line the Python client writes validates against them, as
does every line a real wogan writes to an executor or a controller; what the client refuses to
write, they refuse too."""

import io
import json
import os

import pytest
from helpers import HERE, ROADS, command, wogan_cli

import wogan

# CI installs jsonschema beside the wheel (and the tests fail without it there); a checkout's own
# run may lack it.
if os.environ.get("WOGAN_TEST_INSTALLED"):
    import jsonschema
else:
    jsonschema = pytest.importorskip("jsonschema")

FOLDER = os.path.join(HERE, "..", "..", "docs", "protocols")
HELLO = {"type": "hello", "protocol": "wogan-executor", "version": 3, "units": "metres, seconds",
         "map_size_m": 200.0, "oob_tolerance": 0.85, "speed_limit_kmh": 70.0}


def schema(name, protocol="wogan-executor-v3"):
    with open(os.path.join(FOLDER, f"{protocol}.{name}.schema.json"), encoding="utf-8") as file:
        loaded = json.load(file)
    jsonschema.Draft202012Validator.check_schema(loaded)
    return jsonschema.Draft202012Validator(loaded)


def errors(validator, message):
    return [error.message for error in validator.iter_errors(message)]


class Everything(wogan.Executor):
    """Answers with every field the protocol has, an ERROR with its reason, or raises."""
    name, version = "everything", "1.0"

    def reported_settings(self):
        return {"policy": "idm", "lanes": [1, 2]}

    def drive(self, road):
        if road.id == 1:
            return wogan.Answer(max_bolp=0.9, outcome="FAIL", sim_time_s=12.5, oob_side="left",
                                oob_point=(101.5, 40.25), min_lane_distance_m=-0.3, extra={"note": "x"})
        if road.id == 2:
            return wogan.Answer(max_bolp=0.0, outcome="ERROR", sim_time_s=0.0, error="refused")
        if road.id == 3:
            raise RuntimeError("the simulator fell over")
        return wogan.Answer(max_bolp=0.2)


def test_every_line_the_client_writes_validates():
    roads = [{"type": "road", "id": i, "road_points": [[100.0, 10.0], [100.0, 25.0]]} for i in (1, 2, 3, 4)]
    lines = "".join(json.dumps(m) + "\n" for m in [HELLO, *roads, {"type": "bye"}])
    out = io.StringIO()
    Everything().serve(io.StringIO(lines), out)
    written = [json.loads(line) for line in out.getvalue().splitlines()]
    assert len(written) == 5, written
    assert errors(schema("hello-reply"), written[0]) == [], written[0]
    answer = schema("answer")
    for line in written[1:]:
        assert errors(answer, line) == [], line
    assert written[1]["oob_point"] == [101.5, 40.25] and written[3]["outcome"] == "ERROR"


def test_the_lines_wogan_writes_validate():
    request = schema("request")
    for message in [HELLO, {"type": "road", "id": 7, "road_points": [[1.0, 2.0], [3.0, 4.5]]}, {"type": "bye"}]:
        assert errors(request, message) == [], message
    # A request of no known type, or a road without its points, is not one.
    assert errors(request, {"type": "news"}) and errors(request, {"type": "road", "id": 1})


@pytest.mark.parametrize("fields, refused", [
    ({"max_bolp": 1.5}, "max_bolp"),
    ({"max_bolp": 0.5, "sim_time_s": -1.0}, "sim_time_s"),
    ({"max_bolp": 0.5, "outcome": "pass"}, "outcome"),
    ({"max_bolp": 0.5, "oob_side": "up"}, "oob_side"),
])
def test_what_the_client_refuses_to_write_the_schema_refuses(fields, refused):
    with pytest.raises(ValueError, match=refused):
        wogan.Answer(**fields)
    assert errors(schema("answer"), {"id": 1, **fields}), fields


def test_the_schema_names_the_answers_required_fields_and_an_exit_point_needs_its_side():
    answer = schema("answer")
    assert errors(answer, {"max_bolp": 0.5}) and errors(answer, {"id": 1})
    assert errors(answer, {"id": 1, "max_bolp": 0.5, "oob_point": [1.0, 2.0]})
    assert errors(schema("hello-reply"), {"type": "hello", "protocol": "wogan-executor", "version": 2})


def recorded(path):
    with open(path, encoding="utf-8") as file:
        return [json.loads(line) for line in file]


def test_every_line_a_real_wogan_writes_to_an_executor_validates(tmp_path):
    record = str(tmp_path / "executor.jsonl")
    roads = "".join(json.dumps({"road_points": points}) + "\n" for points in ROADS)
    ran = wogan_cli("simulate", "--jobs", "2", "--executor", f"{command('recording_peer.py')} executor {record}",
                    input=roads)
    assert ran.returncode == 0, ran.stderr
    seen = recorded(record)
    # Two executors (--jobs 2): each told hello and bye; every road sent once.
    assert sorted(m["type"] for m in seen).count("road") == len(ROADS), seen
    assert {m["type"] for m in seen} == {"hello", "road", "bye"}, seen
    request = schema("request")
    for message in seen:
        assert errors(request, message) == [], message
    replies = recorded(record + ".replies")
    assert [errors(schema("hello-reply"), r) for r in replies if r.get("type") == "hello"] in ([[]], [[], []])
    assert all(errors(schema("answer"), r) == [] for r in replies if "id" in r)


@pytest.mark.parametrize("camera", [False, True])
def test_every_line_a_real_wogan_writes_to_a_controller_validates(tmp_path, camera):
    record = str(tmp_path / "controller.jsonl")
    config = tmp_path / "config.json"
    config.write_text(json.dumps({"driver": {"camera": camera}}))
    roads = json.dumps({"road_points": ROADS[0]}) + "\n"
    ran = wogan_cli("simulate", "--oracle", f"{command('recording_peer.py')} controller {record}",
                    "--config", str(config), input=roads)
    assert ran.returncode == 0, ran.stderr
    seen = recorded(record)
    kinds = [m["type"] for m in seen]
    assert kinds[:2] == ["hello", "road"] and kinds.count("step") > 10 and kinds[-2:] == ["end", "bye"], kinds[:3]
    request = schema("request", "wogan-controller-v2")
    for message in seen:
        assert errors(request, message) == [], {k: v for k, v in message.items() if k != "camera"}
    assert all(("camera" in m) == camera for m in seen if m["type"] == "step")
    reply = schema("reply", "wogan-controller-v2")
    assert all(errors(reply, r) == [] for r in recorded(record + ".replies"))
    # Past its bounds, a reply is refused by the schema as by wogan.
    assert errors(reply, {"step": 1, "steering": 1.5, "throttle": 0.0, "brake": 0.0})
