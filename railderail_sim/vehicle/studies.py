"""Numerical studies behind the integration settings: `python -m railderail_sim.vehicle.studies`.

Tolerance study: the same run (R = 1000 m, 280 km/h, car-body centre from 150 to 600 m, through the
transition into flange contact) at several tolerances, each compared with a much tighter reference;
displacements raw, forces low-pass filtered at 20 Hz (4th-order Butterworth, zero phase), as EN 14363
evaluates wheel-rail forces. Prints one line per tolerance; `tolerance --vehicle-set NAME` runs another
suspension set.
"""
from dataclasses import replace
import sys
import time

import numpy as np

from .simulate import scenario, simulate

TOLERANCES = ((1e-9, 1e-8), (3e-9, 3e-8), (1e-8, 1e-7), (3e-8, 3e-7), (1e-7, 1e-6))


def force_filter(x, rate):
    """x (n, ...) sampled at `rate` Hz low-pass filtered at 20 Hz (4th-order Butterworth, zero phase), as the
    study compares the forces."""
    from scipy.signal import butter, filtfilt
    b, a = butter(4, 20.0 / (rate / 2.0))
    return filtfilt(b, a, x, axis=0)


def tolerance_study(speed_kmh=280.0, radius=1000.0, tolerances=TOLERANCES, vehicle_set="hs19"):
    rate = 200.0
    runs = {}
    for atol, rtol in tolerances:
        sc = replace(scenario(radius=radius, speed_kmh=speed_kmh, vehicle_set=vehicle_set), atol=atol, rtol=rtol,
                     start_position=150.0, end_position=600.0, output_rate=rate)
        t = time.perf_counter()
        r = simulate(sc)
        runs[(atol, rtol)] = (r.arrays(), time.perf_counter() - t, r.time[-1])
    ref = runs[tolerances[0]][0]
    rows = []
    for key, (arr, wall, duration) in runs.items():
        n = min(len(arr["time"]), len(ref["time"]))

        def raw(name):
            return float(np.max(np.abs(arr[name][:n] - ref[name][:n])))

        def filtered(name):
            return float(np.max(np.abs(force_filter(arr[name][:n], rate) - force_filter(ref[name][:n], rate))))
        rows.append(dict(atol=key[0], rtol=key[1], real_time_factor=duration / wall,
                         lateral_error_m=raw("wheelset_lateral"), lift_error_m=raw("wheel_lift"),
                         attack_error_rad=raw("attack_angle"), q_error_n=filtered("lateral_force"),
                         p_error_n=filtered("vertical_force")))
    return rows


def main(argv=None):
    import argparse
    from ..parameters import VEHICLE_SETS
    parser = argparse.ArgumentParser(prog="python -m railderail_sim.vehicle.studies")
    parser.add_argument("study", choices=("tolerance",))
    parser.add_argument("--vehicle-set", default="hs19", choices=VEHICLE_SETS, help="suspension parameter set")
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    for r in tolerance_study(vehicle_set=args.vehicle_set):
        print(f"atol {r['atol']:.0e} rtol {r['rtol']:.0e}: lateral {r['lateral_error_m'] * 1e6:.1f} um, "
              f"lift {r['lift_error_m'] * 1e6:.1f} um, attack {r['attack_error_rad'] * 1e6:.1f} urad, "
              f"Q(20 Hz) {r['q_error_n'] / 1e3:.2f} kN, P(20 Hz) {r['p_error_n'] / 1e3:.2f} kN, "
              f"real-time factor {r['real_time_factor']:.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
