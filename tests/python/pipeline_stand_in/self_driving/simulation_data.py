"""The one piece of the pipeline's self_driving.simulation_data an executor needs: the record type."""
from collections import namedtuple

# The 17 fields of one simulation sample, in the pipeline's order.
SimulationDataRecordProperties = [
    "timer", "pos", "dir", "vel", "steering", "steering_input", "brake", "brake_input",
    "throttle", "throttle_input", "wheelspeed", "vel_kmh", "is_oob", "oob_counter",
    "max_oob_percentage", "oob_distance", "oob_percentage",
]

SimulationDataRecord = namedtuple("SimulationDataRecord", SimulationDataRecordProperties)
