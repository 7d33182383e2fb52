"""foxglove/railderail-layout.json: every panel placed, every topic and field path it plots or shows exists in
the message definitions (msg_defs/msg and the installed sensor_msgs, array indexes and slices in range, plotted
leaves numeric), the braking curves' panel plots each curve's row of the message against its positions, and its
threshold lines are the monitor's thresholds (the shipped monitor.yaml) and, in the sensors'
tab, the on-board rules' levels as the Rerun views draw them."""
import json
import re
from pathlib import Path

import pytest
from rosidl_adapter.parser import parse_message_file

from railderail_monitor.supervision.curves import SAMPLES
from railderail_monitor.warning.limits import default_limits
from railderail_monitor.onboard.measured import measured_limits
from railderail_monitor.recording.recorder import msg_file
from railderail_monitor.views.colours import WHEELSET_COLORS
from railderail_monitor.views.sensor_plots import SENSOR_GROUPS, sensor_group, sensor_levels
from railderail_sim.ros import interface as m
from railderail_sim.ros import sensor_messages as sm
from railderail_sim.parameters import VehicleParameters
from railderail_sim.sensors.sensor_set import MOUNTS
from railderail_sim.sensors.config import default_set

ROOT = Path(__file__).resolve().parents[1]
LAYOUT = json.loads((ROOT / "foxglove" / "railderail-layout.json").read_text())
NUMERIC = {"bool", "byte", "char", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64",
           "float32", "float64"}
# a field, field[index] or field[first:last] (Foxglove's slices include their last index)
STEP = re.compile(r"^(\w+)(?:\[(\d+)(?::(\d+))?\])?$")
# the records carried in an unbounded array: (topic, field) -> its length
RECORDS = {(m.SUPERVISION_STATUS, "data"): m.SupervisionStatus.size(),
           (m.BRAKING_CURVES, "data"): m.BrakingCurves.size() * SAMPLES}
TOPICS = {**m.TOPICS, **sm.sensor_topics(default_set()), m.CLOCK: m.CLOCK_TOPIC,
          m.ONBOARD_ESTIMATES: m.ONBOARD_ESTIMATES_TOPIC}


def definition(package, name):
    """The fields of a message type: railderail_msgs from msg_defs/msg, the others as installed."""
    path = ROOT / "msg_defs" / "msg" / f"{name}.msg" if package == "railderail_msgs" else msg_file(package, name)
    return {f.name: f.type for f in parse_message_file(package, str(path)).fields}


def leaf_type(path):
    """The primitive type a message path such as /railderail/wheelset_states.wheel_lift[3] ends on
    (AssertionError naming the path where it does not resolve)."""
    topic, _, rest = path.partition(".")
    assert topic in TOPICS, f"{path}: no topic {topic}"
    package, _, name = TOPICS[topic][0].split("/")
    fields = definition(package, name)
    steps = rest.split(".") if rest else []
    field_type = None
    for i, step in enumerate(steps):
        match = STEP.match(step)
        assert match, f"{path}: {step!r} is not a field or field[index]"
        field, index, last = match.group(1), match.group(2), match.group(3)
        assert fields is not None and field in fields, f"{path}: no field {field}"
        field_type = fields[field]
        if index is not None:
            size = field_type.array_size or RECORDS.get((topic, field)) if field_type.is_array else None
            assert size, f"{path}: {field} is not a fixed-size array"
            assert int(index) <= int(last or index) < size, f"{path}: {field} has {size} elements"
        else:
            assert not field_type.is_array or i == len(steps) - 1, f"{path}: {field} needs an index"
        fields = None if field_type.is_primitive_type() else definition(field_type.pkg_name, field_type.type)
    return field_type


def panels(node):
    """The panels a layout node places, those of its tabs' layouts included."""
    if isinstance(node, str):
        tabs = LAYOUT["configById"].get(node, {}).get("tabs") if node.startswith("Tab!") else None
        return [node] + [p for tab in tabs for p in panels(tab["layout"])] if tabs else [node]
    return panels(node["first"]) + panels(node["second"])


def test_every_panel_is_placed_once():
    placed = panels(LAYOUT["layout"])
    assert sorted(placed) == sorted(LAYOUT["configById"])


def test_every_path_exists_in_the_message_definitions():
    checked = 0
    for panel, config in LAYOUT["configById"].items():
        kind = panel.split("!")[0]
        if "topicPath" in config:                          # Raw Messages: a whole topic or a field of it
            leaf_type(config["topicPath"])
            checked += 1
        for series in config.get("paths", []):
            value = series["value"]
            if kind == "Plot" and re.fullmatch(r"-?\d+(\.\d*)?(e-?\d+)?", value):
                continue                                   # a reference line (a threshold)
            field_type = leaf_type(value)
            if kind == "Plot":
                assert field_type.is_primitive_type() and field_type.type in NUMERIC and not (
                    field_type.is_array and "[" not in value.rsplit(".", 1)[1]), f"{panel}: {value} is not a number"
            checked += 1
    # 4 wheelsets, 3 x 8 wheels, speed and acceleration, 2 timelines, 3 whole topics; the sensors' tab: the
    # mounts' lateral and vertical acceleration, the car body's 3 roll rates, the estimator's 4 sides' unloading
    # and Q/P, and per bogie its 2 sides' loads beside its 4 wheels' P
    # the supervision's tab: 7 series, the planning area's x axis (checked below) and the whole setup topic, the
    # braking curves' 7 series
    assert checked == 35 + 2 * len(MOUNTS) + 3 + 2 * 4 + 2 * (2 + 4) + 7 + 1 + 7


def thresholds(panel):
    return sorted(float(s["value"]) for s in LAYOUT["configById"][panel]["paths"]
                  if not s["value"].startswith("/"))


def test_threshold_lines_are_the_monitor_s():
    L = default_limits()
    P0 = L.static_wheel_load
    assert thresholds("Plot!attack_angle") == [-L.attack_angle, L.attack_angle]
    assert thresholds("Plot!wheel_lift") == [L.wheel_lift, L.wheel_lift_critical]
    assert thresholds("Plot!derailment_coefficient") == [L.derailment_coefficient, L.derailment_coefficient_critical]
    assert thresholds("Plot!wheel_unloading") == pytest.approx(
        [(1 - L.wheel_unloading_critical) * P0, (1 - L.wheel_unloading) * P0, P0], rel=1e-12)


def test_the_same_wheel_has_the_same_colour_in_every_plot():
    colours = {}
    for config in LAYOUT["configById"].values():
        for series in config.get("paths", []):
            # a wheel's (the estimates' arrays are running-gear sides')
            match = re.fullmatch(r"/railderail/(?:wheelset_states|contact_forces)\.(wheel_lift|derailment_coefficient|"
                                 r"vertical_force)\[(\d)\]", series["value"])
            if match:
                colours.setdefault(match.group(2), set()).add(series["color"])
    assert len(colours) == 8 and all(len(c) == 1 for c in colours.values())
    colours = {int(k): c.pop() for k, c in colours.items()}
    assert len(set(colours.values())) == 8
    # the hues of the Rerun views: a wheelset's left wheel in its colour there
    assert [colours[2 * w] for w in range(4)] == ["#%02x%02x%02x" % c for c in WHEELSET_COLORS]


def test_the_sensors_tab_plots_every_mount_with_the_rules_levels_of_the_rerun_views():
    tabs = LAYOUT["configById"][LAYOUT["layout"]]["tabs"]
    assert [tab["title"] for tab in tabs] == ["run", "sensors", "supervision"]
    levels = sensor_levels(VehicleParameters())
    for group, _ in SENSOR_GROUPS:
        for plot, field in (("lateral", "linear_acceleration.y"), ("vertical", "linear_acceleration.z")):
            config = LAYOUT["configById"][f"Plot!sensors_{group}_{plot}"]
            shown = [s["value"] for s in config["paths"] if s["value"].startswith("/")]
            assert shown == [f"{m.SENSORS_NS}/{x}/imu.{field}" for x in MOUNTS if sensor_group(x) == group]
            expected = sorted(sign * level for _, level, _, _ in levels.get((group, plot), ()) for sign in (1, -1))
            assert thresholds(f"Plot!sensors_{group}_{plot}") == expected
    roll = levels[("car_body", "roll_rate")][0][1]
    assert thresholds("Plot!sensors_car_body_roll_rate") == [-roll, roll]


def test_the_estimator_plots_are_the_measured_monitor_s_beside_each_bogie_s_wheels():
    limits, P0 = measured_limits(VehicleParameters()), VehicleParameters().static_wheel_load
    assert thresholds("Plot!sensors_estimator_unloading") == [limits.estimated_running_gear_unloading]
    assert thresholds("Plot!sensors_estimator_ratio") == [limits.estimated_side_ratio]
    for j, bogie in enumerate(("front", "rear")):
        config = LAYOUT["configById"][f"Plot!sensors_estimator_{bogie}_loads"]
        shown = [s["value"] for s in config["paths"] if s["value"].startswith("/")]
        assert shown == [f"{m.ONBOARD_ESTIMATES}.wheel_load[{2 * j}]", f"{m.ONBOARD_ESTIMATES}.wheel_load[{2 * j + 1}]",
                         *(f"{m.FORCES}.vertical_force[{k}]" for k in range(4 * j, 4 * j + 4))]
        assert thresholds(f"Plot!sensors_estimator_{bogie}_loads") == pytest.approx(
            [(1 - limits.estimated_running_gear_unloading) * P0, P0], rel=1e-12)


def test_the_sensors_tab_is_the_one_railderail_monitor_foxglove_writes():
    from railderail_monitor.views.foxglove import with_sensors_tab

    assert with_sensors_tab(LAYOUT) == LAYOUT, "python -m railderail_monitor.views.foxglove writes the tab anew"


def test_the_supervision_tab_plots_the_status_against_the_front_s_position():
    from railderail_monitor.views.foxglove import with_supervision_tab

    assert with_supervision_tab(LAYOUT) == LAYOUT, "python -m railderail_monitor.views.foxglove writes the tab anew"
    config = LAYOUT["configById"]
    planning = config["Plot!supervision_planning"]
    assert planning["xAxisVal"] == "custom"
    x = planning["xAxisPath"]["value"]
    assert leaf_type(x).type == "float64" and x == f"{m.SUPERVISION_STATUS}.data[{int(m.SupervisionStatus.front_m)}]"
    fields = {int(m.SupervisionStatus[f]): f for f in m.SupervisionStatus.names()}
    shown = {p: [fields[int(re.search(r"\[(\d+)\]$", s["value"]).group(1))] for s in config[p]["paths"]]
             for p in ("Plot!supervision_planning", "Plot!supervision_margin", "Plot!supervision_level")}
    assert shown == {"Plot!supervision_planning": ["speed_kmh", "target_speed_kmh", "limit_kmh"],
                     "Plot!supervision_margin": ["margin_kmh", "time_to_intervention_s"],
                     "Plot!supervision_level": ["level", "braking"]}
    assert config["RawMessages!supervision"]["topicPath"] == m.SUPERVISION


def test_the_braking_curves_panel_plots_each_curve_against_the_positions_of_the_latest_message():
    config = LAYOUT["configById"]["Plot!supervision_curves"]
    assert config["xAxisVal"] == "currentCustom"

    def row(path):
        """The BrakingCurves field whose samples a path's slice is, all of them."""
        match = re.fullmatch(rf"{m.BRAKING_CURVES}\.data\[(\d+):(\d+)\]", path)
        first, last = int(match.group(1)), int(match.group(2))
        assert first % SAMPLES == 0 and last == first + SAMPLES - 1, path
        return m.BrakingCurves.names()[first // SAMPLES]
    assert row(config["xAxisPath"]["value"]) == "position_m"
    assert [row(s["value"]) for s in config["paths"]] == m.BrakingCurves.names()[1:]
    tabs = LAYOUT["configById"][LAYOUT["layout"]]["tabs"]
    assert "Plot!supervision_curves" in panels(next(t for t in tabs if t["title"] == "supervision")["layout"])
