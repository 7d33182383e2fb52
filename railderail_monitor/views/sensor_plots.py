"""What the sensors' plots show, for the Rerun views and the Foxglove layout alike: the mounts' groups, their
names in a legend, what a raw reading drawn is not, and the on-board rules' levels drawn +- on them
(onboard/criteria.py)."""
import math

from ..onboard import criteria as onboard
from .colours import ORANGE, RED, YELLOW

# the sensors' mount groups (sensors.sensor_set.MOUNTS by their prefix)
SENSOR_GROUPS = (("car_body", "car body"), ("bogie_frame", "bogie frame"), ("axle_box", "axle box"))


# said in the plot's title: what the raw reading drawn is not (the car body's rules are on its lateral reading)
GROUP_NOTES = {("car_body", "lateral"): ", raw; its rules: ÿ* 2.5 (0.4-10 Hz), ÿ*_qst 1.5 (100 m mean)",
               ("axle_box", "lateral"): ", IEPE: AC coupled, no steady part",
               ("axle_box", "vertical"): ", IEPE: AC coupled, no steady part"}


def mount_label(mount, group):
    """A mount's name in its group's legend, without the group's words: front, frame_0, 0_left."""
    return mount.removeprefix(group + "_").removeprefix("bogie_")


def sensor_group(mount):
    """The plot group of a mount (car_body, bogie_frame, axle_box), None for another name."""
    if mount.startswith("bogie_") and mount.endswith("_frame"):
        return "bogie_frame"
    return next((group for group, _ in SENSOR_GROUPS if mount.startswith(group + "_")), None)


def sensor_levels(vehicle):
    """{(group, plot): [(entity name, level, colour, label)]} of the on-board rules' levels drawn +- on the
    sensors' plots (onboard/criteria.py), each rule's filter named in its label."""
    peak, rms = onboard.bogie_limits(vehicle.bogie_frame_mass + 2.0 * vehicle.wheelset_mass)
    # car_body_roll_rate's level: a roll at its emergency-spring level oscillating at the body's roll frequency
    roll_rate = 2.0 * math.pi * onboard.car_body_roll_frequency(vehicle) * onboard.roll_level(vehicle)
    # the car body's raw reading carries the curve's steady part, which neither of its rules reads as such (ydd*
    # is band-passed, ydd*_qst a 100 m mean): their levels are named in the plot's title, not drawn against it
    return {("bogie_frame", "lateral"): [("limit_peak", peak, RED, f"peak {peak:.2f} (f0 ± 2 Hz band)"),
                                         ("limit_bids", onboard.BIDS_LIMIT, ORANGE,
                                          f"BIDS {onboard.BIDS_LIMIT:g} x {onboard.BIDS_PEAKS} peaks (4-8 Hz band)"),
                                         ("limit_rms", rms, YELLOW, f"r.m.s. {rms:.2f} (f0 ± 2 Hz, 100 m)")],
            ("car_body", "roll_rate"): [("limit_roll_rate", roll_rate, RED, f"{roll_rate:.3f} (0.4-10 Hz band)")]}
