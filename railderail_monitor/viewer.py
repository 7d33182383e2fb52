"""Rerun views of a run: time series with their thresholds, the alerts as a text log and a 3-D
schematic of the car on the track with its contact patches, under a blueprint that opens ready to
read. Live (the viewer node: `railderail view` spawns a viewer, `--connect URL` streams to one,
`--rrd FILE.rrd` writes a file) or from a recording (`railderail replay FILE.mcap --rerun` or
`--rrd OUT.rrd`).

Entities (timeline `sim_time`, simulation time):
  plots/attack_angle           front-to-rear wheelsets, rad; limit line(s) beside
  plots/wheel_lift_mm          8 wheels, mm; warning and critical lines
  plots/derailment_coefficient 8 wheels Q/P; 0.8 and Nadal's limit
  plots/unloading_ratio        8 wheels dP/P0; 0.60 and 0.65
  plots/lateral_force_kN, plots/vertical_force_kN   8 wheels, kN
  plots/speed_kmh
  alerts                       text log (WARN = warning level, ERROR = critical, CRITICAL = derailment)
  scene/...                    the track frame at the car: rails, car body, bogies, wheelsets and the
                               contact patches (colour: Q/P against its levels); displacements and
                               angles are drawn `exaggeration` times (10) larger, the patches 10 times
Scene frames are drawn at `scene_rate` (25 Hz of simulated time); plots take every sample.
"""
from __future__ import annotations

import argparse
import math
import sys

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from rclpy.node import Node

from railderail_sim import ros_interface as m
from railderail_sim.parameters import TrackParameters, VehicleParameters
from railderail_sim.ros_interface import seconds

from .criteria import Limits, default_limits, SEVERITY_CRITICAL, unloading_ratio

WHEELS = [f"ws{w}_{side}" for w in range(4) for side in ("left", "right")]
TIMELINE = "sim_time"
# schematic geometry (m) of the built-in car and track; body sizes only for the picture
_CAR, _TRACK = VehicleParameters(), TrackParameters()
BOGIES = (_CAR.bogie_semi_distance, -_CAR.bogie_semi_distance)              # bogie centres from the car's
STATIONS = tuple(b + w for b in BOGIES for w in (_CAR.wheelbase_semi, -_CAR.wheelbase_semi))   # wheelsets 0..3
RAIL_Y = _TRACK.rail_spacing / 2.0                                          # rail centre from the track centre line
WHEEL_RADIUS = _CAR.rolling_radius
GREEN, ORANGE, RED, GREY = (60, 180, 75), (245, 130, 48), (230, 25, 75), (128, 128, 128)
LEVEL_COLORS = (ORANGE, RED)


def _arr(x):
    return np.asarray(x, dtype=float)


def _quat_xz(roll, yaw):
    """Quaternion (x, y, z, w) of yaw about z after roll about x (small-angle schematic)."""
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return [cy * sr, sy * sr, sy * cr, cy * cr]


class RunViewer:
    """Feed it messages (rclpy or decoded from MCAP: attribute access) with on_states/on_forces/
    on_status/on_alert/on_derailment; choose a sink first (save/spawn/connect); close() at the end."""

    def __init__(self, limits: Limits = None, exaggeration=10.0, scene_rate=25.0, flush_every=100,
                 application="railderail", recording_id=None):
        self.limits = limits or default_limits()
        self.exaggeration = float(exaggeration)
        self.scene_period = 1.0 / scene_rate if scene_rate > 0 else math.inf
        self.flush_every = flush_every
        self.rec = rr.RecordingStream(application, recording_id=recording_id)
        self.buffers = {}          # entity -> (times, values)
        self.last_scene = -math.inf
        self.status = None
        self.forces = None
        self.curve_sign = 0.0
        self.pending = 0
        self.closed = False
        self.scene = self._new_scene()

    # --- sinks ------------------------------------------------------------------------------
    def blueprint(self):
        plots = [rrb.TimeSeriesView(origin=f"/plots/{name}", name=title) for name, title in (
            ("attack_angle", "attack angle (rad)"), ("wheel_lift_mm", "wheel lift (mm)"),
            ("derailment_coefficient", "Q/P"), ("unloading_ratio", "unloading ratio dP/P0"))]
        forces = [rrb.TimeSeriesView(origin=f"/plots/{name}", name=title) for name, title in (
            ("lateral_force_kN", "Q (kN)"), ("vertical_force_kN", "P (kN)"), ("speed_kmh", "speed (km/h)"))]
        return rrb.Blueprint(
            rrb.Horizontal(
                rrb.Vertical(rrb.Spatial3DView(origin="/scene", name="car on the track (displacements x"
                                               f"{self.exaggeration:g})"),
                             rrb.TextLogView(origin="/alerts", name="alerts"), row_shares=[3, 2]),
                rrb.Vertical(*plots),
                rrb.Vertical(*forces),
                column_shares=[4, 4, 3]),
            collapse_panels=True)

    def save(self, path):
        self.rec.save(str(path), default_blueprint=self.blueprint())
        self._static()

    def spawn(self):
        self.rec.spawn(default_blueprint=self.blueprint())
        self._static()

    def connect(self, url=None):
        self.rec.connect_grpc(url, default_blueprint=self.blueprint())
        self._static()

    def _static(self):
        log = self.rec.log
        log("/scene", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
        rails = [[[-16.0, y, 0.0], [16.0, y, 0.0]] for y in (RAIL_Y, -RAIL_Y)]
        log("/scene/track/rails", rr.LineStrips3D(rails, radii=0.035, colors=[GREY, GREY]), static=True)
        sleepers = [[[x, -1.3, -0.1], [x, 1.3, -0.1]] for x in np.arange(-15.0, 15.01, 0.6)]
        log("/scene/track/sleepers", rr.LineStrips3D(sleepers, radii=0.04, colors=[(150, 110, 80)]), static=True)
        log("/scene/track/car/body", rr.Boxes3D(half_sizes=[[12.8, 1.65, 1.3]], centers=[[0.0, 0.0, 2.45]],
                                                colors=[(70, 110, 200, 120)], fill_mode="solid"), static=True)
        for b, name in enumerate(("front", "rear")):
            log(f"/scene/track/car/bogie_{name}", rr.Boxes3D(half_sizes=[[1.7, 1.1, 0.2]], colors=[(90, 90, 90)],
                                                             fill_mode="solid"), static=True)
        for w in range(4):
            wheels = rr.Cylinders3D(lengths=[0.14, 0.14, 1.5], radii=[WHEEL_RADIUS, WHEEL_RADIUS, 0.08],
                                    centers=[[0, RAIL_Y, 0], [0, -RAIL_Y, 0], [0, 0, 0]],
                                    rotation_axis_angles=[rr.RotationAxisAngle(axis=[1, 0, 0], degrees=90)] * 3,
                                    colors=[GREEN, GREEN, (60, 60, 60)], fill_mode="solid")
            log(f"/scene/track/wheelset_{w}", wheels, static=True)
        series = {
            "attack_angle": ([f"ws{w}" for w in range(4)], "attack_angle", 1.0),
            "wheel_lift_mm": (WHEELS, "wheel_lift", 1e3),
            "derailment_coefficient": (WHEELS, "derailment_coefficient", 1.0),
            "unloading_ratio": (WHEELS, "wheel_unloading", 1.0),
        }
        for entity, (names, criterion, scale) in series.items():
            log(f"/plots/{entity}/values", rr.SeriesLines(names=names), static=True)
            for (sev, thr), color in zip(self.limits.levels(criterion), LEVEL_COLORS):
                label = "critical" if sev == SEVERITY_CRITICAL else "warning"
                log(f"/plots/{entity}/limit_{label}", rr.SeriesLines(colors=[color], widths=[2.5],
                                                                     names=[f"{label} {thr * scale:.4g}"]),
                    static=True)
        for entity in ("lateral_force_kN", "vertical_force_kN"):
            log(f"/plots/{entity}", rr.SeriesLines(names=WHEELS), static=True)
        log("/plots/speed_kmh", rr.SeriesLines(names=["speed"]), static=True)

    # --- input ------------------------------------------------------------------------------
    def _append(self, entity, t, values):
        times, vals = self.buffers.setdefault(entity, ([], []))
        times.append(t)
        vals.append(values)

    def _limits(self, entity, criterion, t, scale=1.0):
        """Threshold lines: two points per flushed batch (its first and last time) are enough."""
        for sev, thr in self.limits.levels(criterion):
            name = f"/plots/{entity}/limit_{'critical' if sev == SEVERITY_CRITICAL else 'warning'}"
            times, vals = self.buffers.setdefault(name, ([], []))
            if len(times) < 2:
                times.append(t)
                vals.append(thr * scale)
            else:
                times[1] = t

    def _tick(self):
        self.pending += 1
        if self.pending >= self.flush_every:
            self.flush()

    def on_states(self, msg):
        t = seconds(msg.header.stamp)
        self._append("/plots/attack_angle/values", t, _arr(msg.attack_angle))
        self._limits("attack_angle", "attack_angle", t)
        lift = _arr(msg.wheel_lift)
        self._append("/plots/wheel_lift_mm/values", t, lift * 1e3)
        self._limits("wheel_lift_mm", "wheel_lift", t, 1e3)
        if t - self.last_scene >= self.scene_period - 1e-9:
            self.last_scene = t
            self._scene(t, msg, lift)
        self._tick()

    def on_forces(self, msg):
        t = seconds(msg.header.stamp)
        self.forces = msg
        self._append("/plots/derailment_coefficient/values", t, _arr(msg.derailment_coefficient))
        self._limits("derailment_coefficient", "derailment_coefficient", t)
        self._append("/plots/unloading_ratio/values", t,
                     unloading_ratio(_arr(msg.vertical_force), self.limits.static_wheel_load))
        self._limits("unloading_ratio", "wheel_unloading", t)
        self._append("/plots/lateral_force_kN", t, _arr(msg.lateral_force) * 1e-3)
        self._append("/plots/vertical_force_kN", t, _arr(msg.vertical_force) * 1e-3)

    def on_status(self, msg):
        self.status = msg
        if msg.curvature != 0.0:
            self.curve_sign = math.copysign(1.0, msg.curvature)
        self._append("/plots/speed_kmh", seconds(msg.header.stamp), float(msg.speed) * 3.6)

    def on_alert(self, alert):
        a = m.alert_dict(alert)
        self.rec.set_time(TIMELINE, duration=a["time_s"])
        level = "ERROR" if a["severity"] == SEVERITY_CRITICAL else "WARN"
        self.rec.log("/alerts", rr.TextLog(f"s = {a['track_position']:.1f} m: {a['message']}", level=level))

    def on_derailment(self, event):
        d = m.derailment_dict(event)
        self.rec.set_time(TIMELINE, duration=d["time_s"])
        self.rec.log("/alerts", rr.TextLog(
            f"s = {d['track_position_m']:.1f} m: DERAILED: wheelset {d['wheelset']} {d['wheel_side']} "
            f"({d['rail_side']} rail), {d['mechanism'].replace('_', ' ')}, {d['speed_kmh']:.1f} km/h",
            level="CRITICAL"))

    def on_final_status(self, msg):
        self.rec.set_time(TIMELINE, duration=seconds(msg.header.stamp))
        self.rec.log("/alerts", rr.TextLog(f"run stopped: {msg.message}", level="INFO"))

    # --- scene ------------------------------------------------------------------------------
    def _scene(self, t, states, lift):
        """One 3-D frame into the scene buffers (sent as columns by flush)."""
        ex = self.exaggeration
        b = self.scene
        b["time"].append(t)
        st = self.status
        cant = float(st.cant) if st is not None else 0.0
        # a curve to the left raises the right (outer) rail: roll the track frame by -cant
        b["track"].append(_quat_xz(-self.curve_sign * cant, 0.0))
        if st is not None:
            b["body_t"].append([0.0, ex * st.car_body_lateral_displacement, ex * st.car_body_vertical_displacement])
            b["body_q"].append(_quat_xz(ex * st.car_body_roll, ex * st.car_body_yaw))
            for k in range(2):
                b["bogie_t"][k].append([BOGIES[k], ex * st.bogie_lateral_displacement[k], 0.65])
                b["bogie_q"][k].append(_quat_xz(ex * st.bogie_roll[k], ex * st.bogie_yaw[k]))
        else:
            b["body_t"].append([0.0, 0.0, 0.0])
            b["body_q"].append([0.0, 0.0, 0.0, 1.0])
            for k in range(2):
                b["bogie_t"][k].append([BOGIES[k], 0.0, 0.65])
                b["bogie_q"][k].append([0.0, 0.0, 0.0, 1.0])
        y, z = _arr(states.lateral_displacement), _arr(states.vertical_displacement)
        roll, yaw = _arr(states.roll), _arr(states.yaw)
        thr = [x for _, x in self.limits.levels("wheel_lift")]
        for w in range(4):
            b["ws_t"][w].append([STATIONS[w], ex * y[w], WHEEL_RADIUS + ex * z[w]])
            b["ws_q"][w].append(_quat_xz(ex * roll[w], ex * yaw[w]))
            for k in (2 * w, 2 * w + 1):
                b["ws_c"][w].append((GREEN, ORANGE, RED)[min(sum(lift[k] >= x for x in thr), 2)])
            b["ws_c"][w].append((60, 60, 60))
        f = self.forces
        count = 0
        if f is not None:
            qp = _arr(f.derailment_coefficient)
            levels = [x for _, x in self.limits.levels("derailment_coefficient")]
            for k in range(8):
                if f.contact_count[k] == 0:
                    continue
                side = 1.0 if k % 2 == 0 else -1.0
                w = k // 2
                b["patch_c"].append([STATIONS[w], side * (RAIL_Y + f.contact_position[k]) + ex * y[w], 0.005])
                b["patch_h"].append([5.0 * f.patch_length[k], 5.0 * f.patch_width[k], 0.004])
                b["patch_col"].append((GREEN, ORANGE, RED)[min(sum(qp[k] >= x for x in levels), 2)])
                count += 1
        b["patch_n"].append(count)

    def _new_scene(self):
        return dict(time=[], track=[], body_t=[], body_q=[], bogie_t=([], []), bogie_q=([], []),
                    ws_t=([], [], [], []), ws_q=([], [], [], []), ws_c=([], [], [], []),
                    patch_c=[], patch_h=[], patch_col=[], patch_n=[])

    def _flush_scene(self):
        b = self.scene
        n = len(b["time"])
        if not n:
            return
        send = self.rec.send_columns
        index = [rr.TimeColumn(TIMELINE, duration=np.asarray(b["time"]))]
        send("/scene/track", index, rr.Transform3D.columns(quaternion=b["track"]))
        send("/scene/track/car/body", index, rr.Transform3D.columns(translation=b["body_t"], quaternion=b["body_q"]))
        for k, name in enumerate(("front", "rear")):
            send(f"/scene/track/car/bogie_{name}", index,
                 rr.Transform3D.columns(translation=b["bogie_t"][k], quaternion=b["bogie_q"][k]))
        for w in range(4):
            send(f"/scene/track/wheelset_{w}", index,
                 list(rr.Transform3D.columns(translation=b["ws_t"][w], quaternion=b["ws_q"][w]))
                 + list(rr.Cylinders3D.columns(colors=b["ws_c"][w]).partition([3] * n)))
        counts = b["patch_n"]
        if sum(counts):
            send("/scene/track/contact_patches", index,
                 rr.Ellipsoids3D.columns(half_sizes=b["patch_h"], centers=b["patch_c"],
                                         colors=b["patch_col"]).partition(counts))
        self.scene = self._new_scene()

    # --- output -----------------------------------------------------------------------------
    def flush(self):
        for entity, (times, values) in self.buffers.items():
            if not times:
                continue
            self.rec.send_columns(entity, indexes=[rr.TimeColumn(TIMELINE, duration=np.asarray(times))],
                                  columns=rr.Scalars.columns(scalars=np.asarray(values, dtype=float)))
            times.clear()
            values.clear()
        self._flush_scene()
        self.pending = 0

    def close(self):
        if not self.closed:
            self.closed = True
            self.flush()
            self.rec.flush()
            self.rec.disconnect()


# --- live viewer node ---------------------------------------------------------------------------

class ViewerNode(Node):
    """The viewer node `railderail_viewer`: every /railderail topic into a RunViewer, which it
    closes (flushing the file or the stream) in `destroy_node`."""

    def __init__(self, viewer, saving=None):
        super().__init__("railderail_viewer")
        self.viewer = viewer
        handlers = {m.STATES: viewer.on_states, m.FORCES: viewer.on_forces, m.STATUS: viewer.on_status,
                    m.ALERTS: viewer.on_alert, m.DERAILMENT: viewer.on_derailment,
                    m.FINAL_STATUS: viewer.on_final_status}
        for topic, (_, cls, _, qos) in m.TOPICS.items():
            self.create_subscription(cls, topic, handlers[topic], qos)
        self.get_logger().info("showing /railderail in Rerun" + (f" (saving {saving})" if saving else ""))

    def destroy_node(self):
        self.viewer.close()
        super().destroy_node()


def viewer_node_main(args):
    viewer = RunViewer(exaggeration=args.exaggeration, scene_rate=args.scene_rate, flush_every=20)
    if args.rrd:
        viewer.save(args.rrd)
    elif args.connect:
        viewer.connect(args.connect)
    else:
        viewer.spawn()
    return m.run_node("railderail view", lambda: ViewerNode(viewer, args.rrd))


def add_arguments(parser):
    sink = parser.add_mutually_exclusive_group()
    sink.add_argument("--spawn", action="store_true", help="start a Rerun viewer and stream to it (default)")
    sink.add_argument("--connect", metavar="URL", help="stream to a running viewer (rerun+http://HOST:9876/proxy)")
    sink.add_argument("--rrd", metavar="FILE.rrd", help="write a .rrd file instead (headless)")
    parser.add_argument("--exaggeration", type=float, default=10.0, help="scale of displacements in the 3-D view")
    parser.add_argument("--scene-rate", type=float, default=25.0, help="3-D frames per simulated second")


def command(parser: argparse.ArgumentParser):
    """`railderail view`: the live topics in Rerun."""
    add_arguments(parser)

    def run(args):
        if args.rrd and not args.rrd.endswith(".rrd"):
            raise ValueError(f"--rrd {args.rrd}: the file name must end in .rrd")
        if not 0.0 < args.exaggeration <= 1000.0:
            raise ValueError(f"--exaggeration {args.exaggeration:g} is outside 0-1000")
        return viewer_node_main(args)
    return run


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m railderail_monitor.viewer",
                                     description="Show the live /railderail topics in Rerun.")
    run = command(parser)
    try:
        return run(parser.parse_args(argv))
    except ValueError as error:
        print(f"{parser.prog}: error: {error}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
