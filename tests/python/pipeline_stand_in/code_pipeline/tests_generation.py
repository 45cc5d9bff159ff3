"""A stand-in for the pipeline's code_pipeline.tests_generation: RoadTestFactory numbers the tests it
creates from 1, as the pipeline's does. The road is kept as given (the pipeline also interpolates it
and validates it in the executor; the stand-in executors validate nothing)."""
import types


class RoadTestFactory:
    next_id = 1

    @staticmethod
    def create_road_test(road_points):
        assert type(road_points) is list, "You must provide a list of road points to create a RoadTest"
        the_test = types.SimpleNamespace(id=RoadTestFactory.next_id, road_points=road_points)
        RoadTestFactory.next_id += 1
        return the_test
