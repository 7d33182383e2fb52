"""EN 14363's running-behaviour quantities of the simulation method, per track section (the
one-dimensional method's sections), from a run's signals (`signals.RunSignals`).

Followed: EN 14363:2005 / UIC 518 (the normal measuring method's quantities, which a simulation gives
directly: Y and Q of every wheel), with the small-radius Y/Q limit of EN 14363:2016. The standard's text
was not reachable: every figure below comes from ../shared/reference/onboard-and-assessment.md section 3
and track-and-loads.md section 3, with how sure it is (B: the processing rules, confirmed by GENSYS's
course page and other public sources; C: a recalled limit, not checked in the standard); docs/assessment.md
has the table.

    quantity       signal (filter)                           processing                  statistic
    sum_Y_2m       Y_left + Y_right of a wheelset (20 Hz)    2 m sliding mean, 0.5 m     0.15 % / 99.85 %
    Y_Q_2m         Y/Q of a wheel, Y to its flange (20 Hz)   2 m sliding mean, 0.5 m     99.85 %
    Q_max          Q of a wheel (20 Hz)                      -                           99.85 %
    Q_qst, Y_qst   Q, Y of a wheel (20 Hz)                   circular curves             50 %
    ydd_car_body   floor over a bogie, lateral (0.4-10 Hz)   -                           0.15 % / 99.85 %
    zdd_car_body   the same, vertical                        -                           0.15 % / 99.85 %
    ydd_qst        floor over a bogie, lateral (20 Hz)       circular curves             50 %
    sum_Y_rms      sum Y (f0 +- 2 Hz)                        100 m sliding r.m.s., 10 m  maximum
    ydd_bogie_rms  bogie frame over a wheelset (f0 +- 2 Hz)  100 m sliding r.m.s., 10 m  maximum

A section is a run of one kind of track at the car-body centre (straight, transition, circular curve)
at least MIN_SECTION_M long; each wheelset and each measuring point is assigned to the section it is
over. The quasi-static values are evaluated on circular curves only. Where several sections of one test
zone are assessed, `one_dimensional` combines them (x = mean + k s).
"""
from __future__ import annotations

from dataclasses import dataclass
import math

import numpy as np
from scipy import signal as sps

from . import filters

KMH = 1.0 / 3.6
MIN_SECTION_M = 100.0        # C: EN 14363 curve sections of at least 100 m (sheet section 3.1)
WINDOW_2M = 2.0              # m, B
STEP_2M = 0.5                # m, B
RMS_WINDOW_M = 100.0         # m, C
RMS_STEP_M = 10.0            # m, C
PERCENTILES = (0.15, 99.85)  # %, B
ONE_DIMENSIONAL_K = 2.2      # C: the one-dimensional method's x = y + k s
INSTABILITY_BAND_HZ = (1.5, 12.0)   # where f0 is looked for (bogie hunting 5-8 Hz, car body 1-3 Hz; C)
SECTION_KINDS = {0: "straight", 1: "transition", 2: "curve"}


@dataclass(frozen=True)
class Limit:
    """A limit value with where it comes from."""
    value: float
    unit: str
    source: str
    sure: str


ALPHA_PASSENGER = 1.0        # C: alpha of Prud'homme's limit for locomotives, power heads, coaches, MUs
Q_MAX_BY_SPEED_KMH = ((160.0, 200e3), (200.0, 190e3), (250.0, 180e3), (300.0, 170e3), (math.inf, 160e3))  # C
LIMITS = {
    "Y_Q_2m": Limit(0.8, "-", "EN 14363 / UIC 518, R >= 250 m (railwaynews.net UIC 518 page, GENSYS)", "B"),
    "Y_Q_2m_small_radius": Limit(1.2, "-", "EN 14363:2016, R < 250 m (recalled)", "C"),
    "Q_qst": Limit(145e3, "N", "EN 14363:2005 / UIC 518 (recalled)", "C"),
    "Y_qst": Limit(60e3, "N", "EN 14363:2005 / UIC 518 (recalled; 2016: about 30 + 10500/R kN)", "C"),
    "ydd_car_body": Limit(2.5, "m/s^2", "UIC 518 passenger coaches and MUs (recalled, 2.5-3.0 by edition)", "C"),
    "zdd_car_body": Limit(2.5, "m/s^2", "UIC 518 passenger coaches and MUs (recalled, 2.5-3.0 by edition)", "C"),
    "ydd_qst": Limit(1.5, "m/s^2", "EN 14363:2005 (recalled)", "C"),
}
# the largest cant deficiency of the standard's on-track tests, 1.1 I_adm, with I_adm = 150 mm (EN 13803's
# exceptional limit on lines up to 300 km/h, as assessment/study.py takes it): beyond it the limits above were
# never meant to be met, and a run there says how the car behaves outside the conditions it is accepted for
TEST_CANT_DEFICIENCY = Limit(0.165, "m", "EN 14363:2005 test conditions, cant deficiency up to 1.1 I_adm "
                             "(recalled), I_adm 150 mm (EN 13803, recalled)", "C")


def prudhomme_limit(static_wheel_load, alpha=ALPHA_PASSENGER):
    """Prud'homme's track-shift force limit alpha (10 + 2 Q0 / 3) kN with Q0 the static wheel load in kN
    (= alpha (10 + P0 / 3) with P0 the static axle load), in N. Formula B, alpha C."""
    return alpha * (10.0 + 2.0 * static_wheel_load / 1e3 / 3.0) * 1e3


def q_max_limit(speed):
    """The limit of Q_max (N) at a permitted speed (m/s): 200 kN up to 160 km/h, then 190, 180, 170,
    160 kN above 300 km/h (C)."""
    v = speed / KMH
    return next(q for top, q in Q_MAX_BY_SPEED_KMH if v <= top + 1e-9)


def bogie_rms_limit(bogie_mass):
    """The sliding r.m.s. limit of the bogie frame's lateral acceleration, (12 - M_b / 5) / 2 m/s^2 with
    M_b in t (C)."""
    return (12.0 - bogie_mass / 1e3 / 5.0) / 2.0


def test_zone(kind, radius):
    """EN 14363's test zone of a section (C): 1 straight and R >= 600 m... as the sheet gives them."""
    if kind == "straight":
        return "zone 1 (straight)"
    if kind == "transition":
        return "transition"
    if radius >= 600.0:
        return "zone 2 (R >= 600 m)"
    if radius >= 400.0:
        return "zone 3 (400 <= R < 600 m)"
    if radius >= 250.0:
        return "zone 4 (250 <= R < 400 m)"
    return "small radius (R < 250 m, EN 14363:2016)"


@dataclass(frozen=True)
class Section:
    """A track section: kind, its extent in track coordinates [start, end) (m; a run's first and last end
    at its first and last car-body position),
    the length the run covers, the circular curve's radius (inf otherwise) and the highest speed on it."""
    kind: str
    start: float
    end: float
    covered: float
    radius: float
    max_speed: float

    @property
    def name(self):
        where = f"{self.start:.0f}-{self.end:.0f} m"
        return f"{self.kind} R {self.radius:.0f} m, {where}" if self.kind == "curve" else f"{self.kind}, {where}"

    @property
    def zone(self):
        return test_zone(self.kind, self.radius)

    def samples(self, s):
        """The slice of the samples whose track position s (increasing) lies on the section."""
        return slice(int(np.searchsorted(s, self.start, "left")), int(np.searchsorted(s, self.end, "left")))


def sections(sig):
    """The run's track sections (runs of one `section` flag at the car-body centre) of at least
    MIN_SECTION_M covered; ValueError if none is long enough."""
    flag = sig.section
    change = np.flatnonzero(np.diff(flag)) + 1
    starts = np.concatenate([[0], change])
    stops = np.concatenate([change, [len(flag)]])
    found, short = [], []
    for k, (i, j) in enumerate(zip(starts, stops)):
        # the ends of the run: what lies beyond the car body's first and last sample is not known
        a = sig.position[0] if k == 0 else 0.5 * (sig.position[i - 1] + sig.position[i])
        b = np.nextafter(sig.position[-1], math.inf) if j == len(flag) else 0.5 * (sig.position[j - 1] + sig.position[j])
        covered = sig.position[j - 1] - sig.position[i]
        kind = SECTION_KINDS.get(int(flag[i]), "transition")
        curv = np.abs(sig.curvature[i:j])
        radius = 1.0 / float(np.median(curv)) if kind == "curve" and np.median(curv) > 0 else math.inf
        sec = Section(kind, a, b, float(covered), radius, float(np.max(sig.speed[i:j])))
        (found if covered >= MIN_SECTION_M else short).append(sec)
    if not found:
        raise ValueError(f"{sig.source or 'the run'} has no track section of at least {MIN_SECTION_M:g} m (the "
                         f"longest covers {max(s.covered for s in short):.1f} m): a section's percentiles need it")
    return found


# --- processing --------------------------------------------------------------------------------------
def sliding(s, values, window, step, start, end, power=1):
    """The sliding mean of values**power over `window` m of track, at centres every `step` m with the whole
    window inside [start, end) and inside the samples' span (trapezoidal integral over s); (centres, means)."""
    lo = max(start, s[0]) + 0.5 * window
    hi = min(end, s[-1]) - 0.5 * window
    if len(s) < 2 or hi < lo:
        return np.zeros(0), np.zeros((0,) + values.shape[1:])
    centres = lo + step * np.arange(int(math.floor((hi - lo) / step + 1e-9)) + 1)
    v = values ** power
    ds = np.diff(s).reshape((-1,) + (1,) * (v.ndim - 1))
    integral = np.concatenate([np.zeros((1,) + v.shape[1:]), np.cumsum(0.5 * ds * (v[1:] + v[:-1]), axis=0)])
    cols = integral.reshape(len(s), -1)
    upper = np.stack([np.interp(centres + 0.5 * window, s, c) for c in cols.T], -1)
    lower = np.stack([np.interp(centres - 0.5 * window, s, c) for c in cols.T], -1)
    return centres, ((upper - lower) / window).reshape((len(centres),) + v.shape[1:])


def extreme(values):
    """The 0.15 % or the 99.85 % percentile, whichever is larger in magnitude (signed), per column."""
    lo, hi = np.percentile(values, PERCENTILES, axis=0)
    return np.where(np.abs(hi) >= np.abs(lo), hi, lo)


def spectral_peak(x, rate):
    """The frequency (Hz) of the peak in INSTABILITY_BAND_HZ of the Welch spectrum (4 s segments) of the
    record x (n,) or (n, channels), the channels' spectra summed; None when no frequency of the spectrum
    lies in the band (a record too short)."""
    x = np.asarray(x, dtype=float)
    nper = min(len(x), int(round(4.0 * rate)))
    f, p = sps.welch(x - x.mean(axis=0), fs=rate, nperseg=nper, axis=0)
    band = (f >= INSTABILITY_BAND_HZ[0]) & (f <= INSTABILITY_BAND_HZ[1])
    if not band.any():
        return None
    power = p[band] if p.ndim == 1 else p[band].sum(axis=1)
    return float(f[band][np.argmax(power)])


def instability_frequency(sig):
    """f0 (Hz): the peak of the Welch spectrum in INSTABILITY_BAND_HZ of the bogie frames' lateral
    accelerations (summed over the four places), or of the wheelsets' sum Y without them."""
    x = sig.bogie_frame if sig.bogie_frame is not None else \
        sig.lateral_force[:, 0::2] + sig.lateral_force[:, 1::2]
    f0 = spectral_peak(x, sig.rate)
    return 0.5 * sum(INSTABILITY_BAND_HZ) if f0 is None else f0


@dataclass(frozen=True)
class Row:
    """One assessed value: quantity, section, place (wheelset 0-3 and side, None where not per wheel or
    wheelset), value and limit in SI (`unit`), and the place's name for people."""
    quantity: str
    section: str
    wheelset: int | None
    side: str | None
    value: float
    limit: float | None
    unit: str
    place: str = ""

    @property
    def passes(self):
        return None if self.limit is None else bool(abs(self.value) <= self.limit)

    @property
    def utilisation(self):
        return None if self.limit is None else abs(self.value) / self.limit


SIDES = ("left", "right")


def _wheel_rows(quantity, sec, values, limit, unit):
    return [Row(quantity, sec.name, w // 2, SIDES[w % 2], float(values[w]), limit, unit,
                f"wheelset {w // 2} {SIDES[w % 2]}") for w in range(8)]


def _governing(quantity, sec, values, places, limit, unit):
    """One row of the place with the largest |value| (the car body's ends)."""
    k = int(np.argmax(np.abs(values)))
    return Row(quantity, sec.name, None, None, float(values[k]), limit, unit, places[k])


def assess_forces(sig, sec, filtered_y, filtered_q, stable_y=None):
    """Rows of sum_Y_2m, Y_Q_2m, Q_max (and Q_qst, Y_qst on a circular curve; sum_Y_rms with the
    band-passed sum Y `stable_y`) of one section."""
    rows = []
    q0 = sig.static_wheel_load
    y_lim = prudhomme_limit(q0)
    yq_limit = LIMITS["Y_Q_2m_small_radius" if sec.radius < 250.0 else "Y_Q_2m"].value
    q_lim = q_max_limit(sec.max_speed)
    quasi = {"Q": [], "Y": []}
    for i, station in enumerate(sig.wheelset_stations):
        inside = sec.samples(sig.position + station)
        if inside.stop - inside.start < 3:
            continue
        s = sig.position[inside] + station
        sum_y = filtered_y[inside, 2 * i] + filtered_y[inside, 2 * i + 1]
        _, means = sliding(s, sum_y, WINDOW_2M, STEP_2M, sec.start, sec.end)
        if len(means):
            rows.append(Row("sum_Y_2m", sec.name, i, None, float(extreme(means)), y_lim, "N", f"wheelset {i}"))
        # Y/Q with Y toward each wheel's rail's field side (the push of a flanging wheel): the left wheel's + left
        flange_ward = filtered_y[inside, 2 * i:2 * i + 2] * np.array([1.0, -1.0])
        q = filtered_q[inside, 2 * i:2 * i + 2]
        ratio = np.where(q >= 0.1 * q0, flange_ward / np.maximum(q, 1e-9), 0.0)
        _, yq = sliding(s, ratio, WINDOW_2M, STEP_2M, sec.start, sec.end)
        for k in range(2):
            w = 2 * i + k
            if len(yq):
                rows.append(Row("Y_Q_2m", sec.name, i, SIDES[k], float(np.percentile(yq[:, k], PERCENTILES[1])),
                                yq_limit, "-", f"wheelset {i} {SIDES[k]}"))
            rows.append(Row("Q_max", sec.name, i, SIDES[k], float(np.percentile(q[:, k], PERCENTILES[1])),
                            q_lim, "N", f"wheelset {i} {SIDES[k]}"))
            if sec.kind == "curve":
                quasi["Q"].append((w, float(np.median(q[:, k]))))
                quasi["Y"].append((w, float(np.median(filtered_y[inside, w]))))
        if stable_y is not None:
            _, rms = sliding(s, stable_y[inside, i], RMS_WINDOW_M, RMS_STEP_M, sec.start, sec.end, power=2)
            if len(rms):
                rows.append(Row("sum_Y_rms", sec.name, i, None, float(np.sqrt(rms.max())), 0.5 * y_lim, "N",
                                f"wheelset {i}"))
    for name, values in (("Q_qst", quasi["Q"]), ("Y_qst", quasi["Y"])):
        for w, v in values:
            rows.append(Row(name, sec.name, w // 2, SIDES[w % 2], v, LIMITS[name].value, "N",
                            f"wheelset {w // 2} {SIDES[w % 2]}"))
    return rows


def assess_accelerations(sig, sec, band_floor, low_floor, stable_frame):
    """Rows of ydd_car_body, zdd_car_body (and ydd_qst on a circular curve) at the floor over the bogies,
    and ydd_bogie_rms of the frame over each wheelset, of one section."""
    rows = []
    ends = ("front", "rear")
    peaks_y, peaks_z, qst = [], [], []
    for place, station in zip(ends, sig.bogie_stations):
        inside = sec.samples(sig.position + station)
        if inside.stop - inside.start < 3:
            continue
        peaks_y.append((place, float(extreme(band_floor[place][inside, 1]))))
        peaks_z.append((place, float(extreme(band_floor[place][inside, 2]))))
        if sec.kind == "curve":
            qst.append((place, float(np.median(low_floor[place][inside, 1]))))
    for name, found in (("ydd_car_body", peaks_y), ("zdd_car_body", peaks_z), ("ydd_qst", qst)):
        if found:
            places, values = zip(*found)
            rows.append(_governing(name, sec, np.array(values), [f"car-body floor over the {p} bogie" for p in places],
                                   LIMITS[name].value, "m/s^2"))
    limit = bogie_rms_limit(sig.bogie_mass)
    for i, station in enumerate(sig.wheelset_stations):
        inside = sec.samples(sig.position + station)
        _, rms = sliding(sig.position[inside] + station, stable_frame[inside, i], RMS_WINDOW_M, RMS_STEP_M,
                         sec.start, sec.end, power=2)
        if len(rms):
            rows.append(Row("ydd_bogie_rms", sec.name, i, None, float(np.sqrt(rms.max())), limit, "m/s^2",
                            f"bogie frame over wheelset {i}"))
    return rows


def assess(sig):
    """(rows, sections, f0 Hz) of every EN 14363 quantity the signals allow, per section."""
    secs = sections(sig)
    rate = sig.rate
    low = filters.force_low_pass()
    y = low.apply(sig.lateral_force, rate)
    q = low.apply(sig.vertical_force, rate)
    f0 = instability_frequency(sig)
    band = filters.stability_band_pass(f0)
    stable_y = band.apply(sig.lateral_force[:, 0::2] + sig.lateral_force[:, 1::2], rate)
    rows = []
    if sig.floor is not None:
        body = filters.car_body_band_pass()
        band_floor = {p: body.apply(a, rate) for p, a in sig.floor.items()}
        low_floor = {p: low.apply(a, rate) for p, a in sig.floor.items()}
        stable_frame = band.apply(sig.bogie_frame, rate)
    for sec in secs:
        rows += assess_forces(sig, sec, y, q, stable_y)
        if sig.floor is not None:
            rows += assess_accelerations(sig, sec, band_floor, low_floor, stable_frame)
    return rows, secs, f0


def one_dimensional(values, k=ONE_DIMENSIONAL_K):
    """The one-dimensional method's estimate over the sections of one test zone at one condition: the mean
    of the section values plus k times their sample standard deviation (C); at least 3 sections."""
    v = np.asarray(values, dtype=float)
    if len(v) < 3:
        raise ValueError(f"the one-dimensional method needs at least 3 sections of a zone, {len(v)} given")
    return float(v.mean() + k * v.std(ddof=1))
