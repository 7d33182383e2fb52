"""Friendly API over the vehicle core: scenarios, speed profiles, the stepper object and `simulate`.

    from railderail_sim.vehicle import Scenario, simulate
    result = simulate(Scenario(radius=1000.0, speed_kmh=300.0))
    result.summary()

`Simulation` is the stepper: `Simulation(scenario).advance(duration)` runs the numba core for a given
simulated time into preallocated buffers; `simulate` is the same stepper run to the end of the line.
"""
import copy
from dataclasses import dataclass, field
import math
import operator

import numpy as np

from .. import jsonout
from ..atomic import atomic_write
from ..jit import compiled_entry
from ..contact.layout import GeometryHeader, Wheel
from ..loads.wind import Wind, pack_aero
from ..parameters import (KMH, RADIUS_RANGE, SPEED_RANGE_KMH, AerodynamicParameters, ContactParameters,
                          ElasticTrackParameters, TrackParameters, VehicleParameters, vehicle_parameters)
from ..ranges import check_range
from ..track import alignment
from ..track.irregularity import Irregularity
from ..track.layout import N_RAIL_DOF, ElasticTrack, RailDof
from ..track.rails import rail_deviation
from . import integrator as itg
from .assemble import build_model, failed_elements, static_contact
from .integrator import StepControl, Stepper
from . import run_end
from .run_end import Event
from .layout import N_DOF, N_OUT, N_STATE, N_WHEEL, WHEELSETS, Body, BodyTable, Dof, OutputRow, State, WheelsetOutput

RTOL = 1.0e-7                            # relative error per step; see docs/vehicle-model.md (tolerance study)
ATOL_DISPLACEMENT = 1.0e-8               # m and rad per step; velocities and rates get 100x this in 1/s
MAX_STEP = 2.0e-3                        # s, below the stability limit of the 200 Hz contact modes
MIN_STEP = 1.0e-8                        # s; a step below this means the run has diverged
MECHANISMS = {run_end.MECH_FLANGE_CLIMBING: "flange_climbing", run_end.MECH_WHEEL_UNLOADING: "wheel_unloading"}
STATUS = {itg.RUNNING: "running", itg.DERAILED: "derailed", itg.DIVERGED: "diverged",
          itg.END_OF_LINE: "finished"}


class SimulationDiverged(RuntimeError):
    """The integration ran away: raised with the time, track position and offending state."""


def constant_speed(speed_kmh):
    """Speed table (s, v in m/s) for a constant speed."""
    check_range("speed", speed_kmh, *SPEED_RANGE_KMH, "km/h")
    v = speed_kmh * KMH
    return np.array([[0.0, v], [1.0, v]])


def staircase_speed(start_kmh, step_kmh, first_change_m, hold_m, acceleration, top_kmh):
    """The progressive trial's staircase (Yu 2022, Fig. 3) as a speed table over distance.

    Constant `start_kmh` up to `first_change_m`; then repeatedly accelerate by `step_kmh` at
    `acceleration` (m/s^2) and hold for `hold_m`, up to `top_kmh`. Speed is linear in distance during
    each acceleration (distance (v1^2 - v0^2) / 2a).
    """
    check_range("start speed", start_kmh, *SPEED_RANGE_KMH, "km/h")
    check_range("top speed", top_kmh, start_kmh, SPEED_RANGE_KMH[1], "km/h")
    if step_kmh <= 0 or hold_m <= 0 or acceleration <= 0:
        raise ValueError("speed step, hold length and acceleration must be positive")
    pts = [(0.0, start_kmh * KMH), (first_change_m, start_kmh * KMH)]
    v = start_kmh
    s = first_change_m
    while v < top_kmh - 1e-9:
        v1 = min(v + step_kmh, top_kmh)
        s += ((v1 * KMH) ** 2 - (v * KMH) ** 2) / (2.0 * acceleration)
        pts.append((s, v1 * KMH))
        s += hold_m
        pts.append((s, v1 * KMH))
        v = v1
    return np.array(pts)


@dataclass(frozen=True)
class Scenario:
    """A run: vehicle, track, contact, speed profile and numerical settings (SI inside)."""
    vehicle: VehicleParameters = field(default_factory=vehicle_parameters)
    track: TrackParameters = field(default_factory=TrackParameters)
    contact: ContactParameters = field(default_factory=ContactParameters)
    speed_table: np.ndarray = field(default_factory=lambda: constant_speed(300.0))
    irregularity: Irregularity = None       # the rails' deviations (track.irregularity); None: ideal rails
    track_model: str = "rigid"              # "rigid" or "elastic" (co-running rails, track.elastic)
    elastic_track: ElasticTrackParameters = field(default_factory=ElasticTrackParameters)
    wind: Wind = None                       # the wind (loads.wind); None: still air
    aerodynamics: AerodynamicParameters = field(default_factory=AerodynamicParameters)
    faults: tuple = ()                      # suspension faults, "NAME@LOCATION" (vehicle.assemble.FAULT_NAMES)
    rtol: float = RTOL
    atol: float = ATOL_DISPLACEMENT
    output_rate: float = 200.0              # Hz
    start_position: float = 0.0             # m, car-body centre
    end_position: float = math.nan          # m, default: end of the line
    stop_on_derailment: bool = True
    lift_tolerance: float = 1.0e-3          # m, see run_end.check_derailment

    def validated(self):
        if not math.isinf(self.track.radius):
            check_range("curve radius", self.track.radius, *RADIUS_RANGE, "m")
        if not (1e-10 <= self.rtol <= 1e-2) or not (1e-12 <= self.atol <= 1e-3):
            raise ValueError(f"tolerances rtol {self.rtol:g} / atol {self.atol:g} are outside 1e-10-1e-2 / "
                             "1e-12-1e-3")
        if not (1.0 <= self.output_rate <= 5000.0):
            raise ValueError(f"output rate {self.output_rate:g} Hz is outside 1-5000 Hz")
        if self.wind is not None:
            self.wind.validated()
        failed_elements(self.faults)
        vmin = float(np.min(self.speed_table[:, 1]))
        vmax = float(np.max(self.speed_table[:, 1]))
        check_range("speed", vmin / KMH, *SPEED_RANGE_KMH, "km/h")
        check_range("speed", vmax / KMH, *SPEED_RANGE_KMH, "km/h")
        return self

    def simulated_duration(self):
        """Simulated time (s) from the start to the end position at the speed table's speeds, if nothing
        stops the run earlier: the integral of ds / v(s), v linear in s between the table's points (exact:
        ds ln(v1 / v0) / (v1 - v0) on each piece)."""
        end = self.end_position if not math.isnan(self.end_position) else self.track.line_length
        table = self.speed_table
        s = np.unique(np.concatenate([[self.start_position, end],
                                      table[(table[:, 0] > self.start_position) & (table[:, 0] < end), 0]]))
        v = np.interp(s, table[:, 0], table[:, 1])
        v0, v1, ds = v[:-1], v[1:], np.diff(s)
        ramp = np.abs(v1 - v0) > 1e-9 * v0
        piece = np.where(ramp, ds * np.log(v1 / v0) / np.where(ramp, v1 - v0, 1.0), ds / v0)
        return float(np.sum(piece))


def scenario(radius=1000.0, speed_kmh=300.0, vehicle_set="hs19", contact_model="hertz", creep_model="she",
             wheel_profile="lm", friction=0.3, direction=1, **kwargs):
    """A Scenario from the usual knobs (radius in m, speed in km/h)."""
    check_range("curve radius", radius, *RADIUS_RANGE, "m")
    return Scenario(vehicle=vehicle_parameters(vehicle_set),
                    track=TrackParameters(radius=radius, direction=direction),
                    contact=ContactParameters(normal_model=contact_model, creep_model=creep_model,
                                              wheel_profile=wheel_profile, friction_coefficient=friction),
                    speed_table=constant_speed(speed_kmh), **kwargs).validated()


def straight_track(**changes):
    """Straight track without cant (the root-locus and limit-cycle methods), Table 2 lengths."""
    return TrackParameters(radius=math.inf, cant_height=0.0, **changes)


def curve_extent(track: TrackParameters):
    """(start, end) m of a run's curve: from the start of its entry transition to the end of its exit
    transition."""
    start = track.straight_in
    return start, start + track.transition_in + track.curve_length + track.transition_out


def curve_middle(track: TrackParameters):
    """Distance along the line of the circular curve's middle (m): where an unplaced gust peaks."""
    return track.straight_in + track.transition_in + 0.5 * track.curve_length


def static_state(model):
    """Vertical displacement of the centred car at rest (rigid contact minus the Hertz approach, m) and the
    rolling radius of the centred wheel (m)."""
    z0, radius, _ = static_contact(model.cg, model.cp, model.static_wheel_load)
    return z0, radius


def set_rolling(x, speed, rolling_radius):
    """Spin every wheelset at the free-rolling rate of the centred wheel."""
    for b in WHEELSETS:
        x[State.velocities + N_DOF * b + Dof.pitch] = speed / rolling_radius


def on_the_rails(x, model, speed):
    """Put every wheelset on its rails where it starts (track.rails): shifted and turned with the mean of
    the two rails, rolled by their height difference over the rolling circles' distance, moving with them
    at `speed`; the bogies and the car body keep their places (the suspension takes up the difference in
    the first moments). Without irregularity nothing changes."""
    half = model.cg[GeometryHeader.rolling_circle_distance]
    for b in WHEELSETS:
        o, ov = State.positions + N_DOF * b, State.velocities + N_DOF * b
        sb = x[State.s] + model.bodies[b, BodyTable.station]
        yl, zl, al, cl = rail_deviation(model.rails, 0, sb)
        yr, zr, ar, cr = rail_deviation(model.rails, 1, sb)
        x[o + Dof.lateral] += 0.5 * (yl + yr)
        x[o + Dof.vertical] += 0.5 * (zl + zr)
        x[o + Dof.roll] += 0.5 * (zl - zr) / half
        x[o + Dof.yaw] += 0.5 * (al + ar)
        x[ov + Dof.lateral] += speed * 0.5 * (al + ar)
        x[ov + Dof.vertical] += speed * 0.5 * (cl + cr)
        x[ov + Dof.roll] += speed * 0.5 * (cl - cr) / half


def on_the_elastic_track(x, model):
    """Start on elastic track at its static deflection: each rail pressed down by the static wheel load and
    the whole car lowered with it (the rails' roll and lateral deflection settle in the first moments)."""
    sink = model.static_wheel_load / model.support[ElasticTrack.vertical_stiffness]
    State.split(x)["rail_deflections"][:, RailDof.vertical] = -sink
    State.split(x)["positions"][:, Dof.vertical] -= sink


class Simulation:
    """The stepper over the numba core; holds the state and all preallocated buffers. `t` is the last
    output instant; `x` the stepper's state at its own time (`Stepper.time`: at t or up to one step past
    it, the output rows being interpolated)."""

    def __init__(self, sc: Scenario, model=None):
        self.scenario = sc.validated()
        self.model = model if model is not None else build_model(sc.vehicle, sc.track, sc.contact,
                                                                 sc.lift_tolerance, sc.irregularity,
                                                                 sc.track_model, sc.elastic_track,
                                                                 pack_aero(sc.aerodynamics, sc.wind,
                                                                           curve_middle(sc.track)), sc.faults)
        self.speed_table = np.ascontiguousarray(sc.speed_table, dtype=np.float64)
        self.work = itg.workspace(self.model.cg, len(self.speed_table))
        self.x = np.zeros(N_STATE)
        z0, self.rolling_radius = static_state(self.model)
        State.split(self.x)["positions"][:, Dof.vertical] = z0
        if self.model.track_model == "elastic":
            on_the_elastic_track(self.x, self.model)
        self.x[State.s] = sc.start_position
        speed = float(np.interp(sc.start_position, self.speed_table[:, 0], self.speed_table[:, 1]))
        set_rolling(self.x, speed, self.rolling_radius)
        on_the_rails(self.x, self.model, speed)
        self.t = 0.0
        self.rows_written = 0
        line_end = alignment.end_of_line(self.model.track)
        self.control = StepControl(atol=state_tolerances(sc.atol, self.model.support), rtol=sc.rtol, h_min=MIN_STEP,
                                   h_max=MAX_STEP,
                                   s_end=line_end if math.isnan(sc.end_position) else sc.end_position,
                                   stop_on_derailment=sc.stop_on_derailment)
        self.status = itg.RUNNING
        self.event = self.work.event
        # the compiled stepper's entry point and the arguments it was resolved for (`_advance_core`)
        self._entry = None
        self._entry_args = self._model_fields = self._arrays = ()

    def fork(self):
        """An independent Simulation at this one's state, to go on from here another way (a closed loop going
        on from its open run, supervision.closed_loop): its own state, stepper, speed table and controls, the
        model and the scenario shared (the core never writes into them); it goes on as this one would, bit for
        bit (tested)."""
        twin = copy.copy(self)
        mine = {k: v for k, v in vars(self).items() if k not in ("scenario", "model") and not k.startswith("_")}
        vars(twin).update(copy.deepcopy(mine))        # one deepcopy: `event` stays the stepper's own record
        twin._entry, twin._entry_args, twin._model_fields, twin._arrays = None, (), (), ()
        return twin

    @property
    def output_dt(self):
        return 1.0 / self.scenario.output_rate

    @property
    def steps(self):
        """(accepted, rejected) integration steps so far."""
        return int(self.work.stepper[Stepper.accepted]), int(self.work.stepper[Stepper.rejected])

    def advance(self, duration, out=None):
        """Run for `duration` seconds of simulated time (rounded to whole output periods, or until it
        stops); returns the new output rows (one per output period; the first call also the start). `out`:
        zeroed rows to write them into (at least one more than the periods), whose first rows are returned."""
        if self.status != itg.RUNNING:
            return np.zeros((0, N_OUT))
        n = int(round(duration / self.output_dt))
        first = self.rows_written == 0
        if out is None:
            out = np.zeros((n + 1, N_OUT))
        elif out.shape[0] < n + 1 or out.shape[1:] != (N_OUT,):
            raise ValueError(f"rows for {n} output periods need a buffer of at least {n + 1} x {N_OUT}; "
                             f"it is {out.shape}")
        status, rows, self.t = self._advance_core(n, first, out)
        self.rows_written += rows
        self.status = status
        if status == itg.DIVERGED:
            raise SimulationDiverged(self.divergence_message())
        return out[:rows]

    def _advance_core(self, n, first, out):
        """`integrator.advance` over n output periods into `out`: through the compiled entry point kept from the
        last call (`jit.compiled_entry`) while its array and tuple arguments are the same objects (the model's
        arrays: the model and its fields; the scalars are converted to the types they had), else through
        numba's dispatcher, which compiles if need be (and is kept if it holds no entry point for the types
        after the call). A speed table of another length gets a Workspace.seen_speeds of its length first."""
        if self.speed_table.shape != self.work.seen_speeds.shape:
            self.work = self.work._replace(seen_speeds=itg.seen_speeds_for(len(self.speed_table)))
        model = self.model
        objects = (self.x, self.speed_table, self.control, self.work, model)
        fixed = (self._entry is not None and all(map(operator.is_, objects, self._entry_args))
                 and all(map(operator.is_, vars(model).values(), self._model_fields)))
        arrays = self._arrays if fixed else model.arrays
        args = (self.x, float(self.t), n * self.output_dt, float(self.output_dt), bool(first), arrays,
                self.speed_table, self.control, self.work, out)
        if fixed:
            return self._entry(*args)
        entry = compiled_entry(itg.advance, args)
        result = (entry or itg.advance)(*args)      # the dispatcher: compiles for these types, or loads them
        self._entry = entry or compiled_entry(itg.advance, args) or itg.advance
        self._entry_args, self._model_fields, self._arrays = objects, tuple(vars(model).values()), arrays
        return result

    def divergence_message(self):
        e = self.event
        idx = int(e[Event.state_index])
        where = f"the simulation diverged at t = {e[Event.time]:.4f} s, track position {e[Event.position]:.2f} m: "
        if idx < 0:
            return where + f"the step size fell to {e[Event.state_value]:.3g} s (below {MIN_STEP:g} s)"
        return (where + f"{state_name(idx)} = {e[Event.state_value]:.4g} ran away (limits: displacement "
                f"{run_end.LIMIT_DISPLACEMENT} m, angle {run_end.LIMIT_ANGLE} rad, velocity {run_end.LIMIT_VELOCITY} m/s)")

    def derailment(self):
        """The derailment event as a dict (None if the run did not derail)."""
        if self.status != itg.DERAILED:
            return None
        e = self.event
        side = int(e[Event.side])
        direction = self.scenario.track.direction
        inner_side = 0 if direction > 0 else 1
        wheelset = int(e[Event.wheelset])
        station = float(self.model.bodies[WHEELSETS[wheelset], BodyTable.station])
        # position_m: where the derailed wheelset is; car_body_position_m: the car body's centre then
        return dict(time_s=float(e[Event.time]), position_m=float(e[Event.position]),
                    car_body_position_m=float(e[Event.position]) - station,
                    wheelset=wheelset, wheel_side="left" if side == 0 else "right",
                    rail_side="inner" if side == inner_side else "outer",
                    mechanism=MECHANISMS[int(e[Event.mechanism])], wheel_lift_m=float(e[Event.wheel_lift]),
                    lateral_displacement_m=float(e[Event.lateral_displacement]),
                    attack_angle_rad=float(e[Event.attack_angle]),
                    contact_position_m=float(e[Event.contact_position]),
                    speed_kmh=float(e[Event.speed]) / KMH)


def state_tolerances(atol, support=None):
    """Absolute error tolerance per state: atol for displacements, angles and damper states (m, rad),
    100 atol for velocities and rates (1/s), 1e3 atol for the track position. The rails' states (elastic
    `support`, track.elastic.ElasticTrack) like the bodies', their roll atol / roll-centre depth (the same
    displacement at the rail top); on rigid track (support None or not elastic) inf: not counted by the
    error control, they stay 0."""
    tol = np.full(N_STATE, atol)
    tol[State.velocities.columns] = 100.0 * atol
    tol[State.s] = 1e3 * atol
    tol[State.rail_rates.columns] = 100.0 * atol
    if support is None or support[ElasticTrack.elastic] < 0.5:
        tol[State.rail_deflections.columns] = np.inf
        tol[State.rail_rates.columns] = np.inf
    else:
        roll = np.arange(N_WHEEL) * N_RAIL_DOF + RailDof.roll
        tol[State.rail_deflections + roll] /= support[ElasticTrack.roll_centre_depth]
        tol[State.rail_rates + roll] /= support[ElasticTrack.roll_centre_depth]
    return tol


def state_name(i):
    """Name of entry i of the state vector, e.g. 'wheelset_0 yaw displacement'."""
    for block in (State.positions, State.velocities):
        if block <= i < block.stop:
            body, dof = divmod(i - block, N_DOF)
            what = "displacement" if block is State.positions else "velocity"
            return f"{Body(body).name} {Dof(dof).name} {what}"
    if State.dampers <= i < State.dampers.stop:
        return f"damper {i - State.dampers} elongation"
    for block in (State.rail_deflections, State.rail_rates):
        if block <= i < block.stop:
            wheel, dof = divmod(i - block, N_RAIL_DOF)
            what = "deflection" if block is State.rail_deflections else "rate"
            return (f"rail of wheelset_{wheel // 2}'s {('left', 'right')[wheel % 2]} wheel {RailDof(dof).name} "
                    f"{what}")
    return "track position"


def simulate(sc: Scenario, progress=None, chunk=1.0, observe=None):
    """Run a scenario to the end of the line (or derailment); returns a Result. `observe(sim, rows)`, if
    given, sees each chunk's new output rows (the sensors' log, sensors.measure.SensorLog)."""
    sim = Simulation(sc)
    parts = []
    while sim.status == itg.RUNNING:
        parts.append(sim.advance(chunk))
        if observe is not None:
            observe(sim, parts[-1])
        if progress is not None:
            progress(sim)
    rows = np.concatenate(parts) if parts else np.zeros((0, N_OUT))
    return Result(rows=rows, scenario=sc, status=STATUS[sim.status], derailment=sim.derailment(),
                  flange_height=sim.model.flange_height)


def run_in_pieces(sc: Scenario, piece_s):
    """A run of `sc` as a generator of (the Simulation, the output rows of the next `piece_s` of simulated
    time, the divergence message or ''), up to where it stops (a diverging run's last piece has no rows): a
    caller may stop after any piece, or take the next one later; the pieces together are the rows of one
    `advance` over the whole run (the step sequence does not depend on how a run is cut)."""
    sim = Simulation(sc)
    while sim.status == itg.RUNNING:
        try:
            rows = sim.advance(piece_s)
        except SimulationDiverged as exc:
            yield sim, np.zeros((0, N_OUT)), str(exc)
            return
        yield sim, rows, ""


@dataclass
class Checkpoints:
    """A run's state at the start of each of `run_to_stop`'s chunks ({rows written: Simulation.fork()}) and its
    rows: where another run of the same scenario that follows it for a while goes on from, without simulating
    that stretch again (the closed loops of supervision.closed_loop, up to their first command)."""
    forks: dict = field(default_factory=dict)
    rows: np.ndarray = None

    def at(self, rows):
        """A Simulation that has written `rows` output rows of the run (0 < rows <= the run's): a fork of the
        last checkpoint at or before it, advanced to it."""
        if not 0 < rows <= len(self.rows):
            raise ValueError(f"a run of {len(self.rows)} rows has no state after row {rows}")
        start = max(k for k in self.forks if k <= rows)
        sim = self.forks[start].fork()
        if rows > start:
            sim.advance((rows - start - (start == 0)) * sim.output_dt)     # the first call writes the start too
        return sim


def run_to_stop(sc: Scenario, chunk_s=10.0, checkpoints=None):
    """(the Simulation, its output arrays, the divergence message or '') of a scenario run until it stops,
    `chunk_s` of simulated time at a time: a diverging run keeps the rows before its last chunk (the
    evaluations that must score every run to its end: the warning evaluations). The chunks are written into
    one buffer sized for the whole run (`Scenario.simulated_duration`; zeroed pages cost nothing until
    written), doubled if a run outlasts it: a 30 km line's 300 MB of rows were copied once more, from the
    chunks into the whole, in about a second. `checkpoints` (a Checkpoints) is given the run's state at each
    chunk's start and its rows."""
    sim = Simulation(sc)
    chunk = int(round(chunk_s / sim.output_dt)) + 1
    rows = np.zeros((int(sc.simulated_duration() / sim.output_dt) + 2 * chunk, N_OUT))
    written, error = 0, ""
    while sim.status == itg.RUNNING:
        if written + chunk > len(rows):
            rows = np.concatenate([rows, np.zeros_like(rows)])
        if checkpoints is not None:
            checkpoints.forks[written] = sim.fork()
        try:
            written += len(sim.advance(chunk_s, rows[written:]))
        except SimulationDiverged as exc:
            error = str(exc)
    if checkpoints is not None:
        checkpoints.rows = rows[:written]
    return sim, output_arrays(rows[:written]), error


def output_arrays(rows):
    """Named arrays (views) of output rows: the fields of OutputRow, with the wheelsets' and the wheels'
    records spread into one array per field of WheelsetOutput, (n, 4), and of Wheel, (n, 8) (wheels
    [wheelset 0 left, wheelset 0 right, ...]; `patches` (n, 8, MAX_PATCHES, 6))."""
    fields = OutputRow.split(rows)
    arrays = {name: view for name, view in fields.items() if name not in ("wheelsets", "wheels")}
    arrays.update(WheelsetOutput.split(fields["wheelsets"]))
    arrays.update(Wheel.split(fields["wheels"]))
    return arrays


@dataclass
class Result:
    """Time histories of a run (output rows, `layout.OutputRow`). Arrays are SI; wheel arrays are (n, 8)
    ordered [wheelset 0 left, wheelset 0 right, ...]."""
    rows: np.ndarray
    scenario: Scenario
    status: str
    derailment: dict = None
    flange_height: float = 0.0

    def arrays(self):
        """Named arrays of the documented output format (`output_arrays`)."""
        return output_arrays(self.rows)

    @property
    def time(self):
        return self.rows[:, OutputRow.time]

    @property
    def position(self):
        return self.rows[:, OutputRow.position]

    @property
    def speed(self):
        return self.rows[:, OutputRow.speed]

    def body(self, body, dof):
        """A body's position, e.g. body("car_body", "roll") (names of layout.Body and layout.Dof)."""
        return self.arrays()["body_states"][:, Body[body], Dof[dof]]

    @property
    def wheelset_lateral(self):
        return self.arrays()["wheelset_lateral"]

    @property
    def attack_angle(self):
        return self.arrays()["attack_angle"]

    @property
    def wheelset_roll(self):
        return self.arrays()["wheelset_roll"]

    def wheel(self, name):
        """A field of the wheel record (contact.layout.Wheel) for the 8 wheels, (n, 8)."""
        return self.arrays()[name]

    def patches(self, wheel_index):
        """(n, MAX_PATCHES, 6): one wheel's patches (contact.layout.WheelPatch: lateral position, lead, length,
        width, normal force, contact angle)."""
        return self.arrays()["patches"][:, wheel_index]

    def summary(self):
        a = self.arrays()
        s = dict(status=self.status, duration_s=float(self.time[-1]) if len(self.time) else 0.0,
                 end_position_m=float(self.position[-1]) if len(self.time) else 0.0,
                 max_attack_angle_rad=float(np.max(np.abs(a["attack_angle"][:, 0]))) if len(self.time) else 0.0,
                 max_wheel_lift_m=float(np.max(a["wheel_lift"])) if len(self.time) else 0.0,
                 max_lateral_force_n=float(np.max(a["lateral_force"])) if len(self.time) else 0.0,
                 max_vertical_force_n=float(np.max(a["vertical_force"])) if len(self.time) else 0.0,
                 max_derailment_coefficient=float(np.max(a["derailment_coefficient"])) if len(self.time) else 0.0,
                 track_model=self.scenario.track_model, derailment=self.derailment)
        return s

    def save(self, path, extra=None, extra_metadata=None):
        """Write the documented .npz format (docs/output-format.md) atomically, with the arrays `extra`
        (the sensors' signals) and `extra_metadata` in the metadata."""
        meta = dict(status=self.status, derailment=self.derailment, flange_height_m=self.flange_height,
                    radius_m=self.scenario.track.radius, vehicle_set=self.scenario.vehicle.name,
                    contact_model=self.scenario.contact.normal_model,
                    creep_model=self.scenario.contact.creep_model,
                    wheel_profile=self.scenario.contact.wheel_profile, track_model=self.scenario.track_model,
                    irregularity=(self.scenario.irregularity.name if self.scenario.irregularity is not None
                                  else "none"),
                    wind=None if self.scenario.wind is None else dict(
                        speed_m_s=self.scenario.wind.speed, direction_deg=self.scenario.wind.direction_deg,
                        gust=self.scenario.wind.gust),
                    faults=list(self.scenario.faults), speed_table=self.scenario.speed_table.tolist(),
                    rtol=self.scenario.rtol, atol=self.scenario.atol, **(extra_metadata or {}))
        with atomic_write(path, "wb") as handle:
            np.savez_compressed(handle, metadata=jsonout.dumps(meta), **self.arrays(), **(extra or {}))
