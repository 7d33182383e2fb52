"""The progressive trial on real track: the six radii on rigid and elastic track, smooth and with random
irregularities of several spectra and seeds, and one sharp curve (`railderail real-track`).

Each case is the paper's staircase (Yu 2022 Fig. 3) over one track: the irregularity is a sample along the
staircase's whole line (the same sample for every radius of a seed), so a seed is one track and the spread
over seeds is the spread of the critical derailment speed over tracks of the same quality. The staircase's
speed at the derailment is the result (no bisection: on an irregular track the derailment happens where a
defect meets a high enough speed, and a constant-speed bisection would ask another question).
"""
from dataclasses import dataclass, replace
import math

import numpy as np

from ..track import irregularity as ir
from ..vehicle.simulate import Scenario
from . import sweep as sw
from .progressive_trial import Staircase, trial_track

SHARP_RADIUS_M = 250.0
SHARP_CANT_MM = 150.0          # EN 13803's limit for ballasted track is 160 mm
SHARP_STAIRCASE = Staircase(start_kmh=60.0, top_kmh=250.0)


@dataclass(frozen=True)
class Track:
    """A track of the study: its model and its irregularity (a spectrum name, or none) and seed."""
    model: str = "rigid"
    irregularity: str = ir.NONE
    seed: int = 0

    @property
    def label(self):
        what = "smooth" if self.irregularity == ir.NONE else f"{self.irregularity} seed {self.seed}"
        return f"{self.model}, {what}"


def tracks(models=("rigid", "elastic"), spectra=("erri-low", "erri-high"), seeds=(1, 2, 3)):
    """Smooth track and each spectrum x seed, on each track model."""
    return [Track(m, ir.NONE) for m in models] + [Track(m, s, n) for s in spectra for n in seeds for m in models]


def _scenario(base: Scenario, track: Track, stair: Staircase):
    line = trial_track(base.track, stair).line_length
    return replace(base, track_model=track.model, irregularity=ir.resolve(track.irregularity, track.seed, line))


def _key(row):
    return row["model"], row["irregularity"], row["seed"], row["radius_m"]


def study(track_list, radii=sw.PAPER_RADII, base: Scenario = None, stair: Staircase = Staircase(), workers=None,
          progress=True, known=(), done=None):
    """Rows {model, irregularity, seed, radius_m, the trial's results} of every track x radius. Rows in
    `known` (an earlier, interrupted study of the same cases) are kept and not run again; `done(row)` is
    called for each new row as its track's radii finish."""
    base = base or Scenario()
    have = {_key(r): r for r in known}
    rows = []
    for track in track_list:
        todo = [r for r in radii if (track.model, track.irregularity, track.seed, r) not in have]
        if todo:
            sc = _scenario(base, track, stair)
            for r in sw.sweep(sw.cases(radii=todo), sc, stair, refine=False, workers=workers, progress=progress):
                row = dict(model=track.model, irregularity=track.irregularity, seed=track.seed, **r)
                have[_key(row)] = row
                if done:
                    done(row)
        rows += [have[(track.model, track.irregularity, track.seed, r)] for r in radii]
    return rows


def sharp_curve(track_list, base: Scenario = None, workers=None, progress=True, known=(), done=None):
    """The staircase from 60 km/h on a 250 m curve with 150 mm cant, for each track."""
    base = base or Scenario()
    base = replace(base, track=replace(base.track, cant_height=SHARP_CANT_MM / 1000.0))
    return study(track_list, (SHARP_RADIUS_M,), base, SHARP_STAIRCASE, workers, progress, known, done)


def summary(rows):
    """Per (model, irregularity, radius), in the rows' order: the critical derailment speeds over the seeds (km/h; a case that did
    not derail counts as not derailed), their mean, standard deviation, minimum and maximum, and the
    mechanisms seen."""
    groups = {}
    for r in rows:
        groups.setdefault((r["model"], r["irregularity"], r["radius_m"]), []).append(r)
    out = []
    for (model, irregularity, radius), rs in groups.items():
        v = np.array([r["critical_derailment_speed_kmh"] for r in rs], dtype=float)
        derailed = v[np.isfinite(v)]
        out.append(dict(model=model, irregularity=irregularity, radius_m=radius, seeds=len(rs),
                        derailed=len(derailed),
                        mean_kmh=float(np.mean(derailed)) if len(derailed) else math.nan,
                        std_kmh=float(np.std(derailed, ddof=1)) if len(derailed) > 1 else math.nan,
                        min_kmh=float(np.min(derailed)) if len(derailed) else math.nan,
                        max_kmh=float(np.max(derailed)) if len(derailed) else math.nan,
                        mechanisms=sorted({f"{r['mechanism']} ({r['derailed_side']})" for r in rs if r["mechanism"]})))
    return out


def smooth_reference(summaries, model="rigid"):
    """{radius: mean critical speed} of the smooth track of `model`."""
    return {s["radius_m"]: s["mean_kmh"] for s in summaries if s["model"] == model and s["irregularity"] == ir.NONE}


def _speed(v):
    return "-" if v is None or v != v else f"{v:.0f}"


def markdown(rows, sharp_rows, figure):
    """The report section "On real track" (Markdown lines) of a study's and the sharp curve's rows."""
    summaries = summary(rows)
    smooth = smooth_reference(summaries)
    seeds = sorted({r["seed"] for r in rows if r["irregularity"] != ir.NONE})
    lines = ["# On real track: the critical derailment speed with irregularities and an elastic track", "",
             "The paper's progressive trial (staircase from 200 km/h, 5 km/h steps held 200 m) at the six radii, on "
             "rigid and on elastic track (docs/elastic-track.md), smooth and with random irregularities of the ERRI "
             f"B176 low and high levels (1-150 m, docs/track-irregularity.md), seeds {', '.join(map(str, seeds))}: "
             "each seed is one sample along the staircase's whole line, the same for every radius. The speed is the "
             "staircase's at the derailment (km/h); mean +- standard deviation over the seeds, [min, max]; the "
             "change is against the smooth rigid track.", "", f"![critical derailment speed on real track]({figure})",
             "", "| track | irregularity | R (m) | critical derailment speed (km/h) | change | mechanism (rail) |",
             "|---|---|---|---|---|---|"]
    for s in summaries:
        if s["irregularity"] == ir.NONE:
            speed = _speed(s["mean_kmh"])
        else:
            std = "" if s["std_kmh"] != s["std_kmh"] else f" +- {s['std_kmh']:.1f}"
            speed = (f"{_speed(s['mean_kmh'])}{std} [{_speed(s['min_kmh'])}, {_speed(s['max_kmh'])}]"
                     + ("" if s["derailed"] == s["seeds"] else f", {s['seeds'] - s['derailed']} not derailed"))
        ref = smooth.get(s["radius_m"])
        change = "" if ref is None or s["mean_kmh"] != s["mean_kmh"] else f"{s['mean_kmh'] - ref:+.0f}"
        lines.append(f"| {s['model']} | {s['irregularity']} | {s['radius_m']:.0f} | {speed} | {change} | "
                     f"{', '.join(s['mechanisms'])} |")
    lines += ["", "Change of the mean against the smooth rigid track, over the radii (km/h):", ""]
    for model, irregularity in dict.fromkeys((s["model"], s["irregularity"]) for s in summaries):
        changes = [s["mean_kmh"] - smooth[s["radius_m"]] for s in summaries
                   if (s["model"], s["irregularity"]) == (model, irregularity) and s["radius_m"] in smooth
                   and s["mean_kmh"] == s["mean_kmh"]]
        if changes and (model, irregularity) != ("rigid", ir.NONE):
            lines.append(f"- {model}, {irregularity}: {max(changes):+.0f} to {min(changes):+.0f}")
    if sharp_rows:
        lines += ["", f"## A sharp curve: R = {SHARP_RADIUS_M:.0f} m, cant {SHARP_CANT_MM:.0f} mm", "",
                  f"The staircase from {SHARP_STAIRCASE.start_kmh:.0f} km/h in 5 km/h steps.", "",
                  "| track | irregularity | critical derailment speed (km/h) | mechanism (rail) | wheelset | "
                  "position (m) |", "|---|---|---|---|---|---|"]
        for r in sharp_rows:
            what = r["irregularity"] if r["irregularity"] == ir.NONE else f"{r['irregularity']} seed {r['seed']}"
            lines.append(f"| {r['model']} | {what} | {_speed(r['critical_derailment_speed_kmh'])} | "
                         f"{r['mechanism'] or '-'} ({r['derailed_side'] or '-'}) | {r['derailed_wheelset']} | "
                         f"{r['derailment_position_m']:.0f} |")
    return lines
