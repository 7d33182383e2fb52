"""Built-in profiles read from the shipped data files, and name/path resolution."""
from __future__ import annotations

import dataclasses
from functools import lru_cache
from pathlib import Path

from .arcbuilt import lm, uic60
from .profile import Profile
from .readers import load_profile

__all__ = ["s1002", "uic60_mbench", "builtin", "resolve", "BUILTIN_NAMES", "DATA_DIR"]

#: Folder of the shipped profile files (see its NOTICE).
DATA_DIR = Path(__file__).resolve().parent / "data"

_S1002_NOTES = """\
S1002 wheel (EN 13715), EXACT data: SIMPACK file MBench_S1002_v3.prw of the Manchester contact
benchmark (Shackleton & Iwnicki, VSD 46 (2008)), as shipped with E.A.H. Vollebregt's CONTACT
(Apache-2.0). Header mirror.y = 1 and inversion = 1 applied; flange back at y = -70 mm (the data start
at y = -69.61 mm, the rim side ends at +60 mm); z(0) = 0 to 1e-10 mm.
Dimensions (measured on this profile; EN 13715 nominal in brackets): flange height 28.00 mm (28),
flange thickness 32.50 mm at 10 mm above the tread datum (Sd 32.5), maximum flange angle 70.0 deg (70),
flange tip at y = -55.0 mm. S1002CN (the CRH3 service profile) is not public; S1002 is the exact
public alternative to the reconstructed LM."""

_UIC60_MBENCH_NOTES = """\
UIC60 (60E1) rail head, EXACT data: SIMPACK file MBench_UIC60_v3.prr of the Manchester contact
benchmark (already inclined 1:40, origin at the highest point, gauge side y < 0), shipped with CONTACT
(Apache-2.0). Un-inclined by atan(1/40) about its origin and re-centred (y = 0 midway between the side
faces 14 mm below the top, z = 0 at the top), so it is in our un-inclined rail frame. The file's head
ends 37.5 mm below the crown on both sides (|y| = 37.16 mm, the corner of the 1:20 face with the head
underside, like uic60()). Its R80 shoulder arcs start at |y| = 10.50 mm (uic60(): 10.228 mm per
EN 13674-1), so it lies up to 0.039 mm (normal) above uic60() on the shoulders and gauge corners;
head width 71.968 mm at 14 mm. Used to check the arc-built uic60()."""


@lru_cache(maxsize=None)
def s1002() -> Profile:
    """S1002 wheel (EN 13715) read from the shipped Manchester-benchmark file MBench_S1002_v3.prw."""
    p = load_profile(DATA_DIR / "MBench_S1002_v3.prw", kind="wheel")
    return dataclasses.replace(p, name="S1002", source="EN 13715 S1002; data MBench_S1002_v3.prw "
                               "(Manchester contact benchmark, via CONTACT, Apache-2.0)",
                               notes=_S1002_NOTES + "\nReader log:\n" + p.notes)


@lru_cache(maxsize=None)
def uic60_mbench() -> Profile:
    """UIC60 (60E1) rail from the shipped MBench_UIC60_v3.prr, un-inclined 1:40 and re-centred."""
    p = load_profile(DATA_DIR / "MBench_UIC60_v3.prr", kind="rail", inclination=1.0 / 40.0,
                     recentre=True)
    return dataclasses.replace(p, name="UIC60 (MBench)", source="EN 13674-1 60E1; data "
                               "MBench_UIC60_v3.prr (Manchester contact benchmark, via CONTACT, "
                               "Apache-2.0), un-inclined 1:40",
                               notes=_UIC60_MBENCH_NOTES + "\nReader log:\n" + p.notes)


_BUILTINS = {"lm": lm, "s1002": s1002, "uic60": uic60, "uic60-mbench": uic60_mbench}
_KIND = {"lm": "wheel", "s1002": "wheel", "uic60": "rail", "uic60-mbench": "rail"}
#: Accepted built-in names.
BUILTIN_NAMES = tuple(_BUILTINS)


def _key(name: str) -> str:
    return name.strip().lower().replace("_", "-")


def builtin(name: str) -> Profile:
    """A built-in profile by name: 'lm', 's1002', 'uic60' or 'uic60-mbench' (case-insensitive)."""
    k = _key(str(name))
    if k not in _BUILTINS:
        raise ValueError(f"profile name {name!r} is not a built-in; use one of {', '.join(BUILTIN_NAMES)}")
    return _BUILTINS[k]()


def resolve(name_or_path, kind: str) -> Profile:
    """A Profile from a built-in name, a file path, or a Profile, checked to be of ``kind``.

    ``kind`` is 'wheel' or 'rail'. Files are read with :func:`load_profile` defaults (for SIMPACK rails
    that means re-centring but no un-inclining: load the file yourself to pass ``inclination``).
    """
    if kind not in ("wheel", "rail"):
        raise ValueError(f"kind {kind!r} is not accepted; use 'wheel' or 'rail'")
    if isinstance(name_or_path, Profile):
        prof = name_or_path
    else:
        s = str(name_or_path)
        k = _key(s)
        if k in _BUILTINS:
            if _KIND[k] != kind:
                raise ValueError(f"built-in profile {s!r} is a {_KIND[k]} profile, but a {kind} profile "
                                 f"is needed; {kind} built-ins: "
                                 f"{', '.join(n for n in BUILTIN_NAMES if _KIND[n] == kind)}")
            return _BUILTINS[k]()
        p = Path(s).expanduser()
        if not p.is_file():
            raise ValueError(f"profile {s!r} is neither a built-in ({', '.join(BUILTIN_NAMES)}) nor an "
                             "existing file")
        prof = load_profile(p, kind=kind)
    if prof.kind != kind:
        raise ValueError(f"profile {prof.name!r} is a {prof.kind} profile, but a {kind} profile is needed")
    return prof
