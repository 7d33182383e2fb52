"""The assessment of one run: EN 14363's quantities per section (`en14363`) and the ride comfort of the
run (`comfort`), as rows with their limits; `as_dict` is the JSON of `railderail assess --json`,
`markdown` its table (the governing place of each quantity and section, with its margin).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..parameters import GRAVITY, TrackParameters
from . import comfort, en14363
from .en14363 import Row

QUANTITIES = ("sum_Y_2m", "Y_Q_2m", "Q_max", "Q_qst", "Y_qst", "ydd_car_body", "zdd_car_body", "ydd_qst",
              "sum_Y_rms", "ydd_bogie_rms", "N_MV", "Wz_lateral", "Wz_vertical")
# each quantity in words, in EN 14363's notation (Y lateral, Q vertical wheel-rail force; docs/output-format.md)
NAMES = {"sum_Y_2m": "track-shift force ΣY, 2 m mean", "Y_Q_2m": "derailment quotient Y/Q, 2 m mean",
         "Q_max": "largest vertical wheel force Q", "Q_qst": "quasi-static vertical wheel force Q_qst",
         "Y_qst": "quasi-static lateral wheel force Y_qst", "ydd_car_body": "car-body lateral acceleration ÿ*",
         "zdd_car_body": "car-body vertical acceleration z̈*",
         "ydd_qst": "car-body quasi-static lateral acceleration ÿ*_qst",
         "sum_Y_rms": "track-shift force ΣY r.m.s. (stability)",
         "ydd_bogie_rms": "bogie-frame lateral acceleration r.m.s. (stability)",
         "N_MV": "mean comfort N_MV (EN 12299)", "Wz_lateral": "Sperling's ride index W_z, lateral",
         "Wz_vertical": "Sperling's ride index W_z, vertical"}
DISPLAY = {"N": ("kN", 1e-3)}                 # SI inside, kN in the JSON and the table
TABLE_UNITS = {"m/s^2": "m/s²", "-": ""}      # as the table prints them
N_MV_BLOCK_S = 300.0        # EN 12299: N_MV is the mean over 5 min; a shorter run's value is indicative only
STANDARD = {
    "edition": "EN 14363:2005 / UIC 518 (EN 14363:2016's Y/Q limit below R 250 m); EN 12299:2009; "
               "Sperling W_z as GB 5599",
    "method": "simulation of the normal measuring method's quantities (Y, Q of every wheel); one-dimensional "
              "method per track section (straight, transition, circular curve by radius); comfort N_MV "
              "simplified method at the car-body floor",
    "sources": "docs/assessment.md: every filter, window, percentile and limit with its source and how sure "
               "(B processing rules, C recalled limits)",
}


@dataclass
class Assessment:
    """Every assessed row, the sections, the instability frequency f0 used and what was not assessed."""
    rows: list
    sections: list
    static_wheel_load: float             # N
    instability_frequency: float         # Hz
    source: str = ""
    notes: list = field(default_factory=list)
    conditions: dict = field(default_factory=dict)       # run_conditions

    def as_dict(self):
        """The JSON of `railderail assess --json` (forces in kN)."""
        return dict(static_wheel_load_kN=self.static_wheel_load / 1e3,
                    standard=dict(STANDARD, instability_frequency_Hz=self.instability_frequency,
                                  not_assessed=self.notes),
                    run_conditions=self.conditions, quantities=[row_dict(r) for r in self.rows])

    def governing(self):
        """The row of the largest |value| / limit (or |value|) per quantity and section, in QUANTITIES order."""
        best = {}
        for r in self.rows:
            key = (r.section, r.quantity)
            u = r.utilisation if r.limit is not None else abs(r.value)
            if key not in best or u > best[key][0]:
                best[key] = (u, r)
        order = {q: k for k, q in enumerate(QUANTITIES)}
        names = [s.name for s in self.sections]
        return [r for _, r in sorted(best.values(), key=lambda item: (
            names.index(item[1].section) if item[1].section in names else len(names), order[item[1].quantity]))]

    def limiting(self):
        """The row closest to (or furthest beyond) its limit."""
        limited = [r for r in self.rows if r.limit is not None]
        return max(limited, key=lambda r: r.utilisation) if limited else None

    def markdown(self):
        lines = [f"Assessment of {self.source}: {STANDARD['edition']}.",
                 f"Static wheel load Q0 = {self.static_wheel_load / 1e3:.2f} kN, Prud'homme's limit "
                 f"{en14363.prudhomme_limit(self.static_wheel_load) / 1e3:.2f} kN, instability frequency "
                 f"f0 = {self.instability_frequency:.2f} Hz. The governing place of each quantity and section: "
                 "its magnitude against the limit, its sign apart (forces and accelerations in track axes, y "
                 "left, z up); Y lateral, Q vertical wheel-rail force (EN 14363's notation).", ""]
        lines += conditions_text(self.conditions) + [""]
        lines += ["| section | quantity | place | magnitude | sign | limit | unit | margin | result |",
                  "| --- | --- | --- | ---: | :---: | ---: | --- | ---: | --- |"]
        for r in self.governing():
            unit, scale = DISPLAY.get(r.unit, (r.unit, 1.0))
            unit = TABLE_UNITS.get(unit, unit)
            value = f"{abs(r.value) * scale:.3g}"
            sign = "−" if r.value < 0 else "+"
            if r.limit is None:
                limit = margin = "-"
                result = comfort.comfort_class(r.value) if r.quantity == "N_MV" else "-"
            else:
                limit = f"{r.limit * scale:.3g}"
                margin = f"{(r.limit - abs(r.value)) * scale:.3g}"
                result = "passes" if r.passes else "**fails**"
            lines.append(f"| {r.section} | {NAMES[r.quantity]} | {r.place} | {value} | {sign} | {limit} | {unit} | "
                         f"{margin} | {result} |")
        first = self.limiting()
        if first is not None:
            unit, scale = DISPLAY.get(first.unit, (first.unit, 1.0))
            unit = f" {TABLE_UNITS.get(unit, unit)}" if TABLE_UNITS.get(unit, unit) else ""
            lines += ["", f"Closest to its limit: {NAMES[first.quantity]} at {first.place}, {first.section}: "
                          f"{abs(first.value) * scale:.3g}{unit} ({'−' if first.value < 0 else '+'}) against "
                          f"{first.limit * scale:.3g}{unit} "
                          f"({100.0 * first.utilisation:.0f} % of it)."]
        lines += [f"Not assessed: {n}" for n in self.notes]
        return "\n".join(lines)


def run_conditions(sig, sections):
    """The run against the standard's test conditions: each circular curve's largest cant deficiency (mm; D = e
    a_q / g, a_q the uncompensated acceleration, e the rail spacing) beside EN 14363's test range, and how long
    the comfort record is; the cant deficiency None when the signals have no uncompensated acceleration."""
    e, limit = TrackParameters().rail_spacing, en14363.TEST_CANT_DEFICIENCY
    curves = []
    if sig.uncompensated_acceleration is not None:
        for sec in sections:
            if sec.kind == "curve":
                a_q = float(np.max(sig.uncompensated_acceleration[sec.samples(sig.position)]))
                curves.append(dict(section=sec.name, cant_deficiency_mm=e * a_q / GRAVITY * 1e3,
                                   outside_test_conditions=bool(e * a_q / GRAVITY > limit.value)))
    duration = float(sig.time[-1] - sig.time[0])
    return dict(curves=curves, test_cant_deficiency_mm=limit.value * 1e3, test_cant_deficiency_source=limit.source,
                duration_s=duration, comfort_indicative=bool(sig.floor is not None and duration < N_MV_BLOCK_S))


def conditions_text(c):
    """Lines: each curve's cant deficiency against the test conditions, and the comfort record's caveat."""
    lines = []
    for curve in c["curves"]:
        outside = curve["outside_test_conditions"]
        lines.append(f"Cant deficiency on {curve['section']}: up to {curve['cant_deficiency_mm']:.0f} mm, "
                     f"{'OUTSIDE' if outside else 'within'} the standard's test conditions (up to "
                     f"{c['test_cant_deficiency_mm']:.0f} mm; {c['test_cant_deficiency_source']})"
                     + (": its limits were not set for such a run." if outside else "."))
    if c["comfort_indicative"]:
        lines.append(f"N_MV from {c['duration_s']:.0f} s of record: EN 12299 takes it over {N_MV_BLOCK_S / 60:.0f} "
                     "min blocks, so this value is indicative only.")
    return lines


def row_dict(r: Row):
    unit, scale = DISPLAY.get(r.unit, (r.unit, 1.0))
    return dict(quantity=r.quantity, name=NAMES[r.quantity], section=r.section, wheelset=r.wheelset, side=r.side,
                value=r.value * scale,
                limit=None if r.limit is None else r.limit * scale, unit=unit, passes=r.passes)


def comfort_rows(sig):
    """N_MV per 5 min block and W_z lateral and vertical of the run, at the governing floor place."""
    rows = []
    places = list(sig.floor)
    blocks = {p: comfort.n_mv(sig.floor[p], sig.rate) for p in places}
    window = comfort.WINDOW_S
    for k, (first, last, _) in enumerate(blocks[places[0]]):
        name = "run" if len(blocks[places[0]]) == 1 else f"comfort block {k + 1}, {first * window:.0f}-{last * window:.0f} s"
        values = [blocks[p][k][2] for p in places]
        j = max(range(len(places)), key=lambda i: values[i])
        rows.append(Row("N_MV", name, None, None, values[j], None, "-", f"car-body floor, {places[j]}"))
    for quantity, axis, direction in (("Wz_lateral", 1, "lateral"), ("Wz_vertical", 2, "vertical")):
        values = [float(comfort.sperling(sig.floor[p][:, axis], sig.rate, direction).max()) for p in places]
        j = max(range(len(places)), key=lambda i: values[i])
        rows.append(Row(quantity, "run", None, None, values[j], comfort.WZ_LIMIT, "-", f"car-body floor, {places[j]}"))
    return rows


def assess(sig):
    """The Assessment of a run's signals (`signals.RunSignals`)."""
    rows, secs, f0 = en14363.assess(sig)
    notes = list(sig.notes)
    if sig.floor is not None:
        rows += comfort_rows(sig)
    return Assessment(rows=rows, sections=secs, static_wheel_load=sig.static_wheel_load,
                      instability_frequency=f0, source=sig.source, notes=notes, conditions=run_conditions(sig, secs))

