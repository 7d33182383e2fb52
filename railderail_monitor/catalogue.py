"""The scenario catalogue of the warning evaluation: a YAML file (PyYAML, which comes with the ROS
wheels) with one entry per scenario under `scenarios:`, each seed one run (docs/warnings.md).

    scenarios:
      - name: overspeed-r1000-erri-high     # unique
        radius_m: 1000                       # curve radius of the Table 2 line; .inf for straight track
        speed_kmh: 300                       # constant speed, or `speed: progressive` for the paper's staircase
        cant_mm: 175                         # optional (Table 2)
        irregularity: erri-high              # none | a spectrum | FILE.csv (relative to the catalogue)
        seeds: [1, 2, 3]                     # optional, default [0]
        friction: 0.3                        # optional
        track: rigid                         # optional: rigid | elastic
        line_length_m: 10000                 # optional: the circular curve (or the straight) made longer
        wind_speed_m_s: 0                    # optional: a steady wind from the inside of the curve
        faults: []                           # optional: NAME@LOCATION (docs/vehicle-model.md)

A bad entry is a ValueError naming the file, the entry and the key.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from importlib.resources import files
import math
from pathlib import Path

import yaml

SHIPPED = files("railderail_monitor") / "config" / "catalogue.yaml"
KEYS = ("name", "radius_m", "speed_kmh", "speed", "cant_mm", "irregularity", "seeds", "friction", "track",
        "line_length_m", "wind_speed_m_s", "faults")


@dataclass(frozen=True)
class Entry:
    """One scenario of the catalogue (SI but for the keys' own units); `folder` is where relative files are."""
    name: str
    radius_m: float
    speed_kmh: float = math.nan              # NaN: the progressive staircase
    cant_mm: float = 175.0
    irregularity: str = "none"
    seeds: tuple = (0,)
    friction: float = 0.3
    track: str = "rigid"
    line_length_m: float = math.nan          # NaN: the Table 2 line
    wind_speed_m_s: float = 0.0
    faults: tuple = ()
    folder: str = field(default=".", compare=False)

    @property
    def progressive(self):
        return math.isnan(self.speed_kmh)

    def runs(self):
        """(entry, seed) of each of its runs."""
        return [(self, seed) for seed in self.seeds]

    def key(self, seed):
        """What a run's result depends on, as plain data (the cache's key)."""
        data = {k: getattr(self, k) for k in KEYS if hasattr(self, k)}
        data.update(seed=seed, seeds=None, speed_kmh=None if self.progressive else self.speed_kmh,
                    line_length_m=None if math.isnan(self.line_length_m) else self.line_length_m,
                    radius_m=None if math.isinf(self.radius_m) else self.radius_m, faults=list(self.faults))
        if self.irregularity.endswith(".csv"):
            data["irregularity"] = Path(self.folder, self.irregularity).read_text()
        return data

    def scenario(self, seed):
        """The Scenario of one run (ValueError with a sentence for a bad value)."""
        from railderail_sim.loads.wind import Wind
        from railderail_sim.methods.progressive_trial import Staircase, staircase_scenario
        from railderail_sim.parameters import CANT_RANGE_MM, TrackParameters
        from railderail_sim.ranges import check_range
        from railderail_sim.track.irregularity import resolve
        from railderail_sim.vehicle.simulate import constant_speed, scenario, straight_track

        straight = math.isinf(self.radius_m)
        track = straight_track() if straight else TrackParameters(
            radius=self.radius_m, cant_height=check_range("cant", self.cant_mm, *CANT_RANGE_MM, "mm") / 1000.0)
        if not math.isnan(self.line_length_m):
            track = track.with_line_length(self.line_length_m)
        base = replace(scenario(radius=1000.0 if straight else self.radius_m, friction=self.friction), track=track)
        if self.progressive:
            if straight:
                raise ValueError("the progressive staircase needs a curve (radius_m is .inf)")
            base = staircase_scenario(base, self.radius_m, Staircase())
        else:
            base = replace(base, speed_table=constant_speed(self.speed_kmh))
        irregularity = self.irregularity
        if irregularity.endswith(".csv"):
            irregularity = str(Path(self.folder, irregularity))
        wind = Wind(speed=self.wind_speed_m_s, direction_deg=90.0 * base.track.direction).validated()
        return replace(base, irregularity=resolve(irregularity, seed, base.track.line_length), track_model=self.track,
                       wind=wind if wind.blows else None, faults=tuple(self.faults)).validated()


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
    from railderail_sim.parameters import FRICTION_RANGE, TRACK_MODELS
    from railderail_sim.track.irregularity import NONE, SEEDS, SPECTRA
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
    values = dict(name=name, radius_m=float(radius), speed_kmh=speed, irregularity=irregularity, seeds=tuple(seeds),
                  track=track, faults=tuple(faults), folder=str(folder))
    for key, lo, hi, unit in (("cant_mm", 0.0, 200.0, "mm"), ("friction", *FRICTION_RANGE, ""),
                              ("line_length_m", 0.0, 1.0e6, "m"), ("wind_speed_m_s", 0.0, 60.0, "m/s")):
        if key in item:
            values[key] = _number(where, key, item[key], lo, hi, unit)
    if values.get("friction", 0.3) == 0.0:
        raise ValueError(f"{where}: friction 0 is outside the accepted range (0, 1]")
    return Entry(**values)


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
    return entries
