"""A SignalLog as MCAP (https://mcap.dev), the file Foxglove, PlotJuggler and ROS 2 tools open.

Written and read with the `mcap` package (PyPI); messages are JSON with a JSON schema
("jsonschema"), which Foxglove and PlotJuggler read without plugins. Every value reads back bit
for bit (json_numbers.py), so .npz -> .mcap -> .npz changes nothing. The record layout:

header     profile "" (not a ROS profile), library "kiloloop <version>; mcap-python <version>"
schema     one per signal: name "kiloloop.<signal>", encoding "jsonschema", JSON Schema 2020-12 of
           its message (below), with the unit, label and frame in the descriptions
channel    one per signal, in the log's order: topic "/<signal>", message encoding "json";
           its metadata (all strings):
             signal      the signal's name in the log
             unit        "m", "rad/s", "N m", ... ("" none)
             frame       the frame its vectors are in: "world", "trunk", "heading", ... ("" none)
             label       what it is, for people ("" none)
             components  JSON list of the names along the first axis after time, or "null"
             dtype       numpy's dtype string ("<f8")
             shape       JSON list, one sample's shape ([] a scalar, [12], [4, 3])
             samples     number of messages, one per tick
             non_finite  number of NaN/Inf elements (written as strings: json_numbers.py)
             time        "t": sample k is at t[k]; "tick": at k ms (past the end of t, or no t)
message    one per signal per tick, written tick by tick (so file order is sample order);
           log_time = publish_time = the sample's time [ns] (t[k] rounded to whole ns),
           sequence = k; data: a JSON object
             timestamp   the sample's time [s], t[k] exactly (PlotJuggler's "use timestamp field")
             value       the sample: a number, or (nested) arrays for a vector signal
             <component> value[i] under its component's name, where the log knows the names
                         (characters other than letters, digits and _ become _), so plots read
                         /tau/FL_knee rather than /tau/value[2]
metadata   "kiloloop.log": format "kiloloop-log", version "1", signals (JSON list in the log's
             order), descriptions (the descriptions' JSON text, as the .npz's __meta__ holds it)
           "kiloloop.<section>" for each section of SignalLog.info, in its order (scenario,
             robot, run, settings, criteria, metrics: scenarios/run_info.py): key -> the
             value's JSON text (Python's json: floats exact, NaN and Infinity as its tokens)
"""
from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np

from .json_numbers import from_json_values, non_finite_count, to_json_values

FORMAT, VERSION = "kiloloop-log", "1"
LOG_RECORD = "kiloloop.log"
SECTION_PREFIX = "kiloloop."
TICK_NS = 1_000_000   # [ns] the 1 kHz tick: the time of a sample the log's t does not reach
# One compact encoder for every message (json.dumps with separators would build one per call).
_ENCODE = json.JSONEncoder(separators=(",", ":")).encode


def _field_name(component: str) -> str:
    """A component's name as a field Foxglove's message paths and PlotJuggler's series names
    take as they are (letters, digits, _; not a digit first)."""
    name = re.sub(r"[^A-Za-z0-9_]", "_", component)
    return "_" + name if name[:1].isdigit() else name


def _named_fields(components, first_axis: int) -> list[str] | None:
    """Field names of the per-component view, None where there is none (no names, a length
    that does not match, names that collide with each other or with timestamp/value)."""
    if not components or len(components) != first_axis:
        return None
    names = [_field_name(c) for c in components]
    if len(set(names)) != len(names) or {"timestamp", "value"} & set(names) or "" in names:
        return None
    return names


def _times(t: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, str]:
    """(seconds, nanoseconds, "t" or "tick") of samples 0..n-1: t[k] [s] where the log's t
    reaches and is finite and >= 0 (MCAP times are unsigned), else k ms."""
    tick = np.arange(n, dtype=np.int64)
    seconds = tick * (TICK_NS * 1e-9)
    ok = np.zeros(n, dtype=bool)
    m = min(n, len(t))
    ok[:m] = np.isfinite(t[:m]) & (t[:m] >= 0)
    seconds[ok] = t[:m][ok[:m]]
    ns = np.where(ok, np.round(seconds * 1e9), tick * TICK_NS).astype(np.int64)
    return seconds, ns, "t" if ok.all() else "tick"


def _json_type(dtype: np.dtype, non_finite: int):
    kind = {"b": "boolean", "i": "integer", "u": "integer"}.get(dtype.kind, "number")
    return [kind, "string"] if non_finite else kind


def _schema(name: str, meta: dict, series: np.ndarray, fields, non_finite: int) -> dict:
    what = meta.get("label") or name
    unit = f" [{meta['unit']}]" if meta.get("unit") else ""
    frame = f", {meta['frame']} frame" if meta.get("frame") else ""
    element = {"type": _json_type(series.dtype, non_finite)}
    for size in reversed(series.shape[1:]):
        element = {"type": "array", "items": element, "minItems": size, "maxItems": size}
    properties = {
        "timestamp": {"type": "number", "description": "the sample's time t [s]"},
        "value": dict(element, description=f"{what}{unit}{frame}"),
    }
    if fields is not None:
        item = element["items"]
        for field, component in zip(fields, meta["components"]):
            properties[field] = dict(item, description=f"{what}: {component}{unit}")
    return {"$schema": "https://json-schema.org/draft/2020-12/schema", "title": name,
            "description": f"{what}{unit}{frame}", "type": "object",
            "properties": properties, "required": ["timestamp", "value"]}


def write(log, path) -> Path:
    """Writes `log` (a SignalLog) to `path` as MCAP, the layout of the module doc."""
    from mcap import __version__ as mcap_version
    from mcap.well_known import MessageEncoding, SchemaEncoding
    from mcap.writer import Writer

    from .. import __version__

    path = Path(path)
    names = log.names()
    described = log.described()
    for section, table in log.info.items():
        if not isinstance(table, dict) or SECTION_PREFIX + section == LOG_RECORD:
            raise ValueError(f"log.info[{section!r}]: a section is a dict, and not named 'log'")
    t = np.asarray(log["t"], dtype=float).reshape(-1) if "t" in log else np.empty(0)
    channels = []   # (channel id, samples as JSON values, field names, seconds, ns)
    with open(path, "wb") as f:
        writer = Writer(f)
        writer.start(profile="", library=f"kiloloop {__version__}; mcap-python {mcap_version}")
        for name in names:
            series = np.asarray(log[name])
            meta = described.get(name, {})
            components = meta.get("components")
            fields = _named_fields(components, series.shape[1] if series.ndim > 1 else 0)
            non_finite = non_finite_count(series)
            seconds, ns, time_source = _times(t, len(series))
            schema = _schema(name, meta, series, fields, non_finite)
            schema_id = writer.register_schema(f"kiloloop.{name}", SchemaEncoding.JSONSchema,
                                               json.dumps(schema).encode())
            channel_id = writer.register_channel(f"/{name}", MessageEncoding.JSON, schema_id, {
                "signal": name, "unit": meta.get("unit") or "", "frame": meta.get("frame") or "",
                "label": meta.get("label") or "", "components": json.dumps(components),
                "dtype": series.dtype.str, "shape": json.dumps(list(series.shape[1:])),
                "samples": str(len(series)), "non_finite": str(non_finite),
                "time": time_source})
            channels.append((channel_id, to_json_values(series), fields, seconds.tolist(),
                             ns.tolist()))
        # Tick by tick, every signal's sample k before any signal's k + 1: readers that play the
        # file in order (and mcap's own log-time order) see the run as it happened.
        for k in range(max((len(c[1]) for c in channels), default=0)):
            for channel_id, values, fields, seconds, ns in channels:
                if k >= len(values):
                    continue
                message = {"timestamp": seconds[k], "value": values[k]}
                if fields is not None:
                    message.update(zip(fields, values[k]))
                writer.add_message(channel_id, log_time=ns[k], publish_time=ns[k], sequence=k,
                                   data=_ENCODE(message).encode())
        writer.add_metadata(LOG_RECORD, {"format": FORMAT, "version": VERSION,
                                         "signals": json.dumps(names),
                                         "descriptions": log.descriptions_json()})
        for section, table in log.info.items():
            writer.add_metadata(SECTION_PREFIX + section,
                                {str(k): json.dumps(v) for k, v in table.items()})
        writer.finish()
    return path


def _open(path):
    from mcap.reader import make_reader

    f = open(path, "rb")
    return f, make_reader(f)


def _log_record(reader, path) -> dict:
    for record in reader.iter_metadata():
        if record.name == LOG_RECORD and record.metadata.get("format") == FORMAT:
            return record.metadata
    raise ValueError(f"{path}: an MCAP file, but not a kiloloop log (no {LOG_RECORD!r} "
                     f"metadata record)")


def read_info(reader) -> dict:
    """SignalLog.info from the "kiloloop.<section>" metadata records."""
    info = {}
    for record in reader.iter_metadata():
        if record.name.startswith(SECTION_PREFIX) and record.name != LOG_RECORD:
            info[record.name[len(SECTION_PREFIX):]] = {
                k: json.loads(v) for k, v in record.metadata.items()}
    return info


def read_arrays(path) -> dict[str, np.ndarray]:
    """Every signal of a kiloloop MCAP log as the array it was written from, in the log's
    order (dtype and shape from each channel's metadata)."""
    f, reader = _open(path)
    with f:
        order = json.loads(_log_record(reader, path)["signals"])
        summary = reader.get_summary()
        values = {cid: [] for cid in summary.channels}
        for _schema, channel, message in reader.iter_messages(log_time_order=False):
            values[channel.id].append(json.loads(message.data)["value"])
    arrays = {}
    for cid, channel in summary.channels.items():
        m = channel.metadata
        arrays[m["signal"]] = from_json_values(values[cid], m["dtype"], json.loads(m["shape"]),
                                               int(m["non_finite"]))
    return {name: arrays[name] for name in order}


def read(path, log):
    """Fills `log` (an empty SignalLog) from a kiloloop MCAP log: signals, descriptions, info."""
    for name, series in read_arrays(path).items():
        log.put_array(name, series)
    f, reader = _open(path)
    with f:
        log.describe_from_json(_log_record(reader, path)["descriptions"])
        log.info = read_info(reader)
    return log


def overview(path) -> dict:
    """What `kiloloop log show` prints, from the summary and metadata alone (no message is
    decoded): {"signals": [channel metadata dicts, log order], "start_ns", "end_ns", "info"}."""
    f, reader = _open(path)
    with f:
        _log_record(reader, path)
        summary = reader.get_summary()
        stats = summary.statistics if summary is not None else None
        channels = [c.metadata for c in summary.channels.values()] if summary else []
        return {"signals": channels, "info": read_info(reader),
                "start_ns": stats.message_start_time if stats and stats.message_count else None,
                "end_ns": stats.message_end_time if stats and stats.message_count else None}
