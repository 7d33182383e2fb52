"""The closed loop of the batch path: a run in short chunks, a controller fed each chunk's rows, and the
emergency brake applied on its command by replacing the rest of the speed table with the braking model's
speed over distance (docs/supervision.md, "The closed loop").

The forward speed stays prescribed: the brake acts on the speed table, not through a braking torque or the
longitudinal creep forces. Why the swap is clean: the core reads the table at the car body's position
(`dynamics.speed_at`) and turns the wheelsets with the torque that keeps their spin on the prescribed
acceleration (`traction = I_spin v dv/ds / r0`), so the spin and the creep forces follow the new table
without a jump in any state; the new table equals the old one over the build-up, longer than a chunk plus
a step, so the stepper (up to one step past the last row, integrator.advance) and the rows already written
never see a table that differs from the one they were made with.
"""
from dataclasses import dataclass, replace

import numpy as np

from ..ranges import check_range
from ..vehicle import integrator as itg
from ..vehicle.layout import N_OUT
from ..vehicle.simulate import KMH, MAX_STEP, SPEED_RANGE_KMH, STATUS, Result, Simulation

# s of simulated time between the controller's looks; it decides on every row all the same, and a command's
# brake starts from its own row as long as the chunk is shorter than the build-up (checked): longer chunks
# cost less (each `advance` call has a fixed cost, about 0.1 ms)
CHUNK_S = 0.5


@dataclass(frozen=True)
class BrakeCommand:
    """An emergency brake command: when and where (the car body's centre) it was given, at which speed, and
    the speed the brake holds down to before it is released."""
    time_s: float
    position_m: float
    speed_m_s: float
    release_speed_m_s: float


def braked_table(table, command, braking):
    """The speed table (rows s m, v m/s) with everything from the command on replaced by the braking model's
    curve from it down to the release speed (`floor_of`)."""
    keep = table[table[:, 0] < command.position_m]
    s0, v0, v1 = command.position_m, command.speed_m_s, floor_of(command)
    # a train already at the simulator's slowest speed holds it (to a stop's stopping point)
    braked = braking.speed_table(s0, v0, v1) if v1 < v0 else np.array([[s0, v0], [s0 + 1.0, v0]])
    return np.ascontiguousarray(np.vstack([keep, braked]))


def apply_brake(sim, command, braking):
    """Brake a Simulation on `command` (`braked_table`); for a stop, the run ends at the stopping point (the car
    body's position, m, returned; None for a brake to a speed)."""
    sim.speed_table = braked_table(sim.speed_table, command, braking)
    if command.release_speed_m_s != 0.0:
        return None
    stop = command.position_m + braking.braking_distance(command.speed_m_s, 0.0)
    sim.control = sim.control._replace(s_end=min(sim.control.s_end, stop))
    return stop


@dataclass
class ClosedLoopRun:
    """A closed-loop run: its Result (its scenario carrying the speed table as braked), every brake command,
    and where a brake to a stop ends the run (the car body's position, m; None without one)."""
    result: Result
    commands: list
    stopped_at_m: float = None


def floor_of(command):
    """The release speed (m/s) the simulator brakes down to: the command's, but not below the slowest speed the
    simulator runs (SPEED_RANGE_KMH: held there, faster than the train would be); a stop (release speed 0: an
    end of authority, where the survey found no speed that keeps the margins) is held there up to the
    stopping point, where the run ends (`apply_brake`)."""
    return max(command.release_speed_m_s, min(SPEED_RANGE_KMH[0] * KMH, command.speed_m_s))


def run_closed_loop(sc, controller, braking, chunk_s=CHUNK_S, progress=None, checkpoints=None):
    """Run a scenario in chunks of chunk_s; after each, `controller(sim, rows)` sees the new output rows and
    returns a BrakeCommand or None. A command is applied unless a brake is still on (the speed above its
    release speed); the run goes on to its end (or derailment) at the braked speeds, or, braked to a stop, to
    the stopping point (`floor_of`: the last metres at the simulator's slowest speed, faster than the train
    would be). `checkpoints`: the open run of the same scenario (`simulate.run_to_stop`'s Checkpoints): up to
    the first command the loop is that run, so its chunks are read from its rows (the controller given the
    run's first state as `sim`: it reads the rows, the model and the scenario only) and the loop goes on from
    its state there; the same run, bit for bit (tested), without simulating the approach again."""
    braking = braking.validated()
    check_range("supervision chunk", chunk_s, 1.0 / sc.output_rate, braking.buildup_s - MAX_STEP, "s", hi_open=True)
    commands, release_at, stopped_at = [], -np.inf, None

    def obey(sim, command):
        nonlocal release_at, stopped_at
        if command is not None and command.position_m >= release_at:
            stop = apply_brake(sim, command, braking)
            stopped_at = stopped_at if stop is None else stop
            release_at = sim.speed_table[-2, 0]
            commands.append(command)

    if checkpoints is None:
        sim, parts, command = Simulation(sc), [], None
    else:
        sim, followed, command = _follow(sc, checkpoints, controller, chunk_s)
        parts = [followed]
    end = sim.control.s_end
    obey(sim, command)
    while sim.status == itg.RUNNING:
        rows = sim.advance(chunk_s)
        parts.append(rows)
        obey(sim, controller(sim, rows))
        if progress is not None:
            progress(sim)
    rows = np.concatenate(parts) if parts else np.zeros((0, N_OUT))
    result = Result(rows=rows, scenario=replace(sc, speed_table=sim.speed_table), status=STATUS[sim.status],
                    derailment=sim.derailment(), flange_height=sim.model.flange_height)
    return ClosedLoopRun(result=result, commands=commands,
                         stopped_at_m=stopped_at if stopped_at is not None and stopped_at < end else None)


def _follow(sc, checkpoints, controller, chunk_s):
    """(the Simulation after the chunk of the first command, or after the open run's last row; the rows up to
    there; the command or None) of a closed loop read from its open run's checkpoints, chunk by chunk as the
    loop would have simulated them (the first chunk with the start row)."""
    first = checkpoints.forks.get(0)
    if first is None or first.scenario is not sc:
        raise ValueError("checkpoints of another run: a closed loop goes on only from its own scenario's open run")
    rows, per = checkpoints.rows, int(round(chunk_s / first.output_dt))      # as Simulation.advance counts
    done, command = 0, None
    while done < len(rows) and command is None:
        chunk = rows[done:done + per + (done == 0)]
        command = controller(first, chunk)
        done += len(chunk)
    return checkpoints.at(done), rows[:done], command
