"""The report section docs/report/assessment.md (`railderail assess --study DIR`): the stand-in CRH3 at its
permitted speed over several track qualities and radii, rigid and elastic track, assessed as EN 14363 and
EN 12299 define it, beside the critical derailment speed of the report's real-track study.

Each case is one constant-speed run over the Table 2 line (straight, transition, the circular curve of its
radius with 175 mm cant, transition, straight) with LEAD_IN_M more straight before it, assessed from the
Table 2 line's start (the car's start-up on irregular rails left out), on a seeded irregularity of one spectrum
(track.irregularity), at the speed that gives the curve PERMITTED_CANT_DEFICIENCY of cant deficiency
(capped at the car's top speed); a second speed, at the exceptional EXCEPTIONAL_CANT_DEFICIENCY, shows
what limits first as the speed rises.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass, replace
import json
from pathlib import Path
import statistics

from .. import jsonout, plotting
from ..atomic import atomic_write
from ..parameters import TrackParameters
from ..track import irregularity as ir
from ..vehicle.simulate import Scenario, constant_speed, simulate
from . import assess, signals

KMH = 1.0 / 3.6
PERMITTED_CANT_DEFICIENCY = 0.100    # m; C: EN 13803's recommended limits for high-speed lines are 80-100 mm
EXCEPTIONAL_CANT_DEFICIENCY = 0.150  # m; C: EN 13803's exceptional limit on lines up to 300 km/h
TOP_SPEED_KMH = 350.0                # the CRH3's maximum operating speed (V)
RADII = (800.0, 1000.0, 1200.0, 1400.0, 1600.0, 1800.0)   # m, the paper's six radii
SPECTRA = ("erri-low", "erri-high", "fra-5", "fra-6", "china-hsr")
SEED = 1
LEAD_IN_M = 400.0                    # m of straight before the Table 2 line: the start-up settles there
REAL_TRACK = Path(__file__).resolve().parents[2] / "docs" / "report" / "real-track.jsonl"


@dataclass(frozen=True)
class Case:
    radius: float
    irregularity: str
    model: str = "rigid"
    cant_deficiency: float = PERMITTED_CANT_DEFICIENCY

    @property
    def speed_kmh(self):
        track = TrackParameters(radius=self.radius)
        return min(TOP_SPEED_KMH, track.speed_at_cant_deficiency(self.cant_deficiency) / KMH)

    @property
    def label(self):
        return (f"R {self.radius:.0f} m, {self.irregularity}, {self.model}, {self.speed_kmh:.0f} km/h "
                f"(D {self.cant_deficiency * 1e3:.0f} mm)")


def cases():
    """Every radius on each spectrum (rigid) at the permitted speed; ERRI high on elastic track; ERRI high
    at the exceptional cant deficiency."""
    out = [Case(r, s) for r in RADII for s in SPECTRA]
    out += [Case(r, "erri-high", "elastic") for r in RADII]
    out += [Case(r, "erri-high", cant_deficiency=EXCEPTIONAL_CANT_DEFICIENCY) for r in RADII]
    return out


def run_case(case: Case):
    """{case, speed, status, the assessment's rows (JSON form), the limiting row} of one case."""
    base = Scenario()
    table2 = TrackParameters(radius=case.radius)
    track = replace(table2, straight_in=table2.straight_in + LEAD_IN_M)
    sc = replace(base, track=track, track_model=case.model, speed_table=constant_speed(case.speed_kmh),
                 irregularity=ir.resolve(case.irregularity, SEED, track.line_length)).validated()
    result = simulate(sc)
    a = assess.assess(signals.from_arrays(result.arrays(), sc.vehicle, case.label).after(LEAD_IN_M))
    first = a.limiting()
    return dict(case=asdict(case), label=case.label, speed_kmh=case.speed_kmh,
                uncompensated_acceleration=track.uncompensated_acceleration(case.speed_kmh * KMH),
                status=result.status, simulated_s=float(result.time[-1]),
                governing=[dict(assess.row_dict(r), place=r.place, utilisation=r.utilisation)
                           for r in a.governing()],
                limiting=dict(assess.row_dict(first), place=first.place, utilisation=first.utilisation))


def critical_speeds(path=REAL_TRACK):
    """{(model, irregularity, radius): median critical derailment speed over the seeds (km/h)} of the
    report's real-track study, {} without its file."""
    path = Path(path)
    if not path.is_file():
        return {}
    found = {}
    for line in path.read_text().splitlines():
        row = json.loads(line)
        if row.get("critical_derailment_speed_kmh") is not None and row.get("cant_mm") == 175.0:
            found.setdefault((row["model"], row["irregularity"], row["radius_m"]), []).append(
                row["critical_derailment_speed_kmh"])
    return {key: statistics.median(v) for key, v in found.items()}


def _largest(summary, quantity):
    """(utilisation, row) of a quantity's most used governing row of a case."""
    rows = [r for r in summary["governing"] if r["quantity"] == quantity]
    return max(((r["utilisation"] if r["utilisation"] is not None else r["value"], r) for r in rows),
               key=lambda item: item[0], default=(None, None))


TABLE_QUANTITIES = ("sum_Y_2m", "Y_Q_2m", "Q_max", "Y_qst", "ydd_car_body", "ydd_qst", "ydd_bogie_rms")


def markdown(summaries, critical, command):
    lines = ["# Running behaviour at permitted speeds (EN 14363, EN 12299, Sperling)", "",
             f"Made by `{command}` (railderail_sim.assessment.study): {len(summaries)} constant-speed runs over "
             "the Table 2 line (200 m straight, 200 m transition, 1000 m circular curve with 175 mm cant, 200 m "
             f"transition, 200 m straight) after {LEAD_IN_M:.0f} m more straight (the start-up, not assessed; "
             f"section positions count from the lead-in's start), each on seed {SEED} of its irregularity "
             "spectrum, the stand-in CRH3 "
             f"(hs19) at the speed giving {PERMITTED_CANT_DEFICIENCY * 1e3:.0f} mm of cant deficiency on the curve "
             f"(the permitted speed, C: EN 13803) and, on ERRI high, at {EXCEPTIONAL_CANT_DEFICIENCY * 1e3:.0f} mm "
             "(exceptional). Simulated time "
             f"{sum(s['simulated_s'] for s in summaries):.0f} s in all. Each run assessed by `railderail assess` "
             "(docs/assessment.md: the quantities, filters, windows, limits, their sources and how sure). "
             "Utilisation = governing |value| / limit of the quantity over all sections and places.", "",
             "| case | a_q (m/s^2) | limits first (place, section) | share of its limit | "
             + " | ".join(f"{q} %" for q in TABLE_QUANTITIES) + " | N_MV | Wz lat / vert | critical derailment speed |",
             "| --- | ---: | --- | ---: | " + " | ".join("---:" for _ in TABLE_QUANTITIES) + " | ---: | ---: | ---: |"]
    for s in summaries:
        c = s["case"]
        first = s["limiting"]
        cells = []
        for q in TABLE_QUANTITIES:
            u, _ = _largest(s, q)
            cells.append("-" if u is None else f"{100.0 * u:.0f}")
        n_mv = _largest(s, "N_MV")[0]
        wz = [_largest(s, q)[1] for q in ("Wz_lateral", "Wz_vertical")]
        v_crit = critical.get((c["model"], c["irregularity"], c["radius"]))
        lines.append(f"| {s['label']} | {s['uncompensated_acceleration']:.2f} | {first['quantity']} ({first['place']}, "
                     f"{first['section']}) | {100.0 * first['utilisation']:.0f} % | " + " | ".join(cells)
                     + f" | {n_mv:.2f} | " + " / ".join(f"{r['value']:.2f}" for r in wz)
                     + f" | {'-' if v_crit is None else f'{v_crit:.0f} km/h'} |")
    first = {}
    for s in summaries:
        first.setdefault(s["limiting"]["quantity"], []).append(s["label"])
    failing = {}
    for s in summaries:
        for r in s["governing"]:
            if r["passes"] is False:
                failing.setdefault(r["quantity"], set()).add(s["label"])
    lines += ["", "What limits first: " + "; ".join(f"{q} in {len(v)} of {len(summaries)} cases"
                                                  for q, v in sorted(first.items(), key=lambda kv: -len(kv[1])))
              + ". Beyond a limit somewhere on the line: "
              + ("; ".join(f"{q} in {len(v)} cases ({', '.join(sorted(v))})" for q, v in sorted(failing.items()))
                 or "nothing") + ". One seed per spectrum: a value near its limit may fall on either side with another "
              "track of the same quality; most limits are C (recalled, docs/assessment.md)."]
    lines += ["", "![each quantity's share of its limit in each case](assessment.png)", "",
              "The critical derailment speed is the median over seeds of the report's real-track study "
              "(docs/report/real-track.md, the progressive trial on the same track model and spectrum), where it "
              "was run; '-' where that study has no such track."]
    return "\n".join(lines) + "\n"


def write_study(out_dir, progress=None, workers=None, summaries=None):
    """Run every case (in parallel processes; or take the `summaries` of an earlier run), write
    assessment.md, assessment.json and assessment.png to out_dir; returns the markdown's path."""
    from ..methods.parallel import run_all

    out = Path(out_dir)
    if not out.is_dir():
        raise ValueError(f"study folder {str(out)!r} does not exist")
    if summaries is None:
        summaries = run_all(run_case, cases(), workers=workers, progress=progress is not None, desc="assess")
    critical = critical_speeds()
    command = f"railderail assess --study {out_dir}"
    with atomic_write(out / "assessment.json") as f:
        f.write(jsonout.dumps(summaries, indent=1))
    plotting.assessment_study_figure(summaries, TABLE_QUANTITIES + ("Wz_lateral", "Wz_vertical"),
                                     out / "assessment.png")
    path = out / "assessment.md"
    with atomic_write(path) as f:
        f.write(markdown(summaries, critical, command))
    return path

