"""Array layouts of the numba core, each declared once: its fields in order, with unit and meaning.

The core works on plain float64 arrays (the state vector, the output row, a wheel's record, a contact
patch's row, the body and force-element tables, the packed contact geometry and track, ...). Each such
layout is a `Record`: an `enum.IntEnum` whose members are its fields, declared in order with their unit,
their meaning and, for a field wider than one number, its shape (and the record of its last axis). The
member's value is the field's offset, computed from the widths of the fields before it, so no offset is
written by hand:

    class WheelPatch(Record):
        lateral_position = "m", "contact point on the rail from the head axis, + field side"
        normal_force = "N", "normal force of the patch"

    class Wheel(Record):
        wheel_lift = "m", "lift hp of the wheel"
        patches = "-", "one row per contact patch", (MAX_PATCHES,), WheelPatch

The numba core indexes with the members, which it compiles as integer constants
(`rec[Wheel.wheel_lift]`, `rec[Wheel.patches + k * WheelPatch.size() + WheelPatch.normal_force]`);
module-level sizes (`W_SIZE = Wheel.size()`) give the array lengths. The Python side gets named views
from the same declaration (`Wheel.split(records)["wheel_lift"]`, `Wheel.pack(wheel_lift=0.01)`), and the
documentation its table (`Wheel.describe()`).

Why an IntEnum: numba treats the members of a global IntEnum as integer constants, so the core pays
nothing for the names; a structured numpy dtype would change the type of every core array.
"""
import enum
import math

import numpy as np


class Record(enum.IntEnum):
    """Base class of a core array layout; a member is declared `name = unit, doc[, shape[, record]]`."""

    def __new__(cls, unit, doc, shape=(), record=None):
        offset = sum(member.width for member in cls._member_map_.values())
        field = int.__new__(cls, offset)
        field._value_ = offset
        field.unit = unit
        field.doc = doc
        field.shape = tuple(shape)
        field.record = record
        field.width = math.prod(field.shape) * (record.size() if record is not None else 1)
        return field

    @property
    def stop(self):
        """Offset just past the field."""
        return int(self) + self.width

    @property
    def columns(self):
        """The field's slice of the record's axis."""
        return slice(int(self), self.stop)

    @classmethod
    def size(cls):
        """Number of float64 entries of the record."""
        return sum(field.width for field in cls)

    @classmethod
    def names(cls):
        return [field.name for field in cls]

    @classmethod
    def pack(cls, **values):
        """A new record (float64 array of `size()`) with the named fields set; the others 0."""
        row = np.zeros(cls.size())
        for name, value in values.items():
            field = cls[name]
            row[field.columns] = np.ravel(value) if field.width > 1 else value
        return row

    @classmethod
    def split(cls, array):
        """{field name: view} of an array whose last axis is this record (length `size()`): a field of
        width one as (...,), a wider one as (..., *shape) and, with a record, (..., *shape, record size)."""
        if array.shape[-1] != cls.size():
            raise ValueError(f"{cls.__name__}: the last axis has {array.shape[-1]} entries, the record "
                             f"{cls.size()}")
        lead = array.shape[:-1]
        out = {}
        for field in cls:
            view = array[..., field.columns]
            if field.record is not None:
                view = view.reshape(lead + field.shape + (field.record.size(),))
            elif field.shape:
                view = view.reshape(lead + field.shape)
            else:
                view = view[..., 0]
            out[field.name] = view
        return out

    @classmethod
    def describe(cls):
        """Rows (name, offset, shape, unit, doc) of the layout, for documentation and messages."""
        return [(field.name, int(field), field.shape + ((field.record.__name__,) if field.record else ()),
                 field.unit, field.doc) for field in cls]
