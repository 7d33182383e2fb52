"""`railderail bench`'s figures against their targets (cli/bench.py `against`)."""
import math

from railderail_sim.cli.bench import against


def test_a_figure_is_shown_met_or_short_by_how_much_and_why():
    assert against(80.0, 80.0, "why").strip() == "target 80: met"
    assert against(40.0, 80.0, "the contact").strip() == "target 80: short by 2.00 x (the contact)"
    assert "not measured" in against(math.nan, 2.0, "no git checkout")
    assert "not measured" in against(0.0, 2.0, "nothing timed")
