"""Track irregularities as data: the published spectra, random samples of them, the CSV file format and the
array the numba core reads (docs/track-irregularity.md).

Channels and components. An irregularity is the deviation of each rail's position from the ideal track, in
the track frame of docs/design.md (lateral + to the left, vertical + up), as four channels of s: left
lateral yL, left vertical zL, right lateral yR, right vertical zR. The spectra describe four components:
  vertical profile  v = (zL + zR) / 2
  cross-level       c = zL - zR   a height difference, + when the left rail is the higher one
  alignment         a = (yL + yR) / 2
  gauge             g = yL - yR   + for a widening: the left rail further left, the right rail further right
so that zL = v + c/2, zR = v - c/2, yL = a + g/2, yR = a - g/2. (The spectra are those of zero-mean Gaussian
processes and carry no sign; the signs matter for files and for the core's geometry.)

Samples (`generate`): each component an independent sum of cosines, sum_k a_k cos(Omega_k s + phi_k), on
the lines Omega_k = k dOmega of a period P = N step, N the first fast FFT length (2^a 3^b 5^c) not below
the n points of the sample, so that dOmega = 2 pi / P < 2 pi / length (no repetition within the sample);
phases uniform in [0, 2 pi) from numpy.random.default_rng(seed), drawn component after component. The
amplitude a_k = sqrt(2 S_k dOmega) with S_k the mean of S over the line's cell ((k -+ 1/2) dOmega, clipped
to the band; 4-point Gauss): the cells tile the band, so the variance is the integral of S over the band
(exactly over a whole period; the sample is the first n of the N points). Values and their exact
derivatives d/ds at the points come out of one inverse real FFT each, bit-identical for the same inputs.
Wavelengths longer than 2 P cannot be held; the sample's `band_m` is the band it holds.
"""
from __future__ import annotations

from array import array
from dataclasses import dataclass
import math
import warnings
from pathlib import Path

import numpy as np

from .. import scalarmath
from ..atomic import atomic_write
from ..ranges import check_range
from .rails import HERMITE, RailDeviation, pack_rails, rail_deviation, rail_deviations
from .spectra import COMPONENTS, SPECTRA, checked_component, spectrum_named

COMPONENT_TITLES = {"vertical": "vertical profile", "cross_level": "cross-level (rails' height difference)",
                    "alignment": "alignment", "gauge": "gauge"}
CHANNELS = tuple(RailDeviation.names())
CSV_HEADER = "s_m,left_lateral_mm,left_vertical_mm,right_lateral_mm,right_vertical_mm"
LENGTH_M = (10.0, 200e3)         # accepted sample length
STEP_M = (0.05, 1.0)             # accepted grid step
BAND_LIMITS_M = (0.5, 1000.0)    # a band's wavelengths must lie inside
MAX_FILE_MM = 500.0              # a file value beyond this is a unit error, not a track
STEP_WARNING_MM = 1.0            # a record that starts or ends further off zero meets its rails with a step
SEEDS = (0, 999_999)             # accepted seeds
TAPER_M = 50.0                   # a generated sample's fade-in and fade-out (`taper`)
NONE = "none"                    # no irregularity: the ideal rails
LINE_MARGIN_M = 25.0             # a run's sample reaches this far beyond the end of its line
UNIFORM_TOLERANCE_M = 1e-9       # steps equal to this are one uniform step (Welch needs one)

def checked_band(spectrum, band_m, step_m):
    """The band (shortest, longest wavelength, m) checked: inside BAND_LIMITS_M and the spectrum's validity,
    shortest < longest, and at least two grid steps per shortest wavelength (Nyquist)."""
    if band_m is None:
        band_m = spectrum.band_m
    short, long_ = (check_range("band wavelength", w, *BAND_LIMITS_M, "m") for w in band_m)
    if short >= long_:
        raise ValueError(f"band {short:g}..{long_:g} m: the shortest wavelength must come first and be the "
                         f"smaller")
    if spectrum.validity_m is not None:
        lo, hi = spectrum.validity_m
        if short < lo * (1 - 1e-12) or long_ > hi * (1 + 1e-12):
            raise ValueError(f"band {short:g}..{long_:g} m is outside the accepted range [{lo:g}, {hi:g}] m "
                             f"of {spectrum.name}")
    if short < 2.0 * step_m:
        raise ValueError(f"band shortest wavelength {short:g} m needs a step of at most {short / 2:g} m "
                         f"(the step is {step_m:g} m)")
    return short, long_


GAUSS_X, GAUSS_W = np.polynomial.legendre.leggauss(4)


def fast_length(n):
    """The smallest 2^a 3^b 5^c >= n, a length the FFT does fast."""
    best = 1 << (n - 1).bit_length()
    p5 = 1
    while p5 < best:
        p35 = p5
        while p35 < best:
            best = min(best, p35 << (math.ceil(n / p35) - 1).bit_length())
            p35 *= 3
        p5 *= 5
    return best


def line_amplitudes(spectrum, component, n, step, band):
    """(k, a_k, held) of the lines k dOmega (dOmega = 2 pi / (n step), below the grid's Nyquist frequency)
    whose cells ((k -+ 1/2) dOmega) meet the band: a_k = sqrt(2 x the PSD's integral over the cell within the
    band); held = (lowest, highest) frequency the cells cover, in rad/m."""
    d_omega = 2.0 * math.pi / (n * step)
    lo, hi = 2.0 * math.pi / band[1], 2.0 * math.pi / band[0]
    k = np.arange(max(1, math.floor(lo / d_omega + 0.5)), min((n - 1) // 2, math.ceil(hi / d_omega - 0.5)) + 1)
    left = np.maximum((k - 0.5) * d_omega, lo)
    right = np.minimum((k + 0.5) * d_omega, hi)
    keep = right > left
    if not keep.any():
        raise ValueError(f"band {band[0]:g}..{band[1]:g} m holds no line of the sample's grid (lines every "
                         f"{d_omega:.4g} rad/m): widen the band or lengthen the sample")
    k, left, right = k[keep], left[keep], right[keep]
    half = 0.5 * (right - left)
    nodes = (left + half)[:, None] + half[:, None] * GAUSS_X
    variance = half * (spectrum.psd(component, nodes) @ GAUSS_W)
    return k, np.sqrt(2.0 * variance), (left[0], right[-1])


def check_seed(seed):
    """The seed, if it is an integer in SEEDS; else ValueError naming it and the range."""
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not SEEDS[0] <= seed <= SEEDS[1]:
        raise ValueError(f"seed {seed!r} is outside the accepted range: an integer in [{SEEDS[0]}, {SEEDS[1]}]")
    return seed


def generate(spectrum, length_m, seed, step_m=0.25, band_m=None, taper_m=TAPER_M):
    """A random sample (`Irregularity`, cubic Hermite) of a spectrum (a name of SPECTRA) over 0..length_m at
    step_m, from the seed; band_m (shortest, longest wavelength) defaults to the spectrum's band. The sample
    fades in and out over taper_m (at most a quarter of it) at its ends (`taper`), so that a run meets no
    step where it begins."""
    spec = spectrum_named(spectrum)
    length = check_range("length", length_m, *LENGTH_M, "m")
    step = check_range("step", step_m, *STEP_M, "m")
    check_seed(seed)
    band = checked_band(spec, band_m, step)
    n = math.ceil(length / step - 1e-9) + 1
    period_points = fast_length(n)
    d_omega = 2.0 * math.pi / (period_points * step)
    rng = np.random.default_rng(seed)
    components, slopes, held = {}, {}, None
    for name in COMPONENTS:
        k, a, held = line_amplitudes(spec, name, period_points, step, band)
        lines = np.zeros(period_points // 2 + 1, dtype=complex)
        phase = rng.uniform(0.0, 2.0 * math.pi, size=k.size)
        lines[k] = 0.5 * period_points * a * (scalarmath.cos(phase) + 1j * scalarmath.sin(phase))
        components[name] = np.fft.irfft(lines, period_points)[:n]
        slopes[name] = np.fft.irfft(1j * d_omega * np.arange(lines.size) * lines, period_points)[:n]
    s = step * np.arange(n)
    band_held = (float(2.0 * math.pi / held[1]), float(2.0 * math.pi / held[0]))
    values, slopes = taper(s, rails_from_components(components), rails_from_components(slopes),
                           min(taper_m, 0.25 * (s[-1] - s[0])))
    return Irregularity(s, values, slopes,
                        name=f"{spec.name} seed {seed}",
                        description=f"{spec.title}, random phases",
                        seed=int(seed), spectrum=spec.name, band_m=band_held)


def taper(s, values, slopes, taper_m):
    """Values and slopes (n, 4) times a raised-cosine window that rises from 0 over the first taper_m of s and
    falls to 0 over the last (m; 0: none). The slopes stay exact: w y' + w' y."""
    check_range("taper", taper_m, 0.0, 0.5 * (s[-1] - s[0]), "m")
    if taper_m == 0.0:
        return values, slopes
    u = np.clip(np.minimum(s - s[0], s[-1] - s) / taper_m, 0.0, 1.0)
    w = 0.5 * (1.0 - np.cos(math.pi * u))
    dw = np.where(u < 1.0, 0.5 * math.pi / taper_m * np.sin(math.pi * u), 0.0) \
        * np.where(s - s[0] <= s[-1] - s, 1.0, -1.0)
    return w[:, None] * values, w[:, None] * slopes + dw[:, None] * values


def lateral_kink(start, length, amplitude, step=0.25, periods=1):
    """Both rails moved sideways by one period of a cosine, A/2 (1 - cos(2 pi (s - start) / L)) over
    start <= s <= start + L (m): a smooth (C1) alignment defect of peak A to the left in the middle, the
    limit-cycle method's excitation. With `periods` > 1 that many such periods follow each other with
    alternating sign (2: an S, left then right, which leaves the car no net lateral offset to follow). Cubic
    Hermite on a `step` grid with the exact slopes (the largest error of the shape, A (2 pi step / L)^4 / 384,
    is 2e-9 m for 10 mm over 20 m)."""
    if not (length > 0.0 and step > 0.0) or periods not in (1, 2):
        raise ValueError(f"lateral kink: length {length:g} m and step {step:g} m must be positive and periods "
                         f"{periods!r} 1 or 2")
    n = periods * max(int(round(length / step)), 2) + 1
    s = np.linspace(start, start + periods * length, n)
    w = 2.0 * np.pi / length
    sign = np.where(s - start < length, 1.0, -1.0)
    lateral = 0.5 * amplitude * sign * (1.0 - np.cos(w * (s - start)))
    slope = 0.5 * amplitude * sign * w * np.sin(w * (s - start))
    zero = np.zeros(n)
    shape = "" if periods == 1 else "S-"
    return Irregularity(s, np.column_stack((lateral, zero, lateral, zero)),
                        np.column_stack((slope, zero, slope, zero)), name=f"{shape}kink {amplitude * 1e3:g} mm",
                        description=f"lateral {shape}kink of {amplitude * 1e3:g} mm over {periods * length:g} m "
                                    f"from s = {start:g} m")


def twist(start, length, amplitude, hold, side, step=0.25):
    """One rail (`side` 0 left, 1 right) lowered by a half cosine, A/2 (1 - cos(pi (s - start) / L)) over
    start <= s <= start + L (m), held at A over `hold` m and raised again the same way: a twist of A over L
    (1 : L/A), the other rail untouched. Cubic Hermite on a `step` grid with the exact slopes."""
    if not (length > 0.0 and hold >= 0.0 and step > 0.0) or side not in (0, 1):
        raise ValueError(f"twist: length {length:g} m and step {step:g} m must be positive, hold {hold:g} m not "
                         f"negative and side {side!r} 0 (left) or 1 (right)")
    n = max(int(round(length / step)), 2) + 1
    ramp = np.linspace(0.0, length, n)
    w = math.pi / length
    down, slope_down = -0.5 * amplitude * (1.0 - np.cos(w * ramp)), -0.5 * amplitude * w * np.sin(w * ramp)
    s = np.concatenate((start + ramp, start + length + hold + ramp[1:] if hold > 0 else start + length + ramp[1:]))
    z = np.concatenate((down, down[::-1][1:]))
    slope = np.concatenate((slope_down, -slope_down[::-1][1:]))
    values, slopes = np.zeros((len(s), 4)), np.zeros((len(s), 4))
    values[:, 2 * side + 1], slopes[:, 2 * side + 1] = z, slope
    rail = ("left", "right")[side]
    return Irregularity(s, values, slopes, name=f"twist {amplitude * 1e3:g} mm",
                        description=f"the {rail} rail {amplitude * 1e3:g} mm down over {length:g} m from s = "
                                    f"{start:g} m, held {hold:g} m")


def superpose(a, b):
    """The sum of two irregularities (either may be None) on the union of their points, values and slopes of
    each taken as the core interpolates it (`rails.rail_deviation`), so cubic Hermite throughout."""
    if a is None or b is None:
        return b if a is None else a
    s = np.union1d(a.s, b.s)
    values, slopes = np.zeros((len(s), 4)), np.zeros((len(s), 4))
    for irregularity in (a, b):
        packed = irregularity.pack()
        for i, x in enumerate(s):
            for side in range(2):
                y, z, dy, dz = rail_deviation(packed, side, float(x))
                values[i, 2 * side] += y
                values[i, 2 * side + 1] += z
                slopes[i, 2 * side] += dy
                slopes[i, 2 * side + 1] += dz
    return Irregularity(s, values, slopes, name=f"{a.name} + {b.name}", description=f"{a.description}; {b.description}",
                        seed=a.seed if a.seed is not None else b.seed, spectrum=a.spectrum or b.spectrum,
                        band_m=a.band_m or b.band_m)


def vertical_wave(amplitude, wavelength, length, step):
    """Both rails in one vertical sine, amplitude sin(2 pi s / wavelength) over 0 <= s < length (m), cubic
    Hermite on a `step` grid with the exact slopes: the dynamic wheel load's textbook input."""
    if not (wavelength > 0.0 and length > 0.0 and 0.0 < step < wavelength):
        raise ValueError(f"vertical wave: wavelength {wavelength:g} m, length {length:g} m and step {step:g} m "
                         "must be positive, the step below the wavelength")
    s = np.arange(0.0, length, step)
    k = 2.0 * np.pi / wavelength
    zero = np.zeros_like(s)
    height, slope = amplitude * np.sin(k * s), amplitude * k * np.cos(k * s)
    return Irregularity(s, np.column_stack((zero, height, zero, height)), np.column_stack((zero, slope, zero, slope)),
                        name=f"wave {amplitude * 1e3:g} mm", description=f"vertical sine of {amplitude * 1e3:g} mm, "
                                                                     f"{wavelength:g} m wavelength")


def resolve(source, seed, line_length_m):
    """The irregularity of a run configured with `source`: None for "none", the file of that path (.csv),
    or a sample of the spectrum of that name (SPECTRA) from the seed, over the line and LINE_MARGIN_M
    beyond its end, where the leading wheelset runs when the car body reaches it."""
    if source == NONE:
        return None
    if source in SPECTRA:
        return generate(source, line_length_m + LINE_MARGIN_M, seed)
    if str(source).lower().endswith(".csv"):
        return read_csv(source)
    raise ValueError(f"irregularity {source!r} is not {NONE!r}, a spectrum ({', '.join(SPECTRA)}) or a .csv file")


def rails_from_components(c):
    """(n, 4) rail channels in CHANNELS order from the components v, c, a, g (module docstring)."""
    return np.stack((c["alignment"] + 0.5 * c["gauge"], c["vertical"] + 0.5 * c["cross_level"],
                     c["alignment"] - 0.5 * c["gauge"], c["vertical"] - 0.5 * c["cross_level"]), axis=-1)


@dataclass(frozen=True, eq=False)
class Irregularity:
    """Rail position deviations: s (n,) in m, strictly increasing; values (n, 4) in m, channels in CHANNELS
    order; slopes (n, 4) d/ds for cubic Hermite interpolation, or None for linear interpolation (files);
    zero outside s[0]..s[-1]. seed, spectrum and band_m (wavelengths held) describe a generated sample."""
    s: np.ndarray
    values: np.ndarray
    slopes: np.ndarray | None = None
    name: str = ""
    description: str = ""
    seed: int | None = None
    spectrum: str | None = None
    band_m: tuple | None = None

    def __post_init__(self):
        for name in ("s", "values") + (("slopes",) if self.slopes is not None else ()):
            object.__setattr__(self, name, np.asarray(getattr(self, name), dtype=float))
        n = len(self.s)
        if n < 2 or self.values.shape != (n, 4) or (self.slopes is not None and self.slopes.shape != (n, 4)):
            raise ValueError(f"irregularity {self.name!r}: needs n >= 2 points with (n, 4) values and slopes")
        if not np.all(np.diff(self.s) > 0):
            raise ValueError(f"irregularity {self.name!r}: s must increase strictly")

    def at(self, s):
        """The (..., 4) channels at s (m) as the core interpolates them (`rails.rail_deviation`)."""
        s = np.asarray(s, dtype=float)
        out = np.zeros((s.size, 4))
        rail_deviations(self.pack(), s.ravel(), out)
        return out.reshape(s.shape + (4,))

    def components(self):
        """{component: (n,) array} of the vertical profile, cross-level, alignment and gauge at the points."""
        yl, zl, yr, zr = self.values.T
        return {"vertical": 0.5 * (zl + zr), "cross_level": zl - zr, "alignment": 0.5 * (yl + yr),
                "gauge": yl - yr}

    def uniform_step(self):
        """The points' spacing if it is uniform within UNIFORM_TOLERANCE_M, else 0."""
        steps = np.diff(self.s)
        step = (self.s[-1] - self.s[0]) / (len(self.s) - 1)
        return float(step) if np.all(np.abs(steps - step) <= UNIFORM_TOLERANCE_M) else 0.0

    def pack(self):
        """The core's `rails` array (`rails.pack_rails`): linear without slopes, else cubic Hermite."""
        if self.slopes is None:
            return pack_rails(self.s, self.values)
        return pack_rails(self.s, self.values, self.slopes, HERMITE)

    def summary(self):
        """RMS of the channels and components in mm, with the sample's description."""
        def rms(x):
            return float(np.sqrt(np.mean(np.square(x)))) * 1e3
        return {"name": self.name, "description": self.description, "spectrum": self.spectrum, "seed": self.seed,
                "points": len(self.s), "length_m": float(self.s[-1] - self.s[0]), "step_m": self.uniform_step(),
                "band_m": self.band_m,
                "rms_mm": {**{c: rms(self.values[:, j]) for j, c in enumerate(CHANNELS)},
                           **{c: rms(x) for c, x in self.components().items()}}}


def welch_psd(irregularity, component, segment_m):
    """Welch estimate of a component's one-sided PSD per rad/m (scipy.signal.welch, Hann segments of about
    segment_m with half overlap): (omega in rad/m, S in m^2/(rad/m)); needs uniform points."""
    from scipy.signal import welch

    step = irregularity.uniform_step()
    if step == 0.0:
        raise ValueError(f"irregularity {irregularity.name!r}: a Welch estimate needs uniformly spaced points")
    x = irregularity.components()[checked_component(component)]
    f, p = welch(x, fs=1.0 / step, nperseg=min(len(x), int(round(segment_m / step))))
    return 2.0 * math.pi * f[1:], p[1:] / (2.0 * math.pi)


def write_csv(irregularity, path):
    """Write the file format (docs/track-irregularity.md): CSV_HEADER, then s in m and the channels in mm,
    linear between the points; atomically."""
    table = np.column_stack((irregularity.s, irregularity.values * 1e3)).tolist()
    row = ",".join(["%.6f"] * (1 + len(CHANNELS))) + "\n"     # s in m and the channels in mm, to 1 nm
    with atomic_write(path) as handle:
        handle.write(CSV_HEADER + "\n")
        handle.writelines(row % tuple(values) for values in table)


def read_csv(path):
    """An `Irregularity` (linear) from a file of the format; a bad file is a one-line ValueError naming the
    file, the line and the value."""
    where = f"irregularity file {str(path)!r}"
    names = CSV_HEADER.split(",")
    values = array("d")            # flat, 8 bytes a number: a long file costs no Python objects per value
    number = 0
    try:
        with open(path, encoding="utf-8-sig") as handle:
            for number, line in enumerate(handle, start=1):
                if number == 1:
                    if line.strip() != CSV_HEADER:
                        raise ValueError(f"{where}, line 1: header {line.strip()[:80]!r} is not {CSV_HEADER!r}")
                    continue
                if not line.strip():
                    continue
                fields = line.split(",")
                if len(fields) != len(names):
                    raise ValueError(f"{where}, line {number}: {len(fields)} values {line.strip()[:80]!r}, "
                                     f"expected {len(names)} ({CSV_HEADER})")
                s = _number(where, number, names[0], fields[0])
                if len(values) and s <= values[-len(names)]:
                    raise ValueError(f"{where}, line {number}: s_m {s:g} m does not increase (the line before: "
                                     f"{values[-len(names)]:g} m)")
                values.append(s)
                values.extend(_number(where, number, name, text) for name, text in zip(names[1:], fields[1:]))
    except (OSError, UnicodeDecodeError) as error:
        raise ValueError(f"{where} cannot be read ({getattr(error, 'strerror', None) or error})") from None
    if number == 0:
        raise ValueError(f"{where}, line 1: empty, expected the header {CSV_HEADER!r}")
    table = np.frombuffer(values, dtype=float).reshape(-1, len(names))
    if len(table) < 2:
        raise ValueError(f"{where}, line {number}: {len(table)} data row(s) after the header, at least 2 needed")
    for row, end in ((table[0], "first"), (table[-1], "last")):
        k = int(np.argmax(np.abs(row[1:])))
        if abs(row[1 + k]) > STEP_WARNING_MM:
            warnings.warn(f"{where}: its {end} row (s = {row[0]:g} m) has {names[1 + k]} {row[1 + k]:g}; outside the "
                          f"record the rails are at zero, so a run meets a {abs(row[1 + k]):g} mm step there (start "
                          "and end the record at zero, or taper it)", stacklevel=2)
    return Irregularity(table[:, 0].copy(), table[:, 1:] * 1e-3, None, name=Path(path).stem,
                        description=f"read from {Path(path).name}")


def _number(where, number, name, text):
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"{where}, line {number}: {name} {text.strip()[:40]!r} is not a number") from None
    if not math.isfinite(value):
        raise ValueError(f"{where}, line {number}: {name} {text.strip()!r} is not a finite number")
    if name != "s_m" and abs(value) > MAX_FILE_MM:
        raise ValueError(f"{where}, line {number}: {name} {value:g} mm is outside the accepted range "
                         f"[{-MAX_FILE_MM:g}, {MAX_FILE_MM:g}] mm")
    return value
