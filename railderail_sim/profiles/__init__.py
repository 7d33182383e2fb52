"""Wheel and rail profiles: built-in LM (reconstructed), S1002, UIC60; file readers; uniform tables.

Frames (SI units, metres; see docs/design.md and docs/profiles.md)
------------------------------------------------------------------
* **Wheel**: ``y`` along the axle from the nominal rolling (tape) circle, positive toward the outer rim
  face (field side), flange at negative ``y``; ``z`` = local wheel radius minus nominal radius, so the
  flange tip has large positive ``z`` and ``z(0) = 0``. Flange back (inner) face at ``y = -0.070`` for
  LM and S1002.
* **Rail**: the rail's own *un-inclined* frame: ``y`` positive toward the field side, ``y = 0`` on the
  axis of symmetry of the head; ``z`` up, ``z = 0`` at the crown top. Inclination (1:40) and gauge
  are applied by the contact geometry.

In both frames ``+z`` points from the profile toward the mating body (wheel: radius increase, i.e.
toward the rail; rail: up, toward the wheel).

Curvature sign
--------------
``curvature = z'' / (1 + z'^2)^1.5`` of the curve z(y) in the profile's own frame (the plain signed
curvature, unchanged by rotating the frame, e.g. by the 1:40 inclination). Because ``+z`` points toward
the mating body in both frames: **negative = the surface bulges toward the mating body (convex)**,
positive = it is hollow toward it (concave). Examples: the R300 crown of UIC60 has curvature
``-1/0.300`` 1/m; the LM flange tip (R12) ``-1/0.012``; the LM tread near the rolling circle (R380,
concave) ``+1/0.380``. A transverse radius that is positive for convex surfaces (Hertz convention) is
``-1/curvature``.

Public API
----------
``Profile``            frozen dataclass: name, kind ('wheel'|'rail'), y, z (float64, m, y strictly
                       increasing), source, notes, shape (C2 representation). Methods: ``eval(y, nu)``,
                       ``curvature(y)``, ``table(dy)``; wheel: ``flange_height()``,
                       ``flange_tip_y()``, ``flange_thickness(height_above_rolling_line=0.010,
                       back_face_y=-0.070)``, ``max_flange_angle()`` (rad); rail: ``top_y()``,
                       ``head_width(depth_below_top=0.014)``.
``ProfileTable``       uniform resampling: y0, dy, n, z, slope, curvature (float64 arrays), kind, name;
                       ``ProfileTable.from_profile(profile, dy=5e-5)``.
``ProfileError``       ValueError subclass for bad profile files/arrays (message names file, line, value).
``load_profile(path, kind=None, *, inclination=None, recentre=None, smoothing=None, name=None)``
                       plain two-column text (mm by default) or SIMPACK .prw/.prr.
``lm()``               LM wheel, RECONSTRUCTED as tangent arcs fitted to SIMPACK's example LM.prw.
``s1002()``            S1002 wheel, exact data (Manchester benchmark file).
``uic60()``            UIC60 / 60E1 rail head, exact EN 13674-1 arcs.
``uic60_mbench()``     UIC60 from the Manchester benchmark file, un-inclined and re-centred.
``builtin(name)``      'lm', 's1002', 'uic60', 'uic60-mbench'.
``resolve(name_or_path, kind)``  a built-in name, a file path or a Profile, checked for kind.
"""
from .arcbuilt import lm, uic60
from .builtins import BUILTIN_NAMES, builtin, resolve, s1002, uic60_mbench
from .profile import Profile, ProfileError, ProfileTable
from .readers import load_profile

__all__ = ["Profile", "ProfileTable", "ProfileError", "load_profile", "lm", "s1002", "uic60",
           "uic60_mbench", "builtin", "resolve", "BUILTIN_NAMES"]
