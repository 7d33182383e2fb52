"""The line file (YAML; PyYAML comes with the ROS wheels): SI but for the database's own units at the file's
edge, labelled in the keys (cant in mm, speeds in km/h, defect sizes in mm).

    name: hsr-300-demo
    source: how the line was made, what it rests on
    sureness: C                              # A read in the primary text, B several sources agree, C one/recalled
    length_m: 60000
    line_speed_kmh: 300
    rail_spacing_m: 1.5                      # optional (EN 13803's 1.500 m)
    speed_limits:                            # optional civil limits
      - {start_m: 0, end_m: 3000, permitted_speed_kmh: 160}
    curves:                                  # in order along the line, not overlapping
      - {start_m: 4200, transition_in_m: 430, arc_m: 900, transition_out_m: 430, radius_m: 7000, cant_mm: 150,
         direction: left, permitted_speed_kmh: 300}          # permitted_speed_kmh optional (the line speed)
    defects:                                 # optional: kink (both rails toward the outside of the curve) or
      - {position_m: 5100, kind: kink, size_mm: 15, length_m: 10, source: recording run of ...}
      - {position_m: 9000, kind: twist, size_mm: 12, length_m: 5, hold_m: 10}   # twist: the outer rail lowered
    wind_sites:                              # optional
      - {position_m: 30500, name: viaduct, exposure: open valley, west winds}

`load_line(path)` checks every key and value and says what is wrong in one line naming the file, the section
(`curves[3]`) and the key; `dump_line(line, path)` writes a line back (through `atomic.atomic_write`).
"""
from importlib.resources import files
import math
from pathlib import Path

import yaml

from ..atomic import atomic_write
from .data import Curve, Defect, Line, WindSite

SHIPPED = files("railderail_sim") / "config" / "lines"
TOP_KEYS = {"name": str, "source": str, "sureness": str, "length_m": float, "line_speed_kmh": float,
            "rail_spacing_m": float, "speed_limits": list, "curves": list, "defects": list, "wind_sites": list}
TOP_REQUIRED = ("name", "source", "sureness", "length_m", "line_speed_kmh")
CURVE_KEYS = {"start_m": float, "transition_in_m": float, "arc_m": float, "transition_out_m": float,
              "radius_m": float, "cant_mm": float, "direction": str, "permitted_speed_kmh": float}
CURVE_OPTIONAL = ("permitted_speed_kmh",)
LIMIT_KEYS = {"start_m": float, "end_m": float, "permitted_speed_kmh": float}
DEFECT_KEYS = {"position_m": float, "kind": str, "size_mm": float, "length_m": float, "hold_m": float,
               "source": str}
DEFECT_OPTIONAL = ("hold_m", "source")
SITE_KEYS = {"position_m": float, "name": str, "exposure": str}
SITE_OPTIONAL = ("exposure",)
DIRECTIONS = {"left": 1, "right": -1}


def shipped(name):
    """The path of a shipped line file by its name (`table2`, `hsr-300-demo`), or ValueError naming them."""
    path = SHIPPED / f"{name}.yaml"
    if not path.is_file():
        known = sorted(p.name[:-5] for p in SHIPPED.iterdir() if p.name.endswith(".yaml"))
        raise ValueError(f"line {name!r} is not a shipped line ({', '.join(known)}) nor a .yaml file")
    return Path(str(path))


def resolve(name_or_path):
    """A line file's path: a path ending in .yaml/.yml as it is, else a shipped line's name."""
    text = str(name_or_path)
    return Path(text) if text.endswith((".yaml", ".yml")) else shipped(text)


def _value(where, key, value, kind):
    """The value as `kind` (float: any int or float but a bool, finite; str; list), else ValueError."""
    if kind is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ValueError(f"{where}: {key} {value!r} is not a finite number")
        return float(value)
    if not isinstance(value, kind):
        raise ValueError(f"{where}: {key} {value!r} is not {'a string' if kind is str else 'a list'}")
    return value


def _mapping(where, item, keys, optional=()):
    """{key: checked value} of a mapping with exactly `keys` (those in `optional` may be left out)."""
    if not isinstance(item, dict):
        raise ValueError(f"{where}: is not a mapping of keys to values")
    unknown = sorted(str(k) for k in set(item) - set(keys))
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {', '.join(unknown)}; the keys are {', '.join(keys)}")
    missing = [k for k in keys if k not in item and k not in optional]
    if missing:
        raise ValueError(f"{where}: {', '.join(missing)} missing")
    return {k: _value(where, k, v, keys[k]) for k, v in item.items()}


def _curve(where, item):
    d = _mapping(where, item, CURVE_KEYS, CURVE_OPTIONAL)
    if d["direction"] not in DIRECTIONS:
        raise ValueError(f"{where}: direction {d['direction']!r} is not one of {', '.join(DIRECTIONS)}")
    return Curve(start_m=d["start_m"], transition_in_m=d["transition_in_m"], arc_m=d["arc_m"],
                 transition_out_m=d["transition_out_m"], radius_m=d["radius_m"], cant_m=d["cant_mm"] / 1000.0,
                 direction=DIRECTIONS[d["direction"]], permitted_speed_kmh=d.get("permitted_speed_kmh"))


def _defect(where, item):
    d = _mapping(where, item, DEFECT_KEYS, DEFECT_OPTIONAL)
    return Defect(position_m=d["position_m"], kind=d["kind"], size_m=d["size_mm"] / 1000.0, length_m=d["length_m"],
                  hold_m=d.get("hold_m", 0.0), source=d.get("source", ""))


def _limit(where, item):
    d = _mapping(where, item, LIMIT_KEYS)
    return d["start_m"], d["end_m"], d["permitted_speed_kmh"]


def _site(where, item):
    return WindSite(**_mapping(where, item, SITE_KEYS, SITE_OPTIONAL))


def line_from_dict(data):
    """The Line of a line file's content (a mapping), validated; ValueError naming the section and key."""
    top = _mapping("line", data, TOP_KEYS, ("rail_spacing_m", "speed_limits", "curves", "defects", "wind_sites"))
    sections = {name: tuple(make(f"{name}[{i}]", item) for i, item in enumerate(top.get(name, [])))
                for name, make in (("curves", _curve), ("speed_limits", _limit), ("defects", _defect),
                                   ("wind_sites", _site))}
    return Line(name=top["name"], source=top["source"], sureness=top["sureness"], length_m=top["length_m"],
                line_speed_kmh=top["line_speed_kmh"], rail_spacing=top.get("rail_spacing_m", 1.5),
                **sections).validated()


def load_line(path):
    """The Line of a line file (a path, or a shipped line's name); ValueError in one line naming the file,
    the section and the key of a bad value."""
    path = resolve(path)
    try:
        text = Path(path).read_text()
    except OSError as error:
        raise ValueError(f"line file {path}: cannot be read ({error.strerror or error})") from None
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = f" at line {mark.line + 1}" if mark is not None else ""
        raise ValueError(f"{path}: not a YAML file{where} ({getattr(error, 'problem', None) or 'syntax'})") from None
    try:
        return line_from_dict(data)
    except ValueError as error:
        raise ValueError(f"{path}: {error}") from None


def _mm(value_m):
    """m -> mm for the file: the shortest of the numbers near value_m * 1000 that the loader's / 1000 turns
    back into value_m exactly (float arithmetic leaves 15.299999999999999 for 0.0153 m), so that a line
    written and read again is the same line."""
    exact = value_m * 1000.0
    near = [round(exact, 9), exact]
    for direction in (math.inf, -math.inf):
        y = exact
        for _ in range(4):
            y = math.nextafter(y, direction)
            near.append(y)
    return next((y for y in near if y / 1000.0 == value_m), near[0])


def line_as_dict(line: Line):
    """The content of a line's file (`load_line` reads it back to an equal Line)."""
    side = {v: k for k, v in DIRECTIONS.items()}
    out = dict(name=line.name, source=line.source, sureness=line.sureness, length_m=line.length_m,
               line_speed_kmh=line.line_speed_kmh, rail_spacing_m=line.rail_spacing,
               speed_limits=[dict(start_m=a, end_m=b, permitted_speed_kmh=v) for a, b, v in line.speed_limits],
               curves=[], defects=[], wind_sites=[dict(position_m=w.position_m, name=w.name, exposure=w.exposure)
                                                  for w in line.wind_sites])
    for c in line.curves:
        curve = dict(start_m=c.start_m, transition_in_m=c.transition_in_m, arc_m=c.arc_m,
                     transition_out_m=c.transition_out_m, radius_m=c.radius_m, cant_mm=_mm(c.cant_m),
                     direction=side[c.direction])
        if c.permitted_speed_kmh is not None:
            curve["permitted_speed_kmh"] = c.permitted_speed_kmh
        out["curves"].append(curve)
    for d in line.defects:
        defect = dict(position_m=d.position_m, kind=d.kind, size_mm=_mm(d.size_m), length_m=d.length_m)
        if d.kind == "twist":
            defect["hold_m"] = d.hold_m
        defect["source"] = d.source
        out["defects"].append(defect)
    return out


def dump_line(line: Line, path):
    """Write a line's file (atomically); `load_line(path)` gives the line back."""
    text = yaml.safe_dump(line_as_dict(line.validated()), sort_keys=False, default_flow_style=None, width=120)
    with atomic_write(path) as handle:
        handle.write(f"# line {line.name}, written by railderail (railderail_sim/line/file.py documents the keys)\n")
        handle.write(text)
