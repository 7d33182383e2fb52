"""Limit-cycle method: nonlinear critical speed by time integration after a lateral excitation.

The car runs on straight track through a short lateral alignment defect (the kick: one period of a cosine
kink of both rails, or an S of two periods, `track.irregularity.lateral_kink`; default 10 mm over 20 m), or
through the scenario's own irregularity (a sample over the first EXCITATION_M of the line, or a file), then on
smooth track. Following Yu 2022 (Table 3), the run is unstable when the wheelset lateral displacement does not
decay below 0.1 mm: the largest |lateral displacement| of any wheelset over the last `window_m` metres is
compared with that threshold.

Two definitions of the nonlinear critical speed (`METHODS`):
  "bisection"  the lowest speed whose run after a fixed kick stays unstable, by a scan over a speed grid and
               bisection to a stated tolerance. With a subcritical (Hopf) bifurcation this depends on the
               kick: a larger kick finds the limit cycle at a lower speed.
  "ramp-down"  the usual practice (and the paper's Figure 2 read as a bifurcation diagram): a large kick at
               a high speed puts the car on its limit cycle, then one run lowers the speed in steps, each held
               long enough for the motion to settle, until the limit cycle dies; the lowest speed that still
               holds one (the fold of the subcritical branch) is the critical speed. It does not depend on the
               kick once the kick reaches the limit cycle. A second run repeats the descent with finer steps
               below the last speed that held one.

The bifurcation diagram (`plotting.limit_cycle_figure`) shows both branches: the upward one, the final
amplitude after a small kick (SMALL_KICK_M) at each grid speed, which leaves the trivial solution only near
the linear critical speed; and the downward one, the amplitude held at each step of the descent.
"""
from dataclasses import dataclass, replace

import numpy as np

from ..ranges import check_range
from ..track.irregularity import lateral_kink
from ..vehicle.simulate import KMH, Scenario, constant_speed, simulate, straight_track

THRESHOLD_M = 1.0e-4
EXCITATION_M = 500.0            # m, the length of an irregular excitation (CLI --irregularity)
SPEED_RANGE_KMH = (50.0, 800.0)
METHODS = ("bisection", "ramp-down")
KICK_SHAPES = {"kink": 1, "s-kink": 2}      # shape: periods of lateral_kink
KICK_START_M = 100.0
SMALL_KICK_M = 0.5e-3           # the upward branch's kick: a perturbation of the trivial solution, far below flange
                                # contact (about 7 mm) so that it probes the linearised car
HOLD_M = 600.0                  # m per step of the descent: at 4 Hz and 250 km/h about 35 periods
SUSTAIN = 0.9                   # a held oscillation shrinks by less than this factor between the last two windows
DESCENT_DECELERATION = 2.0      # m/s^2 between the steps: the change is no braking test, the holds do the settling,
                                # and at 0.5 m/s^2 the changes would be three times longer than the holds


@dataclass(frozen=True)
class Kick:
    """The lateral excitation: amplitude (m), length of one period (m) and shape (a key of KICK_SHAPES)."""
    amplitude_m: float = 0.010
    length_m: float = 20.0
    shape: str = "kink"

    def validated(self):
        check_range("kick amplitude", self.amplitude_m * 1e3, 0.1, 30.0, "mm")
        check_range("kick length", self.length_m, 2.0, 200.0, "m")
        if self.shape not in KICK_SHAPES:
            raise ValueError(f"kick shape {self.shape!r} is unknown; choose one of {', '.join(KICK_SHAPES)}")
        return self

    def irregularity(self):
        return lateral_kink(KICK_START_M, self.length_m, self.amplitude_m, periods=KICK_SHAPES[self.shape])

    def as_json(self):
        return dict(amplitude_m=self.amplitude_m, length_m=self.length_m, shape=self.shape)


@dataclass
class Branch:
    """One branch of the bifurcation diagram: speeds (km/h) and the wheelset amplitude held at each (m)."""
    name: str                       # "upward" (small kick at each speed) or "downward" (the descent)
    speeds_kmh: np.ndarray
    amplitudes_m: np.ndarray        # inf: the run derailed there
    kick: Kick

    def as_json(self):
        return dict(name=self.name, kick=self.kick.as_json(),
                    points=[dict(speed_kmh=float(v), amplitude_m=float(a))
                            for v, a in zip(self.speeds_kmh, self.amplitudes_m)])


@dataclass
class LimitCycle:
    nonlinear_critical_speed_kmh: float     # nan if no speed in the range holds a limit cycle
    tolerance_kmh: float
    speeds_kmh: np.ndarray                  # every constant-speed run of the bisection, sorted (empty: ramp-down)
    amplitudes_m: np.ndarray                # final amplitude at each
    excitation_amplitude_m: float           # the kick's (nan: the scenario's irregularity)
    excitation_length_m: float
    excitation: str = ""                    # what excited the runs
    method: str = "bisection"
    kick: Kick = None                       # None: the scenario's irregularity excited the runs
    branches: tuple = ()                    # the bifurcation diagram's Branch-es (upward, downward)

    def as_json(self):
        return dict(nonlinear_critical_speed_kmh=self.nonlinear_critical_speed_kmh, method=self.method,
                    kick=None if self.kick is None else self.kick.as_json(),
                    tolerance_kmh=self.tolerance_kmh, threshold_m=THRESHOLD_M,
                    excitation_amplitude_m=self.excitation_amplitude_m,
                    excitation_length_m=self.excitation_length_m, excitation=self.excitation,
                    speeds_kmh=self.speeds_kmh.tolist(),
                    final_amplitude_m=self.amplitudes_m.tolist(),
                    bifurcation={b.name: b.as_json() for b in self.branches})


def excitation(sc: Scenario, amplitude=0.010, length=20.0, shape="kink"):
    """The scenario's irregularity, or else the kick of `amplitude` over `length` (m)."""
    return sc.irregularity if sc.irregularity is not None else Kick(amplitude, length, shape).irregularity()


def excited_scenario(sc: Scenario, speed_kmh, amplitude=0.010, length=20.0, shape="kink"):
    check_range("limit-cycle speed", speed_kmh, *SPEED_RANGE_KMH, "km/h")
    return replace(sc, track=straight_track(), irregularity=excitation(sc, amplitude, length, shape),
                   speed_table=constant_speed(speed_kmh), stop_on_derailment=True, output_rate=100.0)


def final_amplitude(sc: Scenario, speed_kmh, window_m=300.0, **excitation):
    """Largest |wheelset lateral displacement| over the last window_m of the line (m)."""
    r = simulate(excited_scenario(sc, speed_kmh, **excitation))
    if r.status == "derailed":
        return float("inf")
    sel = r.position >= r.position[-1] - window_m
    return float(np.max(np.abs(r.wheelset_lateral[sel])))


def descent_table(speeds_kmh, hold_m=HOLD_M, deceleration=DESCENT_DECELERATION):
    """Speed table (s, v in m/s) of a descent through `speeds_kmh` (decreasing): each held for hold_m, the
    changes at `deceleration` (speed linear in distance), and the hold intervals (m) as an (n, 2) array."""
    v = np.asarray(speeds_kmh, float) * KMH
    if np.any(np.diff(v) >= 0.0):
        raise ValueError("the descent's speeds must decrease")
    pts, holds, s = [(0.0, v[0])], [], 0.0
    for k, vk in enumerate(v):
        if k:
            s += (v[k - 1] ** 2 - vk ** 2) / (2.0 * deceleration)
            pts.append((s, vk))
        holds.append((s, s + hold_m))
        s += hold_m
        pts.append((s, vk))
    return np.array(pts), np.array(holds)


def descent(sc: Scenario, speeds_kmh, kick: Kick, hold_m=HOLD_M, window_m=None):
    """One run down through `speeds_kmh` after `kick` at the first: for each speed the largest |wheelset
    lateral displacement| over the hold's last window (m; inf where the run derailed, nan for steps it did not
    reach) and whether a limit cycle held there (above THRESHOLD_M and not shrinking by SUSTAIN between the
    hold's last two windows of window_m, default a quarter of the hold)."""
    window_m = 0.25 * hold_m if window_m is None else window_m
    for v in (speeds_kmh[0], speeds_kmh[-1]):
        check_range("limit-cycle speed", v, *SPEED_RANGE_KMH, "km/h")
    table, holds = descent_table(speeds_kmh, hold_m)
    track = straight_track()
    track = track.with_line_length(max(track.line_length, float(holds[-1, 1]) + 1.0))
    r = simulate(replace(sc, track=track, irregularity=kick.irregularity(), speed_table=table,
                         stop_on_derailment=True, output_rate=100.0))
    lateral = np.max(np.abs(r.wheelset_lateral), axis=1)
    amp, held = np.full(len(holds), np.nan), np.zeros(len(holds), bool)
    for k, (a, b) in enumerate(holds):
        if r.position[-1] < b:
            if r.status == "derailed" and r.position[-1] >= a:
                amp[k] = np.inf
            break
        last = lateral[(r.position >= b - window_m) & (r.position <= b)]
        before = lateral[(r.position >= b - 2 * window_m) & (r.position < b - window_m)]
        amp[k] = np.max(last)
        held[k] = amp[k] > THRESHOLD_M and amp[k] >= SUSTAIN * np.max(before)
    return amp, held


def ramp_down(sc: Scenario, top_kmh, bottom_kmh, step_kmh, tolerance_kmh, kick: Kick, hold_m=HOLD_M, progress=None):
    """The downward branch (speeds rising, amplitudes) and the lowest speed holding a limit cycle (km/h; nan if
    none holds one at the top, `bottom_kmh` if the lowest step still does: then the fold lies at or below it)."""
    coarse = np.arange(top_kmh, bottom_kmh - 1e-9, -step_kmh)
    amp, held = descent(sc, coarse, kick, hold_m)
    if progress:
        for v, a, h in zip(coarse, amp, held):
            progress(v, a, h)
    speeds, amps = list(coarse), list(amp)
    vcrit = float("nan")
    if held[0]:
        last = len(held) - 1 if held.all() else int(np.argmin(held)) - 1     # the last of the unbroken run
        vcrit = float(coarse[last])
        # finer steps below the last coarse speed that held one, reached along the same coarse path
        fine = np.arange(coarse[last] - tolerance_kmh, coarse[min(last + 1, len(coarse) - 1)] + 1e-9, -tolerance_kmh)
        fine = fine[fine > coarse[last + 1] + 1e-9] if last + 1 < len(coarse) else fine[:0]
        if fine.size:
            amp_f, held_f = descent(sc, np.concatenate((coarse[:last + 1], fine)), kick, hold_m)
            amp_f, held_f = amp_f[last + 1:], held_f[last + 1:]
            if progress:
                for v, a, h in zip(fine, amp_f, held_f):
                    progress(v, a, h)
            alive = int(np.argmin(held_f)) if not held_f.all() else held_f.size
            if alive:
                vcrit = float(fine[alive - 1])
            speeds += list(fine)
            amps += list(amp_f)
    order = np.argsort(speeds)
    return np.array(speeds)[order], np.array(amps)[order], vcrit


def upward_branch(sc: Scenario, speeds_kmh, window_m=300.0, progress=None):
    """Final amplitude after the small kick at each speed (the branch that leaves the trivial solution)."""
    kick = Kick(SMALL_KICK_M)
    amps = []
    for v in speeds_kmh:
        amps.append(final_amplitude(replace(sc, irregularity=None), v, window_m, amplitude=kick.amplitude_m,
                                    length=kick.length_m, shape=kick.shape))
        if progress:
            progress(v, amps[-1], amps[-1] > THRESHOLD_M)
    return Branch("upward", np.asarray(speeds_kmh, float), np.array(amps), kick)


def limit_cycle(sc: Scenario = None, speeds_kmh=None, tolerance_kmh=1.0, amplitude=0.010, length=20.0,
                window_m=300.0, progress=None, method="bisection", shape="kink", branches=False):
    """Nonlinear critical speed (km/h) by `method` (METHODS) over the speed grid `speeds_kmh`, with the
    bifurcation diagram's two branches over the same grid (`branches`; the downward one after a kick of
    `amplitude` at the top speed). `progress(speed, amplitude, unstable)` is called after each run."""
    sc = sc or Scenario()
    scan = np.arange(200.0, 601.0, 50.0) if speeds_kmh is None else np.sort(np.asarray(speeds_kmh, float))
    for v in (scan.min(), scan.max()):
        check_range("limit-cycle speed", v, *SPEED_RANGE_KMH, "km/h")
    check_range("bisection tolerance", tolerance_kmh, 0.0, 50.0, "km/h", lo_open=True)
    if method not in METHODS:
        raise ValueError(f"limit-cycle method {method!r} is unknown; choose one of {', '.join(METHODS)}")
    kick = Kick(amplitude, length, shape).validated()
    if method == "ramp-down" and sc.irregularity is not None:
        raise ValueError("the ramp-down method starts from a kick; an irregularity is not accepted with it")
    step = float(np.min(np.diff(scan))) if scan.size > 1 else 50.0
    runs, vcrit, down = {}, float("nan"), None
    if method == "ramp-down" or branches:
        speeds, amps, v_fold = ramp_down(sc, scan.max(), scan.min(), step, tolerance_kmh, kick,
                                         progress=progress)
        down = Branch("downward", speeds, amps, kick)
        if method == "ramp-down":
            vcrit = v_fold
    if method == "bisection":
        def amp(v):
            if v not in runs:
                runs[v] = final_amplitude(sc, v, window_m, amplitude=amplitude, length=length, shape=shape)
                if progress:
                    progress(v, runs[v], runs[v] > THRESHOLD_M)
            return runs[v]

        first = next((i for i, v in enumerate(scan) if amp(v) > THRESHOLD_M), None)
        if first is not None:
            if first == 0:
                vcrit = float(scan[0])
            else:
                lo, hi = float(scan[first - 1]), float(scan[first])
                while hi - lo > tolerance_kmh:
                    mid = round(0.5 * (lo + hi), 6)
                    lo, hi = (lo, mid) if amp(mid) > THRESHOLD_M else (mid, hi)
                vcrit = hi
    found = () if not branches else (upward_branch(sc, scan, window_m, progress), down)
    v = np.array(sorted(runs))
    kicked = sc.irregularity is None
    return LimitCycle(nonlinear_critical_speed_kmh=vcrit, tolerance_kmh=tolerance_kmh, speeds_kmh=v,
                      amplitudes_m=np.array([runs[s] for s in v]),
                      excitation_amplitude_m=amplitude if kicked else float("nan"),
                      excitation_length_m=(KICK_SHAPES[shape] * length) if kicked else float(np.ptp(sc.irregularity.s)),
                      excitation=excitation(sc, amplitude, length, shape).description, method=method,
                      kick=kick if kicked else None, branches=found)
