"""CRH3 vehicle-track model: bodies, suspension, equations of motion, stepper and the simulate() API."""
from .simulate import (Result, Scenario, Simulation, SimulationDiverged, constant_speed, scenario,  # noqa: F401
                       simulate, staircase_speed)
