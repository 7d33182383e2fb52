"""Track irregularities (railderail_sim.track.irregularity): the spectra against their published formulas
written out here with the published constants, generated samples against the spectra (Welch, Parseval),
determinism, the CSV format and its errors, the packed layout the core reads, the command."""
import math
import warnings

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.signal import welch

from railderail_sim import cli
from railderail_sim.track import irregularity as ir
from railderail_sim.track import spectra as sp

# Each published formula with its constants typed from the tables (not read from the module), at one
# frequency. Cross-level as the rails' height difference: ERRI's angle times 2b = 1.5 m, squared.
W = 0.5          # rad/m


def erri_shape(wc=0.8246, wr=0.0206):
    return wc ** 2 / ((W ** 2 + wr ** 2) * (W ** 2 + wc ** 2))


def fra_profile(a_cm2, k=0.25, wc=0.8245):
    return k * a_cm2 * 1e-4 * wc ** 2 / (W ** 2 * (W ** 2 + wc ** 2))


def fra_cross(a_cm2, ws, k=0.25, wc=0.8245):
    return 4 * k * a_cm2 * 1e-4 * wc ** 2 / ((W ** 2 + wc ** 2) * (W ** 2 + ws ** 2))


PUBLISHED = [
    ("erri-low", "vertical", 4.032e-7 * erri_shape()),
    ("erri-high", "vertical", 10.80e-7 * erri_shape()),
    ("erri-low", "alignment", 2.119e-7 * erri_shape()),
    ("erri-high", "alignment", 6.125e-7 * erri_shape()),
    ("erri-low", "cross_level", 1.5 ** 2 * 4.032e-7 / 0.75 ** 2 * erri_shape() * W ** 2 / (W ** 2 + 0.4380 ** 2)),
    ("erri-high", "cross_level", 1.5 ** 2 * 10.80e-7 / 0.75 ** 2 * erri_shape() * W ** 2 / (W ** 2 + 0.4380 ** 2)),
    ("erri-low", "gauge", 0.532e-7 * erri_shape() * W ** 2 / (W ** 2 + 0.4380 ** 2)),
    ("erri-high", "gauge", 1.032e-7 * erri_shape() * W ** 2 / (W ** 2 + 0.4380 ** 2)),
    ("fra-1", "vertical", fra_profile(1.2107)),
    ("fra-4", "vertical", fra_profile(0.5376)),
    ("fra-6", "vertical", fra_profile(0.0339)),
    ("fra-1", "alignment", fra_profile(3.3634)),
    ("fra-5", "alignment", fra_profile(0.0762)),
    ("fra-2", "cross_level", fra_cross(1.0181, 0.9308)),
    ("fra-6", "cross_level", fra_cross(0.0339, 0.4380)),
    ("fra-3", "gauge", fra_cross(0.6816, 0.8520)),
    ("fra-4", "gauge", fra_cross(0.5376, 1.1312)),
    # TB/T 3352 at f = W / 2 pi = 0.0796 1/m, in each case's piece, mm^2/(1/m) -> m^2/(rad/m)
    ("china-hsr", "vertical", 1.9784e-2 / (W / (2 * math.pi)) ** 1.3643 * 1e-6 / (2 * math.pi)),
    ("china-hsr", "alignment", 1.1047e-2 / (W / (2 * math.pi)) ** 1.5354 * 1e-6 / (2 * math.pi)),
    ("china-hsr", "cross_level", 4.3685e-2 / (W / (2 * math.pi)) ** 1.0461 * 1e-6 / (2 * math.pi)),
    ("china-hsr", "gauge", 5.4978e-2 / (W / (2 * math.pi)) ** 0.8282 * 1e-6 / (2 * math.pi)),
]


@pytest.mark.parametrize("name, component, expected", PUBLISHED, ids=lambda x: x if isinstance(x, str) else "")
def test_each_spectrum_is_the_published_formula(name, component, expected):
    assert sp.SPECTRA[name].psd(component, W) == pytest.approx(expected, rel=1e-12)


def test_tbt3352_unit_conversion_by_hand():
    # vertical, f = 0.1 1/m (third piece, 0.0474 <= f < 0.1533): 1.9784e-2 / 0.1^1.3643 = 0.45773 mm^2/(1/m);
    # per rad/m: / (2 pi) = 0.072851 mm^2/(rad/m) = 7.2851e-8 m^2/(rad/m), at Omega = 2 pi 0.1 = 0.62832 rad/m
    assert sp.tbt3352_psd_f("vertical", 0.1) == pytest.approx(0.45773, rel=1e-4)
    assert sp.tbt3352_psd("vertical", 0.62832) == pytest.approx(7.2851e-8, rel=1e-4)
    # the pieces switch at the breaks; outside 0.005 .. 0.5 1/m the fit is undefined
    assert sp.tbt3352_psd_f("gauge", 0.3) == pytest.approx(1.8778e-4 / 0.3 ** 4.5948, rel=1e-12)
    assert sp.tbt3352_psd_f("alignment", 0.02) == pytest.approx(3.9513e-3 / 0.02 ** 1.8670, rel=1e-12)
    assert np.isnan(sp.tbt3352_psd_f("vertical", [0.004, 0.6])).all()


def test_erri_cross_level_is_an_angle_and_the_track_gets_the_height_difference():
    angle = sp.erri_psd("cross_level", W, "low")
    assert angle == pytest.approx(4.032e-7 / 0.75 ** 2 * erri_shape() * W ** 2 / (W ** 2 + 0.4380 ** 2))
    assert sp.SPECTRA["erri-low"].psd("cross_level", W) == pytest.approx(1.5 ** 2 * angle)


def test_every_constant_has_a_unit_a_source_and_a_confidence():
    rows = sp.constants_table()
    assert len({row[0] for row in rows}) == len(rows)
    for name, value, unit, source, sure, note in rows:
        assert unit and source in sp.SOURCES and sure in "VSA", name


def octave_errors(omega, estimate, formula, lo, hi):
    """(band start, estimate / formula - 1) of the band-averaged PSDs in each octave of lo..hi."""
    edges = list(lo * 2.0 ** np.arange(0, 1 + math.floor(math.log2(hi / lo)))) + [hi]
    out = []
    for a, b in zip(edges[:-1], edges[1:]):
        inside = (omega >= a) & (omega < b)
        if inside.any():
            out.append((a, estimate[inside].mean() / formula[inside].mean() - 1.0))
    return out


@pytest.mark.parametrize("name", list(sp.SPECTRA))
def test_welch_psd_of_a_sample_follows_the_spectrum_in_every_octave(name):
    spectrum = sp.SPECTRA[name]
    step = 0.25
    sample = ir.generate(name, 40e3, seed=list(sp.SPECTRA).index(name), step_m=step)
    assert sample.band_m == pytest.approx(spectrum.band_m)
    lo, hi = 2 * math.pi / spectrum.band_m[1], 2 * math.pi / spectrum.band_m[0]
    for component, x in sample.components().items():
        f, p = welch(x, fs=1 / step, nperseg=4096)            # one-sided, per 1/m; segments of 1024 m
        omega, estimate = 2 * math.pi * f[1:], p[1:] / (2 * math.pi)
        errors = octave_errors(omega, estimate, spectrum.psd(component, omega), lo, hi)
        assert len(errors) >= 6
        assert all(abs(e) < 0.25 for _, e in errors), (component, errors)


@pytest.mark.parametrize("name", ["erri-high", "fra-3", "china-hsr"])
def test_variance_is_the_integral_of_the_psd_over_the_band(name):
    spectrum = sp.SPECTRA[name]
    sample = ir.generate(name, 20e3, seed=5)
    lo, hi = 2 * math.pi / sample.band_m[1], 2 * math.pi / sample.band_m[0]
    breaks = [2 * math.pi * b for b in (0.0187, 0.0474, 0.1533, 0.045, 0.1234, 0.0258, 0.1163, 0.109, 0.2938)]
    for component, x in sample.components().items():
        integral = quad(lambda w: spectrum.psd(component, w), lo, hi, limit=400,
                        points=[b for b in breaks if lo < b < hi])[0]
        assert np.var(x) == pytest.approx(integral, rel=0.03), component


def test_a_short_sample_holds_no_wavelength_longer_than_its_period():
    sample = ir.generate("erri-low", 40.0, seed=1)
    assert sample.band_m[0] == pytest.approx(1.0) and 80.0 <= sample.band_m[1] < 100.0


def test_same_seed_same_sample_bit_for_bit_another_seed_another():
    a = ir.generate("fra-4", 3000.0, seed=42, step_m=0.1, band_m=(2.0, 120.0))
    b = ir.generate("fra-4", 3000.0, seed=42, step_m=0.1, band_m=(2.0, 120.0))
    c = ir.generate("fra-4", 3000.0, seed=43, step_m=0.1, band_m=(2.0, 120.0))
    assert a.values.tobytes() == b.values.tobytes() and a.slopes.tobytes() == b.slopes.tobytes()
    assert a.s.tobytes() == b.s.tobytes()
    rms = np.sqrt(np.mean(a.values ** 2, axis=0))
    assert np.all(np.sqrt(np.mean((a.values - c.values) ** 2, axis=0)) > 0.5 * rms)


def test_slopes_are_the_derivatives_of_the_channels():
    sample = ir.generate("china-hsr", 2000.0, seed=3, step_m=0.05, band_m=(8.0, 150.0))
    central = (sample.values[2:] - sample.values[:-2]) / (2 * 0.05)      # O((Omega h)^2 / 6) <= 3e-4
    scale = np.abs(sample.slopes).max(axis=0)
    assert np.all(np.abs(central - sample.slopes[1:-1]).max(axis=0) < 1e-3 * scale)
    assert np.all(scale > 0)


def test_components_and_rails_follow_the_sign_conventions():
    unit = {c: np.zeros(1) for c in sp.COMPONENTS}
    widening = ir.rails_from_components({**unit, "gauge": np.ones(1)})[0]
    assert widening.tolist() == [0.5, 0.0, -0.5, 0.0]          # left rail further left, right rail further right
    left_high = ir.rails_from_components({**unit, "cross_level": np.ones(1)})[0]
    assert left_high.tolist() == [0.0, 0.5, 0.0, -0.5]
    sample = ir.generate("erri-low", 500.0, seed=2)
    for name, x in ir.Irregularity(sample.s, ir.rails_from_components(sample.components())).components().items():
        assert np.allclose(x, sample.components()[name], atol=1e-15)


def test_at_interpolates_cubic_hermite_or_linear_and_is_zero_outside():
    s = np.arange(0.0, 20.0001, 0.5)
    wave = 2 * math.pi / 10.0
    values = np.sin(wave * s)[:, None] * np.array([1.0, 2.0, -1.0, 0.5])
    slopes = wave * np.cos(wave * s)[:, None] * np.array([1.0, 2.0, -1.0, 0.5])
    between = np.arange(0.25, 19.9, 0.5)
    exact = np.sin(wave * between)[:, None] * np.array([1.0, 2.0, -1.0, 0.5])
    hermite = ir.Irregularity(s, values, slopes)
    linear = ir.Irregularity(s, values, None)
    assert np.abs(hermite.at(between) - exact).max() < 2e-4 * 2
    assert np.abs(linear.at(between) - exact).max() > 0.02
    assert np.allclose(linear.at(s), values) and np.allclose(hermite.at(s), values)
    assert not hermite.at([-0.01, 20.01]).any()


def test_pack_is_the_documented_layout():
    # header: points, interpolation; then per point s, 4 deviations, 4 slopes (track.rails)
    sample = ir.generate("erri-high", 10.0, seed=0)
    packed = sample.pack()
    n = len(sample.s)
    assert packed.shape == (2 + 9 * n,)
    assert packed[:2].tolist() == [n, 1.0]
    row = packed[2 + 9 * 7: 2 + 9 * 8]
    assert row[0] == sample.s[7] == 1.75
    assert row[1:5].tolist() == sample.values[7].tolist() and row[5:9].tolist() == sample.slopes[7].tolist()
    uneven = ir.Irregularity(np.array([0.0, 1.0, 3.0]), np.array([[0, 0, 0, 0], [1, 0, 0, 0], [0, 0, 0, 0]]))
    packed = uneven.pack()
    assert packed[:2].tolist() == [3.0, 0.0] and packed[2 + 5] == 1.0 and packed[2 + 9 + 5] == -0.5


def test_csv_round_trip_to_the_micrometre(tmp_path):
    sample = ir.generate("fra-5", 300.0, seed=9)
    path = tmp_path / "fra5.csv"
    ir.write_csv(sample, path)
    assert path.read_text().splitlines()[0] == "s_m,left_lateral_mm,left_vertical_mm,right_lateral_mm,right_vertical_mm"
    back = ir.read_csv(path)
    assert back.slopes is None and back.pack()[1] == 0.0
    assert np.abs(back.s - sample.s).max() < 1e-6
    assert np.abs(back.values - sample.values).max() < 1e-6          # m: a micrometre
    assert back.uniform_step() == 0.25


HEADER = "s_m,left_lateral_mm,left_vertical_mm,right_lateral_mm,right_vertical_mm\n"


def test_a_record_off_zero_at_an_end_warns_of_the_step_a_run_meets(tmp_path):
    path = tmp_path / "cut.csv"
    path.write_text(HEADER + "100,0,0,0,0\n110,0,0.5,0,0\n120,0,-4.5,0,0\n")
    with pytest.warns(UserWarning, match=r"last row \(s = 120 m\) has left_vertical_mm -4.5; .* 4.5 mm step"):
        ir.read_csv(path)
    path.write_text(HEADER + "100,0,0,0,0\n110,0,0.5,0,0\n120,0,0.9,0,0\n")      # within 1 mm: quiet
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ir.read_csv(path)
BAD_FILES = [
    ("", "line 1", "empty"),
    ("s,yl,zl,yr,zr\n0,0,0,0,0\n1,0,0,0,0\n", "line 1", "'s,yl,zl,yr,zr'"),
    (HEADER + "0,0,0,0\n1,0,0,0,0\n", "line 2", "4 values '0,0,0,0'"),
    (HEADER + "0,0,0,0,0\n1,0,0,0,0,0\n", "line 3", "6 values '1,0,0,0,0,0'"),
    (HEADER + "0,0,abc,0,0\n1,0,0,0,0\n", "line 2", "left_vertical_mm 'abc' is not a number"),
    (HEADER + "0,0,0,0,0\n1,nan,0,0,0\n", "line 3", "left_lateral_mm 'nan' is not a finite number"),
    (HEADER + "0,0,0,0,0\n1,0,0,0,-inf\n", "line 3", "right_vertical_mm '-inf' is not a finite number"),
    (HEADER + "0,0,0,0,0\n1,0,0,0,0\n1,0,0,0,0\n", "line 4", "s_m 1 m does not increase"),
    (HEADER + "0,0,0,0,0\n2,0,0,0,0\n1.5,0,0,0,0\n", "line 4", "s_m 1.5 m does not increase"),
    (HEADER + "0,0,0,0,0\n", "line 2", "1 data row(s)"),
    (HEADER + "0,0,0,612,0\n1,0,0,0,0\n", "line 2", "right_lateral_mm 612 mm is outside the accepted range"),
]


@pytest.mark.parametrize("content, line, value", BAD_FILES)
def test_a_bad_file_is_one_line_naming_the_file_the_line_and_the_value(tmp_path, content, line, value):
    path = tmp_path / "bad.csv"
    path.write_text(content)
    with pytest.raises(ValueError) as error:
        ir.read_csv(path)
    message = str(error.value)
    assert "\n" not in message and "bad.csv" in message and line in message and value in message, message


def test_a_missing_file_is_one_line(tmp_path):
    with pytest.raises(ValueError, match=r"nothere\.csv' cannot be read \(No such file"):
        ir.read_csv(tmp_path / "nothere.csv")


def test_blank_lines_are_skipped_and_line_numbers_stay_true(tmp_path):
    path = tmp_path / "gaps.csv"
    path.write_text(HEADER + "0,1,2,3,4\n\n2,1,2,3,4\n\n1,0,0,0,0\n")
    with pytest.raises(ValueError, match="line 6: s_m 1 m does not increase"):
        ir.read_csv(path)


def test_the_command_writes_the_file_and_prints_the_summary(tmp_path, capsys):
    out = tmp_path / "t.csv"
    plot = tmp_path / "t.png"
    assert cli.main(["track-irregularity", "--spectrum", "china-hsr", "--seed", "4", "--length-m", "800",
                     "--out", str(out), "--plot", str(plot)]) == 0
    text = capsys.readouterr().out
    assert "seed 4" in text and "wavelengths 2 to 200 m" in text and "gauge" in text and "RMS" in text
    back = ir.read_csv(out)
    again = ir.generate("china-hsr", 800.0, seed=4)
    assert np.abs(back.values - again.values).max() < 1e-6 and plot.stat().st_size > 10_000
    rms_mm = float(text.split("vertical profile ")[1].split(" mm")[0])
    assert rms_mm == pytest.approx(np.sqrt(np.mean(again.components()["vertical"] ** 2)) * 1e3, abs=1e-3)


@pytest.mark.parametrize("options, message", [
    (["--length-m", "5"], "length 5 m is outside the accepted range [10, 200000] m"),
    (["--length-m", "3e5"], "length 300000 m is outside the accepted range [10, 200000] m"),
    (["--step-m", "0.01"], "step 0.01 m is outside the accepted range [0.05, 1] m"),
    (["--band-m", "0.2,150"], "band wavelength 0.2 m is outside the accepted range [0.5, 1000] m"),
    (["--band-m", "1,2000"], "band wavelength 2000 m is outside the accepted range [0.5, 1000] m"),
    (["--band-m", "150,1"], "band 150..1 m: the shortest wavelength must come first"),
    (["--step-m", "1", "--band-m", "1,150"], "band shortest wavelength 1 m needs a step of at most 0.5 m"),
    (["--seed", "-3"], "seed -3 is outside the accepted range: an integer in [0, 999999]"),
    (["--plot", "x.jpg"], "plot file 'x.jpg' must end in .png, .pdf or .svg"),
    (["--out", "x.txt"], "output file 'x.txt' must end in .csv"),
])
def test_bad_options_are_one_line_and_status_2(tmp_path, capsys, options, message):
    args = {"--spectrum": "erri-low", "--seed": "1", "--length-m": "100", "--out": str(tmp_path / "x.csv")}
    args.update(dict(zip(options[::2], options[1::2])))
    assert cli.main(["track-irregularity", *[x for pair in args.items() for x in pair]]) == 2
    err = capsys.readouterr().err
    assert err == f"railderail: error: {message}" + err.split(message, 1)[1] and err.count("\n") == 1, err
    assert not (tmp_path / "x.csv").exists()


def test_china_band_must_stay_where_the_fit_holds(tmp_path, capsys):
    assert cli.main(["track-irregularity", "--spectrum", "china-hsr", "--seed", "1", "--length-m", "100",
                     "--band-m", "1,150", "--out", str(tmp_path / "x.csv")]) == 2
    assert "band 1..150 m is outside the accepted range [2, 200] m of china-hsr" in capsys.readouterr().err


def test_a_generated_sample_fades_in_and_out_without_a_step():
    sample = ir.generate("erri-high", 400.0, seed=4)
    raw = ir.generate("erri-high", 400.0, seed=4, taper_m=0.0)
    assert np.all(sample.values[0] == 0.0) and np.all(sample.values[-1] == 0.0)
    assert np.all(sample.slopes[0] == 0.0) and np.all(sample.slopes[-1] == 0.0)
    middle = (sample.s >= 50.0) & (sample.s <= 350.0)
    assert np.array_equal(sample.values[middle], raw.values[middle])
    # the faded slopes are the derivatives of the faded values (a band of 8 m and longer on a 5 cm grid)
    sample = ir.generate("china-hsr", 300.0, seed=3, step_m=0.05, band_m=(8.0, 150.0))
    central = (sample.values[2:] - sample.values[:-2]) / (2 * 0.05)
    fade = sample.s[1:-1] <= ir.TAPER_M
    scale = np.abs(sample.slopes).max(axis=0)
    assert np.all(np.abs(central - sample.slopes[1:-1])[fade].max(axis=0) < 1e-3 * scale)


def test_resolve_gives_none_a_sample_along_the_line_or_the_file(tmp_path):
    assert ir.resolve("none", 3, 1800.0) is None
    sample = ir.resolve("fra-5", 3, 1800.0)
    assert sample.s[-1] == pytest.approx(1800.0 + ir.LINE_MARGIN_M, abs=0.25) and sample.seed == 3
    ir.write_csv(sample, tmp_path / "site.csv")
    back = ir.resolve(str(tmp_path / "site.csv"), 0, 100.0)
    assert np.abs(back.values - sample.values).max() < 1e-6
    with pytest.raises(ValueError, match=r"irregularity 'bumpy' is not 'none', a spectrum \(erri-low"):
        ir.resolve("bumpy", 0, 100.0)
