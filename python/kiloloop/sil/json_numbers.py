"""Arrays as JSON values that read back bit for bit (the MCAP log's messages, log_mcap.py).

A finite float is written as Python writes it (the shortest repr that reads back as the same
double, -0.0 and subnormals included), an integer or a bool as itself. JSON has no NaN or
infinity, and a NaN has a sign and payload bits (x86's inf - inf is the negative "default NaN",
0xfff8000000000000, not float("nan")'s 0x7ff8000000000000), so a non-finite element is written as
a string that says exactly which one it is:

    "Infinity", "-Infinity"       the infinities
    "NaN"                         the quiet NaN float("nan") is (0x7ff8... in float64)
    "NaN:0x<bits>"                any other NaN: its bits in hex, the element's own width
                                  (16 digits for float64, 8 for float32)

JSON parsers (Foxglove's, PlotJuggler's) read such an element as a string, not a number: the
plots leave a gap there, as they would for a NaN.
"""
from __future__ import annotations

import numpy as np

INF, NINF, NAN = "Infinity", "-Infinity", "NaN"
NAN_BITS = "NaN:0x"


def _uint(dtype: np.dtype) -> np.dtype:
    """The unsigned integer type of a float's width (its bits)."""
    return np.dtype(f"u{dtype.itemsize}")


def _canonical_nan_bits(dtype: np.dtype) -> int:
    return int(np.array(np.nan, dtype=dtype).view(_uint(dtype)))


def non_finite_count(series: np.ndarray) -> int:
    """How many elements of `series` are NaN or infinite (0 for integers and bools)."""
    if series.dtype.kind != "f":
        return 0
    return int(series.size - np.count_nonzero(np.isfinite(series)))


def to_json_values(series: np.ndarray) -> list:
    """series[k] for each k as plain Python values for json.dumps (numbers, nested lists, the
    module doc's strings for non-finite elements)."""
    series = np.ascontiguousarray(series)
    if non_finite_count(series) == 0:
        return series.tolist()   # Python floats and ints: json writes their exact repr
    values = series.astype(object)
    bits = series.view(_uint(series.dtype))
    nan_bits = _canonical_nan_bits(series.dtype)
    width = 2 * series.dtype.itemsize
    for index in zip(*np.nonzero(~np.isfinite(series))):
        x = series[index]
        if np.isinf(x):
            values[index] = INF if x > 0 else NINF
        else:
            b = int(bits[index])
            values[index] = NAN if b == nan_bits else f"{NAN_BITS}{b:0{width}x}"
    return values.tolist()


def from_json_values(values: list, dtype, shape: tuple, non_finite: int | None = None
                     ) -> np.ndarray:
    """The array (len(values),) + shape of dtype that to_json_values made `values` from;
    non_finite: how many non-finite elements the writer counted (0: numbers only, the fast
    path; None: not known, every element is looked at)."""
    dtype = np.dtype(dtype)
    full = (len(values),) + tuple(shape)
    if non_finite == 0:
        return np.array(values, dtype=dtype).reshape(full)
    items = np.array(values, dtype=object).reshape(full)
    out = np.empty(full, dtype=dtype)
    bits = out.view(_uint(dtype))
    nan_bits = _canonical_nan_bits(dtype)
    for index, v in np.ndenumerate(items):
        if not isinstance(v, str):
            out[index] = v
        elif v == INF:
            out[index] = np.inf
        elif v == NINF:
            out[index] = -np.inf
        elif v == NAN:
            bits[index] = nan_bits
        elif v.startswith(NAN_BITS):
            bits[index] = int(v[len(NAN_BITS):], 16)
        else:
            raise ValueError(f"not a number: {v!r}")
    return out
