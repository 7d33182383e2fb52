"""The one JSON encoder of every `--json` output, summary and report file.

Standard JSON (RFC 8259) has no NaN or infinity: a value that is not finite (a criterion that never
fired, a speed that was not reached) is written as null. numpy scalars and arrays become numbers and
lists, dataclasses their fields, paths and other objects their text. A dataclass field whose metadata is
NOT_WRITTEN (drawing arrays, back references) is left out, one marked WRITTEN_IF_SET while it is None
(a part of a result that only some models compute).
"""
import dataclasses
import json
import math
from pathlib import Path, PurePath

import numpy as np

from .atomic import atomic_write

NOT_WRITTEN = {"jsonout": "never"}
WRITTEN_IF_SET = {"jsonout": "if set"}


def plain(obj):
    """obj as plain Python (dict, list, str, int, float, bool, None), non-finite floats as None."""
    if isinstance(obj, dict):
        return {str(k): plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [plain(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return plain(obj.tolist())
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        value = float(obj)
        return value if math.isfinite(value) else None
    if obj is None or isinstance(obj, str):
        return obj
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return plain({f.name: getattr(obj, f.name) for f in dataclasses.fields(obj) if _written(f, obj)})
    if isinstance(obj, PurePath):
        return str(obj)
    return str(obj)


def _written(field, obj):
    rule = field.metadata.get("jsonout")
    return rule != "never" and not (rule == "if set" and getattr(obj, field.name) is None)


def dumps(obj, indent=None):
    """The JSON text of obj (see the module docstring)."""
    return json.dumps(plain(obj), indent=indent, allow_nan=False)


def write(path, obj, indent=1):
    """Write obj as JSON to path atomically (`atomic.atomic_write`)."""
    with atomic_write(path) as handle:
        handle.write(dumps(obj, indent=indent) + "\n")


def write_report(folder, name, data, text):
    """A report section: FOLDER/NAME.json (the data, as `write` writes it) and FOLDER/NAME.md (the markdown text),
    each written whole, the folder made when it is missing; the .md's path."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    write(folder / f"{name}.json", data)
    with atomic_write(folder / f"{name}.md") as handle:
        handle.write(text + "\n")
    return folder / f"{name}.md"
