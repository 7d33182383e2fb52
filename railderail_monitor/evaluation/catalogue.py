"""The scenario catalogue of the warning evaluation: a YAML file (PyYAML, which comes with the ROS
wheels) with one entry per scenario under `scenarios:`, each seed one run (docs/warning-evaluation.md).

    scenarios:
      - name: overspeed-r1000-erri-high     # unique
        family: overspeed                    # what the scenario is for: ordinary | overspeed | defect | gust | fault
        radius_m: 1000                       # curve radius of the Table 2 line; .inf for straight track
        speed_kmh: 300                       # constant speed, or `speed: progressive` for the paper's staircase
        cant_mm: 175                         # optional (Table 2)
        irregularity: erri-high              # none | a spectrum | FILE.csv (relative to the catalogue)
        defect: {kind: kink, amplitude_mm: 40, length_m: 5, at_m: 700}   # optional, over the irregularity;
                                             # kind twist lowers the outer rail, with hold_m
        seeds: [11, 12, 13]                  # optional, default [0]; a random track's seeds its own (below)
        part: test                           # optional: train | test; default alternating within the family
        expect_derailment: true              # optional: the entry is meant to derail (by its family's mechanism)
        critical_speed_kmh: 196              # optional: the speed below which its hazard is cured, where the
                                             # run cannot tell it (a fault's critical speed)
        friction: 0.3                        # optional
        track: rigid                         # optional: rigid | elastic
        line_length_m: 10000                 # optional: the circular curve (or the straight) made longer
        approach_m: 2000                     # optional: the straight before the curve (Table 2: 200 m)
        wind_speed_m_s: 0                    # optional: a steady wind (or the gust's peak) from the inside of the curve
        gust: none                           # optional: none | chinese-hat (the CEN gust at the curve's middle)
        faults: []                           # optional: NAME@LOCATION (docs/vehicle-model.md)
        vehicle_set: hs19                    # optional: the suspension parameter set (railderail_sim.parameters)

An `ordinary` entry is ordinary running: its cant deficiency must be within the permitted one
(`hazards.HazardRules.permitted_cant_deficiency`), or the catalogue is refused. A bad entry is a
ValueError naming the file, the entry and the key.

The split (`load`): all runs of an entry are in one part, its `part`, else train and test alternating over
the entries of its family without one, in the file's order. The parts share no track: a seed of a random
irregularity is used by one entry only (every line its own track), an irregularity file and a defect's
geometry are in one part only, and no two entries in different parts are the same run but for their name.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from importlib.resources import files
import math
from pathlib import Path

import yaml

SHIPPED = files("railderail_monitor") / "config" / "catalogue.yaml"
KEYS = ("name", "family", "radius_m", "speed_kmh", "speed", "cant_mm", "irregularity", "defect", "seeds", "part",
        "friction", "track", "line_length_m", "approach_m", "wind_speed_m_s", "gust", "faults", "expect_derailment",
        "critical_speed_kmh", "vehicle_set")
FAMILIES = ("ordinary", "overspeed", "defect", "gust", "fault")
# the mechanism by which each hazard family is meant to derail (`Entry.mechanism`)
MECHANISMS = {"overspeed": "over-speed unloading", "defect": "flange climb at a defect", "gust": "gust overturning",
              "fault": "fault-driven"}
PARTS = ("train", "test")
# simulated over wall time of one run by kind of track (railderail bench, 2026-12-03): only to order the runs
REAL_TIME_FACTOR = {"rigid smooth": 30.0, "rigid irregular": 8.0, "elastic irregular": 6.0}
DEFECTS = {"kink": ("amplitude_mm", "length_m", "at_m"), "twist": ("amplitude_mm", "length_m", "at_m", "hold_m")}


@dataclass(frozen=True)
class Entry:
    """One scenario of the catalogue (SI but for the keys' own units); `folder` is where relative files are."""
    name: str
    family: str
    radius_m: float
    speed_kmh: float = math.nan              # NaN: the progressive staircase
    cant_mm: float = 175.0
    irregularity: str = "none"
    defect: tuple = ()                       # (kind, amplitude m, length m, at m, hold m) or ()
    seeds: tuple = (0,)
    part: str = ""                           # "": by the seed
    friction: float = 0.3
    track: str = "rigid"
    line_length_m: float = math.nan          # NaN: the Table 2 line
    approach_m: float = math.nan             # NaN: the Table 2 straight before the curve
    wind_speed_m_s: float = 0.0
    gust: str = "none"
    faults: tuple = ()
    expect_derailment: bool = False
    critical_speed_kmh: float = math.nan     # NaN: the run's hazards say what cures them
    vehicle_set: str = "hs19"
    folder: str = field(default=".", compare=False)

    @property
    def progressive(self):
        return math.isnan(self.speed_kmh)

    def runs(self):
        """(entry, seed) of each of its runs."""
        return [(self, seed) for seed in self.seeds]

    def part_of(self, seed):
        """The part of the evaluation a run belongs to: its entry's (every seed the same, `load`)."""
        if not self.part:
            raise ValueError(f"scenario {self.name} has no part (load the catalogue with catalogue.load)")
        return self.part

    @property
    def mechanism(self):
        """The mechanism a hazard entry is meant to derail by (MECHANISMS), None for ordinary running."""
        return MECHANISMS.get(self.family)

    def line(self):
        """What `hazards.hazard_cure` and `hazards.beyond_permitted` take from the entry: the curve (radius m,
        cant m, rail spacing m; radius inf on straight track), the track class's permitted speed (km/h), the
        gust's peak (m/s, 0 without a gust), whether a defect or a failed yaw damper is the cause, the faults,
        and the entry's critical speed (km/h, NaN unless given)."""
        from railderail_sim.parameters import TrackParameters
        from railderail_sim.track.spectra import permitted_speed_kmh
        straight = math.isinf(self.radius_m)
        return dict(radius_m=self.radius_m, cant_m=0.0 if straight else self.cant_mm / 1000.0,
                    rail_spacing_m=TrackParameters().rail_spacing,
                    class_speed_kmh=permitted_speed_kmh(self.irregularity),
                    gust_m_s=self.wind_speed_m_s if self.gust != "none" else 0.0, defect=bool(self.defect),
                    hunting=any(f.startswith("yaw-dampers-failed") for f in self.faults), faults=list(self.faults),
                    critical_speed_kmh=self.critical_speed_kmh)

    def track_samples(self):
        """The random track samples of its runs ((spectrum, seed) of a random irregularity), none otherwise."""
        from railderail_sim.track.spectra import SPECTRA
        return {("random", seed) for seed in self.seeds} if self.irregularity in SPECTRA else set()

    def key(self, seed):
        """What a run's result depends on, as plain data (the cache's key)."""
        data = {k: getattr(self, k) for k in KEYS if hasattr(self, k)}
        data.update(seed=seed, seeds=None, part=None, expect_derailment=None, defect=list(self.defect),
                    speed_kmh=None if self.progressive else self.speed_kmh,
                    line_length_m=None if math.isnan(self.line_length_m) else self.line_length_m,
                    approach_m=None if math.isnan(self.approach_m) else self.approach_m,
                    radius_m=None if math.isinf(self.radius_m) else self.radius_m, faults=list(self.faults),
                    critical_speed_kmh=None if math.isnan(self.critical_speed_kmh) else self.critical_speed_kmh)
        if self.irregularity.endswith(".csv"):
            data["irregularity"] = Path(self.folder, self.irregularity).read_text()
        return data

    def scenario(self, seed):
        """The Scenario of one run (ValueError with a sentence for a bad value)."""
        from railderail_sim.loads.wind import Wind
        from railderail_sim.methods.progressive_trial import Staircase, staircase_scenario
        from railderail_sim.parameters import CANT_RANGE_MM, TrackParameters
        from railderail_sim.ranges import check_range
        from railderail_sim.track.irregularity import resolve, superpose
        from railderail_sim.vehicle.simulate import constant_speed, scenario, straight_track

        straight = math.isinf(self.radius_m)
        track = straight_track() if straight else TrackParameters(
            radius=self.radius_m, cant_height=check_range("cant", self.cant_mm, *CANT_RANGE_MM, "mm") / 1000.0)
        if not math.isnan(self.approach_m):
            track = replace(track, straight_in=self.approach_m)
        if not math.isnan(self.line_length_m):
            track = track.with_line_length(self.line_length_m)
        base = replace(scenario(radius=1000.0 if straight else self.radius_m, friction=self.friction,
                                vehicle_set=self.vehicle_set), track=track)
        if self.progressive:
            if straight:
                raise ValueError("the progressive staircase needs a curve (radius_m is .inf)")
            base = staircase_scenario(base, self.radius_m, Staircase())
        else:
            base = replace(base, speed_table=constant_speed(self.speed_kmh))
        irregularity = self.irregularity
        if irregularity.endswith(".csv"):
            irregularity = str(Path(self.folder, irregularity))
        wind = Wind(speed=self.wind_speed_m_s, direction_deg=90.0 * base.track.direction, gust=self.gust).validated()
        rails = superpose(resolve(irregularity, seed, base.track.line_length), self.defect_rails(base.track))
        return replace(base, irregularity=rails, track_model=self.track,
                       wind=wind if wind.blows else None, faults=tuple(self.faults)).validated()

    def expected_cost(self, seed):
        """A run's expected CPU time (s, roughly): its simulated time (the whole line at the speed table's
        speeds, `Scenario.simulated_duration`) over the real-time factor of its kind of track (the README's
        bench figures, 2-core machine), to start the dearest runs first (`methods.parallel.run_all`)."""
        smooth = self.irregularity == "none" and not self.defect
        factor = (REAL_TIME_FACTOR["rigid smooth"] if smooth else REAL_TIME_FACTOR["rigid irregular"]) \
            if self.track == "rigid" else REAL_TIME_FACTOR["elastic irregular"]
        # the same line and speeds without the rails' deviations, which take longer to make than to time
        return replace(self, irregularity="none", defect=()).scenario(seed).simulated_duration() / factor

    def defect_rails(self, track):
        """The defect's Irregularity on this track (None without one): a kink moves both rails toward the
        outside of the curve (to the right on straight track), a twist lowers the outer rail."""
        from railderail_sim.track.irregularity import lateral_kink, twist
        if not self.defect:
            return None
        kind, amplitude, length, at, hold = self.defect
        outer = 1 if math.isinf(self.radius_m) or track.direction > 0 else 0     # the right rail of a left curve
        if kind == "kink":
            return lateral_kink(at, length, amplitude * (-1.0 if outer == 1 else 1.0))
        return twist(at, length, amplitude, hold, outer)

    def cant_deficiency_m(self):
        """The cant deficiency (m) of the entry's circular curve at its (top) speed; 0 on straight track."""
        if math.isinf(self.radius_m):
            return 0.0
        from railderail_sim.parameters import GRAVITY, TrackParameters
        track = TrackParameters(radius=self.radius_m, cant_height=self.cant_mm / 1000.0)
        speed = (self.speed_kmh if not self.progressive else 400.0) / 3.6
        return track.uncompensated_acceleration(speed) * track.rail_spacing / GRAVITY


def _number(where, key, value, lo, hi, unit):
    from railderail_sim.ranges import check_range
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{where}: {key} {value!r} is not a number")
    try:
        return check_range(key, value, lo, hi, unit)
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None


def entry(item, where, folder):
    """The Entry of one catalogue item (a dict), checked key by key."""
    from railderail_sim.loads.wind import GUSTS
    from railderail_sim.parameters import FRICTION_RANGE, TRACK_MODELS, VEHICLE_SETS
    from railderail_sim.track.irregularity import NONE, SEEDS
    from railderail_sim.track.spectra import SPECTRA
    from railderail_sim.vehicle.assemble import FAULT_NAMES
    from railderail_sim.vehicle.simulate import RADIUS_RANGE, SPEED_RANGE_KMH

    if not isinstance(item, dict):
        raise ValueError(f"{where} is not a mapping of keys to values")
    name = item.get("name")
    if not isinstance(name, str) or not name:
        raise ValueError(f"{where}: name must be a non-empty string")
    where = f"{where} ({name})"
    unknown = sorted(set(item) - set(KEYS))
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {', '.join(unknown)}; the keys are {', '.join(KEYS)}")
    family = item.get("family")
    if family not in FAMILIES:
        raise ValueError(f"{where}: family {family!r} is not one of {', '.join(FAMILIES)}")
    if "radius_m" not in item:
        raise ValueError(f"{where}: radius_m is missing (a radius in m, or .inf for straight track)")
    radius = item["radius_m"]
    if not (isinstance(radius, float) and math.isinf(radius) and radius > 0):
        radius = _number(where, "radius_m", radius, *RADIUS_RANGE, "m")
    if ("speed_kmh" in item) == ("speed" in item):
        raise ValueError(f"{where}: give either speed_kmh (a constant speed) or speed: progressive")
    if "speed" in item and item["speed"] != "progressive":
        raise ValueError(f"{where}: speed {item['speed']!r} is not 'progressive'")
    speed = _number(where, "speed_kmh", item["speed_kmh"], *SPEED_RANGE_KMH, "km/h") if "speed_kmh" in item \
        else math.nan
    irregularity = item.get("irregularity", NONE)
    if not isinstance(irregularity, str) or not (irregularity in (NONE, *SPECTRA) or irregularity.endswith(".csv")):
        raise ValueError(f"{where}: irregularity {irregularity!r} is not none, one of {', '.join(SPECTRA)} or a "
                         ".csv file")
    if irregularity.endswith(".csv") and not Path(folder, irregularity).is_file():
        raise ValueError(f"{where}: irregularity file {Path(folder, irregularity)} does not exist")
    seeds = item.get("seeds", [0])
    if not isinstance(seeds, list) or not seeds or not all(isinstance(s, int) and not isinstance(s, bool)
                                                           and SEEDS[0] <= s <= SEEDS[1] for s in seeds):
        raise ValueError(f"{where}: seeds {seeds!r} is not a non-empty list of integers in [{SEEDS[0]}, {SEEDS[1]}]")
    if len(set(seeds)) != len(seeds):
        raise ValueError(f"{where}: seeds {seeds!r} repeat a seed")
    track = item.get("track", "rigid")
    if track not in TRACK_MODELS:
        raise ValueError(f"{where}: track {track!r} is not one of {', '.join(TRACK_MODELS)}")
    faults = item.get("faults", [])
    if not isinstance(faults, list) or any(f not in FAULT_NAMES for f in faults):
        raise ValueError(f"{where}: faults {faults!r} is not a list of NAME@LOCATION (e.g. yaw-dampers-failed@both)")
    part = item.get("part", "")
    if part not in ("", *PARTS):
        raise ValueError(f"{where}: part {part!r} is not one of {', '.join(PARTS)}")
    gust = item.get("gust", "none")
    if gust not in GUSTS:
        raise ValueError(f"{where}: gust {gust!r} is not one of {', '.join(GUSTS)}")
    vehicle_set = item.get("vehicle_set", "hs19")
    if vehicle_set not in VEHICLE_SETS:
        raise ValueError(f"{where}: vehicle_set {vehicle_set!r} is not one of {', '.join(VEHICLE_SETS)}")
    values = dict(name=name, family=family, radius_m=float(radius), speed_kmh=speed, irregularity=irregularity,
                  defect=_defect(where, item.get("defect")), seeds=tuple(seeds), part=part, track=track, gust=gust,
                  faults=tuple(faults), vehicle_set=vehicle_set, folder=str(folder))
    for key, lo, hi, unit in (("cant_mm", 0.0, 200.0, "mm"), ("friction", *FRICTION_RANGE, ""),
                              ("line_length_m", 0.0, 1.0e6, "m"), ("approach_m", 0.0, 1.0e5, "m"),
                              ("wind_speed_m_s", 0.0, 60.0, "m/s"), ("critical_speed_kmh", 1.0, 600.0, "km/h")):
        if key in item:
            values[key] = _number(where, key, item[key], lo, hi, unit)
    expect = item.get("expect_derailment", False)
    if not isinstance(expect, bool) or (expect and family == "ordinary"):
        raise ValueError(f"{where}: expect_derailment {expect!r} must be true or false (false for ordinary running)")
    values["expect_derailment"] = expect
    if values.get("friction", 0.3) == 0.0:
        raise ValueError(f"{where}: friction 0 is outside the accepted range (0, 1]")
    e = Entry(**values)
    if family == "ordinary":
        from .hazards import HazardRules
        permitted = HazardRules().permitted_cant_deficiency
        if e.progressive or e.cant_deficiency_m() > permitted + 1e-9:
            raise ValueError(f"{where}: an ordinary run's cant deficiency must be within the permitted "
                             f"{permitted * 1e3:.0f} mm; at {e.speed_kmh:g} km/h it is "
                             f"{e.cant_deficiency_m() * 1e3:.0f} mm (give it another family, or a lower speed)")
        from railderail_sim.track.spectra import permitted_speed_kmh
        top = permitted_speed_kmh(e.irregularity)
        if e.speed_kmh > top + 1e-9:
            raise ValueError(f"{where}: an ordinary run on {e.irregularity} track must be within its class's "
                             f"permitted {top:.0f} km/h (49 CFR 213.9 / 213.307); "
                             f"{e.speed_kmh:g} km/h given (give it another family, a lower speed or better track)")
    return e


def _defect(where, item):
    """(kind, amplitude m, length m, at m, hold m) of a `defect:` mapping, or () without one."""
    if item is None:
        return ()
    if not isinstance(item, dict) or item.get("kind") not in DEFECTS:
        raise ValueError(f"{where}: defect must be a mapping with kind one of {', '.join(DEFECTS)}")
    kind = item["kind"]
    unknown = sorted(set(item) - {"kind", *DEFECTS[kind]})
    if unknown or any(k not in item for k in DEFECTS[kind]):
        raise ValueError(f"{where}: defect of kind {kind} takes {', '.join(DEFECTS[kind])}")
    amplitude = _number(where, "defect amplitude_mm", item["amplitude_mm"], 0.0, 200.0, "mm") / 1000.0
    length = _number(where, "defect length_m", item["length_m"], 0.5, 200.0, "m")
    at = _number(where, "defect at_m", item["at_m"], 0.0, 1.0e6, "m")
    hold = _number(where, "defect hold_m", item["hold_m"], 0.0, 1000.0, "m") if kind == "twist" else 0.0
    return kind, amplitude, length, at, hold


def load(path=None):
    """The entries of a catalogue file (default: the shipped one), checked; ValueError naming the file,
    the entry and the key."""
    if path is None:
        text, folder, label = SHIPPED.read_text(), Path(str(SHIPPED)).parent, "the shipped catalogue"
    else:
        path = Path(path)
        try:
            text = path.read_text()
        except OSError as error:
            raise ValueError(f"{path}: cannot read it ({error.strerror})") from None
        folder, label = path.parent, str(path)
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as error:
        raise ValueError(f"{label} is not YAML ({error})") from None
    if not isinstance(data, dict) or not isinstance(data.get("scenarios"), list) or not data["scenarios"]:
        raise ValueError(f"{label}: a catalogue is a mapping with a non-empty list `scenarios:`")
    entries = [entry(item, f"{label}, scenario {i + 1}", folder) for i, item in enumerate(data["scenarios"])]
    names = [e.name for e in entries]
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise ValueError(f"{label}: scenario name(s) {', '.join(repeated)} used more than once")
    return independent(assign_parts(entries), label)


def assign_parts(entries):
    """The entries with their parts: an entry's own, else train and test alternating over the entries of its
    family without one, in the file's order."""
    turn = {}
    out = []
    for e in entries:
        if not e.part:
            k = turn[e.family] = turn.get(e.family, -1) + 1
            e = replace(e, part=PARTS[k % 2])
        out.append(e)
    return out


def independent(entries, label):
    """The entries, checked that the parts share no track: a random track's seed used by one entry only, an
    irregularity file, a defect's geometry or the same run (but its name) in one part only; ValueError naming
    the entries."""
    seen = {}
    for e in entries:
        for sample in e.track_samples():
            if sample in seen:
                raise ValueError(f"{label}: seed {sample[1]} of a random track is used by both {seen[sample]} and "
                                 f"{e.name}; every entry needs its own seeds")
            seen[sample] = e.name
    for what, of in (("irregularity file", lambda e: e.irregularity if e.irregularity.endswith(".csv") else None),
                     ("defect", lambda e: e.defect or None),
                     ("run", lambda e: jsonout_key(e))):
        parts = {}
        for e in entries:
            key = of(e)
            if key is None:
                continue
            other = parts.setdefault(key, (e.part, e.name))
            if other[0] != e.part:
                raise ValueError(f"{label}: {e.name} ({e.part}) and {other[1]} ({other[0]}) share a {what}; "
                                 "the parts must not")
    return entries


def jsonout_key(entry):
    """The runs of an entry as plain text, but its name: two entries equal here are the same runs."""
    from railderail_sim import jsonout
    return jsonout.dumps([{**entry.key(seed), "name": None, "seed": seed if entry.track_samples() else None}
                          for seed in entry.seeds])
