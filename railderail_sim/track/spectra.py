"""The published spectra of track irregularities, each constant with its unit, source and how sure
(docs/track-irregularity.md); `irregularity` draws samples of them. Components: vertical profile, cross-level,
alignment and gauge (`irregularity` says how they make each rail's deviation).

Spectra: one-sided power spectral densities S(Omega) of the spatial angular frequency Omega (rad/m), the
variance being the integral of S over 0 < Omega < infinity; `Spectrum.psd` gives every component in
m^2/(rad/m), the cross-level as the height difference c.
  erri-low, erri-high  ERRI B176 (ORE), the levels of low and high disturbance (`erri_psd`). Its cross-level
                       is an angle (rad^2/(rad/m)); c = 2b times the angle, b = 0.75 m the half distance of
                       the rails, so 2b is the 1.500 m rail spacing of TrackParameters (EN 13803).
  fra-1 .. fra-6       FRA track classes (Hamid et al. 1983, `fra_psd`), A in cm^2 rad/m; cross-level and
                       gauge as height and width differences.
  china-hsr            TB/T 3352-2014, ballastless high-speed track (`tbt3352_psd_f` in the standard's own
                       units: f in 1/m, S in mm^2/(1/m); its cross-level is a height difference in mm, not an
                       angle). S_Omega(Omega) = S_f(Omega / 2 pi) / (2 pi) with mm^2 -> m^2 (`tbt3352_psd`).
Every constant is in ERRI, FRA or TBT3352 below with its unit, source and how sure it is (V verified in a
primary source, S documented in secondary sources, A assumed), as in parameters.py. No primary table was
reachable for this work (docs/track-irregularity.md says what was checked where). Where public
implementations disagree we follow the values the ones citing the primary sources agree on: ERRI low A_v
4.032e-7, high 10.80e-7 m rad, every high-level amplitude above the low one (some scripts swap the levels or
write 1.08e-7 for 10.80e-7); FRA Hamid's profile table with k = 0.25 and Omega_c = 0.8245 (some scripts
invent class values or give the FRA classes ERRI's formula); China the piecewise power law of TB/T 3352
(some scripts give it ERRI's form with an invented A).
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import partial
import math
from typing import Callable

import numpy as np

from .. import scalarmath

COMPONENTS = ("vertical", "cross_level", "alignment", "gauge")
MPH_KMH = 1.609344               # km/h per mph (exact)

SOURCES = {
    "ERRI": "ERRI B176/DT 290, Bogies with steered or steering wheelsets, Report 1, Utrecht 1993 (the ORE B176 "
            "spectra, after Frederich, Rail International 1985), as tabulated by Claus H., Schiehlen W., "
            "Modeling and simulation of railway bogie structural vibrations, Vehicle System Dynamics "
            "(IAVSD 1997 supplement), 1998; the same values in public implementations that agree",
    "FRA": "Hamid A., Rasmussen K., Baluja M., Yang T-L., Analytical descriptions of track geometry "
           "variations, US Federal Railroad Administration report (1983), as reproduced in Garg V.K., "
           "Dukkipati R.V., Dynamics of Railway Vehicle Systems (1984) and in public implementations",
    "TBT3352": "TB/T 3352-2014, PSD of ballastless track irregularities of high-speed railway (China), "
               "the average spectrum, as quoted by three public implementations that agree",
    "CFR": "49 CFR 213.9(a) (classes 1-5) and 213.307(a) (class 6 and higher), Track Safety Standards, "
           "the maximum allowable operating speed for passenger trains of each class (the regulation's text, "
           "public mirrors)",
    "model": "modelling choice of this project (docs/track-irregularity.md)",
}


@dataclass(frozen=True)
class Constant:
    """A constant of a spectrum: value (a number, or a tuple such as one value per level or class), unit,
    source (a key of SOURCES), sure (V, S or A) and a note."""
    value: object
    unit: str
    source: str
    sure: str
    note: str = ""


ERRI_LEVELS = ("low", "high")
ERRI = {
    "omega_c": Constant(0.8246, "rad/m", "ERRI", "S", "break frequency of every component"),
    "omega_r": Constant(0.0206, "rad/m", "ERRI", "S", "low-frequency roll-off"),
    "omega_s": Constant(0.4380, "rad/m", "ERRI", "S", "break of the cross-level and gauge spectra"),
    "b": Constant(0.75, "m", "ERRI", "S", "half the distance of the rails; 2b = 1.500 m, the rail spacing"),
    "A_v": Constant((4.032e-7, 10.80e-7), "m rad", "ERRI", "S", "vertical profile (and cross-level), low, high"),
    "A_a": Constant((2.119e-7, 6.125e-7), "m rad", "ERRI", "S", "alignment, low, high"),
    "A_g": Constant((0.532e-7, 1.032e-7), "m rad", "ERRI", "S", "gauge, low, high"),
    "band": Constant((1.0, 150.0), "m", "model", "A", "no band found in the sources reached"),
}
FRA_CLASSES = (1, 2, 3, 4, 5, 6)
FRA = {
    "k": Constant(0.25, "-", "FRA", "S", "the report's factor of every formula"),
    "omega_c": Constant(0.8245, "rad/m", "FRA", "S", "break frequency of every class"),
    "A_v": Constant((1.2107, 1.0181, 0.6816, 0.5376, 0.2095, 0.0339), "cm^2 rad/m", "FRA", "S",
                    "vertical profile (and cross-level), classes 1..6"),
    "A_a": Constant((3.3634, 1.2107, 0.4128, 0.3027, 0.0762, 0.0339), "cm^2 rad/m", "FRA", "A",
                    "alignment, classes 1..6; unconfirmed: found in no source reached"),
    "omega_s": Constant((0.6046, 0.9308, 0.8520, 1.1312, 0.8209, 0.4380), "rad/m", "FRA", "A",
                        "break of cross-level and gauge, classes 1..6; unconfirmed: found in no source "
                        "reached"),
    "band": Constant((1.524, 304.8), "m", "FRA", "S", "5 ft .. 1000 ft, the wavelengths of the report's fits"),
    "passenger_speed": Constant((15.0, 30.0, 60.0, 80.0, 90.0, 110.0), "mph", "CFR", "V",
                                "the highest speed a passenger train may run on track of each class 1..6: the "
                                "line speed of a class's geometry"),
}
FRA_CROSS_LEVEL_FACTOR = Constant(4.0, "-", "FRA", "A", "cross-level and gauge S = 4 k A_v Omega_c^2 / "
                                  "((Omega^2 + Omega_c^2)(Omega^2 + Omega_s^2)), the gauge with A_v too; "
                                  "unconfirmed: found in no source reached")
TBT3352 = {  # S_f = A_i / f^n_i between the breaks, f in 1/m, S_f in mm^2/(1/m)
    "vertical": Constant(((0.0187, 0.0474, 0.1533), (1.0544e-5, 3.5588e-3, 1.9784e-2, 3.9488e-4),
                          (3.3891, 1.9271, 1.3643, 3.4516)), "1/m; mm^2 (1/m)^(n-1); -", "TBT3352", "S",
                         "breaks, A, n; adjacent pieces meet at the breaks within 0.4 %"),
    "alignment": Constant(((0.0450, 0.1234), (3.9513e-3, 1.1047e-2, 7.5633e-4), (1.8670, 1.5354, 2.8171)),
                          "1/m; mm^2 (1/m)^(n-1); -", "TBT3352", "S", "breaks, A, n; pieces meet within 0.03 %"),
    "cross_level": Constant(((0.0258, 0.1163), (3.6148e-3, 4.3685e-2, 4.5867e-3), (1.7278, 1.0461, 2.0939)),
                            "1/m; mm^2 (1/m)^(n-1); -", "TBT3352", "S",
                            "breaks, A, n of the rails' height difference in mm; pieces meet within 0.13 %"),
    "gauge": Constant(((0.1090, 0.2938), (5.4978e-2, 5.0701e-3, 1.8778e-4), (0.8282, 1.9037, 4.5948)),
                      "1/m; mm^2 (1/m)^(n-1); -", "TBT3352", "S", "breaks, A, n; pieces meet within 0.04 %"),
    "frequencies": Constant((0.005, 0.5), "1/m", "TBT3352", "S",
                            "where the fit holds: wavelengths 2 .. 200 m; the standard's text (as reproduced "
                            "publicly) excludes wavelengths below 2 m and extrapolates beyond 120 m"),
}


def checked_component(component):
    """The component's name, checked (ValueError naming the accepted ones)."""
    if component not in COMPONENTS:
        raise ValueError(f"component {component!r} is not one of {', '.join(COMPONENTS)}")
    return component


def constants_table():
    """Rows (name, value, unit, source, sure, note) of every constant, for documentation."""
    groups = {"erri": ERRI, "fra": FRA, "tbt3352": TBT3352}
    rows = [(f"{group}.{key}", c.value, c.unit, c.source, c.sure, c.note)
            for group, table in groups.items() for key, c in table.items()]
    c = FRA_CROSS_LEVEL_FACTOR
    return rows + [("fra.cross_level_factor", c.value, c.unit, c.source, c.sure, c.note)]


def erri_psd(component, omega, level):
    """ERRI B176 PSD of a component at omega (rad/m) for level 'low' or 'high': m^2/(rad/m), the cross-level
    as an angle in rad^2/(rad/m)."""
    i = ERRI_LEVELS.index(level)
    w2 = np.square(np.asarray(omega, dtype=float))
    wc2, wr2, ws2 = ERRI["omega_c"].value ** 2, ERRI["omega_r"].value ** 2, ERRI["omega_s"].value ** 2
    shape = wc2 / ((w2 + wr2) * (w2 + wc2))
    if checked_component(component) == "vertical":
        return ERRI["A_v"].value[i] * shape
    if component == "alignment":
        return ERRI["A_a"].value[i] * shape
    amplitude = ERRI["A_v"].value[i] / ERRI["b"].value ** 2 if component == "cross_level" else ERRI["A_g"].value[i]
    return amplitude * shape * w2 / (w2 + ws2)


def permitted_speed_kmh(spectrum):
    """The highest speed (km/h) a passenger train may run on the track a spectrum (a name of SPECTRA, or
    any other source: inf) describes (`Spectrum.permitted_speed_kmh`)."""
    return SPECTRA[spectrum].permitted_speed_kmh if spectrum in SPECTRA else math.inf


def fra_psd(component, omega, track_class):
    """FRA PSD of a component at omega (rad/m) for track class 1..6: m^2/(rad/m), the cross-level and the
    gauge as height and width differences."""
    i = FRA_CLASSES.index(track_class)
    w2 = np.square(np.asarray(omega, dtype=float))
    k, wc2, cm2 = FRA["k"].value, FRA["omega_c"].value ** 2, 1e-4
    if checked_component(component) in ("vertical", "alignment"):
        amplitude = FRA["A_v" if component == "vertical" else "A_a"].value[i] * cm2
        return k * amplitude * wc2 / (w2 * (w2 + wc2))
    amplitude = FRA_CROSS_LEVEL_FACTOR.value * k * FRA["A_v"].value[i] * cm2
    return amplitude * wc2 / ((w2 + wc2) * (w2 + FRA["omega_s"].value[i] ** 2))


def tbt3352_psd_f(component, f):
    """TB/T 3352 PSD in the standard's units: f in 1/m, S in mm^2/(1/m) (cross-level: the rails' height
    difference in mm); NaN outside the frequencies where the fit holds."""
    breaks, amplitudes, exponents = TBT3352[checked_component(component)].value
    f = np.asarray(f, dtype=float)
    piece = np.searchsorted(breaks, f, side="right")
    with np.errstate(divide="ignore", invalid="ignore"):
        # libm's pow, not numpy's: its AVX-512 loops round fractional powers differently (scalarmath)
        s = np.asarray(amplitudes)[piece] / scalarmath.power(f, np.asarray(exponents)[piece])
    lo, hi = TBT3352["frequencies"].value
    return np.where((f >= lo) & (f <= hi), s, np.nan)


def tbt3352_psd(component, omega):
    """TB/T 3352 PSD at omega (rad/m) in m^2/(rad/m): S_f(omega / 2 pi) / (2 pi), mm^2 -> m^2."""
    return tbt3352_psd_f(component, np.asarray(omega, dtype=float) / (2.0 * math.pi)) * 1e-6 / (2.0 * math.pi)


@dataclass(frozen=True)
class Spectrum:
    """A named spectrum: `psd(component, omega)` in m^2/(rad/m) with the cross-level as the height
    difference c; `band_m` its default band (shortest, longest wavelength in m); `validity_m` the
    wavelengths outside which it is undefined (None: the formula holds for every wavelength);
    `permitted_speed_kmh` the highest passenger speed on the track it describes, where its source gives one
    (the FRA classes: FRA["passenger_speed"]), else inf."""
    name: str
    title: str
    band_m: tuple
    validity_m: tuple | None
    psd: Callable
    permitted_speed_kmh: float = math.inf


def _erri_rail_psd(component, omega, level):
    scale = (2.0 * ERRI["b"].value) ** 2 if component == "cross_level" else 1.0
    return scale * erri_psd(component, omega, level)


def _spectra():
    table = {f"erri-{level}": Spectrum(f"erri-{level}", f"ERRI B176, {level} level", ERRI["band"].value, None,
                                       partial(_erri_rail_psd, level=level)) for level in ERRI_LEVELS}
    table.update({f"fra-{c}": Spectrum(f"fra-{c}", f"FRA track class {c}", FRA["band"].value, None,
                                       partial(fra_psd, track_class=c), mph * MPH_KMH)
                  for c, mph in zip(FRA_CLASSES, FRA["passenger_speed"].value)})
    lo, hi = TBT3352["frequencies"].value
    table["china-hsr"] = Spectrum("china-hsr", "TB/T 3352-2014, ballastless high-speed track", (1 / hi, 1 / lo),
                                  (1 / hi, 1 / lo), tbt3352_psd)
    return table


SPECTRA = _spectra()


def spectrum_named(name):
    if name not in SPECTRA:
        raise ValueError(f"spectrum {name!r} is not one of {', '.join(SPECTRA)}")
    return SPECTRA[name]

