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
    return f"{SEVERITY_NAMES[severity]}: {criterion.replace('_', ' ')} {amount} on {where}"



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
                        wheel_side=a["wheel_side"], rail_side=a["rail_side"], lead_s=lead_s, lead_m=lead_m)
    return out
