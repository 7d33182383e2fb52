"""The survey of a line's physical speed limits (`railderail survey LINE.yaml`): what a speed supervisor needs
to supervise the car against its own limits rather than against fixed civil ones.

- Each curve: its critical derailment speed by the paper's method, exactly as `railderail trial` computes it
  (`progressive_trial`: the staircase, then the bisection over constant-speed runs), on the curve's own run
  (`Line.scenario_for`: Table 2's 200 m straights around the curve's transitions, its arc cut to
  `SurveyRules.simulated_arc_m`), for every friction and stand-in parameter set asked; the lowest is the
  curve's critical derailment speed, with the spread (max - min) and the case that gave it. A constant-speed
  run at the staircase's top speed comes first: a curve that does not derail at it is, by the bisection's own
  assumption (every speed above a derailing one derails too), not derailed below it either, and its limit is
  reported as that top (`derailed: false`), a lower bound; the staircase and bisection run only on a curve
  that derails at the top.
- Its safe speed: the highest constant speed at which the car passes the curve with every hazard margin intact
  (`margins_intact_up_to_kmh`), by bisection from `SurveyRules.margins_low_kmh` (taken as intact once a faster
  speed keeps every margin) up to the case's critical derailment speed, the margins judged over the curve's
  extent (entry transition to exit transition) by the rules below, lowest over the cases; less ETCS's
  emergency-brake-intervention margin (`SafetyMargin`, SUBSET-026's dV_ebi). Why not the critical derailment
  speed less dV_ebi: ETCS's emergency brake curve reaches a target at its speed plus dV_ebi, so a train held to
  it would meet the curve at its critical derailment speed; a civil limit carries its own margin, a physical
  limit does not. The sensitivity to the margin
  (none, twice dV_ebi, 10 % of the speed) is in every curve's row.
- Each known defect: the highest constant speed at which the car passes it with every margin intact, by the
  same bisection over `margins_low_kmh` .. the staircase's top (for both, where `margins_low_kmh` breaks a
  margin, down to the simulator's slowest speed before the answer is 0: a stop). The margins are the simulator's own,
  judged on the run's output rows while the car-body centre is within `defect_window_m` of the defect (over a
  curve's extent for a curve): no derailment (the core's geometric check) anywhere on the run; Q/P of every
  wheel, its mean over 1.524 m (49 CFR 213.333's 5 ft), below Nadal's limit at the profile pair's largest
  contact angle and the run's friction; the unloading dQ/Q0 of every wheel, its mean over 1.524 m, below 0.90;
  every wheel's lift below half its flange height (the warning evaluation's levels, which its HazardRules take
  from `SurveyRules`, here without its 20 Hz force filter). The defect's safe speed is that speed less the same
  margin; lowest over the cases.
- Each wind site: the characteristic wind curve of the track there (`cwc.characteristic_wind_speed`): the
  CEN gust's peak at which a running gear unloads to 0.90, against the vehicle speed, on the curve the site
  stands on (the gust at its middle) or on straight track.
- How the live inputs move each curve's limit, at the reference case (the `--vehicle-set` and `--friction`):
  its critical derailment speed in a steady crosswind from the inside of the curve (which adds to the
  centrifugal unloading of the inner wheels) at a few wind speeds, and with each shipped fault; reported as
  the change against the reference case without them (run on its own when it is not among the cases).

Every case is one item of `parallel.run_all` (processes or Dask), cached on disk under the SHA-256 of its
inputs and of railderail_sim's sources (`survey_cache`; a curve's case by the curve's shape, shared by every
line with that curve), so a second survey of the same line returns at once and an interrupted one resumes.
The speed profile along the line the supervisor consumes is survey_profile.py's.
"""
from dataclasses import asdict, dataclass, field, replace
import functools
import json
import math
from pathlib import Path

import numpy as np

from .. import jsonout
from ..line.data import Line
from ..line.file import line_as_dict, line_from_dict
from ..loads.wind import Wind
from ..parameters import FRICTION_RANGE, SPEED_RANGE_KMH as SIMULATED_KMH, VEHICLE_SETS, parameter, vehicle_parameters
from ..ranges import check_range
from ..supervision.margin import SafetyMargin
from ..vehicle.simulate import (KMH, Scenario, constant_speed, curve_extent, output_arrays, run_in_pieces,
                                straight_track)
from .parallel import run_all
from .progressive_trial import SPEED_RANGE_KMH, Staircase, bisect_constant_speeds, constant_run, progressive_trial
from .survey_cache import case_key

DEFAULT_FRICTIONS = (0.2, 0.3, 0.4, 0.6)
DEFAULT_WIND_SPEEDS_M_S = (10.0, 20.0, 30.0)
SHIPPED_FAULTS = ("yaw-dampers-failed@both", "air-spring-deflated@front")
DEFAULT_CWC_SPEEDS_KMH = (200.0, 250.0, 300.0, 350.0)


@dataclass(frozen=True)
class SurveyRules:
    """How the survey cuts the line into runs and judges a defect."""
    simulated_arc_m: float = parameter(1000.0, "m", "Yu2022 Table 2's arc; a modelling choice", "-",
                                       "a longer arc is cut to this: the car settles into its steady curving "
                                       "within a few hundred metres (its body modes are about 1 Hz), and the "
                                       "runs near the critical speed derail in the transition or early in the arc")
    margins_low_kmh: float = parameter(60.0, "km/h", "a modelling choice", "-",
                                       "the lowest speed a defect or a curve is tried at for its margins; where "
                                       "it breaks one, the simulator's slowest speed (30 km/h) is tried, and the "
                                       "bisection runs between them; the safe speed is 0 (a stop) only where "
                                       "that breaks one too")
    defect_window_m: float = parameter(150.0, "m", "a modelling choice", "-",
                                       "the car-body centre's distance before and after the defect over which "
                                       "its margins are judged (the car is 25 m long; the wheelsets' response "
                                       "dies out within it)")
    defect_lead_m: float = parameter(500.0, "m", "a modelling choice", "-",
                                     "straight run before a defect on straight track")
    margin_window_m: float = parameter(5.0 * 0.3048, "m", "49 CFR 213.333: the 5 ft window of the wheel-force "
                                       "limits", "B", "track over which a wheel's Q/P and dQ/Q0 are averaged (the "
                                       "one definition of the hazard margins: the warning evaluation takes it)")
    unloading_level: float = parameter(0.90, "-", "49 CFR 213.333 (single-wheel vertical load ratio >= 0.10); "
                                       "EN 14067-6 running-gear unloading 0.90", "B",
                                       "a wheel's unloading dQ/Q0 at or above this breaks its margin (a near miss)")
    lift_share: float = parameter(0.5, "-", "no standard value (none of EN 14363, 49 CFR 213.333, GB/T 5599 limits "
                                  "a lift): half way up the flange, a modelling choice; the derailment itself is "
                                  "the full flange height. Sensitivity: the warning evaluation's report counts the "
                                  "runs whose lift reaches 0.25, 0.5 and 0.75 of it (`margin_peaks`)", "-",
                                  "a wheel's lift at or above this share of the flange height breaks its margin")
    defect_guard_m: float = parameter(25.0, "m", "ICE 3 end car's length (ICE3)", "B",
                                      "a defect's speed limit holds this far before and after it (survey_targets)")


RULES = SurveyRules()
MARGIN = SafetyMargin()
# km/h: where margins_low_kmh breaks a margin, the speed tried before a stop: the slowest the simulator runs
MARGINS_FLOOR_KMH = SIMULATED_KMH[0]


@dataclass(frozen=True)
class Settings:
    """What every case of a survey shares (the cache key holds it)."""
    frictions: tuple = DEFAULT_FRICTIONS
    vehicle_sets: tuple = VEHICLE_SETS
    reference_set: str = "hs19"
    reference_friction: float = 0.3
    wind_speeds_m_s: tuple = DEFAULT_WIND_SPEEDS_M_S
    faults: tuple = SHIPPED_FAULTS
    cwc_speeds_kmh: tuple = DEFAULT_CWC_SPEEDS_KMH
    tolerance_kmh: float = 1.0
    cwc_tolerance_m_s: float = 0.5
    start_kmh: float = Staircase().start_kmh
    top_kmh: float = Staircase().top_kmh

    def validated(self):
        if not self.frictions or not self.vehicle_sets:
            raise ValueError("the survey needs at least one friction and one vehicle parameter set")
        for f in (*self.frictions, self.reference_friction):
            check_range("friction coefficient", f, *FRICTION_RANGE, lo_open=True)
        for s in (*self.vehicle_sets, self.reference_set):
            vehicle_parameters(s)
        for u in self.wind_speeds_m_s:
            check_range("crosswind speed", u, 0.0, 60.0, "m/s", lo_open=True)
        from ..vehicle.assemble import failed_elements
        failed_elements(self.faults)
        for v in self.cwc_speeds_kmh:
            check_range("characteristic wind curve speed", v, 60.0, 400.0, "km/h")
        check_range("bisection tolerance", self.tolerance_kmh, 0.0, 20.0, "km/h", lo_open=True)
        check_range("characteristic wind speed tolerance", self.cwc_tolerance_m_s, 0.01, 5.0, "m/s")
        check_range("staircase start speed", self.start_kmh, *SPEED_RANGE_KMH, "km/h")
        check_range("staircase top speed", self.top_kmh, self.start_kmh, SPEED_RANGE_KMH[1], "km/h")
        return self

    @property
    def staircase(self):
        return Staircase(start_kmh=self.start_kmh, top_kmh=self.top_kmh)


QUICK = dict(frictions=(0.2, 0.6), vehicle_sets=("hs19",), wind_speeds_m_s=(20.0,), cwc_speeds_kmh=(300.0,),
             tolerance_kmh=4.0, cwc_tolerance_m_s=1.0)


# --- the cases -------------------------------------------------------------------------------------------
def _case_scenario(base: Scenario, vehicle_set, friction, **changes):
    return replace(base, vehicle=vehicle_parameters(vehicle_set),
                   contact=replace(base.contact, friction_coefficient=friction), **changes)


def curve_case(line: Line, index, base: Scenario, settings: Settings, vehicle_set, friction, wind_m_s=0.0,
               fault=None):
    """The trial of one curve in one case (as `railderail trial` on the curve's run) and, without wind and
    fault, the highest speed with every margin intact over the curve (`highest_intact` up to the critical
    derailment speed): a dict."""
    curve = line.curves[index]
    wind = Wind(speed=wind_m_s, direction_deg=90.0 * curve.direction).validated() if wind_m_s > 0.0 else base.wind
    sc = line.scenario_for(curve, _case_scenario(base, vehicle_set, friction, wind=wind,
                                                 faults=base.faults + ((fault,) if fault else ())),
                           arc_m=min(curve.arc_m, RULES.simulated_arc_m))
    critical, derailment = _critical_speed(sc, curve, settings)
    row = dict(vehicle_set=vehicle_set, friction=friction, wind_speed_m_s=wind_m_s, fault=fault, **critical)
    if wind_m_s > 0.0 or fault:
        return row       # the live inputs move the critical derailment speed (the tables' changes) only
    known = {}
    if derailment is not None and derailment["car_body_position_m"] < curve_extent(sc.track)[1]:
        # the trial's run at the critical speed is curve_run's scenario at a quarter of its output rate: the same
        # steps (they do not depend on the output instants), its derailment checked at instants curve_run's has
        known[row["critical_derailment_speed_kmh"]] = Judged(False, "derailment")
    margins = highest_intact(functools.partial(curve_run, sc), RULES.margins_low_kmh,
                             row["critical_derailment_speed_kmh"], settings.tolerance_kmh, known, lo_assumed=True,
                             floor=MARGINS_FLOOR_KMH)
    return dict(row, margins_intact_up_to_kmh=margins["margins_intact_up_to_kmh"],
                first_broken=margins["first_broken"], runs=row["runs"] + margins["runs"])


def _critical_speed(sc: Scenario, curve, settings: Settings):
    """A curve's critical derailment speed on its run `sc` by the paper's method (module docstring): (its row,
    the derailment of the bisection's run at it, or None)."""
    top = constant_run(sc, curve.radius_m, settings.top_kmh)
    if top.derailment is None:
        # the bisection's own assumption (a speed above a derailing one derails too) read the other way: no
        # derailment at the top, none below it; one run instead of the staircase's tens of kilometres
        return dict(derailed=False, critical_derailment_speed_kmh=settings.top_kmh, staircase_speed_kmh=math.nan,
                    method="no derailment at the top speed", mechanism="", side="", wheelset=-1, section="",
                    runs=1), None
    runs = {}
    r = progressive_trial(sc, curve.radius_m, settings.staircase, refine=True, tolerance_kmh=settings.tolerance_kmh,
                          runs=runs)
    staircase = r.critical_derailment_speed_kmh
    if not math.isfinite(staircase):
        # the staircase held on to its top, the constant run at the top did not (its entry): bisect down from it
        r = replace(r, critical_derailment_speed_kmh=settings.top_kmh)
        bisect_constant_speeds(sc, curve.radius_m, r, settings.tolerance_kmh, runs)
    refined = math.isfinite(r.refined_speed_kmh)
    return dict(derailed=True,
                critical_derailment_speed_kmh=r.refined_speed_kmh if refined else r.critical_derailment_speed_kmh,
                staircase_speed_kmh=staircase, method="bisection" if refined else "staircase",
                mechanism=r.refined_mechanism if refined else r.mechanism,
                side=r.refined_side if refined else r.derailed_side,
                wheelset=r.refined_wheelset if refined else r.derailed_wheelset,
                section=r.refined_section, runs=r.runs + 1), \
        runs[round(r.refined_speed_kmh, 6)].derailment if refined else None


@functools.lru_cache(maxsize=16)
def _largest_contact_angle(contact, track, rolling_radius):
    """The profile pair's largest contact angle (rad), for Nadal's limit: once per pair (the search takes about
    as long as a run near the critical speed, and every run of a case has the same pair)."""
    from ..contact.conicity import max_contact_angle
    from ..vehicle.assemble import contact_geometry
    return max_contact_angle(contact_geometry(contact, track, rolling_radius))[0]


class MarginsRun:
    """One run of `sc` judged by `SurveyRules` while the car-body centre is within [lo, hi] m, simulated in
    pieces of `PIECE_M` and only as far as the question asked needs. `intact()` stops at the first margin
    broken: a sliding mean over the rows so far is, at the same place, the whole run's to the bit (the same
    rows, the same sums in the same order; only windows that end before the last row are judged), so a margin
    broken on a part is broken on the whole. `outcome()` runs it to its end: (margins intact, '' or the margin
    broken: diverged, derailment, or the first of flange_climb, wheel_unloading, wheel_lift that broke, in
    this order and not in time's)."""
    PIECE_M = 100.0       # m of track between two looks at the margins (a look is a few ms; a run 1-2 km)

    def __init__(self, sc: Scenario, lo, hi):
        self.scenario, self.lo, self.hi = sc, lo, hi
        self._pieces, self._sim, self._error, self._running, self._verdict = None, None, "", True, None
        self.simulated_m = sc.start_position     # how far it has been simulated: the car-body centre's last row
        self._columns = {k: [] for k in ("position", "vertical_force", "derailment_coefficient", "wheel_lift")}

    def _next_piece(self):
        if self._pieces is None:
            speed = float(np.max(self.scenario.speed_table[:, 1]))
            self._pieces = run_in_pieces(self.scenario, self.PIECE_M / speed)
        try:
            self._sim, rows, self._error = next(self._pieces)
        except StopIteration:
            self._running = False
            return
        arrays = output_arrays(rows)
        for k, parts in self._columns.items():
            parts.append(arrays[k].copy())       # the columns judged, not the whole rows
        if len(rows):
            self.simulated_m = float(arrays["position"][-1])

    def _broken(self, whole):
        """'' or the first margin broken (outcome's order) on the rows so far; `whole`: the run has ended."""
        from ..assessment.en14363 import sliding
        from ..contact.nadal import nadal_limit

        if self._error:
            return "diverged"
        if self._sim.derailment() is not None:
            return "derailment"
        sc = self.scenario
        a = {k: np.concatenate(parts) for k, parts in self._columns.items()}
        s = a["position"]
        if len(s) < 2:
            return ""
        # the windows judged on a part end a window's length before its last row, inside the rows the whole
        # run's windows at the same places see
        end = self.hi if whole else min(self.hi, s[-1] - RULES.margin_window_m)
        p0 = sc.vehicle.static_wheel_load
        _, unloading = sliding(s, (p0 - a["vertical_force"]) / p0, RULES.margin_window_m, 0.25, self.lo, end)
        _, qp = sliding(s, a["derailment_coefficient"], RULES.margin_window_m, 0.25, self.lo, end)
        nadal = float(nadal_limit(_largest_contact_angle(sc.contact, sc.track, sc.vehicle.rolling_radius),
                                  sc.contact.friction_coefficient))
        lift = a["wheel_lift"][(s >= self.lo) & (s <= self.hi)]
        for name, broken in (("flange_climb", np.any(qp >= nadal)),
                             ("wheel_unloading", np.any(unloading >= RULES.unloading_level)),
                             ("wheel_lift", np.any(lift >= RULES.lift_share * self._sim.model.flange_height))):
            if broken:
                return name
        return ""

    def intact(self):
        """Whether the whole run keeps every margin, simulated up to the first margin broken."""
        while self._verdict is None and self._running:
            self._next_piece()
            if self._running and self._broken(whole=False):
                self._verdict = False
        if self._verdict is None:
            self._verdict = self.outcome()[0]
        return self._verdict

    def outcome(self):
        """(margins intact, '' or which margin broke) of the whole run, simulated to its end."""
        while self._running:
            self._next_piece()
        why = self._broken(whole=True)
        return not why, why


@dataclass(frozen=True)
class Judged:
    """A speed whose outcome is known without a run (the trial's own derailment): as a MarginsRun."""
    ok: bool
    why: str

    def intact(self):
        return self.ok

    def outcome(self):
        return self.ok, self.why


def defect_run(line: Line, index, base: Scenario, vehicle_set, friction, speed_kmh):
    """One constant-speed run over a defect, its margins judged while the car-body centre is within
    `defect_window_m` of it (`MarginsRun`)."""
    defect = line.defects[index]
    curve = line.curve_at(defect.position_m)
    if curve is None:
        track = straight_track(rail_profile=base.track.rail_profile, straight_in=RULES.defect_lead_m)
        at = RULES.defect_lead_m
    else:
        track = line.track_for(curve, base.track)
        at = line.local_position(curve, defect.position_m)
    end = at + (defect.end_m - defect.position_m)
    sc = _case_scenario(base, vehicle_set, friction, track=track, irregularity=defect.irregularity(at, track),
                        speed_table=constant_speed(speed_kmh), stop_on_derailment=True, output_rate=200.0,
                        end_position=min(end + RULES.defect_window_m, track.line_length))
    return MarginsRun(sc, at - RULES.defect_window_m, end + RULES.defect_window_m)


def curve_run(sc: Scenario, speed_kmh):
    """One constant-speed run over a curve's run (`Line.scenario_for`), its margins judged over the curve's
    extent (`curve_extent`, `MarginsRun`)."""
    lo, hi = curve_extent(sc.track)
    return MarginsRun(replace(sc, speed_table=constant_speed(speed_kmh), stop_on_derailment=True, output_rate=200.0,
                              end_position=hi), lo, hi)


def highest_intact(run, lo, hi, tolerance_kmh, known=None, lo_assumed=False, floor=None):
    """The highest speed (km/h) in [lo, hi] at which `run(speed_kmh)` (a MarginsRun) keeps every margin, by
    bisection (a margin broken at a speed is taken as broken above it too): {margins_intact_up_to_kmh (0 when
    broken at lo), first_broken (the lowest speed tried that broke a margin, and which: its whole run's), runs
    (the speeds tried)}. `known`: {speed: Judged} for speeds whose outcome is known without a run.
    `lo_assumed`: lo is not run first but taken as intact, by the bisection's own assumption read downwards,
    once a faster speed keeps every margin, and run only if none does (a curve's; not a defect's, whose margins,
    a twist's, may be hardest to keep at low speed). `floor`: where lo breaks a margin, this slower speed is
    tried before the answer is 0, and the bisection runs between them if it keeps every margin."""
    known = known or {}
    tried = {}
    bottom = lo

    def passes(v):
        if v not in tried:
            tried[v] = known[v] if v in known else run(v)
        return tried[v].intact()

    def bisect(lo, hi):
        """The highest speed within the tolerance below hi (broken) from lo (intact or assumed so)."""
        while hi - lo > tolerance_kmh:
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if passes(mid) else (lo, mid)
        return lo

    def below(top):
        """The answer when `top` breaks a margin: the floor's bisection, or 0."""
        return bisect(floor, top) if floor is not None and floor < top and passes(floor) else 0.0

    if passes(hi):
        intact = hi
    elif not lo_assumed and not passes(lo):
        intact = below(lo)
    else:
        lo = bisect(lo, hi)
        intact = lo if lo > bottom or passes(bottom) else below(bottom)
    broken = sorted(v for v, r in tried.items() if not r.intact())
    # only the lowest broken run is simulated to its end, for which margin its whole run breaks
    return dict(margins_intact_up_to_kmh=intact,
                first_broken=dict(speed_kmh=broken[0], margin=tried[broken[0]].outcome()[1]) if broken else None,
                runs=len(tried))


def defect_case(line: Line, index, base: Scenario, settings: Settings, vehicle_set, friction):
    """The highest speed (km/h) with every margin intact over one defect in one case (`highest_intact`)."""
    return dict(vehicle_set=vehicle_set, friction=friction,
                **highest_intact(functools.partial(defect_run, line, index, base, vehicle_set, friction),
                                 RULES.margins_low_kmh, settings.top_kmh, settings.tolerance_kmh,
                                 floor=MARGINS_FLOOR_KMH))


def wind_site_case(line: Line, index, base: Scenario, settings: Settings, speed_kmh):
    """One point of a wind site's characteristic wind curve (m/s, NaN if not reached)."""
    from .cwc import CwcCase, characteristic_wind_speed
    site = line.wind_sites[index]
    curve = line.curve_at(site.position_m)
    sc = _case_scenario(base, settings.reference_set, settings.reference_friction)
    if curve is None:
        case = CwcCase(None)
    else:
        sc = line.scenario_for(curve, sc, arc_m=min(curve.arc_m, RULES.simulated_arc_m))
        case = CwcCase(sc.track.uncompensated_acceleration(speed_kmh * KMH))
    u, tried = characteristic_wind_speed(speed_kmh, sc, case, settings.cwc_tolerance_m_s)
    return dict(speed_kmh=speed_kmh, wind_speed_m_s=u, runs=len(tried))


KINDS = {"curve": curve_case, "defect": defect_case, "wind_site": wind_site_case}
# each case's expected cost in trial-equivalents (to start the dearest first, `run_all`)
COST = {"curve": 1.0, "defect": 0.6, "wind_site": 0.8}


def run_case(item, line_data, base: Scenario, settings: Settings, cache=None):
    """One case (kind, index, *arguments) of a survey, from the cache when it holds it (a module-level
    function for the process pool and Dask)."""
    kind, index, *arguments = item
    if cache:
        key = case_key(item, line_data, base, settings)
        path = Path(cache, key[:2], key + ".json")
        if path.exists():
            return json.loads(path.read_text())
    out = KINDS[kind](line_from_dict(line_data), index, base, settings, *arguments)
    if cache:
        path.parent.mkdir(parents=True, exist_ok=True)
        jsonout.write(path, out)
        out = json.loads(path.read_text())     # the cached form, so that a first and a second survey agree
    return out


def cases(line: Line, settings: Settings):
    """Every case of a survey: (kind, index, *arguments)."""
    ref = (settings.reference_set, settings.reference_friction)
    grid = [(s, f) for s in settings.vehicle_sets for f in settings.frictions]
    out = [("curve", i, s, f) for i in range(len(line.curves)) for s, f in grid]
    if ref not in grid and (settings.wind_speeds_m_s or settings.faults):     # what the tables' changes are against
        out += [("curve", i, *ref) for i in range(len(line.curves))]
    out += [("curve", i, *ref, u) for i in range(len(line.curves)) for u in settings.wind_speeds_m_s]
    out += [("curve", i, *ref, 0.0, fault) for i in range(len(line.curves)) for fault in settings.faults]
    out += [("defect", i, s, f) for i in range(len(line.defects)) for s in settings.vehicle_sets
            for f in settings.frictions]
    out += [("wind_site", i, v) for i in range(len(line.wind_sites)) for v in settings.cwc_speeds_kmh]
    return out


# --- the result --------------------------------------------------------------------------------------------
def margin_sensitivity(critical_kmh):
    """The safe speed (km/h) of a critical derailment speed under other margins than ETCS's dV_ebi."""
    v = critical_kmh * KMH
    twice = SafetyMargin(*(2.0 * x for x in (MARGIN.dv_min, MARGIN.dv_max)), MARGIN.v_min, MARGIN.v_max)
    return dict(none=critical_kmh, etcs_dv_ebi=MARGIN.safe_speed(v) / KMH, twice_etcs_dv_ebi=twice.safe_speed(v) / KMH,
                ten_percent=0.9 * critical_kmh)


def _lowest(rows, key):
    """(the row with the lowest `key`, max - min of `key`)."""
    values = [r[key] for r in rows]
    low = rows[int(np.argmin(values))]
    return low, float(max(values) - min(values))


def _curve_row(line: Line, i, rows, settings: Settings):
    curve = line.curves[i]
    plain = [r for r in rows if r["wind_speed_m_s"] == 0.0 and r["fault"] is None]
    base = [r for r in plain if r["vehicle_set"] in settings.vehicle_sets and r["friction"] in settings.frictions]
    low, spread = _lowest(base, "critical_derailment_speed_kmh")
    weakest, intact_spread = _lowest(base, "margins_intact_up_to_kmh")
    reference = next((r for r in plain if (r["vehicle_set"], r["friction"]) ==
                      (settings.reference_set, settings.reference_friction)), None)   # run if the tables need it
    critical = low["critical_derailment_speed_kmh"]
    intact = weakest["margins_intact_up_to_kmh"]

    def change(r):
        return r["critical_derailment_speed_kmh"] - reference["critical_derailment_speed_kmh"]

    wind = [dict(wind_speed_m_s=r["wind_speed_m_s"], critical_derailment_speed_kmh=r["critical_derailment_speed_kmh"],
                 derailed=r["derailed"], change_kmh=change(r)) for r in rows if r["wind_speed_m_s"] > 0.0]
    faults = [dict(fault=r["fault"], critical_derailment_speed_kmh=r["critical_derailment_speed_kmh"],
                   derailed=r["derailed"], change_kmh=change(r)) for r in rows if r["fault"]]
    sensitivity = margin_sensitivity(intact)
    by_friction = {f"{f:g}": MARGIN.safe_speed(min(r["margins_intact_up_to_kmh"] for r in base
                                                   if r["friction"] == f) * KMH) / KMH for f in settings.frictions}
    return dict(index=i, start_m=curve.start_m, end_m=curve.end_m, radius_m=curve.radius_m, cant_mm=curve.cant_m * 1e3,
                direction=curve.direction, permitted_speed_kmh=line.permitted_speed_kmh(curve),
                critical_derailment_speed_kmh=critical, derailed=low["derailed"], spread_kmh=spread,
                lowest_case=dict(vehicle_set=low["vehicle_set"], friction=low["friction"]),
                margins_intact_up_to_kmh=intact, margins_spread_kmh=intact_spread,
                margins_lowest_case=dict(vehicle_set=weakest["vehicle_set"], friction=weakest["friction"]),
                first_broken=weakest["first_broken"],
                safe_speed_kmh=sensitivity["etcs_dv_ebi"], safe_speed_by_friction_kmh=by_friction,
                safe_speed_sensitivity_kmh=sensitivity,
                mechanism=low["mechanism"], side=low["side"], section=low["section"], cases=base,
                reference_case=dict(vehicle_set=settings.reference_set, friction=settings.reference_friction),
                crosswind=wind, faults=faults)


def _defect_row(line: Line, i, rows):
    defect = line.defects[i]
    low, spread = _lowest(rows, "margins_intact_up_to_kmh")
    intact = low["margins_intact_up_to_kmh"]
    return dict(index=i, position_m=defect.position_m, end_m=defect.end_m, kind=defect.kind,
                size_mm=defect.size_m * 1e3,
                length_m=defect.length_m, margins_intact_up_to_kmh=intact, spread_kmh=spread,
                safe_speed_kmh=MARGIN.safe_speed(intact * KMH) / KMH,
                lowest_case=dict(vehicle_set=low["vehicle_set"], friction=low["friction"]),
                first_broken=low["first_broken"], cases=rows)


def _site_row(line: Line, i, rows):
    site = line.wind_sites[i]
    curve = line.curve_at(site.position_m)
    return dict(index=i, position_m=site.position_m, name=site.name, exposure=site.exposure,
                track="straight" if curve is None else f"curve R {curve.radius_m:g} m, cant {curve.cant_m * 1e3:g} mm",
                curve=dict(speed_kmh=[r["speed_kmh"] for r in rows],
                           wind_speed_m_s=[r["wind_speed_m_s"] for r in rows]),
                runs=sum(r["runs"] for r in rows))


@dataclass
class SurveyResult:
    """A survey: the line (its file's content, and name and length), the settings and margin, and the rows of
    its curves, defects and wind sites (km/h and mm where the names say so)."""
    line: dict
    settings: dict
    margin: dict
    curves: list = field(default_factory=list)
    defects: list = field(default_factory=list)
    wind_sites: list = field(default_factory=list)

    def as_dict(self):
        return jsonout.plain(dict(line=self.line, settings=self.settings, margin=self.margin, curves=self.curves,
                                  defects=self.defects, wind_sites=self.wind_sites))

    @classmethod
    def from_dict(cls, data):
        """The result of a survey's JSON (`as_dict`); ValueError if a section is missing."""
        missing = [k for k in ("line", "settings", "margin", "curves", "defects", "wind_sites") if k not in data]
        if missing:
            raise ValueError(f"survey result: {', '.join(missing)} missing (not a `railderail survey --json` file?)")
        if any("margins_intact_up_to_kmh" not in c for c in data["curves"]):
            raise ValueError("survey result: its curves have no margins_intact_up_to_kmh (a survey made before a "
                             "curve's safe speed came from its margins, 2026-12-06): run the survey again")
        return cls(**{k: data[k] for k in ("line", "settings", "margin", "curves", "defects", "wind_sites")})

    @classmethod
    def load(cls, path):
        try:
            return cls.from_dict(json.loads(Path(path).read_text()))
        except (OSError, json.JSONDecodeError) as error:
            raise ValueError(f"survey result {path}: cannot be read ({error})") from None

    def save(self, path):
        jsonout.write(path, self.as_dict())


def survey(line: Line, base: Scenario = None, settings: Settings = Settings(), workers=None, scheduler=None,
           progress=True, cache=None):
    """The survey of a line (module docstring): a SurveyResult."""
    base = base or Scenario()
    settings = settings.validated()
    line = line.validated()
    items = cases(line, settings)
    line_data = line_as_dict(line)
    rows = run_all(functools.partial(run_case, line_data=line_data, base=base, settings=settings, cache=cache),
                   items, workers=workers, scheduler=scheduler, progress=progress, desc="survey", unit="case",
                   cost=[COST[item[0]] for item in items])
    by = {}
    for item, row in zip(items, rows):
        by.setdefault((item[0], item[1]), []).append(row)
    return SurveyResult(
        line=dict(name=line.name, length_m=line.length_m, line_speed_kmh=line.line_speed_kmh, source=line.source,
                  sureness=line.sureness, file=line_data),
        settings=asdict(settings),
        margin=dict(rule="safe speed V with V + dV_ebi(V) = the limit", **{
            f.name: dict(value_kmh=getattr(MARGIN, f.name) / KMH, source=f.metadata["source"], sure=f.metadata["sure"])
            for f in SafetyMargin.__dataclass_fields__.values()}),
        curves=[_curve_row(line, i, by[("curve", i)], settings) for i in range(len(line.curves))],
        defects=[_defect_row(line, i, by[("defect", i)]) for i in range(len(line.defects))],
        wind_sites=[_site_row(line, i, by[("wind_site", i)]) for i in range(len(line.wind_sites))])
