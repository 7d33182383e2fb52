"""The warning evaluation's ground truth and scoring on synthetic runs, checked by hand: the margins and their
places, the windows and labels (beyond permitted running among them), Prud'homme's limit, the braking model
on dry and wet rail, each mechanism's cure and the lead it needs, attribution (place, and only an alarm
standing at the hazard), the lead capped at the window, the false-alarm episodes counted over normal running
only and that cannot fall as the threshold falls (where a count of onsets does), the intervals against their
closed forms and the scenario bootstrap."""
from dataclasses import replace
import math

import numpy as np
import pytest

from railderail_monitor.evaluation import scoring
from railderail_monitor.evaluation.hazards import (BEYOND_PERMITTED, Car, HazardRules, beyond_permitted,
                                                   braking_time, hazard_cure, hazards, lead_needed,
                                                   track_shift_force, useful_lead, window_of, windows,
                                                   with_cure_leads)
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
    label = windows(a["time"], found, 5.0)[1]
    places = scoring.channel_places("wheel_lift", 8)
    # the other wheel of the derailing wheelset, 15 ms before: no warning; false, inside the window (apart)
    left = scoring.score(_alarms(4000, (0, 2997, 3000)), places, scoring.Samples.of(a), found, 5.0, label)
    assert left["warnings"] == [None] and left["false_episodes"] == 0 and left["window_false_episodes"] == 1
    # the rear wheelset of the same bogie on the same side, 2 s before: a true warning, no false alarm
    same = scoring.score(_alarms(4000, (3, 2600, 3000)), places, scoring.Samples.of(a), found, 5.0, label)
    assert same["warnings"] == [(pytest.approx(2.0), 50.0)] and same["false_episodes"] == 0
    assert same["window_false_episodes"] == 0
    # raised 8 s before and still on: its lead counts from the window's start, its first 3 s are false
    early = scoring.score(_alarms(4000, (1, 1400, 3000)), places, scoring.Samples.of(a), found, 5.0, label)
    assert early["warnings"] == [(pytest.approx(5.0), 50.0)]
    assert early["false_time_s"] == pytest.approx(3.0, abs=0.01) and early["false_episodes"] == 1
    # the lead of 5 s at 180 km/h is not enough for braking 10 %: 3 s, then 180 -> 170 km/h at 1.05 m/s^2 and
    # 170 -> 162 km/h at 1.2 m/s^2, 7.50 s
    need = 3.0 + 10 / 3.6 / 1.05 + 8 / 3.6 / 1.2
    assert not scoring.is_useful(early["warnings"][0], RULES, None, 0.1)
    assert not scoring.is_useful((need - 0.01, 50.0), RULES, None, 0.1)
    assert scoring.is_useful((need + 0.01, 50.0), RULES, None, 0.1)


def test_only_an_alarm_standing_at_the_hazard_warns_it():
    """An alarm at the hazard's place that ended before the hazard is not a warning of it (and is false,
    counted apart inside the window); a later one standing at the hazard's last sample is, its lead from its
    own start; of two matching channels standing, the earlier start counts."""
    a = quiet_run()
    event = dict(time_s=15.0, speed_kmh=180.0, car_body_position_m=750.0, wheelset=0, wheel_side="right",
                 mechanism="flange_climbing")
    found = hazards(a, event, CAR, RULES)
    label = windows(a["time"], found, 5.0)[1]
    places, rows = scoring.channel_places("wheel_lift", 8), scoring.Samples.of(a)
    # on from 4 s to 2 s before the derailment (samples 2200-2600), then off: unwarned
    ended = scoring.score(_alarms(4000, (1, 2200, 2600)), places, rows, found, 5.0, label)
    assert ended["warnings"] == [None] and ended["window_false_episodes"] == 1 and ended["false_episodes"] == 0
    # on until the derailment's own sample but off at the last sample before it: unwarned
    assert scoring.score(_alarms(4000, (1, 2200, 2999)), places, rows, found, 5.0, label)["warnings"] == [None]
    # the ended one and a later one standing from 1 s before: warned 1 s ahead; the ended one stays false
    later = scoring.score(_alarms(4000, (1, 2200, 2600), (3, 2800, 3000)), places, rows, found, 5.0, label)
    assert later["warnings"] == [(pytest.approx(1.0), 50.0)] and later["window_false_episodes"] == 1
    # two standing: from 3 s and from 1 s before; the lead is the earlier start's
    two = scoring.score(_alarms(4000, (1, 2400, 3000), (3, 2800, 3000)), places, rows, found, 5.0, label)
    assert two["warnings"] == [(pytest.approx(3.0), 50.0)] and two["window_false_episodes"] == 0


def test_a_hazard_s_window_is_at_least_the_lead_its_cure_needs():
    """A hazard whose cure needs a longer lead than W (a stop before a defect from 180 km/h on wet rail: 1 + 2 s,
    then 0.8 m/s^2 down to 170 km/h and 0.9 below) has a window that long: an alarm standing since 10 s before it is credited with 10 s at W = 5 s,
    the running before it is in the window, not normal; without the cure's lead the same alarm counts from W."""
    a = quiet_run()
    event = dict(time_s=15.0, speed_kmh=180.0, car_body_position_m=750.0, wheelset=0, wheel_side="right",
                 mechanism="flange_climbing")
    line = dict(radius_m=800.0, cant_m=0.15, rail_spacing_m=1.5, class_speed_kmh=math.inf, gust_m_s=0.0,
                defect=True, hunting=False, faults=[], critical_speed_kmh=math.nan)
    plain = hazards(a, event, CAR, RULES)
    (cured,) = with_cure_leads(plain, line, RULES)
    assert cured["cure_lead_s"] == pytest.approx(3.0 + 10 / 3.6 / 0.8 + 170 / 3.6 / 0.9)
    assert window_of(cured, 5.0) == cured["cure_lead_s"] and window_of(plain[0], 5.0) == 5.0
    assert window_of(cured, 80.0) == 80.0
    places, rows = scoring.channel_places("wheel_lift", 8), scoring.Samples.of(a)
    standing = _alarms(4000, (1, 1000, 3000))              # from 10 s before the derailment
    label = windows(a["time"], [cured], 5.0)[1]
    assert not np.any(label[:3000] == scoring.NORMAL)      # 58.9 s reach back past the run's start
    assert scoring.score(standing, places, rows, [cured], 5.0, label)["warnings"] == [(pytest.approx(10.0), 50.0)]
    label = windows(a["time"], plain, 5.0)[1]
    assert scoring.score(standing, places, rows, plain, 5.0, label)["warnings"] == [(pytest.approx(5.0), 50.0)]


def test_false_alarms_are_counted_over_normal_running_only():
    """A near miss's window and running beyond permitted conditions are not exposure: a false alarm there is
    not a counted episode, and the exposure is the normal samples' km."""
    a = quiet_run(n=8000)                                       # 40 s, 2 km
    beyond = a["time"] >= 30.0                                  # the last 10 s above the permitted speed
    near = dict(kind="near_miss", margin="wheel_unloading", time_s=12.0, end_s=13.0, speed_m_s=50.0,
                position_m=600.0, places=[(1, 0)])
    label = windows(a["time"], [near], 5.0, beyond)[1]
    assert np.array_equal(label == BEYOND_PERMITTED, beyond)
    places, rows = scoring.channel_places("wheel_lift", 8), scoring.Samples.of(a)
    assert scoring.exposure(rows, label)[0] == pytest.approx((40.0 - 10.0 - 6.0) * 50.0 / 1000.0, abs=1e-3)
    # wheelset 0 (front bogie) in alarm in the rear bogie's near-miss window and in the beyond-permitted part
    out = scoring.score(_alarms(8000, (0, 1600, 2200), (0, 7000, 7200)), places, rows, [near], 5.0, label)
    assert out["false_episodes"] == 0 and out["false_time_s"] == 0.0 and out["window_false_episodes"] == 1
    # the same alarm in normal running (2 s to 5 s) is a counted episode of 3 s
    out = scoring.score(_alarms(8000, (0, 400, 1000)), places, rows, [near], 5.0, label)
    assert out["false_episodes"] == 1 and out["false_time_s"] == pytest.approx(3.0, abs=0.01)


def test_the_scored_episodes_cannot_fall_as_the_threshold_falls_over_random_runs():
    """Over seeded random signals of eight wheels with a derailment and a near miss, each threshold's
    alarms scored: a lower threshold never has fewer false-alarm episodes, less time in false alarm, or a
    hazard unwarned that a higher one warned (a standing episode only grows)."""
    rng = np.random.default_rng(7)
    a = quiet_run(n=6000)
    found = [dict(kind="near_miss", margin="wheel_unloading", time_s=9.0, end_s=9.5, speed_m_s=50.0,
                  position_m=450.0, places=[(0, 1)]),
             dict(kind="derailment", margin="flange_climbing", time_s=25.0, end_s=25.0, speed_m_s=50.0,
                  position_m=1250.0, places=[(1, 0)])]
    label = windows(a["time"], found, 5.0)[1]
    places = scoring.channel_places("wheel_lift", 8)
    for case in range(20):
        values = np.cumsum(rng.normal(0.0, 0.05, size=(6000, 8)), axis=0) * (1 + case % 3)
        values = np.abs(values - values.mean(axis=0))
        rows = []
        for thr in np.linspace(0.2, 2.0, 10):
            mask = np.array([scoring.in_alarm(values[:, k], a["position"], thr, 2.0, 0.9, 20.0) for k in range(8)])
            rows.append(scoring.score(mask, places, scoring.Samples.of(a), found, 5.0, label))
        for low, high in zip(rows, rows[1:]):
            assert low["false_episodes"] >= high["false_episodes"], case
            assert low["false_time_s"] >= high["false_time_s"] - 1e-12, case
            for wl, wh in zip(low["warnings"], high["warnings"]):
                assert wh is None or (wl is not None and wl[0] >= wh[0] - 1e-12), case


def test_each_mechanism_s_cure_and_the_lead_it_needs_by_hand():
    line = dict(radius_m=1000.0, cant_m=0.175, rail_spacing_m=1.5, class_speed_kmh=math.inf, gust_m_s=0.0,
                defect=False, hunting=False, faults=[], critical_speed_kmh=math.nan)
    at = lambda kmh, margin="wheel_unloading": dict(kind="derailment", margin=margin, speed_m_s=kmh / 3.6)
    # over-speed: v_c = sqrt(R (a_c + g h / e)) = 286.3 km/h, cured at 1/1.1 of it; permitted at 150 mm
    over = hazard_cure(RULES, at(295.0), line)
    critical = math.sqrt(1000.0 * (5.18 + 9.81 * 0.175 / 1.5)) * 3.6
    assert over["critical_speed_kmh"] == pytest.approx(critical) and over["speed_kmh"] == pytest.approx(critical / 1.1)
    assert over["permitted_speed_kmh"] == pytest.approx(math.sqrt(1000.0 * 9.81 * 0.325 / 1.5) * 3.6)
    # braking 295 -> 260.3 km/h: 0.9 m/s^2 to 230 would be past it, so all at 0.9; wet at the braking model's
    # degraded-adhesion 0.7 of the 230-300 km/h band
    cure = critical / 1.1
    assert lead_needed(RULES, 295 / 3.6, cure) == pytest.approx(3.0 + (295 - cure) / 3.6 / 0.9)
    assert lead_needed(RULES, 295 / 3.6, cure, "wet") == pytest.approx(3.0 + (295 - cure) / 3.6 / 0.7)
    # already below the cure: reaction and build-up only
    assert lead_needed(RULES, 250 / 3.6, cure) == pytest.approx(3.0)
    # a defect: a stop (from 160 km/h, 1.2 m/s^2 dry; 0.9 wet, the band below 170 km/h)
    stop = hazard_cure(RULES, at(160.0, "flange_climbing"), {**line, "defect": True})
    assert stop["speed_kmh"] == 0.0 and stop["mechanism"] == "flange climb at a defect"
    assert lead_needed(RULES, 160 / 3.6, 0.0, "wet") == pytest.approx(3.0 + 160 / 3.6 / 0.9)
    # a gust of 40 m/s on a curve: the curve's CWC passes 40.234 at 240 and 38.828 at 260 km/h
    gust = hazard_cure(RULES, at(280.0), {**line, "radius_m": 2000.0, "gust_m_s": 40.0})
    assert gust["speed_kmh"] == pytest.approx(240 + 20 * (40.234375 - 40.0) / (40.234375 - 38.828125))
    # hunting with a fault's own critical speed; without it the healthy car's nonlinear critical speed
    hunt = hazard_cure(RULES, at(250.0, "instability"), {**line, "radius_m": math.inf, "hunting": True,
                                                          "critical_speed_kmh": 196.0, "faults": ["yaw"]})
    assert hunt["speed_kmh"] == 196.0 and hunt["mechanism"] == "hunting with yaw"
    assert hazard_cure(RULES, at(250.0, "instability"), {**line, "radius_m": math.inf})["speed_kmh"] == 234.375


def test_running_beyond_the_permitted_speed_or_cant_deficiency_is_its_own_label():
    line = dict(radius_m=math.inf, cant_m=0.0, rail_spacing_m=1.5, class_speed_kmh=177.0, gust_m_s=0.0)
    from railderail_sim.parameters import GRAVITY
    speed = np.array([170.0, 176.9, 177.1, 170.0]) / 3.6
    deficiency = np.array([0.1, 0.1, 0.1, 0.16])          # m: the last above the permitted 150 mm
    a = dict(speed=speed, uncompensated_acceleration=deficiency * GRAVITY / 1.5)
    assert beyond_permitted(a, line, RULES).tolist() == [False, False, True, True]


def test_the_cure_s_car_values_are_the_shipped_reports():
    """The critical uncompensated acceleration is the smallest of the shipped progressive trials', and the
    characteristic wind curves are the shipped cwc.json's."""
    import json
    from pathlib import Path
    from railderail_monitor.evaluation import hazards as hz
    report = Path(__file__).resolve().parents[1] / "docs" / "report"
    trials = json.loads((report / "report.json").read_text())["trials"]
    g = 9.81
    a = [(t["refined_speed_kmh"] / 3.6) ** 2 / t["radius_m"] - g * t["cant_mm"] / 1000 / 1.5 for t in trials
         if t["friction"] == 0.3 and t["vehicle_set"] == "hs19"]
    assert RULES.critical_uncompensated_acceleration == pytest.approx(min(a), abs=0.01)
    curves = {c["case"]: c for c in json.loads((report / "cwc.json").read_text())["curves"]}
    assert tuple(curves["straight track"]["speed_kmh"]) == hz.CWC_SPEEDS_KMH
    assert tuple(curves["straight track"]["wind_speed_m_s"]) == hz.CWC_STRAIGHT_M_S
    assert tuple(curves["curve, a_q = 1 m/s^2"]["wind_speed_m_s"]) == hz.CWC_CURVE_M_S
    limit_cycle = json.loads((report / "report.json").read_text())["limit_cycle"]
    assert RULES.nonlinear_critical_speed_kmh == limit_cycle["nonlinear_critical_speed_kmh"]


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
    label = windows(a["time"], [], 5.0)[1]
    out = {}
    for thr in (0.8, 1.0):
        mask = np.zeros((8, len(s)), dtype=bool)
        mask[0] = scoring.in_alarm(v, s, thr, 2.0, 0.9, 20.0)
        out[thr] = scoring.score(mask, scoring.channel_places("wheel_lift", 8), scoring.Samples.of(a), [], 5.0, label)
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
    # the resolvable exposure: 1000 x 3.689 / budget (the Garwood bound of no event), 1230 km at 3 per 1000 km
    assert scoring.resolvable_km(3.0) == pytest.approx(1000 * -math.log(0.025) / 3.0)


def test_the_scenario_bootstrap_resamples_whole_scenarios_seeded():
    """Clusters that all have the same share give that share exactly; scenarios whose runs agree with each
    other (two identical runs each) give a wider interval than the same runs spread one per scenario, which
    the exact interval, taking the runs as independent, cannot tell apart; the same seed, the same interval."""
    same = np.array([[1, 2, 0, 100], [2, 4, 0, 100], [3, 6, 0, 100]], dtype=float)
    assert scoring.cluster_bootstrap(same, lambda x: x[:, 0] / x[:, 1]) == [0.5, 0.5]
    runs = np.array([[k % 2, 1, 0, 1] for k in range(20)], dtype=float)       # 10 warned of 20, one per scenario
    paired = np.array([[2, 2, 0, 2]] * 5 + [[0, 2, 0, 2]] * 5, dtype=float)     # the same, two alike per scenario
    share = lambda x: x[:, 0] / x[:, 1]
    lo1, hi1 = scoring.cluster_bootstrap(runs, share)
    lo2, hi2 = scoring.cluster_bootstrap(paired, share)
    assert hi2 - lo2 > hi1 - lo1
    assert scoring.cluster_bootstrap(runs, share) == [lo1, hi1]
