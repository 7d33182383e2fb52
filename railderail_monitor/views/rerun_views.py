"""Rerun views of a run: time series with their thresholds, the alerts as a text log and a 3-D
schematic of the car on the track with its contact patches, under a blueprint that opens ready to
read. Live (the viewer node, viewer_node.py: `railderail view` spawns a viewer, `--connect URL` streams to
one, `--rrd FILE.rrd` writes a file) or from a recording (`railderail replay FILE.mcap --rerun` or
`--rrd OUT.rrd`).

Entities, on two timelines: `sim_time` (simulation time) and `track_position_mm` (the car-body centre along the
line, mm: an integer timeline, so that an engineer scrubs along the line and reads an alert's place off the axis;
a sample's place from the wheelset states at its time, interpolated; none without them, a recording of sensors only):
  plots/attack_angle_mrad/values   front-to-rear wheelsets, mrad; the warning line once the
                                   attack angle reaches half of it (so that the data sets the scale)
  plots/NAME/left, plots/NAME/right    the left and the right wheels of the four wheelsets, for NAME
                                   wheel_lift_mm, derailment_coefficient (Y/Q), unloading_ratio (ΔQ/Q0),
                                   lateral_force_kN (Y), vertical_force_kN (Q); levels in
                                   plots/NAME/limit_warning and limit_critical, named as the alerts
                                   round them (warning.alerts.level_text)
  plots/speed_kmh
  alerts                       text log (WARN = warning level, ERROR = critical, CRITICAL = derailment), the
                               ground-truth and the measured-mode monitors' alerts marked as the demo marks them,
                               each entry's time and place in its text
  sensors/GROUP/lateral/MOUNT, sensors/GROUP/vertical/MOUNT    with the simulator's sensors on (or a
                               recording of their topics): each mount's measured acceleration (m/s^2, its
                               body's axes), GROUP car_body, bogie_frame or axle_box; on the lateral plots the
                               on-board rules' levels +- (onboard/criteria.py: car-body ydd* 2.5 and ydd*_qst
                               1.5; bogie-frame peak 12 - M_b/5, its r.m.s. half, BIDS 8), each applying to the
                               rule's filtered signal (docs/onboard-criteria.md)
  sensors/car_body/roll_rate/MOUNT    the car body's roll rate (gyro x, rad/s) and the roll-rate rule's level
  sensors/estimator/BOGIE/estimated, .../ground_truth    a running gear's unloading dQ/Q0 per side (left,
                               right): onboard.estimator's estimate from the recorded sensor topics beside the
                               simulator's wheel loads, with the monitor's running_gear_unloading levels
                               (computed over the record so far every `estimate_period` s of simulated time)
  scene/...                    the track frame at the car: rails, a wire-frame car body, bogies, labelled
                               wheelsets (wheels coloured by their lift levels) and the contact patches
                               (coloured by the worst level their wheel reached: Y/Q, lift, unloading);
                               displacements and angles drawn `exaggeration` times (10) larger, patches 10 times
One colour per wheelset in every plot; left and right wheels in side-by-side panels. Every plot shows
the run so far (from its start to the time cursor). Scene frames are drawn at `scene_rate` (25 Hz of
simulated time); plots take every sample. The sensors' plots are a second tab, "sensors", present once a
sensor topic's message has come (no sensors, no tab).
"""
from __future__ import annotations

import math

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from railderail_sim.parameters import TrackParameters, VehicleParameters
from railderail_sim.ros import interface as m
from railderail_sim.ros.interface import seconds
from railderail_sim.sensors.sensor_set import AIR_SPRING_EFFECTIVE_AREA

from ..warning.alerts import level_text
from ..warning.limits import Limits, default_limits, SEVERITY_CRITICAL
from ..warning.quantities import unloading_ratio
from .colours import GREEN, GREY, ORANGE, RED, WHEELSET_COLORS
from .planning import PlanningArea, planning_view
from .plots import POSITION, TIMELINE, plot
from .sensor_tab import SIDES, SensorTab

WHEELSETS = [f"ws{w}" for w in range(4)]
# schematic geometry (m) of the built-in car and track; body sizes only for the picture
_CAR, _TRACK = VehicleParameters(), TrackParameters()
BOGIES = (_CAR.bogie_semi_distance, -_CAR.bogie_semi_distance)              # bogie centres from the car's
STATIONS = tuple(b + w for b in BOGIES for w in (_CAR.wheelbase_semi, -_CAR.wheelbase_semi))   # wheelsets 0..3
RAIL_Y = _TRACK.rail_spacing / 2.0                                          # rail centre from the track centre line
WHEEL_RADIUS = _CAR.rolling_radius
LEVEL_COLORS = (ORANGE, RED)
# per-wheel plots: (entity, criterion of its levels or None, scale from SI, title)
# (EN 14363's notation: Y lateral, Q vertical wheel-rail force; docs/output-format.md)
WHEEL_PLOTS = (("wheel_lift_mm", "wheel_lift", 1e3, "lift h_p (mm)"),
               ("derailment_coefficient", "derailment_coefficient", 1.0, "Y/Q"),
               ("unloading_ratio", "wheel_unloading", 1.0, "ΔQ/Q0"),
               ("lateral_force_kN", None, 1e-3, "Y (kN)"),
               ("vertical_force_kN", None, 1e-3, "Q (kN)"))
ATTACK = "attack_angle_mrad"
def _arr(x):
    return np.asarray(x, dtype=float)


def _place(t, position):
    """An entry of the alerts' log: its time and place, as the demo prints them."""
    return f"t = {t:.3f} s, s = {position:.1f} m"


def _quat_xz(roll, yaw):
    """Quaternion (x, y, z, w) of yaw about z after roll about x (small-angle schematic)."""
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return [cy * sr, sy * sr, sy * cr, cy * cr]


class RunViewer(SensorTab):
    """Feed it messages (rclpy or decoded from MCAP: attribute access) with on_states/on_forces/
    on_status/on_alert/on_derailment; choose a sink first (save/spawn/connect); close() at the end."""

    def __init__(self, limits: Limits = None, exaggeration=10.0, scene_rate=25.0, flush_every=100,
                 application="railderail", recording_id=None, vehicle=None, effective_area=AIR_SPRING_EFFECTIVE_AREA,
                 air_spring_height=None, estimate_period=1.0):
        self.limits = limits or default_limits()
        self._init_sensors(vehicle or _CAR, effective_area, air_spring_height, estimate_period)
        self.sink = False
        self.exaggeration = float(exaggeration)
        self.scene_period = 1.0 / scene_rate if scene_rate > 0 else math.inf
        self.flush_every = flush_every
        self.rec = rr.RecordingStream(application, recording_id=recording_id)
        self.buffers = {}          # entity -> (times, values)
        self.track = ([], [])      # time and track position (m) of every wheelset-states sample: the position timeline
        self.track_arrays = None   # the same as arrays, made again when it has grown
        self.last_scene = -math.inf
        self.status = None
        self.forces = None
        self.curve_sign = 0.0
        self.attack_limit_shown = False
        self.derailed_at = None          # time of the derailment event, once it came
        self.final_entry = None          # a derailed run's final status waiting for the derailment event
        self.pending = 0
        self.closed = False
        self.scene = self._new_scene()
        self.planning = PlanningArea(self.rec, self._append, self.scene_period)

    # --- sinks ------------------------------------------------------------------------------
    def blueprint(self):
        """The run's views; with sensor messages seen, in a tab "run" beside the tab "sensors", and with the speed
        supervision's status the tab "supervision"."""
        run = self.run_view()
        tabs = (([self.sensors_view()] if self.sensors.messages else [])
                + ([planning_view()] if self.planning.seen else []))
        layout = rrb.Tabs(run, *tabs, active_tab=0) if tabs else run
        return rrb.Blueprint(
            layout,
            # the time cursor follows the data: at the latest sample live, at the end (the derailment) of a file
            rrb.TimePanel(timeline=TIMELINE, play_state="following", state="collapsed"),
            collapse_panels=True)

    def run_view(self):
        # each wheel panel's legend names the wheelsets' colours and the level lines with their values; the
        # title stays short enough to be read whole in a third of the width
        def sides(entity, criterion, title):
            limits = ["$origin/limit_warning", "$origin/limit_critical"]
            return rrb.Horizontal(*(plot(f"/plots/{entity}", f"{title}, {side}", [f"$origin/{side}", *limits])
                                    for side in SIDES))

        rows = {entity: sides(entity, criterion, title) for entity, criterion, _, title in WHEEL_PLOTS}
        attack = plot(f"/plots/{ATTACK}", "attack angle (mrad), warning "
                      + level_text("attack_angle", self.limits.attack_angle))
        # the car looked at from the inner side of the built-in (left) curve, a little ahead and above: the inner
        # wheels, which unload and lift, in front of the bogies, and the four wheelsets (and their labels) apart
        eye = rrb.EyeControls3D(kind=rrb.Eye3DKind.Orbital, position=[1.5, 18.5, 4.5], look_target=[0.0, 0.0, 0.8],
                                eye_up=[0.0, 0.0, 1.0])
        scene = rrb.Spatial3DView(origin="/scene", name=f"car on the track (displacements x{self.exaggeration:g})",
                                  eye_controls=eye)
        return rrb.Vertical(
            rrb.Horizontal(
                rrb.Vertical(scene, plot("/plots/speed_kmh", "speed (km/h)"), attack, row_shares=[4, 1, 2]),
                rrb.Vertical(rows["wheel_lift_mm"], rows["derailment_coefficient"], rows["unloading_ratio"]),
                rrb.Vertical(rows["lateral_force_kN"], rows["vertical_force_kN"]),
                column_shares=[4, 5, 4]),
            # the whole width, so that an alert's sentence is read whole; its time and place are in the sentence
            # (the log's timeline columns are as wide as their names: sim_time's cut its value), not its entity
            rrb.TextLogView(origin="/alerts", name="alerts", columns=rrb.archetypes.TextLogColumns(
                timeline_columns=[rrb.encodings.TimelineColumn(line, visible=False) for line in (TIMELINE, POSITION)],
                text_log_columns=[rrb.encodings.TextLogColumn(kind, visible=kind != "EntityPath")
                                  for kind in ("LogLevel", "EntityPath", "Body")])),
            row_shares=[4, 1], name="run")

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
        self.sink = True
        self._static_scene()

    def _static_scene(self):
        log = self.rec.log
        log("/scene", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
        rails = [[[-16.0, y, 0.0], [16.0, y, 0.0]] for y in (RAIL_Y, -RAIL_Y)]
        log("/scene/track/rails", rr.LineStrips3D(rails, radii=0.035, colors=[GREY, GREY]), static=True)
        sleepers = [[[x, -1.3, -0.1], [x, 1.3, -0.1]] for x in np.arange(-15.0, 15.01, 0.6)]
        log("/scene/track/sleepers", rr.LineStrips3D(sleepers, radii=0.04, colors=[(150, 110, 80)]), static=True)
        # a wire frame: a solid body hides the bogies and patches and takes every hover
        log("/scene/track/car/body", rr.Boxes3D(half_sizes=[[12.8, 1.65, 1.3]], centers=[[0.0, 0.0, 2.45]],
                                                colors=[(70, 110, 200)], radii=0.02, fill_mode="majorwireframe"),
            static=True)
        for b, name in enumerate(("front", "rear")):
            # wire frames too: a solid bogie hid its wheels' middle from the side
            log(f"/scene/track/car/bogie_{name}", rr.Boxes3D(half_sizes=[[1.7, 1.1, 0.2]], colors=[(90, 90, 90)],
                                                             radii=0.03, fill_mode="majorwireframe"), static=True)
        for w in range(4):
            # no colours here: static data shadows temporal data in Rerun, and the wheels' colours (their lift
            # levels) are the frames'; a static green kept every wheel green through the derailment
            wheels = rr.Cylinders3D(lengths=[0.14, 0.14, 1.5], radii=[WHEEL_RADIUS, WHEEL_RADIUS, 0.08],
                                    centers=[[0, RAIL_Y, 0], [0, -RAIL_Y, 0], [0, 0, 0]],
                                    rotation_axis_angles=[rr.RotationAxisAngle(axis=[1, 0, 0], degrees=90)] * 3,
                                    fill_mode="solid")
            log(f"/scene/track/wheelset_{w}", wheels, static=True)
            # the label below the rails: over the wheel it hid the wheel's colour
            log(f"/scene/track/wheelset_{w}/label", rr.Points3D([[0.0, 0.0, -WHEEL_RADIUS - 0.5]], radii=0.02,
                                                                labels=[f"ws{w}"], show_labels=True), static=True)
        log(f"/plots/{ATTACK}/values", rr.SeriesLines(names=WHEELSETS, colors=WHEELSET_COLORS), static=True)
        self._static_limits(f"/plots/{ATTACK}", "attack_angle")
        for entity, criterion, scale, _ in WHEEL_PLOTS:
            for side in SIDES:
                log(f"/plots/{entity}/{side}", rr.SeriesLines(names=WHEELSETS, colors=WHEELSET_COLORS), static=True)
            if criterion is not None:
                self._static_limits(f"/plots/{entity}", criterion)
        log("/plots/speed_kmh", rr.SeriesLines(names=["speed"], colors=[GREY]), static=True)

    def _static_limits(self, origin, criterion):
        for (sev, thr), color in zip(self.limits.levels(criterion), LEVEL_COLORS):
            label = "critical" if sev == SEVERITY_CRITICAL else "warning"
            self.rec.log(f"{origin}/limit_{label}", rr.SeriesLines(
                colors=[color], widths=[2.5], names=[f"{label} {level_text(criterion, thr)}"]), static=True)

    def _style(self, entity, names, colors, widths=None):
        """Log an entity's series style (rr.SeriesLines) once, the first time it has data: built only then (an
        rr.SeriesLines per sensor message was two thirds of the time a demo's .rrd took to write)."""
        if entity not in self.sensor_series:
            self.sensor_series.add(entity)
            self.rec.log(entity, rr.SeriesLines(names=names, colors=colors, widths=widths), static=True)

    # --- input ------------------------------------------------------------------------------
    def _append(self, entity, t, values):
        times, vals = self.buffers.setdefault(entity, ([], []))
        times.append(t)
        vals.append(values)

    def _wheels(self, entity, t, values):
        """Eight wheel values into the entity's left and right series."""
        self._append(f"/plots/{entity}/left", t, values[0::2])
        self._append(f"/plots/{entity}/right", t, values[1::2])

    def _line(self, entity, t, value):
        """A level line: two points per flushed batch (its first and last time) are enough."""
        times, vals = self.buffers.setdefault(entity, ([], []))
        if len(times) < 2:
            times.append(t)
            vals.append(value)
        else:
            times[1] = t

    def _limits(self, entity, criterion, t, scale=1.0, origin="/plots"):
        """Threshold lines of a criterion's levels."""
        for sev, thr in self.limits.levels(criterion):
            self._line(f"{origin}/{entity}/limit_{'critical' if sev == SEVERITY_CRITICAL else 'warning'}", t,
                       thr * scale)

    def _tick(self):
        self.pending += 1
        if self.pending >= self.flush_every:
            self.flush()

    def on_states(self, msg):
        t = seconds(msg.header.stamp)
        self.track[0].append(t)
        self.track[1].append(float(msg.track_position))
        attack = _arr(msg.attack_angle)
        self._append(f"/plots/{ATTACK}/values", t, attack * 1e3)
        # its 0.06 rad line would flatten attack angles of a few mrad: drawn once they reach half of it
        self.attack_limit_shown |= bool(abs(attack[0]) >= 0.5 * self.limits.attack_angle)
        if self.attack_limit_shown:
            self._limits(ATTACK, "attack_angle", t, 1e3)
        lift = _arr(msg.wheel_lift)
        self._wheels("wheel_lift_mm", t, lift * 1e3)
        self._limits("wheel_lift_mm", "wheel_lift", t, 1e3)
        if t - self.last_scene >= self.scene_period - 1e-9:
            self.last_scene = t
            self._scene(t, msg, lift)
        self._tick()

    def on_forces(self, msg):
        t = seconds(msg.header.stamp)
        self.forces = msg
        self._wheels("derailment_coefficient", t, _arr(msg.derailment_coefficient))
        self._limits("derailment_coefficient", "derailment_coefficient", t)
        self._wheels("unloading_ratio", t, unloading_ratio(_arr(msg.vertical_force), self.limits.static_wheel_load))
        self._limits("unloading_ratio", "wheel_unloading", t)
        self._wheels("lateral_force_kN", t, _arr(msg.lateral_force) * 1e-3)
        self._wheels("vertical_force_kN", t, _arr(msg.vertical_force) * 1e-3)
        for column, values in zip(self.wheel_loads, (t, _arr(msg.vertical_force), _arr(msg.lateral_force))):
            column.append(values)

    def on_status(self, msg):
        self.status = msg
        if msg.curvature != 0.0:
            self.curve_sign = math.copysign(1.0, msg.curvature)
        self._append("/plots/speed_kmh", seconds(msg.header.stamp), float(msg.speed) * 3.6)

    def on_alert(self, alert, signals="ground_truth"):
        """An Alert message into the alerts' log, marked with the monitor's signals (as the demo prints it)."""
        a = m.alert_dict(alert)
        self._set_time(a["time_s"], a["track_position"])
        level = "ERROR" if a["severity"] == SEVERITY_CRITICAL else "WARN"
        self.rec.log("/alerts", rr.TextLog(f"[{signals}] {_place(a['time_s'], a['track_position'])}, "
                                           f"{a['speed'] * 3.6:.1f} km/h: {a['message']}", level=level))

    def on_onboard_alert(self, alert):
        """A measured-mode monitor's alert (/railderail/onboard_alerts)."""
        self.on_alert(alert, "measured")

    def on_brake(self, msg):
        """A speed supervision's emergency brake command (railderail_msgs/BrakeCommand) in the alerts' log."""
        t = seconds(msg.header.stamp)
        self._set_time(t, msg.track_position)
        self.rec.log("/alerts", rr.TextLog(
            f"{_place(t, msg.track_position)}: EMERGENCY BRAKE commanded at {msg.speed * 3.6:.1f} km/h, held down to "
            f"{msg.release_speed * 3.6:.1f} km/h ({msg.reason})", level="ERROR"))

    def on_supervision(self, msg):
        """What the speed supervision supervises (/railderail/supervision): the planning area's lines."""
        self.planning.on_setup(msg)

    def on_supervision_status(self, msg):
        """The speed supervision at a sample (/railderail/supervision_status); the first adds its tab."""
        if self.planning.on_status(msg) and self.sink:
            self.rec.send_blueprint(self.blueprint(), make_active=True, make_default=True)
        self._tick()

    def on_derailment(self, event):
        d = m.derailment_dict(event)
        self.derailed_at = d["time_s"]
        self._set_time(d["time_s"], d["track_position_m"])
        self.rec.log("/alerts", rr.TextLog(
            f"{_place(d['time_s'], d['track_position_m'])}: DERAILED: wheelset {d['wheelset']} {d['wheel_side']} "
            f"({d['rail_side']} rail), {d['mechanism'].replace('_', ' ')}, {d['speed_kmh']:.1f} km/h",
            level="CRITICAL"))
        if self.final_entry is not None:
            self._log_final(*self.final_entry)

    def on_final_status(self, msg):
        entry = (seconds(msg.header.stamp), msg.track_position, f"run stopped: {msg.message}")
        if msg.state == m.msgs.VehicleStatus.STATE_DERAILED and self.derailed_at is None:
            self.final_entry = entry        # logged after the DERAILED line, whichever message comes first
        else:
            self._log_final(*entry)

    def _log_final(self, t, position, text):
        if self.derailed_at is not None:    # the log is sorted by time: after the derailment
            t = max(t, self.derailed_at + 1e-6)
        self._set_time(t, position)
        self.rec.log("/alerts", rr.TextLog(text, level="INFO"))
        self.final_entry = None

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
        lift_level = [self._level("wheel_lift", x) for x in lift]
        for w in range(4):
            b["ws_t"][w].append([STATIONS[w], ex * y[w], WHEEL_RADIUS + ex * z[w]])
            b["ws_q"][w].append(_quat_xz(ex * roll[w], ex * yaw[w]))
            for k in (2 * w, 2 * w + 1):
                b["ws_c"][w].append((GREEN, ORANGE, RED)[lift_level[k]])
            b["ws_c"][w].append((60, 60, 60))
        f = self.forces
        count = 0
        if f is not None:
            qp = _arr(f.derailment_coefficient)
            unloading = unloading_ratio(_arr(f.vertical_force), self.limits.static_wheel_load)
            derailed = self.derailed_at is not None and t >= self.derailed_at
            for k in range(8):
                if f.contact_count[k] == 0:
                    continue
                side = 1.0 if k % 2 == 0 else -1.0
                w = k // 2
                b["patch_c"].append([STATIONS[w], side * (RAIL_Y + f.contact_position[k]) + ex * y[w], 0.005])
                b["patch_h"].append([5.0 * f.patch_length[k], 5.0 * f.patch_width[k], 0.004])
                # the worst level the wheel has reached now, by any criterion; every patch red once derailed
                level = 2 if derailed else max(lift_level[k], self._level("derailment_coefficient", qp[k]),
                                                self._level("wheel_unloading", unloading[k]))
                b["patch_col"].append((GREEN, ORANGE, RED)[level])
                count += 1
        b["patch_n"].append(count)

    def _set_time(self, t, position):
        """The time and the place of what is logged next (an entry of the alerts' log)."""
        self.rec.set_time(TIMELINE, duration=t)
        self.rec.set_time(POSITION, sequence=int(round(position * 1e3)))

    def _index(self, times):
        """The index columns of samples at `times`: simulation time and, once wheelset states have come, the
        track position at those times (interpolated between the states' samples, held beyond them)."""
        t = np.asarray(times, dtype=float)
        index = [rr.TimeColumn(TIMELINE, duration=t)]
        if self.track[0]:
            if self.track_arrays is None or len(self.track_arrays[0]) != len(self.track[0]):  # once per flush
                self.track_arrays = tuple(np.asarray(x) for x in self.track)
            s = np.interp(t, *self.track_arrays)
            index.append(rr.TimeColumn(POSITION, sequence=np.round(s * 1e3).astype(np.int64)))
        return index

    def _level(self, criterion, value):
        """0 below a criterion's levels, 1 at or above its first, 2 at or above its second."""
        return min(sum(value >= x for _, x in self.limits.levels(criterion)), 2)

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
        index = self._index(b["time"])
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
        self._estimate(final=self.closed)
        for entity, (times, values) in self.buffers.items():
            if not times:
                continue
            self.rec.send_columns(entity, indexes=self._index(times),
                                  columns=rr.Scalars.columns(scalars=np.asarray(values, dtype=float)))
            times.clear()
            values.clear()
        self._flush_scene()
        self.pending = 0

    def close(self):
        if not self.closed:
            self.closed = True
            if self.final_entry is not None:      # the derailment event never came
                self._log_final(*self.final_entry)
            self.flush()
            self.rec.flush()
            self.rec.disconnect()
