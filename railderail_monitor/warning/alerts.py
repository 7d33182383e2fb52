"""The alert record (field for field the Alert message), its wording, and the lead of each first alert before a
derailment."""
from __future__ import annotations

from dataclasses import asdict, dataclass
import math

from .limits import SEVERITY_NAMES


@dataclass
class AlertRecord:
    """An alert, field for field the Alert message (time_s is the header stamp in seconds)."""
    time_s: float
    sample: int
    criterion: str
    severity: int
    value: float
    threshold: float
    wheelset: int
    wheel_side: str
    rail_side: str
    track_position: float
    speed: float
    message: str = ""

    def as_dict(self):
        return asdict(self)


# What a user reads for each criterion, in EN 14363's notation (Y lateral, Q vertical wheel-rail force; the
# paper's Q/P is Y/Q here): docs/output-format.md, "Notation", is the table every label follows.
LABELS = {"attack_angle": "attack angle", "wheel_lift": "wheel lift h_p",
          "derailment_coefficient": "derailment quotient Y/Q", "wheel_unloading": "wheel unloading ΔQ/Q0",
          "running_gear_unloading": "running-gear unloading ΔQ/Q0",
          "derailment_coefficient_duration": "Y/Q held over its duration",
          "derailment_coefficient_mean": "Y/Q sliding mean",
          "flange_climb_distance": "flange-climb distance ratio",
          # the on-board criteria on measured signals (onboard.measured)
          "bogie_rms": "bogie-frame lateral r.m.s.", "bogie_peak": "bogie-frame lateral peak",
          "bids_peak_count": "BIDS peak count", "bids_peak_count_china": "Chinese on-board rule's peak count",
          "car_body_lateral": "car-body lateral ÿ*", "car_body_lateral_qst": "car-body lateral ÿ*_qst",
          "car_body_roll": "car-body roll", "car_body_roll_rate": "car-body roll rate",
          "estimated_running_gear_unloading": "estimated running-gear unloading ΔQ/Q0",
          "estimated_side_ratio": "estimated Y/Q of a bogie side"}
UNIT_TEXT = {"m/s^2": "m/s²", "": ""}         # a parameter table's unit as printed


def amount_text(value, threshold, unit):
    """'value unit >= threshold unit' with four significant digits, as the measured alerts print it."""
    u = UNIT_TEXT.get(unit, unit)
    return f"{value:.4g}{' ' + u if u else ''} >= {threshold:.4g}{' ' + u if u else ''}"


def label(criterion):
    """A criterion's name as a user reads it (LABELS; any other criterion with its underscores as spaces)."""
    return LABELS.get(criterion, criterion.replace("_", " "))


def level_text(criterion, value):
    """A value of a criterion as the alerts and the views write it: the same rounding everywhere."""
    if criterion == "wheel_lift":
        return f"{value * 1e3:.1f} mm"
    if criterion == "attack_angle":
        return f"{value:.4f} rad"
    return f"{value:.3f}"


def describe(criterion, severity, value, threshold, wheelset, wheel_side, rail):
    where = f"wheelset {wheelset}" + (f" {wheel_side}" if wheel_side else "") + (f" ({rail})" if rail else "")
    amount = f"{level_text(criterion, value)} >= {level_text(criterion, threshold)}"
    return f"{SEVERITY_NAMES[severity]}: {label(criterion)} {amount} on {where}"



def lead_times(alerts, derailment):
    """First alert of each (criterion, severity) with its lead before the derailment.

    `alerts`: AlertRecords (or dicts with the same keys); `derailment`: dict with time_s and
    track_position_m (car-body centre), or None. Returns {"criterion/severity": {...}}, lead_s and
    lead_m being NaN when no derailment follows (a false alarm)."""
    first = {}
    for a in alerts:
        a = a.as_dict() if isinstance(a, AlertRecord) else a
        key = f"{a['criterion']}/{SEVERITY_NAMES[a['severity']]}"
        if key not in first:
            first[key] = a
    out = {}
    for key, a in first.items():
        lead_s = lead_m = math.nan
        if derailment is not None:
            lead_s = derailment["time_s"] - a["time_s"]
            lead_m = derailment["track_position_m"] - a["track_position"]
        out[key] = dict(time_s=a["time_s"], track_position_m=a["track_position"], speed_kmh=a["speed"] * 3.6,
                        value=a["value"], threshold=a["threshold"], wheelset=a["wheelset"],
                        wheel_side=a["wheel_side"], rail_side=a["rail_side"], lead_s=lead_s, lead_m=lead_m,
                        margin_kmh=margin_kmh(a, derailment))
    return out


def margin_kmh(alert, derailment):
    """The speed the car still gained between an alert and the derailment (km/h; NaN without a derailment):
    the warning's margin in the trial's own terms, which a lead in seconds is not (it depends on the ramp)."""
    if derailment is None:
        return math.nan
    return derailment["speed_kmh"] - alert["speed"] * 3.6


def user_alert(alert):
    """An alert dict (AlertRecord.as_dict or ros.interface.alert_dict) with its SI fields renamed by their unit
    for what a user reads (summary.json): speed_kmh, track_position_m."""
    out = {k: v for k, v in alert.items() if k not in ("speed", "track_position")}
    return dict(out, speed_kmh=alert["speed"] * 3.6, track_position_m=alert["track_position"])
