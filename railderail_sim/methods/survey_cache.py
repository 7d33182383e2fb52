"""Where a survey's cases are cached (`survey.run_case`): the key of each case, from its inputs and the sources
of railderail_sim, so that a cached case is reused only by a case that would compute the same."""
from dataclasses import asdict
import functools
import hashlib
from pathlib import Path

from .. import jsonout


@functools.lru_cache(maxsize=1)
def source_hash():
    """SHA-256 of railderail_sim's Python sources: a cached case is valid for these only."""
    digest = hashlib.sha256()
    for path in sorted(Path(__file__).resolve().parents[1].rglob("*.py")):
        digest.update(path.read_bytes())
    return digest.hexdigest()


def case_key(item, line_data, base, settings):
    """The SHA-256 a case (kind, index, *arguments) of the line `line_data` (its file's content) is cached under,
    with the base Scenario and the survey's Settings. A curve's case reads of its line only the curve's shape
    and the gauge (its run is `Line.scenario_for`'s, placed on Table 2's straights), so it is keyed on those and
    shared by every line with that curve (the warning evaluation's lines with a defect on another's curve)."""
    kind, index, *arguments = item
    if kind == "curve":
        shape = {k: v for k, v in line_data["curves"][index].items() if k not in ("start_m", "permitted_speed_kmh")}
        item, line_data = (kind, 0, *arguments), dict(curve=shape, rail_spacing_m=line_data["rail_spacing_m"])
    return hashlib.sha256(jsonout.dumps(dict(item=list(item), line=line_data, base=_base_key(base),
                                             settings=asdict(settings), code=source_hash())).encode()).hexdigest()


def _base_key(base):
    """What a survey's runs take from the base scenario, as plain data."""
    return dict(contact=asdict(base.contact), rail_profile=base.track.rail_profile, track_model=base.track_model,
                wind=None if base.wind is None else asdict(base.wind), faults=list(base.faults),
                elastic_track=asdict(base.elastic_track), aerodynamics=asdict(base.aerodynamics))
