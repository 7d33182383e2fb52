"""The line as an infrastructure manager's database gives it: curves by position (entry transition, circular
arc, exit transition, radius, cant, hand, permitted speed), civil speed limits, the known track defects
(as the last track-recording run found them) and the wind-measurement sites. SI inside; the permitted
speeds keep the database's km/h, labelled in their names; `Line.permitted_speed_at` gives m/s.

`Line.validated()` checks the whole line and names the section and key of a bad value (`curves[3]:
radius_m ...`); the file reader (`file.load_line`) puts the file's name in front. `Line.scenario_for(curve)`
is the run of one curve as the simulator takes it: the curve between a straight approach and a straight
exit (the Table 2 line's shape, `TrackParameters`), so that the progressive trial runs it unchanged;
`Line.from_track` is the one-curve line of a scenario's own geometry (a catalogue scenario's line).

How sure each rule is: A read in the primary text, B several secondary sources agree, C one source or
recalled.
"""
from dataclasses import dataclass, replace
import math

from ..parameters import CANT_RANGE_MM, KMH, RADIUS_RANGE, SPEED_RANGE_KMH, TrackParameters, parameter
from ..ranges import check_range

DEFECT_KINDS = ("kink", "twist")     # what track.irregularity builds: lateral_kink, twist
SURENESS = ("A", "B", "C")


@dataclass(frozen=True)
class LineRules:
    """The rules a line file is checked against, and how a curve is cut out of the line for a run."""
    max_cant_gradient: float = parameter(2.25e-3, "m/m", "EN 13803 (track alignment design), the largest cant "
                                         "gradient along a transition, as recalled", "C",
                                         "a transition shorter than cant / this cannot ramp the cant")
    approach_m: float = parameter(200.0, "m", "Yu2022", "A", "the straight simulated before a curve's entry "
                                  "transition: Table 2's, so that a curve's run is the paper's line")
    exit_m: float = parameter(200.0, "m", "Yu2022", "A", "the straight simulated after a curve's exit "
                              "transition: Table 2's")
    defect_size_mm: tuple = parameter((0.0, 200.0), "mm", "the catalogue's accepted defect amplitudes "
                                      "(railderail_monitor/catalogue.py)", "-")
    defect_length_m: tuple = parameter((0.5, 200.0), "m", "the catalogue's accepted defect lengths", "-")
    rail_spacing_m: tuple = parameter((1.4, 1.8), "m", "EN13803", "B", "accepted distances between the rail "
                                      "centres: standard (1.500 m) to broad gauge")


RULES = LineRules()


@dataclass(frozen=True)
class Curve:
    """One curve: its entry transition starts at `start_m`; clothoid transitions with a linear cant ramp
    around a circular arc (the alignment of `track.alignment`)."""
    start_m: float
    transition_in_m: float
    arc_m: float
    transition_out_m: float
    radius_m: float
    cant_m: float
    direction: int = 1                          # +1 curve to the left, -1 to the right
    permitted_speed_kmh: float = None           # None: the line's speed

    @property
    def end_m(self):
        """Where the exit transition ends (m)."""
        return self.start_m + self.transition_in_m + self.arc_m + self.transition_out_m

    @property
    def extent(self):
        """(start, end) m: where the curve's curvature or cant differs from straight track, the stretch over
        which a speed limit of the curve holds (the train's length is the supervisor's to add)."""
        return self.start_m, self.end_m

    @property
    def full_curve_extent(self):
        """(start, end) m of the circular arc: full curvature and full cant."""
        arc_start = self.start_m + self.transition_in_m
        return arc_start, arc_start + self.arc_m

    def checked(self, where, line_length_m, rules=RULES):
        """This curve, or ValueError naming `where` (e.g. "curves[3]") and the key."""
        _within(where, "radius_m", self.radius_m, *RADIUS_RANGE, "m")
        _within(where, "cant_mm", self.cant_m * 1e3, *CANT_RANGE_MM, "mm")
        if self.direction not in (1, -1):
            raise ValueError(f"{where}: direction {self.direction!r} is neither +1 (left) nor -1 (right)")
        _within(where, "arc_m", self.arc_m, 0.0, 1.0e5, "m", lo_open=True)
        need = self.cant_m / rules.max_cant_gradient
        for key in ("transition_in_m", "transition_out_m"):
            length = getattr(self, key)
            _within(where, key, length, 0.0, 1.0e4, "m", lo_open=True)
            if length < need - 1e-9:
                raise ValueError(f"{where}: {key} {length:g} m is too short to ramp the cant of "
                                 f"{self.cant_m * 1e3:g} mm: at most {rules.max_cant_gradient * 1e3:g} mm/m needs "
                                 f"at least {need:g} m")
        _within(where, "start_m", self.start_m, 0.0, line_length_m, "m")
        if self.end_m > line_length_m + 1e-9:
            raise ValueError(f"{where}: start_m {self.start_m:g} m: the curve ends at {self.end_m:g} m, beyond "
                             f"the line's end at {line_length_m:g} m")
        if self.permitted_speed_kmh is not None:
            _within(where, "permitted_speed_kmh", self.permitted_speed_kmh, *SPEED_RANGE_KMH, "km/h")
        return self


@dataclass(frozen=True)
class Defect:
    """A known track defect: a lateral kink of both rails toward the outside of the curve (to the right on
    straight track), or a twist, the outer rail lowered over `length_m` and held over `hold_m`
    (`track.irregularity.lateral_kink`, `twist`); `size_m` its amplitude, `source` where it was found."""
    position_m: float
    kind: str
    size_m: float
    length_m: float
    hold_m: float = 0.0
    source: str = ""

    @property
    def end_m(self):
        """Where the defect ends (m): a twist rises again over its length after its hold."""
        return self.position_m + self.length_m + (self.hold_m + self.length_m if self.kind == "twist" else 0.0)

    def checked(self, where, line_length_m, rules=RULES):
        if self.kind not in DEFECT_KINDS:
            raise ValueError(f"{where}: kind {self.kind!r} is not one of {', '.join(DEFECT_KINDS)}")
        _within(where, "position_m", self.position_m, 0.0, line_length_m, "m")
        _within(where, "size_mm", self.size_m * 1e3, *rules.defect_size_mm, "mm", lo_open=True)
        _within(where, "length_m", self.length_m, *rules.defect_length_m, "m")
        _within(where, "hold_m", self.hold_m, 0.0, 1000.0, "m")
        if self.kind == "kink" and self.hold_m:
            raise ValueError(f"{where}: hold_m {self.hold_m:g} m: a kink has no hold (only a twist)")
        return self

    def irregularity(self, at_m, track: TrackParameters):
        """The defect's rails (`track.irregularity.Irregularity`) at `at_m` on a run's track."""
        from ..track.irregularity import lateral_kink, twist
        outer = 1 if math.isinf(track.radius) or track.direction > 0 else 0   # the right rail of a left curve
        if self.kind == "kink":
            return lateral_kink(at_m, self.length_m, self.size_m * (-1.0 if outer == 1 else 1.0))
        return twist(at_m, self.length_m, self.size_m, self.hold_m, outer)


@dataclass(frozen=True)
class WindSite:
    """An anemometer by the line: where, its name, and what it is exposed to (a note)."""
    position_m: float
    name: str
    exposure: str = ""

    def checked(self, where, line_length_m):
        _within(where, "position_m", self.position_m, 0.0, line_length_m, "m")
        if not self.name:
            raise ValueError(f"{where}: name is empty")
        return self


@dataclass(frozen=True)
class Line:
    """A line: what it is and where it comes from (`source`, how sure: A, B or C), its length (m), its line
    speed and civil speed limits (start m, end m, km/h), curves in order, defects, wind sites and the
    distance between the rail centres (m)."""
    name: str
    source: str
    sureness: str
    length_m: float
    line_speed_kmh: float
    curves: tuple = ()
    speed_limits: tuple = ()
    defects: tuple = ()
    wind_sites: tuple = ()
    rail_spacing: float = 1.5

    def validated(self, rules=RULES):
        """This line, or ValueError naming the section and the key of the first bad value."""
        if not self.name:
            raise ValueError("line: name is empty")
        if self.sureness not in SURENESS:
            raise ValueError(f"line: sureness {self.sureness!r} is not one of {', '.join(SURENESS)}")
        _within("line", "length_m", self.length_m, 0.0, 1.0e7, "m", lo_open=True)
        _within("line", "line_speed_kmh", self.line_speed_kmh, *SPEED_RANGE_KMH, "km/h")
        _within("line", "rail_spacing_m", self.rail_spacing, *rules.rail_spacing_m, "m")
        previous = None
        for i, curve in enumerate(self.curves):
            curve.checked(f"curves[{i}]", self.length_m, rules)
            if previous is not None and curve.start_m < previous.end_m - 1e-9:
                raise ValueError(f"curves[{i}]: start_m {curve.start_m:g} m is before the end of curves[{i - 1}] "
                                 f"at {previous.end_m:g} m: curves must be in order and must not overlap")
            previous = curve
        for i, (start, end, speed) in enumerate(self.speed_limits):
            where = f"speed_limits[{i}]"
            _within(where, "start_m", start, 0.0, self.length_m, "m")
            _within(where, "end_m", end, start, self.length_m, "m", lo_open=True)
            _within(where, "permitted_speed_kmh", speed, *SPEED_RANGE_KMH, "km/h")
        for i, defect in enumerate(self.defects):
            defect.checked(f"defects[{i}]", self.length_m, rules)
        for i, site in enumerate(self.wind_sites):
            site.checked(f"wind_sites[{i}]", self.length_m)
        return self

    def curve_at(self, s):
        """The curve whose extent holds s (m), or None on straight track."""
        for curve in self.curves:
            if curve.start_m <= s < curve.end_m:
                return curve
        return None

    def permitted_speed_at(self, s):
        """The permitted speed at s (m/s): the lowest of the line speed, the speed limits and the permitted
        speed of a curve whose extent holds s."""
        speeds = [self.line_speed_kmh] + [v for a, b, v in self.speed_limits if a <= s < b]
        curve = self.curve_at(s)
        if curve is not None and curve.permitted_speed_kmh is not None:
            speeds.append(curve.permitted_speed_kmh)
        return min(speeds) * KMH

    def permitted_speed_kmh(self, curve):
        """A curve's own permitted speed (km/h): its file value, else the line speed."""
        return self.line_speed_kmh if curve.permitted_speed_kmh is None else curve.permitted_speed_kmh

    def track_for(self, curve, base: TrackParameters = None, approach_m=None, arc_m=None, rules=RULES):
        """The run's track of one curve: `approach_m` of straight (default `rules.approach_m`), the curve
        (its arc `arc_m` long if given) and `rules.exit_m` of straight, the other values (rail profile,
        gauge) from `base`."""
        return replace(base or TrackParameters(), straight_in=rules.approach_m if approach_m is None else approach_m,
                       transition_in=curve.transition_in_m, curve_length=curve.arc_m if arc_m is None else arc_m,
                       transition_out=curve.transition_out_m, straight_out=rules.exit_m, radius=curve.radius_m,
                       cant_height=curve.cant_m, direction=curve.direction, rail_spacing=self.rail_spacing)

    def scenario_for(self, curve, base=None, approach_m=None, arc_m=None, **changes):
        """The `vehicle.simulate.Scenario` of one curve with its approach straight (`track_for`), the rest from
        `base` (default `Scenario()`) with `changes` (Scenario fields); the progressive trial runs it as it is."""
        from ..vehicle.simulate import Scenario       # here: reading a line file does not load the numba core
        base = base or Scenario()
        return replace(base, track=self.track_for(curve, base.track, approach_m, arc_m), **changes)

    def local_position(self, curve, s, approach_m=None, rules=RULES):
        """Where the line's position s (m) lies on the run of `curve` (`track_for`)."""
        return s - curve.start_m + (rules.approach_m if approach_m is None else approach_m)

    @classmethod
    def from_track(cls, track: TrackParameters, name, source="a scenario's own geometry", line_speed_kmh=None,
                   defects=(), permitted_speed_kmh=None):
        """The one-curve line of a scenario's track (Table 2's shape): a catalogue scenario's line, supervised
        from its own geometry; straight track (infinite radius) gives a line without curves. The line speed
        defaults to the top of the accepted speeds (the scenario says nothing about a civil limit)."""
        curves = () if math.isinf(track.radius) else (Curve(
            start_m=track.straight_in, transition_in_m=track.transition_in, arc_m=track.curve_length,
            transition_out_m=track.transition_out, radius_m=track.radius, cant_m=track.cant_height,
            direction=track.direction, permitted_speed_kmh=permitted_speed_kmh),)
        return cls(name=name, source=source, sureness="A", length_m=track.line_length,
                   line_speed_kmh=SPEED_RANGE_KMH[1] if line_speed_kmh is None else line_speed_kmh, curves=curves,
                   defects=tuple(defects), rail_spacing=track.rail_spacing).validated()


def _within(where, key, value, lo, hi, unit, lo_open=False):
    """check_range with the section and key in front of the sentence."""
    try:
        return check_range(key, value, lo, hi, unit, lo_open=lo_open)
    except (TypeError, ValueError) as error:
        raise ValueError(f"{where}: {error}") from None
