"""The `sensors` tab of the Foxglove layout (foxglove/railderail-layout.json), made from the sensor set's
mounts (sensors.config.MOUNTS) and the Rerun views' groups, colours and on-board levels (viewer.py), so that
the two views show the same; `python -m railderail_monitor.foxglove` writes it into the layout file (the
`run` tab, hand-made, is kept). tests/test_foxglove_layout.py checks that the file holds what this gives.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

from railderail_sim.parameters import VehicleParameters
from railderail_sim.ros_interface import SENSORS_NS
from railderail_sim.sensors.config import MOUNTS

from .viewer import MOUNT_COLORS, SENSOR_GROUPS, sensor_group, sensor_levels

LAYOUT = Path(__file__).resolve().parents[1] / "foxglove" / "railderail-layout.json"
TABS = "Tab!views"
# what each plot of a group shows: (plot, the Imu's field, unit, what)
PLOTS = (("lateral", "linear_acceleration.y", "m/s²", "lateral acceleration"),
         ("vertical", "linear_acceleration.z", "m/s²", "vertical acceleration"),
         ("roll_rate", "angular_velocity.x", "rad/s", "roll rate"))


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
            paths = [dict(value=f"{SENSORS_NS}/{mount}/imu.{field}", enabled=True, timestampMethod="receiveTime",
                          label=mount, color=_hex(MOUNT_COLORS[k % len(MOUNT_COLORS)]))
                     for k, mount in enumerate(mounts)]
            lines = levels.get((group, plot), [])
            paths += [dict(value=repr(sign * level), enabled=True, timestampMethod="receiveTime", label=label,
                           color=_hex(colour), lineSize=1) for _, level, colour, label in lines for sign in (1, -1)]
            name = f"{title} {what} ({unit}, measured)" + (": ± " + ", ".join(line[3] for line in lines)
                                                            if lines else "")
            panels[f"Plot!sensors_{group}_{plot}"] = {"foxglove.panelTitle": name, "paths": paths, **style}
    return panels


def sensors_layout():
    """The tab's arrangement: the car body's three plots, the frames' two, the axle boxes' two."""
    def column(*panels):
        node = panels[-1]
        for k, panel in reversed(list(enumerate(panels[:-1]))):
            node = dict(first=panel, second=node, direction="column", splitPercentage=100.0 / (len(panels) - k))
        return node
    return dict(first=column(*(f"Plot!sensors_car_body_{p}" for p in ("lateral", "vertical", "roll_rate"))),
                second=dict(first=column("Plot!sensors_bogie_frame_lateral", "Plot!sensors_bogie_frame_vertical"),
                            second=column("Plot!sensors_axle_box_lateral", "Plot!sensors_axle_box_vertical"),
                            direction="row", splitPercentage=50.0),
                direction="row", splitPercentage=34.0)


def with_sensors_tab(layout):
    """The layout (a parsed file) with its sensors tab made anew, its run tab kept."""
    config = dict(layout["configById"])
    tabs = config[TABS]["tabs"]
    style = {k: v for k, v in config["Plot!speed"].items() if k not in ("foxglove.panelTitle", "paths")}
    config = {k: v for k, v in config.items() if not k.startswith("Plot!sensors_")}
    config.update(sensor_panels(style))
    config[TABS] = dict(config[TABS], tabs=[tab for tab in tabs if tab["title"] != "sensors"]
                        + [dict(title="sensors", layout=sensors_layout())])
    return dict(layout, configById=config)


def main(argv=None):
    layout = json.loads(LAYOUT.read_text())
    LAYOUT.write_text(json.dumps(with_sensors_tab(layout), indent=2, ensure_ascii=False) + "\n")
    print(f"{LAYOUT}: sensors tab written ({len(MOUNTS)} mounts)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
