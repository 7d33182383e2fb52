"""Each running gear's load per side, its unloading ratio and its lateral force from the on-board sensors
only: a quasi-static roll balance of each bogie (frame and wheelsets) under the car body.

Why a balance and not a Kalman filter: every term is measured or a design value (masses, heights,
spacings, the anti-roll bar's stiffness), the balance has no state to diverge and no tuning, and its error
is bounded term by term (docs/onboard-criteria.md). Methods of the literature it follows: the indirect
measurement of wheel-rail forces as suspension forces plus inertial forces (review, Adv. Mech. Eng. 2023,
doi:10.1177/16878132231158991, A for the abstract); the inverse wagon models of Xia, Cole and Wolfs (body
accelerations to contact forces, A for the abstract).

Per bogie j (front 0, rear 1), track axes, y left, z up, moments about the track centre line at rail level,
body rotational inertia neglected (quasi-static):
  car body, over the bogie:  F_j = m_c/2 (f_front + f_rear)/2 +- I_z (f_front - f_rear) / (4 l^2)
                             (the floor accelerometers over the bogies, rotated into the track plane by the
                             car body's roll to its bogie from the air-spring heights)
  lateral:                   Y_j = m_f f_frame + 2 m_w f_wheelset + F_j            (rails on the wheels)
  vertical:                  P_L + P_R = F_sL + F_sR + (m_f + 2 m_w) f_z,frame
  roll:                      b0 (P_L - P_R) = b_s (F_sL - F_sR) - h_s F_j - k_bar phi
                                              - h_f m_f f_frame - 2 r0 m_w f_wheelset
F_s: an air spring's force, its pressure times its effective area, plus its emergency spring's force from
the deflection beyond the clearance (the pressure does not carry it); phi: the car body's roll to the bogie,
(d_R - d_L) / 2 b_s; f_wheelset: the frame's lateral reading below the axle-box sensors' AC-coupling corner
plus the axle boxes' mean reading above it (complementary first-order filters at that corner).
With a wind given (`GivenWind`: measured on the train or the line, or a forecast), the car body's
aerodynamic side force F_y and yawing moment M_z (the simulator's coefficients, loads.wind.car_body_load, at
the relative wind of the odometer's speed) are taken out of the floor accelerometers' reading, which is the
secondary's force plus the wind's:  F_j -= F_y/2 +- M_z/(2 l). The air springs' pressures carry the wind's
lift and rolling moment already. Without a wind given the estimate is blind to it: a steady crosswind's
force is balanced by the secondary's and the floors read about zero (docs/onboard-criteria.md).
Assumptions: the bogie frame does not roll on its primary springs (a few mrad); the secondary lateral force
acts at the air springs' height (the lateral bump stop, 0.3 m lower, carries part of it once touched); the
wind's load on the car body only, as the simulator applies it; the two wheelsets of a bogie share its side's
load equally (frame warp not observable).
"""
from __future__ import annotations

import numpy as np
from scipy import signal as sps

from dataclasses import dataclass

from railderail_sim.parameters import AerodynamicParameters
from railderail_sim.sensors.instruments import INSTRUMENTS
from railderail_sim.vehicle.layout import RUNNING_GEARS

from .criteria import SosFilter

# m: half the distance of the rolling circles, the wheel loads' lever arm (TB449: 1493 mm, parameters.SOURCES)
CONTACT_SEMI_DISTANCE = 0.7465
BOGIES = ("front", "rear")


AXLE_BOXES = tuple(tuple(f"axle_box_{w}_{side}" for w in gear for side in ("left", "right")) for gear in RUNNING_GEARS)
# the sensor units the balance reads: the air springs, the floors over the bogies, the frames, the axle boxes
INPUTS = (("air_springs",) + tuple(f"car_body_{g}" for g in BOGIES) + tuple(f"bogie_{g}_frame" for g in BOGIES)
          + sum(AXLE_BOXES, ()))
TIME_BASE = "car_body_centre"


@dataclass(frozen=True)
class GivenWind:
    """A wind the estimator is told: at each of `time` (s, the sensors' clock) its speed (m/s) and where it
    comes from (rad, relative to the track, + from the left, 0 a head wind), each (n,) or a number for all;
    held from each time to the next (a zero-order hold, as any input); the car body's coefficients
    `aerodynamics` (the simulator's by default)."""
    time: object
    speed: object
    direction: object
    aerodynamics: AerodynamicParameters = AerodynamicParameters()

    def load(self, time, train_speed):
        """(n, 2) the car body's aerodynamic side force F_y (N, + left) and yawing moment M_z (N m) at the
        stamps, at the train's speed (m/s) there."""
        from railderail_sim.loads.wind import car_body_load
        t = np.atleast_1d(np.asarray(self.time, dtype=float))
        speed, direction = (np.broadcast_to(np.asarray(x, dtype=float), t.shape) for x in (self.speed, self.direction))
        k = np.maximum(np.searchsorted(t, time, "right") - 1, 0)
        load = car_body_load(self.aerodynamics, speed[k], direction[k], train_speed)
        return load[:, [2, 6]]


def hold(source_time, values, time):
    """The last sample of a stream at or before each time (a zero-order hold: causal; each time at or after
    the stream's first sample)."""
    return np.asarray(values)[np.searchsorted(source_time, time, "right") - 1]


def held_inputs(a, time):
    """{unit: its signals held at `time`} of INPUTS from `sensor_*` arrays: the air springs' (deflection,
    pressure), the others' acceleration (n, 3)."""
    springs_t = a["sensor_air_springs_time"]
    out = {"air_springs": (hold(springs_t, a["sensor_air_springs_deflection"], time),
                           hold(springs_t, a["sensor_air_springs_pressure"], time))}
    for unit in INPUTS[1:]:
        out[unit] = hold(a[f"sensor_{unit}_time"], a[f"sensor_{unit}_acceleration"], time)
    return out


class RollBalance:
    """The balance over the inputs held at successive stamps of a stream at rate_hz, fed in chunks: the
    axle boxes' complementary filter carries its state (the same output whatever the chunks). Both bogies
    at once, as columns [front, rear]: half the array calls of a loop over them (a stamp at a time, the
    calls are its cost)."""

    def __init__(self, vehicle, effective_area, axle_box_corner_hz=INSTRUMENTS["iepe_axle_box"].high_pass_hz,
                 rate_hz=200.0):
        self.vehicle, self.effective_area = vehicle, effective_area
        self.low = SosFilter(sps.butter(1, axle_box_corner_hz, fs=rate_hz, output="sos"))

    def __call__(self, h, aero=None):
        """{side_load (n, 4) N [front left, front right, rear left, rear right], unloading (n, 4),
        lateral_force (n, 2) N, derailment_coefficient (n, 4)} from `held_inputs` at n stamps; `aero`: (n, 2)
        the car body's aerodynamic side force and yawing moment there (`GivenWind.load`), if known."""
        vp = self.vehicle
        d, pressure = h["air_springs"]
        force = pressure * self.effective_area
        force = force + vp.air_spring_emergency_stiffness * np.maximum(d - vp.air_spring_emergency_clearance, 0.0)
        left, right = force[:, 0::2], force[:, 1::2]                  # (n, 2): [front, rear]
        b_s, l = vp.air_spring_semi_spacing, vp.bogie_semi_distance
        roll = (d[:, 1::2] - d[:, 0::2]) / (2.0 * b_s)
        floor = np.stack([h[f"car_body_{g}"] for g in BOGIES], axis=1)             # (n, 2, 3)
        floor = floor[:, :, 1] * np.cos(roll) - floor[:, :, 2] * np.sin(roll)    # the track plane's lateral
        mean = 0.5 * (floor[:, 0] + floor[:, 1])
        turn = vp.car_body_yaw_inertia * (floor[:, 0] - floor[:, 1]) / (4.0 * l * l)
        body = np.stack([0.5 * vp.car_body_mass * mean + turn, 0.5 * vp.car_body_mass * mean - turn], axis=1)
        if aero is not None:           # the floors read the secondary's force and the wind's: the wind's out
            yaw = aero[:, 1] / (2.0 * l)
            body = body - np.stack([0.5 * aero[:, 0] + yaw, 0.5 * aero[:, 0] - yaw], axis=1)
        m_f, m_w, p0 = vp.bogie_frame_mass, vp.wheelset_mass, vp.static_wheel_load
        frame = np.stack([h[f"bogie_{g}_frame"] for g in BOGIES], axis=1)          # (n, 2, 3)
        fy = frame[:, :, 1]
        boxes = [np.stack([h[gear[k]][:, 1] for gear in AXLE_BOXES], axis=1) for k in range(4)]
        wheelset = self.low(fy) + (boxes[0] + boxes[1] + boxes[2] + boxes[3]) / 4.0
        lateral = m_f * fy + 2.0 * m_w * wheelset + body
        total = left + right + (m_f + 2.0 * m_w) * frame[:, :, 2]
        moment = (b_s * (left - right) - vp.secondary_height * body - vp.anti_roll_stiffness * roll
                  - vp.bogie_frame_cog_height * m_f * fy - 2.0 * vp.rolling_radius * m_w * wheelset)
        diff = moment / CONTACT_SEMI_DISTANCE
        side_load = np.stack([0.5 * (total + diff), 0.5 * (total - diff)], axis=2).reshape(len(fy), 4)
        return dict(side_load=side_load, unloading=1.0 - side_load / (2.0 * p0), lateral_force=lateral,
                    derailment_coefficient=side_ratios(lateral, side_load))


def estimate(a, vehicle, effective_area, axle_box_corner_hz=INSTRUMENTS["iepe_axle_box"].high_pass_hz, rate_hz=None,
             wind: GivenWind = None):
    """{time (n,), side_load (n, 4) N [front left, front right, rear left, rear right], unloading (n, 4) the
    mean dP/P0 of a running gear's two wheels on one side, lateral_force (n, 2) N of the rails on each bogie's
    wheels (+ left), derailment_coefficient (n, 4): the gear's lateral force toward a side's field side over
    that side's load} from the `sensor_*` arrays of a run (docs/output-format.md), at the car-body centre's
    stamps from the first at which every input has a sample; rate_hz: that sensor's sample rate (default:
    from its stamps); `wind`: a GivenWind, its load at the odometer's speed (`sensor_odometer_speed` held)."""
    t = np.asarray(a[f"sensor_{TIME_BASE}_time"], dtype=float)
    rate = rate_hz or 1.0 / float(np.median(np.diff(t)))
    t = t[t >= max(a[f"sensor_{unit}_time"][0] for unit in INPUTS)]
    aero = None if wind is None else wind.load(t, hold(a["sensor_odometer_time"], a["sensor_odometer_speed"], t))
    out = RollBalance(vehicle, effective_area, axle_box_corner_hz, rate)(held_inputs(a, t), aero)
    return dict(time=t, **out)


def side_ratios(lateral, side_load):
    """(n, 4) each side's ratio: the gear's lateral force pushing that rail outward over the side's load."""
    y = np.repeat(lateral, 2, axis=1) * np.tile([-1.0, 1.0], lateral.shape[1])
    return y / np.maximum(side_load, 1.0)


def truth(a, vehicle):
    """The same quantities from the simulator's wheel forces (P vertical_force, Q lateral_force + toward each
    rail's field side), on its own clock."""
    p, q = np.asarray(a["vertical_force"]), np.asarray(a["lateral_force"])
    side = np.stack([p[:, 2 * w0 + s] + p[:, 2 * w1 + s] for w0, w1 in RUNNING_GEARS for s in (0, 1)], axis=1)
    lateral = np.stack([sum(q[:, 2 * w + 1] - q[:, 2 * w] for w in gear) for gear in RUNNING_GEARS], axis=1)
    return dict(time=np.asarray(a["time"]), side_load=side, unloading=1.0 - side / (2.0 * vehicle.static_wheel_load),
                lateral_force=lateral, derailment_coefficient=side_ratios(lateral, side))


# the places of each estimated quantity: a running gear's side, or a bogie
PLACES = {"unloading": tuple(f"{b}_{side}" for b in BOGIES for side in ("left", "right")),
          "lateral_force": BOGIES,
          "derailment_coefficient": tuple(f"{b}_{side}" for b in BOGIES for side in ("left", "right"))}


def estimator_error(a, vehicle, effective_area, settle_s=1.0, wind: GivenWind = None, truth_vehicle=None):
    """{quantity: {place: {bias, rms, p95}}} of the estimate against the truth (at the estimate's stamps, so
    the sensors' latency counts as error) per place (PLACES: the sides' errors have opposite signs and are
    never pooled), after settle_s of the run (its start-up); p95 is the 95th percentile of the absolute error.
    `vehicle` is the estimator's model of the car, `truth_vehicle` the simulated car (default the same: a
    model mismatch is the two differing); `wind`: a GivenWind told to the estimator."""
    est, tru = estimate(a, vehicle, effective_area, wind=wind), truth(a, truth_vehicle or vehicle)
    keep = est["time"] >= tru["time"][0] + settle_s
    out = {}
    for name, places in PLACES.items():
        ref = np.stack([np.interp(est["time"], tru["time"], c) for c in tru[name].T], axis=1)
        e = (est[name] - ref)[keep]
        out[name] = {place: dict(bias=float(np.mean(e[:, k])), rms=float(np.sqrt(np.mean(e[:, k] ** 2))),
                                 p95=float(np.percentile(np.abs(e[:, k]), 95.0))) for k, place in enumerate(places)}
    return out
