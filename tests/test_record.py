"""The array layouts of the core (railderail_sim.record): offsets from the declaration, named views,
and the core's records as the numba core and the Python side both read them."""
import numba
import numpy as np
import pytest

from railderail_sim import jit
from railderail_sim.contact.layout import W_SIZE, Wheel, WheelPatch
from railderail_sim.record import Record
from railderail_sim.loads.layout import AeroLoad
from railderail_sim.track.layout import RailDof
from railderail_sim.vehicle.layout import N_OUT, N_STATE, Body, Dof, OutputRow, State, WheelsetOutput


class Point(Record):
    x = "m", "x"
    y = "m", "y"


class Sample(Record):
    time = "s", "time"
    points = "-", "three points", (3,), Point
    grid = "m", "a 2 x 2 grid", (2, 2)
    flag = "-", "a flag"


def test_offsets_follow_the_widths_in_declaration_order():
    assert [int(f) for f in Sample] == [0, 1, 7, 11]
    assert [f.width for f in Sample] == [1, 6, 4, 1]
    assert Sample.size() == 12 and Sample.points.stop == 7
    assert Sample.points.columns == slice(1, 7)
    assert Sample.grid.unit == "m" and Sample.points.record is Point


def test_split_gives_named_views_and_pack_fills_by_name():
    rows = np.arange(2 * Sample.size(), dtype=float).reshape(2, Sample.size())
    views = Sample.split(rows)
    assert views["time"].tolist() == [0.0, 12.0]
    assert views["points"].shape == (2, 3, 2) and views["points"][1, 2, Point.y] == 12.0 + 6.0
    assert views["grid"].shape == (2, 2, 2) and views["grid"][0, 1, 0] == 9.0
    views["flag"][:] = -1.0                       # views, not copies
    assert rows[:, 11].tolist() == [-1.0, -1.0]
    row = Sample.pack(time=2.5, points=[[1, 2], [3, 4], [5, 6]], flag=1.0)
    assert row.tolist() == [2.5, 1, 2, 3, 4, 5, 6, 0, 0, 0, 0, 1.0]
    with pytest.raises(ValueError, match="the record 12"):
        Sample.split(np.zeros((2, 11)))
    with pytest.raises(KeyError):
        Sample.pack(speed=1.0)


@numba.njit(cache=False, **jit.OPTIONS)
def _write(row):
    row[Sample.points + 2 * 2 + Point.y] = 7.0
    row[Sample.flag] = 1.0


def test_the_numba_core_indexes_with_the_members():
    row = np.zeros(Sample.size())
    _write(row)
    assert Sample.split(row)["points"][2, Point.y] == 7.0 and row[Sample.flag] == 1.0


def test_core_layouts_agree_with_the_array_sizes():
    assert N_STATE == 2 * len(Body) * Dof.size() + State.dampers.width + 1 + 2 * State.rail_deflections.width
    assert N_OUT == OutputRow.wheels + 8 * W_SIZE + 8 * RailDof.size() + AeroLoad.size() + len(Body) * 9
    assert W_SIZE == Wheel.patches + Wheel.patches.shape[0] * WheelPatch.size()
    x = np.arange(N_STATE, dtype=float)
    positions = State.split(x)["positions"]
    assert positions[Body.wheelset_2, Dof.yaw] == Dof.size() * Body.wheelset_2 + Dof.yaw
    rows = np.zeros((3, N_OUT))
    rows[:, OutputRow.wheelsets + WheelsetOutput.size() + WheelsetOutput.attack_angle] = 0.004
    assert WheelsetOutput.split(OutputRow.split(rows)["wheelsets"])["attack_angle"][:, 1].tolist() == [0.004] * 3
