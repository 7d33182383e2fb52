"""Loads on the vehicle besides the wheel-rail contact: the aerodynamic loads of a crosswind on the car
body (`layout` the records, `aerodynamics` the core, `wind` the wind and its gusts)."""
