"""The signals an assessment reads, from a run's output arrays (`vehicle.simulate.output_arrays`, the
`.npz` of `railderail simulate --out`, docs/output-format.md) or from any other source that fills them
(a recording: railderail_monitor.recording.assess).

Forces per wheel in track axes, as `contact-case` reports a wheel's force on its rail: Y lateral, + left
(the left wheel's Q toward its rail's field side is + left, the right wheel's is - left), Q vertical, + down.
Accelerations are what ideal accelerometers read (the specific force, +g up at rest), in the body's own axes
(x forward, y left, z up), at the measuring points of EN 14363 and EN 12299 (`MEASURING_POINTS`).
"""
from __future__ import annotations

from dataclasses import dataclass, field
import json
from pathlib import Path

import numpy as np

from ..parameters import VehicleParameters, vehicle_parameters

# where the accelerometers sit: car-body floor over each bogie centre and in the middle (EN 14363's
# ydd*, zdd* over the bogies; EN 12299's floor positions), bogie frame over each wheelset (EN 14363's ydd+)
FLOOR_HEIGHT = 1.26          # m above the rail top; A: the Velaro's floor height as commonly quoted, not
#                              read in a datasheet (moves the lateral reading by roll acceleration x 0.26 m)
FLOOR_PLACES = ("front", "centre", "rear")
REQUIRED = ("time", "position", "speed", "section", "curvature", "lateral_force", "vertical_force")


@dataclass
class RunSignals:
    """A run's signals on its time axis (uniformly sampled). n samples; wheels [ws0 left, ws0 right, ...]."""
    time: np.ndarray                    # (n,) s
    position: np.ndarray                # (n,) m, the car-body centre along the line
    speed: np.ndarray                   # (n,) m/s
    section: np.ndarray                 # (n,) 0 straight, 1 transition, 2 circular curve (car-body centre)
    curvature: np.ndarray               # (n,) 1/m, + left
    lateral_force: np.ndarray           # (n, 8) N, Y of each wheel on its rail, track axes, + left
    vertical_force: np.ndarray          # (n, 8) N, Q of each wheel on its rail, + down
    wheelset_stations: np.ndarray       # (4,) m ahead of the car-body centre
    bogie_stations: np.ndarray          # (2,) m ahead of the car-body centre
    static_wheel_load: float            # N, Q0
    bogie_mass: float                   # kg, a bogie with its wheelsets (EN 14363's M_b)
    uncompensated_acceleration: np.ndarray = None   # (n,) m/s^2, in the track plane, + outward, or None
    floor: dict = None                  # place -> (n, 3) m/s^2 car-body floor (x, y, z body axes), or None
    bogie_frame: np.ndarray = None      # (n, 4) m/s^2 bogie frame's lateral reading over each wheelset, or None
    source: str = ""
    notes: list = field(default_factory=list)

    @property
    def rate(self):
        """Sampling rate (Hz)."""
        return (len(self.time) - 1) / (self.time[-1] - self.time[0])

    def after(self, position_m):
        """These signals from the first sample whose car-body position reaches position_m (m): a run's
        start-up left out."""
        k = int(np.searchsorted(self.position, position_m, "left"))
        if len(self.position) - k < 3:
            raise ValueError(f"{self.source or 'the run'} ends at {self.position[-1]:.1f} m, before the assessment's "
                             f"start at {position_m:g} m")
        cut = {name: (value[k:] if isinstance(value, np.ndarray) and value.shape[:1] == self.time.shape else value)
               for name, value in vars(self).items()}
        cut["floor"] = None if self.floor is None else {p: a[k:] for p, a in self.floor.items()}
        return RunSignals(**cut)

    def validated(self):
        """self, or ValueError naming what cannot be assessed (too few samples, uneven sampling, the car
        standing or running backwards)."""
        n = len(self.time)
        if n < 3:
            raise ValueError(f"{self.source or 'the run'} has {n} samples: at least 3 are needed")
        dt = np.diff(self.time)
        if np.ptp(dt) > 1e-6 * np.mean(dt) + 1e-9:
            raise ValueError(f"{self.source or 'the run'}: the samples are not evenly spaced in time "
                             f"({dt.min():.6g}-{dt.max():.6g} s); the filters need one sampling rate")
        if np.any(np.diff(self.position) <= 0.0):
            raise ValueError(f"{self.source or 'the run'}: the car-body position does not increase at every "
                             "sample (the windows are in distance, the car must move forward)")
        return self


def stations(vehicle: VehicleParameters):
    """(wheelset stations (4,), bogie stations (2,)), m ahead of the car-body centre."""
    a, b = vehicle.bogie_semi_distance, vehicle.wheelbase_semi
    return np.array([a + b, a - b, -a + b, -a - b]), np.array([a, -a])


def track_axes_lateral(q_to_field_side):
    """Y in track axes (+ left) of the wheels' lateral forces Q (+ toward their rail's field side):
    the left rail's field side is to the left, the right rail's to the right."""
    y = np.array(q_to_field_side, dtype=float)
    y[:, 1::2] *= -1.0
    return y


def from_arrays(arrays, vehicle: VehicleParameters = None, source="run"):
    """RunSignals of a run's output arrays (`output_arrays` names; `body_motion` gives the accelerations,
    without it the accelerations are None and a note says so)."""
    from ..vehicle.layout import Body
    from ..vehicle.motion import point_motion

    vehicle = vehicle or vehicle_parameters()
    missing = [name for name in REQUIRED if name not in arrays]
    if missing:
        raise ValueError(f"{source} has no {', '.join(missing)}: an assessment needs "
                         f"{', '.join(REQUIRED)} (docs/output-format.md)")
    ws, bg = stations(vehicle)
    floor = frame = None
    notes = []
    if "body_motion" in arrays and "body_states" in arrays:
        z = FLOOR_HEIGHT - vehicle.car_body_cog_height
        floor = {place: point_motion(arrays, Body.car_body, (x, 0.0, z))[0]
                 for place, x in zip(FLOOR_PLACES, (bg[0], 0.0, bg[1]))}
        frame = np.stack([point_motion(arrays, Body.front_bogie if i < 2 else Body.rear_bogie,
                                       (ws[i] - bg[0 if i < 2 else 1], 0.0, 0.0))[0][:, 1] for i in range(4)], -1)
    else:
        notes.append(f"{source} has no body_motion: the accelerations (car body, bogie frames, comfort) are "
                     "not assessed")
    return RunSignals(time=np.asarray(arrays["time"], float), position=np.asarray(arrays["position"], float),
                      speed=np.asarray(arrays["speed"], float), section=np.asarray(arrays["section"]).astype(int),
                      curvature=np.asarray(arrays["curvature"], float),
                      uncompensated_acceleration=(np.asarray(arrays["uncompensated_acceleration"], float)
                                                  if "uncompensated_acceleration" in arrays else None),
                      lateral_force=track_axes_lateral(arrays["lateral_force"]),
                      vertical_force=np.asarray(arrays["vertical_force"], float),
                      wheelset_stations=ws, bogie_stations=bg, static_wheel_load=vehicle.static_wheel_load,
                      bogie_mass=vehicle.bogie_frame_mass + 2.0 * vehicle.wheelset_mass,
                      floor=floor, bogie_frame=frame, source=source, notes=notes).validated()


ZIP_MAGIC = b"PK\x03\x04"


def from_npz(path, vehicle_set=None):
    """RunSignals of a `railderail simulate --out` file; the vehicle parameter set from its metadata unless
    `vehicle_set` is given (ValueError naming the file and what it lacks)."""
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such file")
    with open(path, "rb") as f:
        head = f.read(4)
    if head != ZIP_MAGIC:           # numpy would speak of pickles about any other file
        raise ValueError(f"{path} is not a .npz archive of `railderail simulate --out` (a .npz is a zip file; "
                         f"this one starts with {head!r})")
    try:
        data = np.load(path, allow_pickle=False)
        arrays = {name: data[name] for name in data.files}
    except (OSError, ValueError) as error:
        raise ValueError(f"{path} is not a readable .npz file ({error})") from None
    meta = json.loads(str(arrays.pop("metadata"))) if "metadata" in arrays else {}
    return from_arrays(arrays, vehicle_parameters(vehicle_set or meta.get("vehicle_set", "hs19")), str(path))
