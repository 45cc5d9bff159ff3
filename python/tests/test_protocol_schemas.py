"""The executor protocol's JSON Schemas (docs/protocols/, written from wogan's Rust message types
and checked against them there) hold both ends: every line the Python client writes validates
against them, as do the lines wogan writes; what the client refuses to write, they refuse too."""

import io
import json
import os

import pytest
from helpers import HERE

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


def schema(name):
    with open(os.path.join(FOLDER, f"wogan-executor-v3.{name}.schema.json"), encoding="utf-8") as file:
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
