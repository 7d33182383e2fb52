"""The line as data (railderail_sim/line): the shipped line files, the loader's one-line errors (each naming the
file, the section and the key), the round trip, and a curve's run as the simulator takes it."""
import math
import os
from pathlib import Path
import subprocess
import sys

import pytest
import yaml

from railderail_sim.line.data import Curve, Defect, Line, WindSite
from railderail_sim.line.file import dump_line, line_as_dict, load_line
from railderail_sim.parameters import TrackParameters
from railderail_sim.vehicle.simulate import KMH, Scenario

ROOT = Path(__file__).resolve().parents[1]


def test_shipped_lines_load():
    table2 = load_line("table2")
    assert len(table2.curves) == 1 and table2.length_m == TrackParameters().line_length
    demo = load_line("hsr-300-demo")
    assert demo.length_m >= 50000.0 and demo.line_speed_kmh == 300.0
    assert sum(800.0 <= c.radius_m <= 7000.0 for c in demo.curves) >= 10
    assert {d.kind for d in demo.defects} == {"kink", "twist"} and len(demo.wind_sites) == 2


def test_demo_line_keeps_its_stated_design_rules():
    """What the file's header says it was made by: cant at most 175 mm, every permitted speed within 100 mm of
    cant deficiency and the line speed, cant rates at most 33 mm/s at it."""
    demo = load_line("hsr-300-demo")
    for c in demo.curves:
        track = demo.track_for(c)
        v = demo.permitted_speed_kmh(c)
        assert c.cant_m <= 0.175 and v <= demo.line_speed_kmh
        assert v * KMH <= track.speed_at_cant_deficiency(0.100) + 1e-9
        assert c.cant_m / min(c.transition_in_m, c.transition_out_m) * v * KMH <= 0.033


def test_table2_curve_runs_as_the_default_scenario():
    """The Table 2 line's curve is run on exactly the default scenario's track: `trial` and `survey` agree."""
    line = load_line("table2")
    assert line.scenario_for(line.curves[0]).track == Scenario().track
    assert Line.from_track(TrackParameters(), "table2").curves == line.curves
    assert Line.from_track(TrackParameters(radius=math.inf, cant_height=0.0), "straight").curves == ()


def test_positions():
    c1 = Curve(100.0, 50.0, 200.0, 50.0, 1200.0, 0.1, -1, 160.0)
    c2 = Curve(600.0, 60.0, 300.0, 60.0, 3000.0, 0.12)
    line = Line("x", "test", "C", 2000.0, 250.0, (c1, c2), ((1500.0, 1800.0, 120.0),)).validated()
    assert c1.end_m == 400.0 and c1.full_curve_extent == (150.0, 350.0)
    assert line.curve_at(99.9) is None and line.curve_at(100.0) is c1 and line.curve_at(400.0) is None
    assert line.curve_at(700.0) is c2
    assert line.permitted_speed_at(200.0) == pytest.approx(160.0 * KMH)
    assert line.permitted_speed_at(700.0) == pytest.approx(250.0 * KMH)      # no limit of its own: the line's
    assert line.permitted_speed_at(1600.0) == pytest.approx(120.0 * KMH)
    assert line.local_position(c2, 700.0) == 300.0                           # 200 m of approach before it


def test_round_trip(tmp_path):
    demo = load_line("hsr-300-demo")
    dump_line(demo, tmp_path / "demo.yaml")
    assert load_line(tmp_path / "demo.yaml") == demo
    built = Line("built", "test", "B", 5000.0, 200.0,
                 (Curve(1000.0, 120.0, 333.3, 120.0, 1111.1, 0.0153, -1, 145.0),),
                 ((0.0, 500.0, 80.0),), (Defect(1200.0, "twist", 0.0137, 3.0, 7.0, "a note"),
                                         Defect(3000.0, "kink", 0.011, 4.0)), (WindSite(2500.0, "mast", "open"),))
    dump_line(built, tmp_path / "built.yaml")
    assert load_line(tmp_path / "built.yaml") == built


def _demo_data():
    return line_as_dict(load_line("hsr-300-demo"))


def _break_overlap(d):
    d["curves"][1]["start_m"] = d["curves"][0]["start_m"] + 10.0


def _break_order(d):
    d["curves"][0], d["curves"][1] = d["curves"][1], d["curves"][0]


def _set(section, index, key, value):
    def change(d):
        d[section][index][key] = value
    return change


def _drop(key):
    def change(d):
        del d[key]
    return change


def _add(key, value):
    def change(d):
        d[key] = value
    return change


@pytest.mark.parametrize("change, section, key", [
    (_break_overlap, "curves[1]", "start_m"),
    (_break_order, "curves[1]", "start_m"),
    (_set("curves", 3, "radius_m", 100.0), "curves[3]", "radius_m"),
    (_set("curves", 2, "transition_in_m", 20.0), "curves[2]", "transition_in_m"),
    (_set("curves", 2, "cant_mm", "a lot"), "curves[2]", "cant_mm"),
    (_set("curves", 2, "cant_mm", 250.0), "curves[2]", "cant_mm"),
    (_set("curves", 0, "direction", "up"), "curves[0]", "direction"),
    (_set("curves", 4, "radius", 3000.0), "curves[4]", "radius"),
    (_set("curves", 11, "start_m", 59900.0), "curves[11]", "start_m"),
    (_set("speed_limits", 0, "end_m", -5.0), "speed_limits[0]", "end_m"),
    (_set("defects", 1, "kind", "dip"), "defects[1]", "kind"),
    (_set("defects", 0, "size_mm", True), "defects[0]", "size_mm"),
    (_set("wind_sites", 1, "position_m", 70000.0), "wind_sites[1]", "position_m"),
    (_drop("length_m"), "line", "length_m"),
    (_add("speed", 300), "line", "speed"),
    (_add("line_speed_kmh", 1000), "line", "line_speed_kmh"),
])
def test_loader_names_file_section_and_key(tmp_path, change, section, key):
    data = _demo_data()
    change(data)
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    with pytest.raises(ValueError) as error:
        load_line(path)
    message = str(error.value)
    assert "\n" not in message
    assert message.startswith(f"{path}: {section}: ") and key in message


def test_loader_refuses_what_is_not_a_line_file(tmp_path):
    path = tmp_path / "broken.yaml"
    path.write_text("name: [unclosed\n")
    with pytest.raises(ValueError, match=r"broken.yaml: not a YAML file at line"):
        load_line(path)
    path.write_text("- a list\n")
    with pytest.raises(ValueError, match=r"broken.yaml: line: is not a mapping"):
        load_line(path)
    with pytest.raises(ValueError, match="is not a shipped line"):
        load_line("no-such-line")


def test_reading_a_line_does_not_load_the_core():
    """The monitor's side reads line files without numba (docs/design.md)."""
    code = ("import sys; from railderail_sim.line.file import load_line; load_line('hsr-300-demo'); "
            "assert 'numba' not in sys.modules, 'numba loaded'")
    subprocess.run([sys.executable, "-c", code], check=True, cwd=ROOT, env=dict(os.environ, PYTHONPATH=str(ROOT)))
