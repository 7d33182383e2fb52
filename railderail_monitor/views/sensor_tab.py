"""The sensors' tab of the Rerun views (rerun_views.RunViewer, whose base class this is): what the simulator's
sensors measure, the on-board rules' levels drawn on the lateral plots, and the on-board estimator's
running-gear unloading beside the ground truth's. Its messages come through the viewer's own buffers and styles
(`_append`, `_style`, `_line`, `_limits`), so that its series are flushed with the run's."""
from __future__ import annotations

import math

import numpy as np

from railderail_sim.ros import interface as m
from railderail_sim.ros import sensor_messages as sm
from railderail_sim.ros.interface import seconds
from railderail_sim.sensors.sensor_set import MOUNTS
import rerun.blueprint as rrb

from ..onboard import estimator
from ..warning.alerts import level_text
from .colours import ESTIMATE_COLORS, MOUNT_COLORS, TRUTH_COLORS
from .plots import plot
from .sensor_plots import GROUP_NOTES, SENSOR_GROUPS, mount_label, sensor_group, sensor_levels

SIDES = ("left", "right")                  # wheel k is wheelset k // 2, side k % 2
# a plot's legend is cut where the plot is shorter than it: each row of the sensors' tab has as its share its longest
# legend's entries and this many more (the view's title, time axis and the legend's frame: about 4 entries' height,
# seen at 1920x1080 in the viewer)
LEGEND_FRAME_ENTRIES = 4


class SensorTab:
    """The sensors' state of a RunViewer and the tab that shows it."""

    def _init_sensors(self, vehicle, effective_area, air_spring_height, estimate_period):
        """The vehicle and air springs of the estimator, the rules' levels, and the record of sensor messages."""
        self.vehicle, self.effective_area, self.estimate_period = vehicle, effective_area, estimate_period
        self.sensors = sm.SensorRecord(air_spring_height)
        self.sensor_levels = sensor_levels(self.vehicle)
        self.sensor_series = set()       # entities whose series styles have been logged
        self.wheel_loads = ([], [], [])  # time, vertical and lateral forces of the ground truth's unloading
        self.estimated_until = self.truth_until = -math.inf
        self.sensor_time = self.next_estimate = -math.inf

    def sensors_view(self):
        """What the sensors measure, each lateral plot with its rules' levels in the legend, and the
        estimator's unloading beside the ground truth's."""
        panels = {}          # (group, plot): (view, its legend's entries)
        for group, title in SENSOR_GROUPS:
            mounts = sum(sensor_group(mount) == group for mount in MOUNTS)     # of the shipped set
            for axis in ("lateral", "vertical", "roll_rate") if group == "car_body" else ("lateral", "vertical"):
                name = ("car body roll rate (rad/s)" if axis == "roll_rate"
                        else f"{title} {axis} (m/s²){GROUP_NOTES.get((group, axis), '')}")
                # a level drawn +- is one entry
                panels[group, axis] = (plot(f"/sensors/{group}/{axis}", name),
                                       mounts + len(self.sensor_levels.get((group, axis), ())))
        levels = self.limits.levels("running_gear_unloading")
        unloading = " / ".join(level_text("running_gear_unloading", thr) for _, thr in levels)
        for bogie in estimator.BOGIES:     # estimated and ground truth, each side, and the levels
            panels["estimator", bogie] = (plot(f"/sensors/estimator/{bogie}", f"{bogie} gear ΔQ/Q0, estimate and "
                                               f"truth: {unloading}"), 2 * len(SIDES) + len(levels))
        # three rows, so that every legend is whole at 1920x1080 (in four, one of them was cut): the car body's
        # lateral panel wider, its title naming the rules; the estimates, whose legends are shorter, beside the
        # axle boxes
        rows = (((("car_body", "lateral"), ("car_body", "vertical"), ("car_body", "roll_rate")), [2, 1, 1]),
                ((("bogie_frame", "lateral"), ("bogie_frame", "vertical")), [1, 1]),
                ((("axle_box", "lateral"), ("axle_box", "vertical"), *(("estimator", b) for b in estimator.BOGIES)),
                 [1, 1, 1, 1]))
        return rrb.Vertical(*(rrb.Horizontal(*(panels[key][0] for key in keys), column_shares=shares)
                              for keys, shares in rows),
                            row_shares=[max(panels[key][1] for key in keys) + LEGEND_FRAME_ENTRIES
                                        for keys, _ in rows], name="sensors")

    def on_sensor(self, topic, msg):
        """A message of a sensor topic (/railderail/sensors/..., sensor_messages.sensor_topics): an IMU's
        acceleration and roll rate into its group's plots; every one kept for the estimator. The first
        one adds the sensors' tab to the blueprint."""
        first = not self.sensors.messages
        if not self.sensors.add(topic, msg):
            return
        if first and self.sink:
            self.rec.send_blueprint(self.blueprint(), make_active=True, make_default=True)
        mount, _, kind = topic[len(m.SENSORS_NS) + 1:].partition("/")
        group = sensor_group(mount)
        if kind != "imu" or group is None:
            return
        t = seconds(msg.header.stamp)
        self.sensor_time = max(self.sensor_time, t)
        plots = [("lateral", msg.linear_acceleration.y), ("vertical", msg.linear_acceleration.z)]
        if group == "car_body" and msg.angular_velocity_covariance[0] != -1.0:
            plots.append(("roll_rate", msg.angular_velocity.x))
        for name, value in plots:
            origin = f"/sensors/{group}/{name}"
            entity = f"{origin}/{mount}"
            if entity not in self.sensor_series:
                shown = sum(e.startswith(origin + "/") and "/limit_" not in e for e in self.sensor_series)
                self._style(entity, [mount_label(mount, group)], [MOUNT_COLORS[shown % len(MOUNT_COLORS)]])
            self._append(entity, t, value)
            for line, level, colour, label in self.sensor_levels.get((group, name), ()):
                # one name for the + and - lines: the legend shows the pair as one entry
                self._style(f"{origin}/{line}", [f"±{label}"] * 2, [colour] * 2, [2.0] * 2)
                self._line(f"{origin}/{line}", t, (level, -level))

    def _estimate(self, final):
        """The estimator's running-gear unloading over the sensor record so far (onboard.estimator: the
        viewer computes nothing itself), its samples after those already shown, and the ground truth's from
        the wheel loads beside it; every estimate_period s of sensor time and at the end. A sensor set
        without the estimator's mounts shows no estimate."""
        if not self.sensors.messages or not (final or self.sensor_time >= self.next_estimate):
            return
        self.next_estimate = self.sensor_time + self.estimate_period
        a = self.sensors.arrays()
        try:
            est = estimator.estimate(a, self.vehicle, self.effective_area) if len(
                a.get("sensor_car_body_centre_time", ())) >= 2 else None
        except KeyError:            # a mount or the air springs it needs are not in the record
            est = None
        if est is not None:
            new = est["time"] > self.estimated_until
            if np.any(new):
                self.estimated_until = est["time"][new][-1]
                self._estimated("estimated", est["time"][new], est["unloading"][new], ESTIMATE_COLORS)
        t = np.asarray(self.wheel_loads[0])
        new = t > self.truth_until
        if est is not None and np.any(new):
            self.truth_until = t[new][-1]
            truth = estimator.truth(dict(time=t[new], vertical_force=np.asarray(self.wheel_loads[1])[new],
                                         lateral_force=np.asarray(self.wheel_loads[2])[new]), self.vehicle)
            self._estimated("ground_truth", t[new], truth["unloading"], TRUTH_COLORS)

    def _estimated(self, series, times, unloading, colours):
        """(n,) times and (n, 4) unloading [front left, front right, rear left, rear right] into the two
        running gears' plots, with the monitor's running_gear_unloading levels."""
        for j, bogie in enumerate(estimator.BOGIES):
            origin = f"/sensors/estimator/{bogie}"
            label = series.replace("_", " ")
            self._style(f"{origin}/{series}", [f"{label} {side}" for side in SIDES], list(colours))
            if f"{origin}/limit_warning" not in self.sensor_series:
                self.sensor_series |= {f"{origin}/limit_warning", f"{origin}/limit_critical"}
                self._static_limits(origin, "running_gear_unloading")
            buffer = self.buffers.setdefault(f"{origin}/{series}", ([], []))
            buffer[0].extend(times)
            buffer[1].extend(unloading[:, 2 * j:2 * j + 2])
            for t in (times[0], times[-1]):
                self._limits(bogie, "running_gear_unloading", t, origin="/sensors/estimator")
