"""The warning evaluation's ground truth and scoring on synthetic runs, checked by hand: the margins and their
places, the windows and labels, Prud'homme's limit, the braking model, attribution (place and window),
the lead capped at the window, the false-alarm episodes that cannot fall as the threshold falls (where a
count of onsets does), and the intervals against their closed forms."""
from dataclasses import replace
import math

import numpy as np
import pytest

from railderail_monitor.evaluation import scoring
from railderail_monitor.evaluation.hazards import (Car, HazardRules, braking_time, hazards, track_shift_force,
                                                   useful_lead, windows)
from railderail_monitor.warning.alarms import alarm_intervals, alert_indices

P0 = 56064.15
RULES = HazardRules()
CAR = Car(flange_height=0.0278, max_contact_angle=math.radians(69.54), static_wheel_load=P0, friction=0.3)


def quiet_run(n=4000, speed=50.0, rate=200.0):
    """n samples of a car at `speed` on its rails, every wheel at its static load."""
    t = np.arange(n) / rate
    return dict(time=t, position=speed * t, speed=np.full(n, speed), vertical_force=np.full((n, 8), P0),
                derailment_coefficient=np.zeros((n, 8)), lateral_force=np.zeros((n, 8)), wheel_lift=np.zeros((n, 8)))


def test_prudhommes_limit_and_the_track_shift_force_by_hand():
    # alpha (10 + P0/3) kN with the axle load P0 = 2 x 56.06 kN: 47.38 kN
    assert CAR.track_shift_limit(RULES) == pytest.approx((10.0 + 2 * 56.06415 / 3.0) * 1e3)
    # the left wheel pushes its rail 30 kN to the left, the right one 10 kN to the right: 20 kN to the left
    q = np.array([[30e3, 10e3, 0, 0, 0, 0, 0, 0]])
    assert track_shift_force(q)[0].tolist() == [20e3, 0.0, 0.0, 0.0]
    assert CAR.nadal == pytest.approx((math.tan(math.radians(69.54)) - 0.3) / (1 + 0.3 * math.tan(math.radians(69.54))))


def test_a_margin_falls_at_its_place_and_labels_its_window():
    a = quiet_run()
    a["vertical_force"][2000:2100, 3] = 0.05 * P0          # wheelset 1 right unloads to 0.95 for 0.5 s (25 m)
    found = hazards(a, None, CAR, replace(RULES, low_pass_forces=False))     # the window counted by hand
    (h,) = found
    assert (h["kind"], h["margin"], h["places"]) == ("near_miss", "wheel_unloading", [(0, 1)])
    # the 1.524 m mean holds 7 samples 0.25 m apart: 6 unloaded of 7 give 0.81, all 7 give 0.95
    assert h["time_s"] == pytest.approx(a["time"][2006])
    place, label = windows(a["time"], found, 10.0)
    inside = (a["time"] >= h["time_s"] - 10.0) & (a["time"] <= h["end_s"])
    assert np.array_equal(place[(0, 1)], inside) and not place[(0, 0)].any() and not place[(1, 1)].any()
    assert np.array_equal(label == 1, inside) and np.all(label[~inside] == 0)


def test_margins_are_judged_on_the_forces_low_passed_20_hz():
    from railderail_monitor.evaluation.hazards import filtered_forces
    # a wheel fully unloaded for 35 ms (7 samples, 1.75 m at 50 m/s): a spike of the rigid track's contact, gone
    # through the 20 Hz low-pass; the same for 0.5 s is a margin fallen either way, later by about the filter's
    # group delay when filtered (a 4-pole Butterworth: 2.61 / (2 pi 20 Hz) = 21 ms at low frequency)
    spike, long = quiet_run(), quiet_run()
    spike["vertical_force"][2000:2007, 3] = 0.0
    long["vertical_force"][2000:2100, 3] = 0.0
    raw = replace(RULES, low_pass_forces=False)
    assert [h["margin"] for h in hazards(spike, None, CAR, raw)] == ["wheel_unloading"]
    assert hazards(spike, None, CAR, RULES) == []
    (unfiltered,), (filtered,) = hazards(long, None, CAR, raw), hazards(long, None, CAR, RULES)
    assert 0.01 < filtered["time_s"] - unfiltered["time_s"] < 0.04
    # the low-pass passes a steady load unchanged and takes the 20 Hz cut-off's -3 dB (4-pole Butterworth)
    t = quiet_run()["time"]
    a = dict(time=t, vertical_force=P0 + 1e3 * np.sin(2 * np.pi * 20.0 * t)[:, None] * np.ones(8),
             lateral_force=np.zeros((len(t), 8)))
    vertical, _ = filtered_forces(a, RULES)
    assert vertical[400:, 0].mean() == pytest.approx(P0, rel=1e-5)
    assert np.std(vertical[400:, 0] - P0) * math.sqrt(2) == pytest.approx(1e3 / math.sqrt(2), rel=0.02)


def test_a_hunting_wheelset_is_a_near_miss_by_instability_at_its_bogie():
    # wheelset 2 (rear bogie) pushes its rails 5 Hz back and forth from t = 5 s: sum Y = amplitude sin, its
    # r.m.s. amplitude / sqrt 2 against half Prud'homme's 47.38 kN; 40 kN (28.3 rms) is unstable, 25 kN
    # (17.7 rms) is not
    def hunting(amplitude):
        a = quiet_run()
        t = a["time"]
        y = np.where(t >= 5.0, amplitude * np.sin(2 * np.pi * 5.0 * t), 0.0)
        a["lateral_force"][:, 4], a["lateral_force"][:, 5] = 0.5 * y, -0.5 * y
        return hazards(a, None, CAR, RULES)
    (h,) = hunting(40e3)
    assert (h["margin"], h["places"]) == ("instability", [(1, 0), (1, 1)])
    # the 100 m window (2 s at 50 m/s) fills with the oscillation: its r.m.s. reaches 23.7 kN after 1.4 s
    assert 5.0 < h["time_s"] < 7.0
    assert hunting(25e3) == []


def test_a_derailment_window_is_the_last_w_before_it_at_the_derailed_wheel():
    a = quiet_run()
    event = dict(time_s=15.0, speed_kmh=180.0, car_body_position_m=750.0, wheelset=2, wheel_side="left",
                 mechanism="flange_climbing")
    found = hazards(a, event, CAR, RULES)
    assert [(h["kind"], h["places"]) for h in found] == [("derailment", [(1, 0)])]
    place, label = windows(a["time"], found, 5.0)
    assert np.array_equal(label == 2, (a["time"] >= 10.0) & (a["time"] <= 15.0))
    assert np.array_equal(place[(1, 0)], label == 2)


def test_the_braking_model_band_by_band():
    # 300 km/h by 10 %: 8.33 m/s at 0.9 m/s^2; the lead adds 1 s reaction and 2 s build-up
    assert braking_time(RULES, 300 / 3.6) == pytest.approx(30 / 3.6 / 0.9)
    assert useful_lead(RULES, 300 / 3.6) == pytest.approx(3.0 + 30 / 3.6 / 0.9)
    # 240 km/h by 20 %: 240 -> 230 at 0.9, 230 -> 192 at 1.05
    assert braking_time(RULES, 240 / 3.6, 0.2) == pytest.approx(10 / 3.6 / 0.9 + 38 / 3.6 / 1.05)
    # to a stop from 100 km/h: all of it at 1.2
    assert braking_time(RULES, 100 / 3.6, 1.0) == pytest.approx(100 / 3.6 / 1.2)


def _alarms(n, *spans):
    mask = np.zeros((8, n), dtype=bool)
    for channel, a, b in spans:
        mask[channel, a:b] = True
    return mask


def test_only_an_alarm_at_the_hazards_place_and_in_its_window_warns_it():
    a = quiet_run()
    event = dict(time_s=15.0, speed_kmh=180.0, car_body_position_m=750.0, wheelset=0, wheel_side="right",
                 mechanism="flange_climbing")
    found = hazards(a, event, CAR, RULES)
    place, label = windows(a["time"], found, 5.0)
    places = scoring.channel_places("wheel_lift", 8)
    # the other wheel of the derailing wheelset, 15 ms before: no warning, a false alarm
    left = scoring.score(_alarms(4000, (0, 2997, 3000)), places, a, found, 5.0, place, label)
    assert left["warnings"] == [None] and left["false_episodes"] == 1
    # the rear wheelset of the same bogie on the same side, 2 s before: a true warning, no false alarm
    same = scoring.score(_alarms(4000, (3, 2600, 3000)), places, a, found, 5.0, place, label)
    assert same["warnings"] == [(pytest.approx(2.0), 50.0)] and same["false_episodes"] == 0
    # raised 8 s before and still on: its lead counts from the window's start, its first 3 s are false
    early = scoring.score(_alarms(4000, (1, 1400, 3000)), places, a, found, 5.0, place, label)
    assert early["warnings"] == [(pytest.approx(5.0), 50.0)]
    assert early["false_time_s"] == pytest.approx(3.0, abs=0.01) and early["false_episodes"] == 1
    # the lead of 5 s at 180 km/h is not enough for braking 10 %: 3 s, then 180 -> 170 km/h at 1.05 m/s^2 and
    # 170 -> 162 km/h at 1.2 m/s^2, 7.50 s
    need = 3.0 + 10 / 3.6 / 1.05 + 8 / 3.6 / 1.2
    assert not scoring.is_useful(early["warnings"][0], RULES)
    assert not scoring.is_useful((need - 0.01, 50.0), RULES) and scoring.is_useful((need + 0.01, 50.0), RULES)


def test_false_alarm_episodes_cannot_fall_as_the_threshold_falls_where_onsets_do():
    """Two excursions 30 m apart: at 1.0 the channel re-arms between them (two onsets), at 0.8 it does not
    (one onset); the episodes (km of track with a false alarm) and the time in alarm only grow."""
    s = np.arange(0.0, 4000.0, 0.25)
    v = np.zeros_like(s)
    v[(s > 990) & (s < 1000)] = 1.2
    v[(s > 1030) & (s < 1040)] = 1.2
    v[(s > 1000) & (s < 1030)] = 0.85                 # below 0.9 x 1.0, above 0.9 x 0.8
    onsets = {thr: len(alert_indices(v, s, thr, 2.0, 0.9, 20.0)) for thr in (0.8, 1.0)}
    assert onsets == {0.8: 1, 1.0: 2}                  # the count of onsets falls with the threshold
    a = dict(time=s / 50.0, position=s, speed=np.full(len(s), 50.0))
    place, label = windows(a["time"], [], 5.0)
    out = {}
    for thr in (0.8, 1.0):
        mask = np.zeros((8, len(s)), dtype=bool)
        mask[0] = scoring.in_alarm(v, s, thr, 2.0, 0.9, 20.0)
        out[thr] = scoring.score(mask, scoring.channel_places("wheel_lift", 8), a, [], 5.0, place, label)
    assert out[0.8]["false_episodes"] >= out[1.0]["false_episodes"] >= 1
    assert out[0.8]["false_time_s"] > out[1.0]["false_time_s"] > 0.0
    # a lower threshold's alarm contains the higher one's, sample for sample
    high, low = scoring.in_alarm(v, s, 1.0, 2.0, 0.9, 20.0), scoring.in_alarm(v, s, 0.8, 2.0, 0.9, 20.0)
    assert np.all(low[high])


def test_alarm_intervals_end_where_the_channel_re_arms():
    s = np.arange(0.0, 500.0, 1.0)
    v = np.where((s >= 100) & (s < 120), 1.0, 0.0)
    ((start, end),) = alarm_intervals(v, s, 0.5, 2.0, 0.9, 50.0)
    assert (s[start], s[end]) == (102.0, 170.0)       # raised after 2 m above, re-armed 50 m after it fell


def test_the_intervals_against_their_closed_forms():
    assert scoring.share_interval(0, 10) == [0.0, pytest.approx(1 - 0.025 ** 0.1)]
    assert scoring.share_interval(10, 10) == [pytest.approx(0.025 ** 0.1), 1.0]
    assert scoring.count_interval(0)[1] == pytest.approx(-math.log(0.025))        # 3.689
    lo, hi = scoring.count_interval(5)
    assert (lo, hi) == (pytest.approx(1.6235, abs=1e-4), pytest.approx(11.6683, abs=1e-4))
    assert scoring.resolvable_km(0.1) == pytest.approx(36889, rel=1e-3)
    assert scoring.rate_per_1000_km(2, 500.0)[0] == 4.0
