"""Limit-cycle method: nonlinear critical speed by time integration after a lateral excitation.

The car runs on straight track through a short lateral alignment defect (one period of a cosine kink of
both rails, `track.irregularity.lateral_kink`; default 10 mm over 20 m), or through the scenario's own
irregularity (a sample over the first EXCITATION_M of the line, or a file), then on smooth track. Following Yu 2022
(Table 3), the run is unstable when the wheelset lateral displacement does not decay below 0.1 mm: the
largest |lateral displacement| of any wheelset over the last `window_m` metres of the line is compared
with that threshold. The nonlinear critical speed is the lowest speed whose run stays unstable, found by a
scan over a speed grid and bisection to a stated tolerance. With a subcritical (Hopf) bifurcation the
result depends on the excitation size: a larger kick finds the limit cycle at a lower speed, which is why
it lies below the linear critical speed.

The bifurcation-style diagram (Yu 2022, Fig. 2; `plotting.limit_cycle_figure`) is the final oscillation
amplitude against speed.
"""
from dataclasses import dataclass, replace

import numpy as np

from ..ranges import check_range
from ..track.irregularity import lateral_kink
from ..vehicle.simulate import Scenario, constant_speed, simulate, straight_track

THRESHOLD_M = 1.0e-4
EXCITATION_M = 500.0            # m, the length of an irregular excitation (CLI --irregularity)
SPEED_RANGE_KMH = (50.0, 800.0)


@dataclass
class LimitCycle:
    nonlinear_critical_speed_kmh: float     # nan if every speed in the range decays
    tolerance_kmh: float
    speeds_kmh: np.ndarray                  # every speed run (scan and bisection), sorted
    amplitudes_m: np.ndarray                # final amplitude at each
    excitation_amplitude_m: float           # the kink's (nan: the scenario's irregularity)
    excitation_length_m: float
    excitation: str = ""                    # what excited the runs

    def as_json(self):
        return dict(nonlinear_critical_speed_kmh=self.nonlinear_critical_speed_kmh,
                    tolerance_kmh=self.tolerance_kmh, threshold_m=THRESHOLD_M,
                    excitation_amplitude_m=self.excitation_amplitude_m,
                    excitation_length_m=self.excitation_length_m, excitation=self.excitation,
                    speeds_kmh=self.speeds_kmh.tolist(),
                    final_amplitude_m=self.amplitudes_m.tolist())


def excitation(sc: Scenario, amplitude=0.010, length=20.0, start=100.0):
    """The scenario's irregularity, or else the lateral kink of `amplitude` over `length` from `start` (m)."""
    return sc.irregularity if sc.irregularity is not None else lateral_kink(start, length, amplitude)


def excited_scenario(sc: Scenario, speed_kmh, amplitude=0.010, length=20.0, start=100.0):
    check_range("limit-cycle speed", speed_kmh, *SPEED_RANGE_KMH, "km/h")
    return replace(sc, track=straight_track(), irregularity=excitation(sc, amplitude, length, start),
                   speed_table=constant_speed(speed_kmh), stop_on_derailment=True, output_rate=100.0)


def final_amplitude(sc: Scenario, speed_kmh, window_m=300.0, **excitation):
    """Largest |wheelset lateral displacement| over the last window_m of the line (m)."""
    r = simulate(excited_scenario(sc, speed_kmh, **excitation))
    if r.status == "derailed":
        return float("inf")
    sel = r.position >= r.position[-1] - window_m
    return float(np.max(np.abs(r.wheelset_lateral[sel])))


def limit_cycle(sc: Scenario = None, speeds_kmh=None, tolerance_kmh=1.0, amplitude=0.010, length=20.0,
                window_m=300.0, progress=None):
    """Nonlinear critical speed (km/h) by scan and bisection, with every run's final amplitude."""
    sc = sc or Scenario()
    scan = np.arange(200.0, 601.0, 50.0) if speeds_kmh is None else np.sort(np.asarray(speeds_kmh, float))
    for v in (scan.min(), scan.max()):
        check_range("limit-cycle speed", v, *SPEED_RANGE_KMH, "km/h")
    check_range("bisection tolerance", tolerance_kmh, 0.0, 50.0, "km/h", lo_open=True)
    runs = {}

    def amp(v):
        if v not in runs:
            runs[v] = final_amplitude(sc, v, window_m, amplitude=amplitude, length=length)
            if progress:
                progress(v, runs[v])
        return runs[v]

    vcrit = float("nan")
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
    v = np.array(sorted(runs))
    kink = sc.irregularity is None
    return LimitCycle(nonlinear_critical_speed_kmh=vcrit, tolerance_kmh=tolerance_kmh, speeds_kmh=v,
                      amplitudes_m=np.array([runs[s] for s in v]),
                      excitation_amplitude_m=amplitude if kink else float("nan"),
                      excitation_length_m=length if kink else float(np.ptp(sc.irregularity.s)),
                      excitation=excitation(sc, amplitude, length).description)

