"""The assessment's filters and frequency weightings, each an analog transfer function H(s) (numerator
and denominator polynomials in s, rad/s, highest power first, as scipy.signal builds them), applied in the
frequency domain: the record's FFT times H(j 2 pi f) at every bin (`scipy.signal.freqs`), then the inverse
FFT. So every gain is the standard's analog gain at every frequency up to the Nyquist frequency (a
bilinear digital filter at the 200 Hz output rate would move the weightings' 100 Hz band limit to 64 Hz),
and a sine of a whole number of periods comes out with exactly |H| times its amplitude and H's phase.

The record is taken as one period of a periodic signal; a ramp that closes the step where the period
wraps round (from the first sample to the one that would follow the last) is taken out before the FFT
and put back times H(0), the DC gain (a slow ramp passes a low-pass unchanged but for a delay of tens of milliseconds, a high-pass not
at all).

Filters (docs/assessment.md gives each one's source and how sure it is):
  EN 14363 forces, quasi-static accelerations  low-pass 20 Hz, Butterworth 4 poles
  EN 14363 car-body accelerations              band-pass 0.4-10 Hz, Butterworth 2 + 2 poles
  EN 14363 stability (sum Y, bogie frame)      band-pass f0 +- 2 Hz, Butterworth 2 + 2 poles
  EN 12299 / ISO 2631 / BS 6841 weightings     Wd (horizontal), Wb (vertical): H = Hh Hl Ht [Hs]
  Sperling (UIC 513's predecessor, GB 5599)    B(f) of the vertical and lateral directions, 0.5-40 Hz
"""
from __future__ import annotations

from dataclasses import dataclass
import math

import numpy as np
from scipy import signal

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class AnalogFilter:
    """H(s) = b(s) / a(s) (s in rad/s), optionally cut to a frequency band [band_hz[0], band_hz[1]]
    outside which the gain is zero (Sperling's band)."""
    name: str
    b: tuple
    a: tuple
    band_hz: tuple = (0.0, math.inf)

    def response(self, frequency_hz):
        """H(j 2 pi f) at each frequency (Hz)."""
        f = np.atleast_1d(np.asarray(frequency_hz, dtype=float))
        _, h = signal.freqs(self.b, self.a, worN=TWO_PI * f)
        return np.where((f >= self.band_hz[0]) & (f <= self.band_hz[1]), h, 0.0)

    def gain(self, frequency_hz):
        """|H(j 2 pi f)| at each frequency (Hz)."""
        return np.abs(self.response(frequency_hz))

    def apply(self, x, rate_hz):
        """The filtered record x (axis 0 is time, sampled at rate_hz) as described in the module."""
        x = np.asarray(x, dtype=float)
        n = x.shape[0]
        if n < 2:
            raise ValueError(f"the {self.name} filter needs at least 2 samples, the record has {n}")
        # the step where the period wraps round: the next sample, extrapolated from the last two, less the first
        step = 2.0 * x[-1] - x[-2] - x[0]
        trend = step * (np.arange(n) / n).reshape((n,) + (1,) * (x.ndim - 1))
        h = self.response(np.fft.rfftfreq(n, 1.0 / rate_hz)).reshape((-1,) + (1,) * (x.ndim - 1))
        y = np.fft.irfft(np.fft.rfft(x - trend, axis=0) * h, n, axis=0)
        return y + float(np.real(self.response(0.0)[0])) * trend


def butterworth(name, order, cutoff_hz, kind):
    """An analog Butterworth filter (scipy.signal.butter(analog=True)): low-pass of `order` poles at
    cutoff_hz, or band-pass of `order` poles at each edge of cutoff_hz = (low, high)."""
    b, a = signal.butter(order, TWO_PI * np.asarray(cutoff_hz, dtype=float), btype=kind, analog=True)
    return AnalogFilter(name, tuple(b), tuple(a))


FORCE_LOW_PASS_HZ = 20.0                 # EN 14363 / UIC 518: Y, Q and the quasi-static values (B)
CAR_BODY_BAND_HZ = (0.4, 10.0)           # EN 14363: car-body accelerations (B)
STABILITY_HALF_BAND_HZ = 2.0             # EN 14363: f0 +- 2 Hz (B)


def force_low_pass():
    return butterworth("20 Hz low-pass", 4, FORCE_LOW_PASS_HZ, "lowpass")


def car_body_band_pass():
    return butterworth("0.4-10 Hz band-pass", 2, CAR_BODY_BAND_HZ, "bandpass")


def stability_band_pass(f0_hz):
    """The band f0 +- 2 Hz around the instability frequency f0 (its lower edge at least 0.5 Hz)."""
    low = max(f0_hz - STABILITY_HALF_BAND_HZ, 0.5)
    return butterworth(f"{low:.2f}-{f0_hz + STABILITY_HALF_BAND_HZ:.2f} Hz band-pass", 2,
                       (low, f0_hz + STABILITY_HALF_BAND_HZ), "bandpass")


# --- the comfort weightings of ISO 2631-1 / BS 6841 / EN 12299 ----------------------------------------
@dataclass(frozen=True)
class WeightingParameters:
    """The parameters of H = Hh Hl Ht Hs (frequencies in Hz): band limits f1, f2 with Q1; the
    acceleration-velocity transition f3, f4 with Q2; the upward step f5, f6 with Q3, Q4 and gain K
    (f5 = None: no step)."""
    f1: float
    f2: float
    f3: float
    f4: float
    q1: float
    q2: float
    f5: float = None
    f6: float = None
    q3: float = None
    q4: float = None
    k: float = 1.0
    source: str = ""


WEIGHTINGS = {
    # ../shared/reference/onboard-and-assessment.md section 4.2 (B): BS 6841 in public code, the same
    # f-values and K in comfpy (whose Q2 = 0.63, Q3 = Q4 = 0.8 the sheet takes for a copy error)
    "Wb": WeightingParameters(0.4, 100.0, 16.0, 16.0, 0.71, 0.55, 2.5, 4.0, 0.9, 0.95, 0.4,
                              "EN 12299 / BS 6841, vertical (B)"),
    "Wd": WeightingParameters(0.4, 100.0, 2.0, 2.0, 0.71, 0.63, source="EN 12299 / ISO 2631-1, horizontal (B)"),
    # ISO 2631-1:1997 Table A.2 (memory, C): not used by the assessment; its tabulated gains (ISO 2631-1
    # Table 3) check the form H = Hh Hl Ht Hs shared with Wb, whose own table was not found
    # K = (f5/f6)^2: ISO writes the step rising from (f5/f6)^2 to 1
    "Wk": WeightingParameters(0.4, 100.0, 12.5, 12.5, 0.71, 0.63, 2.37, 3.35, 0.91, 0.91, (2.37 / 3.35) ** 2,
                              "ISO 2631-1, vertical seated (C)"),
}


def _second_order(w, q):
    """s^2 + w s / q + w^2."""
    return np.array([1.0, w / q, w * w])


def weighting(name):
    """The weighting `name` (a key of WEIGHTINGS) as an AnalogFilter."""
    p = WEIGHTINGS[name]
    w1, w2, w3, w4 = (TWO_PI * f for f in (p.f1, p.f2, p.f3, p.f4))
    b = np.polymul([1.0, 0.0, 0.0], [w2 * w2])                        # Hh Hl numerators: s^2 w2^2
    a = np.polymul(_second_order(w1, p.q1), _second_order(w2, p.q1))
    # Ht = (1 + s/w3) / (1 + s/(Q2 w4) + s^2/w4^2) = (w4^2/w3) (s + w3) / (s^2 + w4 s/Q2 + w4^2)
    b = np.polymul(b, np.array([1.0, w3]) * (w4 * w4 / w3))
    a = np.polymul(a, _second_order(w4, p.q2))
    if p.f5 is not None:
        w5, w6 = TWO_PI * p.f5, TWO_PI * p.f6
        # Hs = K (1 + s/(Q3 w5) + s^2/w5^2) / (1 + s/(Q4 w6) + s^2/w6^2)
        b = np.polymul(b, _second_order(w5, p.q3) * (p.k * w6 * w6 / (w5 * w5)))
        a = np.polymul(a, _second_order(w6, p.q4))
    else:
        b = b * p.k
    return AnalogFilter(name, tuple(b), tuple(a))


# --- Sperling's frequency weighting B(f) -------------------------------------------------------------
SPERLING_BAND_HZ = (0.5, 40.0)           # GB 5599 (C)
SPERLING_LATERAL_FACTOR = 1.25           # B_y = 1.25 B_z (B: two public codes)


def sperling_weighting(direction):
    """B(f) of `direction` ("vertical" or "lateral") as an AnalogFilter: with p = s / 2 pi,
    B_z(p) = 0.588 (0.25 p^2 + sqrt(1.911) p) / (0.0368 p^3 + 0.277 p^2 + 1.563 p + 1), whose gain is the
    tabulated |B_z(f)| = 0.588 sqrt((1.911 f^2 + (0.25 f^2)^2) / ((1 - 0.277 f^2)^2 + (1.563 f - 0.0368 f^3)^2))
    (B: comfpy, janiex/SimulinkMatlab); B_y = 1.25 B_z."""
    if direction not in ("vertical", "lateral"):
        raise ValueError(f"Sperling direction {direction!r} is not vertical or lateral")
    scale = 0.588 * (SPERLING_LATERAL_FACTOR if direction == "lateral" else 1.0)
    p = 1.0 / TWO_PI                                                   # p = s / 2 pi
    b = scale * np.array([0.25 * p * p, math.sqrt(1.911) * p, 0.0])
    a = np.array([0.0368 * p ** 3, 0.277 * p * p, 1.563 * p, 1.0])
    return AnalogFilter(f"Sperling B ({direction})", tuple(b), tuple(a), SPERLING_BAND_HZ)


def sperling_correction(frequency_hz, direction):
    """Sperling's tabulated correction F(f) of GB 5599 (C): vertical 0.325 f^2 (0.5-5.9 Hz), 400/f^2
    (5.9-20 Hz), 1 above; lateral 0.8 f^2 (0.5-5.4 Hz), 650/f^2 (5.4-26 Hz), 1 above. The single-frequency
    index is W_z = 0.896 (A^3 F(f) / f)^0.1, A in cm/s^2; B(f)^3 is its continuous form (B^3 ~ 0.896^10 F / f)."""
    f = np.asarray(frequency_hz, dtype=float)
    if direction == "vertical":
        return np.where(f <= 5.9, 0.325 * f * f, np.where(f <= 20.0, 400.0 / (f * f), 1.0))
    return np.where(f <= 5.4, 0.8 * f * f, np.where(f <= 26.0, 650.0 / (f * f), 1.0))
