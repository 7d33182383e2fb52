"""The `sensors` and `supervision` tabs of the Foxglove layout (foxglove/railderail-layout.json). The sensors tab is made from the sensor set's
mounts (sensors.sensor_set.MOUNTS) and the Rerun views' groups, colours and on-board levels (rerun_views.py), so that
the two views show the same, and the measured-mode monitor's estimates (/railderail/onboard_estimates) beside
the ground truth's wheel loads. The supervision tab is the speed supervision's (the monitor's
/railderail/supervision_status, interface.SupervisionStatus, /railderail/braking_curves, interface.BrakingCurves,
and /railderail/supervision): a driver's planning area (the speed, the target speed and the limit in force
against the front's position along the line, so far), beside it the braking curves to the target from the
latest message (the EBD, EBI, SBI, warning, permitted and indication speeds against the front's position, the
train's speed at its first sample: a Plot of the current message's arrays, each curve a slice of the message's
data, Foxglove's slices ending at their last index), the margin and the time to the last braking point, the
level and the brake, what it supervises; Foxglove draws only what messages carry, so the survey's critical
derailment speeds are the Rerun tab's alone. `python -m railderail_monitor.views.foxglove` writes both tabs
into the layout file (the `run` tab, hand-made, is kept). tests/test_foxglove_layout.py checks that the file
holds what this gives.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

from railderail_sim.parameters import VehicleParameters
from railderail_sim.ros.interface import (BRAKING_CURVES, FORCES, ONBOARD_ESTIMATES, SENSORS_NS, SUPERVISION,
                                          SUPERVISION_STATUS)
from railderail_sim.ros.interface import BrakingCurves, SupervisionStatus
from railderail_sim.sensors.sensor_set import MOUNTS
from railderail_sim.vehicle.layout import RUNNING_GEARS

from ..onboard.estimator import BOGIES
from ..onboard.measured import GEAR_SIDES, measured_limits
from ..supervision.curves import SAMPLES
from .colours import MOUNT_COLORS, RED
from .planning import COLOURS as PLANNING_COLOURS
from .sensor_plots import SENSOR_GROUPS, sensor_group, sensor_levels

LAYOUT = Path(__file__).resolve().parents[2] / "foxglove" / "railderail-layout.json"
TABS = "Tab!views"
# what each plot of a group shows: (plot, the Imu's field, unit, what)
PLOTS = (("lateral", "linear_acceleration.y", "m/s²", "lateral acceleration"),
         ("vertical", "linear_acceleration.z", "m/s²", "vertical acceleration"),
         ("roll_rate", "angular_velocity.x", "rad/s", "roll rate"))
# the estimates of the four running-gear sides (GEAR_SIDES' order), in hues apart from the wheels' and mounts'
GEAR_SIDE_COLORS = ((23, 190, 207), (227, 119, 194), (44, 160, 44), (255, 127, 14))
GREY = (127, 127, 127)


def _hex(colour):
    return "#%02x%02x%02x" % colour


def sensor_panels(style, vehicle=None):
    """{panel id: config} of the sensors tab: per mount group its lateral and vertical acceleration (and
    the car body's roll rate), every mount of the group in the Rerun views' colours, the rules' levels +-
    as reference lines; `style` the plot settings shared with the run tab's plots."""
    levels = sensor_levels(vehicle or VehicleParameters())
    panels = {}
    for group, title in SENSOR_GROUPS:
        mounts = [mount for mount in MOUNTS if sensor_group(mount) == group]
        for plot, field, unit, what in PLOTS:
            if plot == "roll_rate" and group != "car_body":
                continue
            paths = [_series(f"{SENSORS_NS}/{mount}/imu.{field}", mount, _hex(MOUNT_COLORS[k % len(MOUNT_COLORS)]))
                     for k, mount in enumerate(mounts)]
            lines = levels.get((group, plot), [])
            paths += [_series(repr(sign * level), label, _hex(colour), lineSize=1)
                      for _, level, colour, label in lines for sign in (1, -1)]
            name = f"{title} {what} ({unit}, measured)" + (": ± " + ", ".join(line[3] for line in lines)
                                                            if lines else "")
            panels[f"Plot!sensors_{group}_{plot}"] = {"foxglove.panelTitle": name, "paths": paths, **style}
    return panels


def _series(value, label, color, **style):
    """A plot's series: a message path, or a number (a reference line)."""
    return dict(value=value, enabled=True, timestampMethod="receiveTime", label=label, color=color, **style)


def estimator_panels(style, wheel_colours, vehicle=None):
    """{panel id: config} of the estimator's plots: the four sides' unloading and Y/Q at the measured
    monitor's levels, and per bogie the sides' wheel loads beside the ground truth's Q of each of its
    wheels (`wheel_colours` {wheel: colour}, the run tab's)."""
    vehicle = vehicle or VehicleParameters()
    limits, p0 = measured_limits(vehicle), vehicle.static_wheel_load
    panels = {}
    for name, field, criterion, what in (("unloading", "unloading", "estimated_running_gear_unloading",
                                          "unloading ΔQ/Q0"),
                                         ("ratio", "derailment_coefficient", "estimated_side_ratio", "Y/Q")):
        level = getattr(limits, criterion)
        paths = [_series(f"{ONBOARD_ESTIMATES}.{field}[{k}]", side.replace("_", " "), _hex(GEAR_SIDE_COLORS[k]))
                 for k, side in enumerate(GEAR_SIDES)]
        paths.append(_series(repr(level), f"{criterion} {level:g}", _hex(RED), lineSize=1))
        panels[f"Plot!sensors_estimator_{name}"] = {
            "foxglove.panelTitle": f"running gear {what}, estimated from the sensors: warning at {level:g}",
            "paths": paths, **style}
    unloading = limits.estimated_running_gear_unloading
    for j, bogie in enumerate(BOGIES):
        paths = [_series(f"{ONBOARD_ESTIMATES}.wheel_load[{2 * j + s}]", f"{side} estimated",
                         _hex(GEAR_SIDE_COLORS[2 * j + s]), lineSize=3) for s, side in enumerate(("left", "right"))]
        paths += [_series(f"{FORCES}.vertical_force[{2 * w + s}]", f"ws{w} {side} (truth)", wheel_colours[2 * w + s])
                  for w in RUNNING_GEARS[j] for s, side in enumerate(("left", "right"))]
        paths += [_series(repr((1.0 - unloading) * p0), f"unloading {unloading:g}", _hex(RED), lineSize=1),
                  _series(repr(p0), "static wheel load Q0", _hex(GREY), lineSize=1)]
        panels[f"Plot!sensors_estimator_{bogie}_loads"] = {
            "foxglove.panelTitle": f"{bogie} bogie wheel loads (N): each side's estimated from the sensors (its two "
                                   "wheels alike) beside the ground truth's Q", "paths": paths, **style}
    return panels


def sensors_layout():
    """The tab's arrangement: the car body's three plots, the frames' two, the axle boxes' two."""
    def column(*panels):
        node = panels[-1]
        for k, panel in reversed(list(enumerate(panels[:-1]))):
            node = dict(first=panel, second=node, direction="column", splitPercentage=100.0 / (len(panels) - k))
        return node
    measured = dict(first=column(*(f"Plot!sensors_car_body_{p}" for p in ("lateral", "vertical", "roll_rate"))),
                    second=dict(first=column("Plot!sensors_bogie_frame_lateral", "Plot!sensors_bogie_frame_vertical"),
                                second=column("Plot!sensors_axle_box_lateral", "Plot!sensors_axle_box_vertical"),
                                direction="row", splitPercentage=50.0),
                    direction="row", splitPercentage=34.0)
    estimated = column("Plot!sensors_estimator_unloading", "Plot!sensors_estimator_ratio",
                       *(f"Plot!sensors_estimator_{bogie}_loads" for bogie in BOGIES))
    return dict(first=measured, second=estimated, direction="row", splitPercentage=75.0)


def _with_tab(tabs, new):
    """The tabs with `new` in the place of the one of its title, or after them."""
    if any(tab["title"] == new["title"] for tab in tabs):
        return [new if tab["title"] == new["title"] else tab for tab in tabs]
    return tabs + [new]


def with_sensors_tab(layout):
    """The layout (a parsed file) with its sensors tab made anew, its run tab kept."""
    config = dict(layout["configById"])
    tabs = config[TABS]["tabs"]
    style = {k: v for k, v in config["Plot!speed"].items() if k not in ("foxglove.panelTitle", "paths")}
    config = {k: v for k, v in config.items() if not k.startswith("Plot!sensors_")}
    config.update(sensor_panels(style))
    wheel_colours = {int(p["value"].rsplit("[", 1)[1][:-1]): p["color"] for p in config["Plot!wheel_unloading"]["paths"]
                     if p["value"].startswith(f"{FORCES}.vertical_force[")}
    config.update(estimator_panels(style, wheel_colours))
    config[TABS] = dict(config[TABS], tabs=_with_tab(tabs, dict(title="sensors", layout=sensors_layout())))
    return dict(layout, configById=config)


def _status(field):
    """The message path of a SupervisionStatus field."""
    return f"{SUPERVISION_STATUS}.data[{int(SupervisionStatus[field])}]"


# the planning area's and the time plots' series: (panel, field, label, colour)
SUPERVISION_SERIES = (
    ("planning", "speed_kmh", "speed", PLANNING_COLOURS["train"]),
    ("planning", "target_speed_kmh", "target speed (the next to brake for)", PLANNING_COLOURS["targets"]),
    ("planning", "limit_kmh", "limit in force", PLANNING_COLOURS["permitted"]),
    ("margin", "margin_kmh", "margin to the target (km/h)", PLANNING_COLOURS["targets"]),
    ("margin", "time_to_intervention_s", "time to the last braking point (s)", PLANNING_COLOURS["ebi"]),
    ("level", "level", "level", PLANNING_COLOURS["critical"]),
    ("level", "braking", "emergency brake commanded", GREY))
SUPERVISION_TITLES = {
    "planning": "planning area: speed, target speed and the limit in force (km/h) along the line (the front, m)",
    "margin": "margin to the target (km/h) and time to its last braking point (s)",
    "level": "supervision level (1 indication, 2 warning, 3 intervention) and the emergency brake (1: commanded)"}


def _curve(field):
    """The message path of a BrakingCurves field: its row of SAMPLES, a slice of the data (Foxglove's slices
    end at their last index, inclusive)."""
    first = int(BrakingCurves[field]) * SAMPLES
    return f"{BRAKING_CURVES}.data[{first}:{first + SAMPLES - 1}]"


# the braking curves' panel: (BrakingCurves field, label, colour), the train's speed a point at the front
CURVE_SERIES = (
    ("speed_kmh", "speed (the train now)", PLANNING_COLOURS["train"]),
    ("ebd_kmh", "EBD (emergency brake deceleration)", PLANNING_COLOURS["ebd"]),
    ("ebi_kmh", "EBI (emergency brake intervention)", PLANNING_COLOURS["ebi"]),
    ("sbi_kmh", "SBI (service brake intervention)", PLANNING_COLOURS["sbi"]),
    ("warning_kmh", "warning", PLANNING_COLOURS["warning"]),
    ("permitted_kmh", "permitted (the driver's curve; the target's speed in it)", PLANNING_COLOURS["driver"]),
    ("indication_kmh", "indication", PLANNING_COLOURS["indication"]))


def supervision_panels(style):
    """{panel id: config} of the supervision tab; `style` the run tab's plot settings."""
    panels = {}
    for panel, title in SUPERVISION_TITLES.items():
        paths = [_series(_status(field), label, _hex(colour)) for p, field, label, colour in SUPERVISION_SERIES
                 if p == panel]
        panels[f"Plot!supervision_{panel}"] = {"foxglove.panelTitle": title, "paths": paths, **style}
    # speed against the front's position: a driver's planning area
    panels["Plot!supervision_planning"].update(xAxisVal="custom", xAxisPath=dict(value=_status("front_m"),
                                                                                  enabled=True))
    # the braking curves to the target: the latest message's rows against its positions
    paths = [_series(_curve(field), label, _hex(colour)) for field, label, colour in CURVE_SERIES]
    paths[0].update(showLine=False, lineSize=4)
    panels["Plot!supervision_curves"] = {
        "foxglove.panelTitle": "braking curves to the target (km/h) along the line (the front, m), the latest",
        "paths": paths, **style, "xAxisVal": "currentCustom", "timeRange": "latest",
        "xAxisPath": dict(value=_curve("position_m"), enabled=True)}
    panels["RawMessages!supervision"] = {
        "foxglove.panelTitle": "what the supervision supervises (its targets, the survey's curves, live inputs)",
        "topicPath": SUPERVISION, "diffEnabled": False, "diffMethod": "custom", "diffTopicPath": "",
        "showFullMessageForDiff": False}
    return panels


def supervision_layout():
    return dict(first=dict(first="Plot!supervision_planning", second="Plot!supervision_curves", direction="row",
                           splitPercentage=50.0),
                second=dict(first=dict(first="Plot!supervision_margin", second="Plot!supervision_level",
                                       direction="column", splitPercentage=50.0),
                            second="RawMessages!supervision", direction="row", splitPercentage=70.0),
                direction="column", splitPercentage=55.0)


def with_supervision_tab(layout):
    """The layout (a parsed file) with its supervision tab made anew, the others kept."""
    config = dict(layout["configById"])
    style = {k: v for k, v in config["Plot!speed"].items() if k not in ("foxglove.panelTitle", "paths")}
    config = {k: v for k, v in config.items() if "!supervision" not in k}
    config.update(supervision_panels(style))
    config[TABS] = dict(config[TABS], tabs=_with_tab(config[TABS]["tabs"], dict(title="supervision",
                                                                               layout=supervision_layout())))
    return dict(layout, configById=config)


def main(argv=None):
    layout = json.loads(LAYOUT.read_text())
    LAYOUT.write_text(json.dumps(with_supervision_tab(with_sensors_tab(layout)), indent=2, ensure_ascii=False) + "\n")
    print(f"{LAYOUT}: sensors tab ({len(MOUNTS)} mounts) and supervision tab written")
    return 0


if __name__ == "__main__":
    sys.exit(main())
