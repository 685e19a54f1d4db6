"""A TOML writer for robot files (tables, arrays of tables, numbers, strings, booleans and arrays
of them): what a robot file holds. tomllib reads TOML but does not write it."""
from __future__ import annotations

import json
import math
import re

_BARE = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(k: str) -> str:
    return k if _BARE.match(k) else json.dumps(k)


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            raise ValueError(f"TOML has no {v!r} in a robot file")
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} as a TOML value")


def _is_table_array(v) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


def dumps(data: dict, _prefix: str = "") -> str:
    """The TOML text of `data` (key order kept: values first, then tables, then table arrays)."""
    lines, tables, arrays = [], [], []
    for k, v in data.items():
        if isinstance(v, dict):
            tables.append((k, v))
        elif _is_table_array(v):
            arrays.append((k, v))
        else:
            lines.append(f"{_key(k)} = {_value(v)}")
    out = "\n".join(lines) + ("\n" if lines else "")
    for k, v in tables:
        name = f"{_prefix}{_key(k)}"
        body = dumps(v, name + ".")
        has_values = any(not isinstance(x, dict) and not _is_table_array(x) for x in v.values())
        if has_values or not v:
            out += f"\n[{name}]\n"
        out += body
    for k, v in arrays:
        name = f"{_prefix}{_key(k)}"
        for item in v:
            out += f"\n[[{name}]]\n" + dumps(item, name + ".")
    return out
