"""The ROS 2 nodes' parameter tables: one `ParameterSpec` per parameter (its default, meaning, unit and accepted
range, declared through rclpy's ParameterDescriptor so that `ros2 param describe` shows them), their
declaration with checks on every change (`declare_parameters`) and the parameter file a node's defaults are
written to (`parameter_file`)."""
from __future__ import annotations

from dataclasses import dataclass
import math

from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor, SetParametersResult
from rclpy.parameter import Parameter

from ..ranges import check_range

REAL_TIME_FACTOR_RANGE = (0.0, 1000.0)      # simulated (or recorded) seconds per wall second; 0 = as fast as possible


@dataclass(frozen=True)
class ParameterSpec:
    """One node parameter: its default, description, unit and accepted values (a row of a node's
    parameter table; `declare_parameters` declares a table)."""
    name: str
    default: bool | int | float | str | list    # a list: a string array
    description: str
    unit: str = ""
    accepted: tuple | None = None       # (lo, hi) of a number, both ends included unless lo_open
    lo_open: bool = False
    nan_disables: bool = False          # NaN is accepted: it disables what the parameter sets
    choices: tuple = ()                 # the accepted strings (of a string array: of each element)
    read_only: bool = False             # fixed once the node runs

    def checked(self, value):
        """The value if accepted (a float parameter takes an integer: `-p radius:=1000`), else a
        ValueError naming it and what is accepted."""
        if isinstance(self.default, float):
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ValueError(f"{self.name} {value!r} is not a number")
            value = float(value)
            if self.nan_disables and math.isnan(value):
                return value
        if self.accepted is not None:
            lo, hi = self.accepted
            check_range(self.name, value, lo, hi, self.unit, lo_open=self.lo_open, hi_open=math.isinf(hi))
        if isinstance(self.default, list):
            if value is None:           # a string array given as [] in a parameter file is left unset by rcl
                return []
            if isinstance(value, str) or not all(isinstance(v, str) for v in value):
                raise ValueError(f"{self.name} {value!r} is not a list of strings")
            value = list(value)
            for v in value:
                if self.choices and v not in self.choices:
                    raise ValueError(f"{self.name}: {v!r} is not one of {', '.join(self.choices)}")
            return value
        if self.choices and value not in self.choices:
            raise ValueError(f"{self.name} {value!r} is not one of {', '.join(self.choices)}")
        return value

    def descriptor(self):
        """Its ParameterDescriptor: what `ros2 param describe` shows and rclpy enforces (the type,
        read-only, a FloatingPointRange for a double, an IntegerRange for an integer)."""
        text = self.description + (f" [{self.unit}]" if self.unit else "")
        if self.nan_disables:
            text += "; NaN disables it"
        d = ParameterDescriptor(description=text, read_only=self.read_only,
                                dynamic_typing=isinstance(self.default, float))
        if not d.dynamic_typing:
            d.type = self.parameter_type.value
        if self.accepted is not None and all(map(math.isfinite, self.accepted)) and not self.nan_disables:
            lo, hi = self.accepted
            if isinstance(self.default, float):     # applies to doubles only: an integer value is checked by `checked`
                d.floating_point_range = [FloatingPointRange(from_value=float(lo), to_value=float(hi))]
            else:
                d.integer_range = [IntegerRange(from_value=int(lo), to_value=int(hi), step=1)]
        if self.choices:
            d.additional_constraints = ("each " if isinstance(self.default, list) else "") + "one of: " + \
                ", ".join(self.choices)
        return d

    @property
    def parameter_type(self):
        """Its rclpy Parameter.Type (a list default is a string array, even empty: rclpy would take an empty
        list for a byte array)."""
        if isinstance(self.default, list):
            return Parameter.Type.STRING_ARRAY
        return Parameter.Type.from_parameter_value(self.default)


def accepted_text(spec):
    """What a ParameterSpec accepts, in words ('[150, 20000] m', 'one of hertz, discrete'; '' if anything)."""
    parts = []
    if spec.accepted is not None:
        lo, hi = spec.accepted
        right = ")" if math.isinf(hi) else "]"
        parts.append(f"{'(' if spec.lo_open else '['}{lo:g}, {hi:g}{right}" + (f" {spec.unit}" if spec.unit else ""))
    if spec.choices:
        parts.append(("each " if isinstance(spec.default, list) else "") + "one of " + ", ".join(spec.choices))
    return "; ".join(parts)


def yaml_value(value):
    """A parameter value as rcl's YAML parser reads it back with the same type: strings quoted (so
    that 'none' or 'true' stay strings), floats with a decimal point, NaN as .nan."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return ".nan" if math.isnan(value) else repr(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, list):
        return "[" + ", ".join(map(yaml_value, value)) + "]"
    return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'


def parameter_file(node_name, specs, header):
    """The text of a ROS 2 parameter file (`--ros-args --params-file`) holding every parameter of a
    node's table with its default, each under a comment with its unit, meaning and accepted values;
    `header` is the list of comment lines at the top (without '# ')."""
    lines = [f"# {line}" for line in header] + [f"{node_name}:", "  ros__parameters:"]
    for spec in specs:
        accepted = accepted_text(spec)
        lines.append(f"    # {spec.unit or '-'}: {spec.description}." + (f" Accepted: {accepted}." if accepted else "")
                     + (" Read-only." if spec.read_only else ""))
        lines.append(f"    {spec.name}: {yaml_value(spec.default)}")
    return "\n".join(lines) + "\n"


def declare_parameters(node, specs, check=None, apply=None):
    """Declare a table of ParameterSpecs on `node`; return {name: value}, kept up to date.

    At start each value (default, `-p`, `--params-file`) goes through `spec.checked` and then all
    through `check(values)` (rules between parameters): a ValueError names the value and the
    accepted range (the node's main prints it as one line, exit status 2). The parameters are
    declared without their ranges first so that this message, not rclpy's, answers a bad value;
    the full descriptors follow. While running, rclpy refuses a read-only parameter and a double
    outside its FloatingPointRange; an on-set callback refuses what `checked` or `check` refuses
    (an integer given for a float parameter passes rclpy's range test); once a change is set,
    `apply(changed)` gets the changed values."""
    table = {spec.name: spec for spec in specs}
    values = {}
    for spec in specs:
        first = ParameterDescriptor(dynamic_typing=isinstance(spec.default, float))
        if isinstance(spec.default, list):
            # declared by its type: a string array left unset (no override, or [] in a file) gets its default
            if node.declare_parameter(spec.name, spec.parameter_type, first).type_ == Parameter.Type.NOT_SET:
                node.set_parameters([Parameter(spec.name, spec.parameter_type, spec.default)])
            values[spec.name] = spec.checked(node.get_parameter(spec.name).value)
        else:
            values[spec.name] = spec.checked(node.declare_parameter(spec.name, spec.default, first).value)
    if check is not None:
        check(values)
    for spec in specs:
        node.set_descriptor(spec.name, spec.descriptor())

    def ours(parameters):               # rclpy's own parameters (use_sim_time) pass through
        return {p.name: table[p.name].checked(p.value) for p in parameters if p.name in table}

    def on_set(parameters):
        try:
            changed = ours(parameters)
            if changed and check is not None:
                check({**values, **changed})
        except ValueError as error:
            return SetParametersResult(successful=False, reason=str(error))
        return SetParametersResult(successful=True)

    def after_set(parameters):
        changed = ours(parameters)
        values.update(changed)
        if changed and apply is not None:
            apply(changed)

    node.add_on_set_parameters_callback(on_set)
    node.add_post_set_parameters_callback(after_set)
    return values
