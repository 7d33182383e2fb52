"""Tests of railderail_sim.profiles: built-in profiles, cross-checks, readers, tables, errors.

Cross-check numbers quoted in docs/profiles.md are asserted here.
"""
import math

import numpy as np
import pytest

from railderail_sim.profiles import (BUILTIN_NAMES, Profile, ProfileError, ProfileTable, builtin,
                                     lm, load_profile, resolve, s1002, uic60, uic60_mbench)
from railderail_sim.profiles.arcbuilt import (LM_DATUM_SHIFT_MM, LM_PARAMS_MM, LM_PRW_EXTRACT_MM,
                                              lm_chain_mm, uic60_chain_mm)
from railderail_sim.profiles.builtins import DATA_DIR
from railderail_sim.profiles.readers import estimate_noise

MM = 1e-3


# ----------------------------------------------------------------------------- helpers
def _normal_dev(a: Profile, b: Profile, lo=None, hi=None, n=20001):
    """Max |z_a - z_b| measured normal to b, over the common y range (m)."""
    lo = max(a.y_min, b.y_min) if lo is None else lo
    hi = min(a.y_max, b.y_max) if hi is None else hi
    y = np.linspace(lo, hi, n)
    s = b.eval(y, 1)
    return float(np.max(np.abs(a.eval(y) - b.eval(y)) / np.sqrt(1.0 + s * s)))


def _assert_names(err, path, line, value):
    msg = str(err.value)
    assert str(path) in msg, msg
    assert f"line {line}" in msg, msg
    assert str(value) in msg, msg
    assert err.value.line == line


SIMPACK_HEAD = """\
! test file
  header.begin
    version = 1
    type = {type}
  header.end
  spline.begin
    approx.smooth = 0.0
    file = 'synthetic.txt'   ! original file
    comment = 'synthetic profile; with a ! inside quotes'
    shift.y = {shift_y!r}
    shift.z = {shift_z!r}
    rotate = {rotate!r}
    mirror.y = {mirror_y}
    mirror.z = {mirror_z}
    inversion = {inversion}
    units.len.f = {lenf!r}
    units.ang.f = {angf!r}
    point.begin
"""
SIMPACK_TAIL = """\
    point.end
  spline.end
"""


def _write_simpack(path, y, z, *, type=1, shift_y=0.0, shift_z=0.0, rotate=0.0, mirror_y=0,
                   mirror_z=0, inversion=0, lenf=1000.0, angf=1.0):
    head = SIMPACK_HEAD.format(type=type, shift_y=shift_y, shift_z=shift_z, rotate=rotate,
                               mirror_y=mirror_y, mirror_z=mirror_z, inversion=inversion, lenf=lenf,
                               angf=angf)
    body = "".join(f"      {a:.10e}  {b:.10e}\n" for a, b in zip(y, z))
    path.write_text(head + body + SIMPACK_TAIL)
    return path


def _simpack_forward(y_m, z_ours_m, kind, *, shift=(0.0, 0.0), rotate=0.0, mirror_y=0, mirror_z=0,
                     inversion=0, lenf=1000.0):
    """File values such that the documented processing gives back (y_m, z_ours_m)."""
    y = np.asarray(y_m) * lenf
    z = np.asarray(z_ours_m) * lenf * (1.0 if kind == "wheel" else -1.0)  # SIMPACK z is down
    if mirror_z:
        z = -z
    if mirror_y:
        y = -y
    c, s = math.cos(-rotate), math.sin(-rotate)   # undo the rotation the reader will apply
    y, z = c * y - s * z, s * y + c * z
    y, z = y - shift[0], z - shift[1]
    if inversion:
        y, z = y[::-1], z[::-1]
    return y, z


# ----------------------------------------------------------------------------- UIC60
def test_uic60_tangent_points_match_recomputed_table():
    """Tangent points computed by hand from the EN 13674-1 arcs: R300/R80 at 10.228, R80 centre (7.5005, -80.1279), R80/R13 at
    (26.0265, -2.3025), R13 centre (23.0160, -14.9491), 1:20 tangent at (36.000, -14.300)."""
    pieces = uic60_chain_mm().pieces
    line_l, r13_l, r80_l, r300_l, r300_r, r80_r, r13_r, line_r = pieces
    assert r300_r.r == 300.0 and r300_r.ya == 0.0 and r300_r.yb == pytest.approx(10.228)
    assert (r80_r.yc, r80_r.zc) == pytest.approx((7.5005, -80.1279), abs=1e-4)
    assert r80_r.yb == pytest.approx(26.0265)
    ch = uic60_chain_mm()
    assert ch(26.0265) == pytest.approx(-2.3025, abs=1e-4)
    assert (r13_r.yc, r13_r.zc) == pytest.approx((23.0160, -14.9491), abs=1e-4)
    assert (line_r.ya, ch(line_r.ya)) == pytest.approx((36.000, -14.300), abs=1e-3)
    assert line_r.m == -20.0 and line_l.m == 20.0
    # cut at the intersection of the 1:20 face with the 1:2.75 underside through (0, -51)
    assert (line_r.yb, ch(line_r.yb)) == pytest.approx((37.1592, -37.4876), abs=1e-4)
    assert line_r.yb == pytest.approx(-line_l.ya)
    # symmetric, and C1 at every joint (also checked by ArcChain itself)
    y = np.linspace(-37.0, 37.0, 1001)
    assert np.allclose(ch(y), ch(-y), atol=1e-12)
    for a, b in zip(pieces[:-1], pieces[1:]):
        yj = np.array([a.yb])
        assert a.eval(yj, 1)[0] == pytest.approx(b.eval(yj, 1)[0], abs=1e-9)


def test_uic60_head_width_and_top():
    u = uic60()
    assert u.kind == "rail"
    assert u.top_y() == pytest.approx(0.0, abs=1e-6)
    assert u.eval(0.0) == pytest.approx(0.0, abs=1e-12)
    assert u.head_width(0.014) / MM == pytest.approx(71.963, abs=0.001)
    assert u.head_width(0.0143) / MM == pytest.approx(72.000, abs=0.001)
    a, b = u.head_sides_y(0.014)
    assert a == pytest.approx(-b, abs=1e-9)


def test_uic60_arcs_agree_with_mbench_file():
    """Arc-built 60E1 vs the Manchester-benchmark UIC60 (un-inclined 1:40, re-centred).

    Crown (|y| <= 10 mm): identical (< 1 um). Beyond, the file's R80 starts at |y| = 10.50 mm instead of
    10.228 mm (EN 13674-1 per rohrbecka/EN13674), which lifts its shoulder/gauge corner by up to
    0.040 mm: measured max normal deviation 0.039 mm. Tolerance stated: 0.045 mm over the head.
    """
    u, m = uic60(), uic60_mbench()
    assert _normal_dev(m, u, -0.010, 0.010) < 1e-6
    dev = _normal_dev(m, u)
    assert dev < 0.045 * MM
    assert dev == pytest.approx(0.039 * MM, abs=0.002 * MM)
    assert m.head_width(0.014) / MM == pytest.approx(71.96, abs=0.01)
    assert abs(m.head_width(0.014) - u.head_width(0.014)) < 0.01 * MM
    # the file's head ends 37.5 mm below the crown on both sides, like the arc-built cut (37.49 mm)
    assert m.y_min == pytest.approx(-0.03716, abs=5e-5) and m.y_max == pytest.approx(0.03716, abs=5e-5)
    assert m.z[0] == pytest.approx(-0.0375, abs=1e-4) and m.z[-1] == pytest.approx(-0.0375, abs=1e-4)
    # the file's shoulder arc: R80 centred at (+-7.700, -80.135) mm -> tangent to R300 at |y| = 10.50
    sel = (m.y > 0.012) & (m.y < 0.025)
    yc, zc = 7.700 * MM, -80.1348 * MM
    assert np.allclose(np.hypot(m.y[sel] - yc, m.z[sel] - zc), 0.080, atol=1e-6)


def test_uic60_mbench_curvature_is_smooth():
    m = uic60_mbench()
    k = m.curvature(np.linspace(-0.009, 0.009, 19))
    assert np.allclose(k, -1 / 0.300, rtol=0.01)
    k80 = m.curvature(np.linspace(0.012, 0.024, 13))
    assert np.allclose(k80, -1 / 0.080, rtol=0.01)
    k13 = m.curvature(np.linspace(0.027, 0.035, 9))
    assert np.allclose(k13, -1 / 0.013, rtol=0.01)


# ----------------------------------------------------------------------------- ProfileTable
def test_table_slope_and_curvature_match_analytic_arcs():
    u = uic60()
    t = u.table(dy=5e-5)
    assert isinstance(t, ProfileTable)
    assert t.z.dtype == np.float64 and t.slope.dtype == np.float64 and t.curvature.dtype == np.float64
    assert t.z.shape == t.slope.shape == t.curvature.shape == (t.n,)
    assert t.y0 == u.y_min and t.y0 + (t.n - 1) * t.dy <= u.y_max + 1e-12
    y = t.y
    crown = np.abs(y) < 0.0102
    u_ = y[crown]
    assert np.allclose(t.slope[crown], -u_ / np.sqrt(0.3 ** 2 - u_ ** 2), atol=1e-12)
    assert np.allclose(t.z[crown], -0.3 + np.sqrt(0.3 ** 2 - u_ ** 2), atol=1e-15)
    # sign convention: convex crown (bulging toward the wheel) has negative curvature -1/R
    assert np.allclose(t.curvature[crown], -1.0 / 0.300, rtol=1e-12)
    r80 = (y > 0.0103) & (y < 0.0260)
    assert np.allclose(t.curvature[r80], -1.0 / 0.080, rtol=1e-12)
    r13 = (y > 0.0261) & (y < 0.0359)
    assert np.allclose(t.curvature[r13], -1.0 / 0.013, rtol=1e-12)
    face = y > 0.0361
    assert np.allclose(t.slope[face], -20.0) and np.allclose(t.curvature[face], 0.0)
    # wheel: concave R380 tread near the rolling circle is positive, the R12 flange tip negative
    tl = lm().table()
    yl = tl.y
    assert np.allclose(tl.curvature[np.abs(yl) < 0.008], 1.0 / 0.380, rtol=1e-12)
    tip = np.abs(yl + 0.054) < 0.005
    assert np.allclose(tl.curvature[tip], -1.0 / 0.012, rtol=1e-12)
    with pytest.raises(ValueError, match="dy"):
        u.table(dy=0.0)
    with pytest.raises(ValueError, match="dy"):
        u.table(dy=0.05)


def test_table_of_point_data_is_not_noisy():
    t = s1002().table()
    tread = np.abs(t.y) < 0.02
    # S1002's tread is a smooth polynomial: curvature on the tread is small and has no ripple
    k = t.curvature[tread]
    assert np.all(np.abs(k) < 20.0)
    assert np.max(np.abs(np.diff(k, 2))) < 0.05


# ----------------------------------------------------------------------------- LM
def test_lm_against_extract_table():
    """LM reconstruction vs the LM.prw coordinate extract (arcbuilt.LM_PRW_EXTRACT_MM): max 0.046 mm at y = -37
    (flange root, the least clean arc); tread (y >= -28 mm) within 0.001 mm; flange back, tip and face
    (-62 .. -40 mm) within 0.015 mm."""
    y, z = LM_PRW_EXTRACT_MM[:, 0], LM_PRW_EXTRACT_MM[:, 1]
    ch = lm_chain_mm(prw_datum=True)
    dev = ch(y) - z
    assert np.max(np.abs(dev)) < 0.050
    assert np.max(np.abs(dev)) == pytest.approx(0.046, abs=0.002)
    assert np.argmax(np.abs(dev)) == list(y).index(-37.0)
    assert np.max(np.abs(dev[y >= -28.0])) < 0.001
    assert np.max(np.abs(dev[(y >= -62.0) & (y <= -40.0)])) < 0.015
    # lm() itself is the same chain shifted so that z(0) = 0
    w = lm()
    assert w.eval(0.0) == pytest.approx(0.0, abs=1e-15)
    assert np.allclose(w.eval(y * MM) / MM - LM_DATUM_SHIFT_MM, ch(y), atol=1e-9)
    assert LM_DATUM_SHIFT_MM == pytest.approx(0.093, abs=0.001)


def test_lm_parameters_are_a_least_squares_optimum():
    """Refitting the free (least sure) parameters to the extract improves the RMS deviation by less
    than 0.001 mm: the shipped rounded values are the fit (r380_cz is rounded to centre the tread
    residuals rather than to minimise the RMS)."""
    from scipy.optimize import least_squares
    E = LM_PRW_EXTRACT_MM
    free = ["face_r", "flank_deg", "root_r", "r380_cz", "back_r"]

    def res(q):
        return lm_chain_mm(dict(zip(free, q)), prw_datum=True)(E[:, 0]) - E[:, 1]

    q0 = [LM_PARAMS_MM[k] for k in free]
    opt = least_squares(res, q0)
    rms = lambda r: float(np.sqrt(np.mean(r ** 2)))  # noqa: E731
    assert rms(res(q0)) <= rms(opt.fun) + 0.001


def test_lm_dimensions():
    w = lm()
    assert w.kind == "wheel"
    assert 0.0277 <= w.flange_height() <= 0.0278
    assert w.flange_height() / MM == pytest.approx(27.79, abs=0.005)
    assert w.flange_tip_y() / MM == pytest.approx(-54.0, abs=0.01)
    assert 69.0 <= math.degrees(w.max_flange_angle()) <= 70.0
    assert w.flange_thickness(0.012) / MM == pytest.approx(32.3, abs=0.1)
    # flange thickness read off the LM.prw table (heights above its z = 0 line, back face at -70 mm)
    sh = LM_DATUM_SHIFT_MM * MM
    for h, thick in [(10, 33.4), (12, 32.3), (13, 31.9), (15, 31.2)]:
        assert w.flange_thickness(h * MM + sh) / MM == pytest.approx(thick, abs=0.06)
    assert w.flange_thickness(w.flange_height() - 0.010) / MM == pytest.approx(30.0, abs=0.05)
    # rolling-circle zone: slope 1:15 at y = 0, horizontal at y = +25, reconstructed 1:8 outer slope
    assert w.eval(0.0, 1) == pytest.approx(-1 / 15, abs=0.002)
    assert w.eval(0.025, 1) == pytest.approx(0.0, abs=1e-12)
    assert w.eval(0.060, 1) == pytest.approx(-1 / 8, abs=1e-12)
    assert w.y_min == pytest.approx(-0.0695) and w.y_max == pytest.approx(0.065)


def _rigid_contact_y_on_wheel(wheel, rail, shift, inclination=1 / 40, gauge=1.435, depth=0.014,
                              half_rolling=0.7465):
    """Wheel y of the rigid contact point (minimum vertical gap) of the right wheel on the right rail
    when the wheelset is shifted by ``shift`` toward that rail's field side."""
    a = math.atan(inclination)
    yr = np.linspace(rail.y_min, rail.y_max, 20001)
    zr = rail.eval(yr)
    Y = yr * math.cos(a) - zr * math.sin(a)      # top turned toward the track centre (-Y)
    Z = yr * math.sin(a) + zr * math.cos(a)
    Z = Z - Z.max()
    top = int(np.argmax(Z))
    Y = Y + 0.5 * gauge - np.interp(-depth, Z[:top + 1], Y[:top + 1])
    c = half_rolling + shift
    yg = np.linspace(max(Y[0], wheel.y_min + c), min(Y[-1], wheel.y_max + c), 20001)
    gap = -wheel.eval(yg - c) - np.interp(yg, Y, Z)
    return float(yg[np.argmin(gap)] - c)


def test_lm_outer_tread_reached_only_late():
    """docs/profiles.md 3.4: within the flange clearance the contact stays in -40 .. +25 mm; the
    reconstructed outer tread (y > +34.5 mm) is reached only at ~38 mm lateral shift."""
    w, r = lm(), uic60()
    ys = [_rigid_contact_y_on_wheel(w, r, s * MM) for s in range(-10, 11, 2)]
    assert min(ys) > -0.041 and max(ys) < 0.0255
    assert _rigid_contact_y_on_wheel(w, r, 0.010) < -0.035          # flange contact
    assert _rigid_contact_y_on_wheel(w, r, -0.036) < 0.0345
    assert _rigid_contact_y_on_wheel(w, r, -0.040) > 0.0345


def test_lm_is_tangent_continuous():
    pieces = lm_chain_mm().pieces
    assert len(pieces) == 9
    for a, b in zip(pieces[:-1], pieces[1:]):
        yj = np.array([a.yb])
        assert a.eval(yj, 0)[0] == pytest.approx(b.eval(yj, 0)[0], abs=1e-10)
        assert a.eval(yj, 1)[0] == pytest.approx(b.eval(yj, 1)[0], abs=1e-9)
    w = lm()
    y = np.linspace(w.y_min, w.y_max, 200001)
    s = w.eval(y, 1)
    assert np.max(np.abs(np.diff(s))) < 0.01  # no slope jumps anywhere (fine grid)
    assert "RECONSTRUCTED" in w.notes and "ASSUMED" in w.notes


# ----------------------------------------------------------------------------- S1002
def test_s1002_dimensions():
    """EN 13715 nominal: flange height 28 mm, Sd 32.5 mm at 10 mm, flange angle 70 deg."""
    s = s1002()
    assert s.kind == "wheel"
    assert s.flange_height() / MM == pytest.approx(28.00, abs=0.005)
    assert s.flange_thickness(0.010) / MM == pytest.approx(32.50, abs=0.005)
    assert math.degrees(s.max_flange_angle()) == pytest.approx(70.0, abs=0.1)
    assert s.flange_tip_y() / MM == pytest.approx(-55.0, abs=0.01)
    assert s.eval(0.0) == pytest.approx(0.0, abs=1e-7)
    assert s.y_min / MM == pytest.approx(-69.6126) and s.y_max / MM == pytest.approx(60.0)


# ----------------------------------------------------------------------------- names
def test_builtin_and_resolve(tmp_path):
    assert set(BUILTIN_NAMES) == {"lm", "s1002", "uic60", "uic60-mbench"}
    assert builtin("LM") is lm()
    assert builtin("uic60_mbench") is uic60_mbench()
    assert resolve("s1002", "wheel") is s1002()
    assert resolve(uic60(), "rail") is uic60()
    with pytest.raises(ValueError, match="rail profile"):
        resolve("uic60", "wheel")
    with pytest.raises(ValueError, match="neither a built-in"):
        resolve(str(tmp_path / "missing.txt"), "wheel")
    with pytest.raises(ValueError, match="not a built-in"):
        builtin("s1003")
    f = tmp_path / "w.txt"
    f.write_text("".join(f"{a:.6f} {b:.6f}\n" for a, b in zip(lm().y / MM, lm().z / MM)))
    p = resolve(str(f), "wheel")
    assert p.kind == "wheel" and p.name == "w.txt"


def test_profile_validation():
    with pytest.raises(ProfileError, match="strictly increasing"):
        Profile("x", "rail", [0.0, 1.0, 1.0, 2.0], [0, 0, 0, 0])
    with pytest.raises(ValueError, match="kind"):
        Profile("x", "axle", [0.0, 1.0, 2.0, 3.0], [0, 0, 0, 0])
    with pytest.raises(ProfileError, match="not finite"):
        Profile("x", "rail", [0.0, 1.0, 2.0, 3.0], [0, np.nan, 0, 0])
    with pytest.raises(ValueError, match="outside profile"):
        uic60().eval(0.5)
    with pytest.raises(ValueError, match="wheel profile"):
        uic60().flange_height()
    with pytest.raises(ValueError, match="rail profile"):
        lm().head_width()
    with pytest.raises(ValueError, match="outside the head"):
        uic60().head_width(0.050)
    assert not lm().y.flags.writeable


# ----------------------------------------------------------------------------- text reader
def test_text_round_trip_mm_and_m(tmp_path):
    u = uic60()
    f = tmp_path / "rail_mm.txt"
    f.write_text("# UIC60 head written by the test\n# units: mm\n# kind: rail\n"
                 + "".join(f"{a:.9f}, {b:.9f}\n" for a, b in zip(u.y / MM, u.z / MM)))
    p = load_profile(f)
    assert p.kind == "rail" and p.name == "rail_mm.txt"
    assert np.allclose(p.y, u.y, atol=1e-12) and np.allclose(p.z, u.z, atol=1e-12)
    assert _normal_dev(p, u) < 0.2e-6
    assert p.head_width(0.014) == pytest.approx(u.head_width(0.014), abs=1e-6)
    g = tmp_path / "wheel_m.txt"
    w = lm()
    g.write_text("# units: m\n" + "".join(f"{a:.12f} {b:.12f}  # comment\n" for a, b in zip(w.y, w.z)))
    q = load_profile(g, kind="wheel", name="LM copy")
    assert q.name == "LM copy" and q.kind == "wheel"
    assert _normal_dev(q, w) < 0.2e-6
    assert q.flange_height() == pytest.approx(w.flange_height(), abs=1e-6)
    # text files are in our frame: no re-centring unless asked
    assert q.eval(0.0) == pytest.approx(0.0, abs=1e-7)


def test_text_rail_inclination_and_recentre(tmp_path):
    u = uic60()
    a = math.atan(1 / 40)
    y = math.cos(a) * u.y - math.sin(a) * u.z + 0.003   # canted 1:40 toward the gauge side, shifted
    z = math.sin(a) * u.y + math.cos(a) * u.z - 0.001
    f = tmp_path / "canted.txt"
    f.write_text("# kind: rail\n" + "".join(f"{p:.9f} {q:.9f}\n" for p, q in zip(y / MM, z / MM)))
    p = load_profile(f, inclination=1 / 40, recentre=True)
    assert _normal_dev(p, u, -0.036, 0.036) < 2e-6
    assert p.top_y() == pytest.approx(0.0, abs=2e-5)


# ----------------------------------------------------------------------------- SIMPACK reader
@pytest.mark.parametrize("opts", [
    dict(),
    dict(mirror_y=1, inversion=1),
    dict(mirror_z=1, lenf=1.0),
    dict(shift=(1.5, -0.25), rotate=0.01),
    dict(mirror_y=1, mirror_z=1, inversion=1, shift=(-2.0, 3.0), rotate=-0.02, lenf=1000.0),
])
def test_simpack_wheel_processing_keys(tmp_path, opts):
    w = lm()
    y, z = _simpack_forward(w.y, w.z, "wheel", **opts)
    angf = 180.0 / math.pi   # rotate given in degrees
    f = _write_simpack(tmp_path / "wheel.prw", y, z, type=1, shift_y=opts.get("shift", (0, 0))[0],
                       shift_z=opts.get("shift", (0, 0))[1], rotate=opts.get("rotate", 0.0) * angf,
                       mirror_y=opts.get("mirror_y", 0), mirror_z=opts.get("mirror_z", 0),
                       inversion=opts.get("inversion", 0), lenf=opts.get("lenf", 1000.0), angf=angf)
    p = load_profile(f)
    assert p.kind == "wheel"
    assert _normal_dev(p, w) < 1e-6
    assert p.flange_height() == pytest.approx(w.flange_height(), abs=1e-6)


def test_simpack_rail_is_negated_uninclined_and_recentred(tmp_path):
    u = uic60()
    a = math.atan(1 / 40)
    yc = math.cos(a) * u.y - math.sin(a) * u.z       # canted like the MBench file ...
    zc = math.sin(a) * u.y + math.cos(a) * u.z
    i = int(np.argmax(zc))
    yc, zc = yc - yc[i], zc - zc[i]                  # ... origin at the highest point
    f = _write_simpack(tmp_path / "rail.prr", yc / MM, -zc / MM, type=0)   # z downward
    p = load_profile(f, inclination=1 / 40)          # re-centring is the default for SIMPACK rails
    assert p.kind == "rail"
    assert _normal_dev(p, u, -0.036, 0.036) < 2e-6
    assert "re-centred" in p.notes and "un-inclined" in p.notes
    with pytest.raises(ProfileError, match="declares a rail"):
        load_profile(f, kind="wheel")


def test_simpack_reads_shipped_files_like_the_builtins():
    p = load_profile(DATA_DIR / "MBench_S1002_v3.prw")
    assert p.kind == "wheel" and p.flange_height() == pytest.approx(0.028, abs=1e-5)
    assert "mirror.y" in p.notes and "inversion" in p.notes


def test_reduction_drops_vertical_and_overhanging_parts(tmp_path):
    """A vertical back face below the flange back rounding and a vertical rim face that turns back
    under the tread: the reduction keeps the top point of each vertical run and drops the rest."""
    w = lm()
    yb = np.full(8, -0.070)                                        # back face, z = 6 .. 0 mm
    zb = np.linspace(0.0, 0.006, 8)
    yr = np.concatenate([np.full(5, w.y[-1]), w.y[-1] - np.linspace(0.001, 0.004, 4)])
    zr = np.concatenate([w.z[-1] - np.linspace(0.001, 0.012, 5), np.full(4, w.z[-1] - 0.012)])
    y = np.concatenate([yb, w.y, yr])
    z = np.concatenate([zb, w.z, zr])
    f = tmp_path / "wheel_with_faces.txt"
    f.write_text("# kind: wheel\n" + "".join(f"{a:.9f} {b:.9f}\n" for a, b in zip(y / MM, z / MM)))
    p = load_profile(f)
    assert p.y_min == pytest.approx(-0.070) and p.z[0] == pytest.approx(0.006)
    assert p.y_max == pytest.approx(w.y_max) and p.z[-1] == pytest.approx(w.z[-1])
    assert "7 points dropped at the low-y end and 9 at the high-y end" in p.notes
    assert _normal_dev(p, w, w.y_min + 0.001, w.y_max) < 0.5e-6


def test_auto_smoothing_removes_measurement_noise(tmp_path):
    rng = np.random.default_rng(7)
    y = np.linspace(-0.025, 0.025, 501)
    z = -0.3 + np.sqrt(0.09 - y * y)
    zn = z + rng.normal(0.0, 5e-6, y.size)            # 5 um measurement noise
    assert estimate_noise(y, zn) == pytest.approx(5e-6, rel=0.3)
    f = tmp_path / "noisy.txt"
    f.write_text("# kind: rail\n" + "".join(f"{a:.7f} {b:.7f}\n" for a, b in zip(y / MM, zn / MM)))
    smooth = load_profile(f)
    raw = load_profile(f, smoothing=0.0)
    yy = np.linspace(-0.02, 0.02, 401)
    assert np.max(np.abs(smooth.curvature(yy) * 0.3 + 1.0)) < 0.15
    assert np.max(np.abs(raw.curvature(yy) * 0.3 + 1.0)) > 1.0
    assert np.max(np.abs(smooth.eval(yy) - (-0.3 + np.sqrt(0.09 - yy * yy)))) < 5e-6
    assert "automatic" in smooth.notes


# ----------------------------------------------------------------------------- bad files
def _wheel_lines(n=None):
    w = lm()
    idx = np.arange(len(w.y))[::20] if n is None else np.linspace(0, len(w.y) - 1, n).astype(int)
    return [f"{w.y[i] / MM:.6f} {w.z[i] / MM:.6f}" for i in idx]


def test_error_non_numeric_value(tmp_path):
    lines = ["# kind: wheel"] + _wheel_lines()
    lines[30] = "-12.5 abc"
    f = tmp_path / "bad.txt"
    f.write_text("\n".join(lines) + "\n")
    with pytest.raises(ProfileError) as e:
        load_profile(f)
    _assert_names(e, f, 31, "'abc'")
    assert isinstance(e.value, ValueError)


def test_error_nan_value(tmp_path):
    lines = ["# kind: wheel"] + _wheel_lines()
    lines[12] = "nan 1.0"
    f = tmp_path / "nan.txt"
    f.write_text("\n".join(lines) + "\n")
    with pytest.raises(ProfileError, match="not a finite number") as e:
        load_profile(f)
    _assert_names(e, f, 13, "'nan'")


def test_error_too_few_points(tmp_path):
    lines = ["# kind: wheel"] + _wheel_lines(9)
    f = tmp_path / "few.txt"
    f.write_text("\n".join(lines) + "\n")
    with pytest.raises(ProfileError, match="at least 10") as e:
        load_profile(f)
    _assert_names(e, f, 10, "only 9")


def test_error_non_monotonic_y(tmp_path):
    lines = ["# kind: wheel"] + _wheel_lines()
    w = lm()
    i = int(np.argmin(np.abs(w.y[::20] - 0.010)))      # on the tread, where the profile is flat
    lines[1 + i], lines[2 + i] = lines[2 + i], lines[1 + i]
    f = tmp_path / "zigzag.txt"
    f.write_text("\n".join(lines) + "\n")
    with pytest.raises(ProfileError, match="single-valued") as e:
        load_profile(f)
    bad_y = lines[2 + i].split()[0]
    _assert_names(e, f, 3 + i, repr(bad_y))


def test_error_implausible_unit(tmp_path):
    lines = ["# units: m", "# kind: wheel"] + _wheel_lines()   # mm data declared as metres
    f = tmp_path / "unit_m.txt"
    f.write_text("\n".join(lines) + "\n")
    with pytest.raises(ProfileError, match="implausible") as e:
        load_profile(f)
    w = lm()
    ys = [ln.split()[0] for ln in lines[2:]]
    j = int(np.argmax(np.abs([float(v) for v in ys])))
    _assert_names(e, f, 3 + j, repr(ys[j]))
    assert "unit 'm'" in str(e.value)
    g = tmp_path / "unit_mm.txt"                      # metre data read with the default (mm)
    g.write_text("# kind: wheel\n" + "".join(f"{a:.7f} {b:.7f}\n" for a, b in zip(w.y, w.z)))
    with pytest.raises(ProfileError, match=r"0\.1345 mm wide") as e:
        load_profile(g)
    gl = g.read_text().splitlines()
    k = 1 + int(np.argmax([abs(float(s.split()[0])) for s in gl[1:]]))
    _assert_names(e, g, k + 1, repr(gl[k].split()[0]))
    assert "unit 'mm'" in str(e.value)


def test_error_unknown_simpack_key(tmp_path):
    w = lm()
    f = _write_simpack(tmp_path / "key.prw", w.y / MM, w.z / MM)
    text = f.read_text().replace("    version = 1\n", "    version = 1\n    colour = 'red'\n")
    f.write_text(text)
    line = text.splitlines().index("    colour = 'red'") + 1
    with pytest.raises(ProfileError, match="unknown header key") as e:
        load_profile(f)
    _assert_names(e, f, line, "'colour'")


def test_error_bad_simpack_value(tmp_path):
    w = lm()
    f = _write_simpack(tmp_path / "val.prw", w.y / MM, w.z / MM)
    text = f.read_text().replace("units.len.f = 1000.0", "units.len.f = 1e3x")
    f.write_text(text)
    line = [i for i, s in enumerate(text.splitlines(), 1) if "units.len.f" in s][0]
    with pytest.raises(ProfileError, match="not a number") as e:
        load_profile(f)
    _assert_names(e, f, line, "'1e3x'")


def test_error_missing_point_begin_or_end(tmp_path):
    w = lm()
    f = _write_simpack(tmp_path / "nobegin.prw", w.y / MM, w.z / MM)
    text = f.read_text()
    f.write_text(text.replace("    point.begin\n", ""))
    lines = f.read_text().splitlines()
    first = [i for i, s in enumerate(lines, 1) if s.strip().startswith("-6.95")][0]
    with pytest.raises(ProfileError, match="point.begin") as e:
        load_profile(f)
    _assert_names(e, f, first, lines[first - 1].strip())
    g = tmp_path / "neither.prw"
    g.write_text("".join(s + "\n" for s in text.splitlines() if not s.strip()[:1].isdigit()
                         and not s.strip().startswith(("-", "point."))))
    n = len(g.read_text().splitlines())
    with pytest.raises(ProfileError, match="no 'point.begin' found") as e:
        load_profile(g)
    _assert_names(e, g, n, "point.begin")
    h = tmp_path / "noend.prw"
    h.write_text(text.replace("    point.end\n", ""))
    n = h.read_text().splitlines().index("  spline.end") + 1
    with pytest.raises(ProfileError, match="never closed") as e:
        load_profile(h)
    _assert_names(e, h, n, "point.end")
    k = tmp_path / "noend_eof.prw"
    k.write_text(text.replace("    point.end\n", "").replace("  spline.end\n", ""))
    n = len(k.read_text().splitlines())
    with pytest.raises(ProfileError, match="never closed") as e:
        load_profile(k)
    _assert_names(e, k, n, "point.end")


def test_error_wheel_flange_at_positive_y(tmp_path):
    src = (DATA_DIR / "MBench_S1002_v3.prw").read_text()
    f = tmp_path / "nomirror.prw"
    f.write_text(src.replace("mirror.y       =  1", "mirror.y       =  0"))
    with pytest.raises(ProfileError, match="flange tip is at positive y") as e:
        load_profile(f)
    lines = f.read_text().splitlines()
    _assert_names(e, f, e.value.line, repr(lines[e.value.line - 1].split()[0]))
    assert float(e.value.value) == pytest.approx(54.9, abs=0.2)


def test_error_kind_missing(tmp_path):
    f = tmp_path / "nokind.txt"
    f.write_text("\n".join(_wheel_lines()) + "\n")
    with pytest.raises(ProfileError, match="kind"):
        load_profile(f)
    assert load_profile(f, kind="wheel").kind == "wheel"
