"""The on-board criteria on measured signals (railderail_monitor.onboard.criteria): closed cases on
synthetic records (a sine's sliding r.m.s. is its amplitude over sqrt 2 through the band's unit gain at its
centre; a burst of k peaks over the limit counts k), the limits from the bogie mass, the alarm masks."""
import math

import numpy as np
import pytest

from railderail_sim.assessment import filters
from railderail_sim.parameters import vehicle_parameters
from railderail_monitor.onboard import criteria as oc
from railderail_monitor.evaluation.scoring import in_alarm

RATE = 200.0
SPEED = 250.0 / 3.6


def _record(seconds, f, amplitude, start=0.0):
    t = np.arange(0.0, seconds, 1.0 / RATE)
    x = np.where(t >= start, amplitude * np.sin(2 * math.pi * f * (t - start)), 0.0)
    return t, x, SPEED * t


def test_bogie_limits_from_the_bogie_mass():
    # 6.86 t (a 3.3 t frame and two 1.78 t wheelsets): 12 - 6.86/5 = 10.628 m/s^2, r.m.s. half of it
    assert oc.bogie_limits(6860.0) == pytest.approx((10.628, 5.314))
    with pytest.raises(ValueError, match="bogie mass -1 kg"):
        oc.bogie_limits(-1.0)


def test_the_sliding_rms_of_a_sine_at_f0_is_its_amplitude_over_root_two():
    t, x, _ = _record(10.0, 5.0, 6.0)
    s = 100.0 / 1.4 * t                  # 100 m in 1.4 s: each window holds 7 whole periods
    m = oc.bogie_rms(t, x, s, 6860.0, 5.0)
    late = s > 300.0                     # the filter settled, whole windows of 100 m behind
    gain = filters.stability_band_pass(5.0).gain(5.0)[0]          # the analog filter's
    assert np.nanmin(m.value[late]) == pytest.approx(gain * 6.0 / math.sqrt(2.0), rel=2e-3)
    assert np.nanmax(m.value[late]) == pytest.approx(gain * 6.0 / math.sqrt(2.0), rel=2e-3)
    assert np.isnan(m.value[s < 99.0]).all()      # no window complete before 100 m
    # 4.24 r.m.s. stays under the 5.31 limit; 8 m/s^2 (5.66 r.m.s.) goes over
    assert not m.alarm_mask(s).any()
    assert oc.bogie_rms(t, 8.0 / 6.0 * x, s, 6860.0, 5.0).alarm_mask(s)[late].all()


def test_a_sine_off_the_band_is_rejected():
    t, x, s = _record(10.0, 15.0, 6.0)
    m = oc.bogie_rms(t, x, s, 6860.0, 5.0)
    assert np.nanmax(m.value[s > 300.0]) < 0.1 * 6.0 / math.sqrt(2.0)


def test_the_peak_count_counts_consecutive_half_waves_over_the_limit():
    x = np.array([0.0, 9.0, 3.0, -2.0, -9.0, -1.0, 2.0, 5.0, 1.0, -10.0, -3.0])
    # half-waves: [0, 9, 3] peak 9, [-2, -9, -1] peak -9, [2, 5, 1] peak 5 under the limit, [-10, -3] peak -10
    assert list(oc.consecutive_peaks(x, 8.0)) == [0, 1, 1, 1, 2, 2, 2, 2, 2, 1, 1]


def test_the_peak_count_within_a_window_drops_the_peaks_older_than_it():
    x = np.array([9.0, -9.0, 9.0, 1.0, -9.0, -1.0, 1.0, 1.0, -1.0])
    # half-wave peaks over 8 at samples 0, 1, 2, 4, the run broken by the half-wave [1, 1]; a window of 3 samples
    # keeps those
    # reached at n-2..n
    assert list(oc.consecutive_peaks(x, 8.0)) == [1, 2, 3, 3, 4, 4, 4, 4, 0]
    assert list(oc.consecutive_peaks(x, 8.0, 3)) == [1, 2, 3, 2, 2, 1, 1, 0, 0]


@pytest.mark.parametrize("window", [None, 1, 7, 40])
def test_the_peak_count_is_the_same_whatever_the_chunks(window):
    rng = np.random.default_rng(3)
    x = np.round(rng.normal(0.0, 6.0, 600))           # zeros and signed zeros, repeated values
    x[::37] = -0.0
    whole = oc.consecutive_peaks(x, 8.0, window)
    assert oc.consecutive_peaks(x, 8.0).max() >= 3     # runs of several peaks, broken and started again
    cuts = np.sort(rng.choice(np.arange(1, 600), 25, replace=False))
    counter = oc.PeakCounter(8.0, window)
    chunked = np.concatenate([counter(part) for part in np.split(x, cuts)])
    assert chunked.tolist() == whole.tolist()


@pytest.mark.parametrize("hz, cycles, alarms", [(7.5, 2.5, False), (7.5, 4.5, True), (4.5, 10.0, False)])
def test_the_bids_rule_alarms_on_more_than_six_peaks_within_500_ms(hz, cycles, alarms):
    # in the 4-8 Hz band, amplitude 14 (over the 8 m/s^2 limit after the band's gain): at 7.5 Hz 2.5 cycles
    # give 5 half-wave peaks (no alarm), 4.5 give 8 within 0.47 s (alarm at the seventh); at 4.5 Hz the
    # half-waves are 111 ms apart, so 500 ms never holds more than 5 of the 20 (no alarm)
    t = np.arange(0.0, 6.0, 1.0 / RATE)
    burst = (t >= 1.0) & (t < 1.0 + cycles / hz)
    x = np.where(burst, 14.0 * np.sin(2 * math.pi * hz * (t - 1.0)), 0.0)
    m = oc.peak_count(t, x)
    s = SPEED * t
    assert m.alarm_mask(s).any() == alarms
    assert (in_alarm(m.value, s, m.level, 0.0, 0.9, 50.0) == m.alarm_mask(s)).all()
    if hz == 4.5:        # without the window the same burst alarms: the window is what keeps it silent
        assert oc.peak_count(t, x, window_s=None).alarm_mask(s).any()


def test_car_body_lateral_and_its_quasi_static_value():
    t, x, s = _record(20.0, 2.0, 3.0)
    late = t > 5.0
    gain = filters.car_body_band_pass().gain(2.0)[0]
    assert np.max(oc.car_body_lateral(t, x).value[late]) == pytest.approx(3.0 * gain, rel=2e-3)
    assert oc.car_body_lateral(t, x).alarm_mask(s)[late].any()
    assert np.max(oc.car_body_lateral(t, 0.8 * x).value[late]) < 2.5          # 2.4 m/s^2
    steady = np.full_like(t, 1.6)
    q = oc.car_body_lateral_qst(t, steady, s)
    assert q.value[s > 150.0] == pytest.approx(1.6, rel=1e-3)
    assert q.alarm_mask(s)[s > 150.0].all() and not oc.car_body_lateral_qst(t, steady - 0.2, s).alarm_mask(s).any()


def test_car_body_roll_from_the_air_springs():
    vp = vehicle_parameters("hs19")
    t = np.arange(0.0, 5.0, 1.0 / 50.0)
    level = oc.roll_level(vp)                       # 35 mm over 1.23 m
    assert level == pytest.approx(0.035 / 1.23)
    roll = 1.1 * level
    d = np.zeros((len(t), 4))
    d[:, 1] = roll * 1.23                            # the right springs compressed: the left side up, roll +
    d[:, 0] = -roll * 1.23
    m = oc.car_body_roll(t, d, vp)
    assert m.value[-1] == pytest.approx(roll, rel=1e-3)
    assert m.alarm_mask(SPEED * t)[-1] and not oc.car_body_roll(t, d / 1.2, vp).alarm_mask(SPEED * t).any()


def test_the_odometer_distance_is_the_integrated_speed():
    t = np.arange(0.0, 10.0, 0.1)
    assert oc.odometer_distance(t, np.full_like(t, 50.0), [0.0, 5.0, 9.9]) == pytest.approx([0.0, 250.0, 495.0])
