"""SIL scenarios, one file per scenario, registered by name (`kiloloop list`).

A scenario module defines NAME, DESCRIPTION, DEFAULTS (settings a user may --set), CRITERIA
(metric -> (comparison, threshold)) and run(settings, seed) -> ScenarioResult. The criteria live
beside the scenario and are the very ones its pytest asserts.
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass, field

from ..sil.log import SignalLog

# Scenario name -> module (one concept per file; the name is the CLI name).
_MODULES = {
    "arm-track": "arm_track",
    "quadruped-stand": "quadruped_stand",
    "quadruped-slope": "quadruped_slope",
    "quadruped-trot": "quadruped_trot",
    "quadruped-push": "quadruped_push",
    "quadruped-tilt-stop": "quadruped_tilt_stop",
    "arm-line": "arm_line",
    "arm-rrt": "arm_rrt",
    "arm-press": "arm_press",
    "arm-estop": "arm_estop",
    "aerial-hover": "aerial_hover",
    "aerial-attitude-step": "aerial_attitude_step",
    "aerial-arm-sweep": "aerial_arm_sweep",
    "aerial-reach": "aerial_reach",
    "aerial-rotor-fault": "aerial_rotor_fault",
}


@dataclass
class ScenarioResult:
    scenario: str
    metrics: dict[str, float]
    criteria: dict[str, dict] = field(default_factory=dict)
    log: SignalLog | None = None
    settings: dict = field(default_factory=dict)

    @property
    def passed(self) -> bool:
        return all(c["passed"] for c in self.criteria.values())

    def to_json(self) -> dict:
        return {"scenario": self.scenario, "passed": self.passed, "metrics": self.metrics,
                "criteria": self.criteria, "settings": self.settings}


_OPS = {"<": lambda a, b: a < b, "<=": lambda a, b: a <= b,
        ">": lambda a, b: a > b, ">=": lambda a, b: a >= b}


def evaluate(criteria: dict[str, tuple[str, float]], metrics: dict[str, float]) -> dict[str, dict]:
    """Checks each metric against its criterion; a NaN or missing metric fails."""
    out = {}
    for name, (op, threshold) in criteria.items():
        value = metrics.get(name, float("nan"))
        out[name] = {"value": value, "op": op, "threshold": threshold,
                     "passed": bool(_OPS[op](value, threshold))}
    return out


def names() -> list[str]:
    return list(_MODULES)


def get(name: str):
    if name not in _MODULES:
        raise KeyError(f"unknown scenario {name!r}; known: {', '.join(_MODULES)}")
    return importlib.import_module(f"{__name__}.{_MODULES[name]}")


def parse_settings(defaults: dict, overrides: list[str] | dict | None) -> dict:
    """Applies `key=value` overrides to a scenario's DEFAULTS, converting to the default's type."""
    settings = dict(defaults)
    items = overrides.items() if isinstance(overrides, dict) else (
        item.split("=", 1) for item in (overrides or []))
    for key, value in items:
        if key not in defaults:
            raise ValueError(f"unknown setting {key!r}; known: {', '.join(sorted(defaults))}")
        settings[key] = _convert(defaults[key], value, key)
    return settings


def _convert(default, value, key):
    if not isinstance(value, str):
        return value
    if isinstance(default, bool):
        if value.lower() in ("1", "true", "yes", "on"):
            return True
        if value.lower() in ("0", "false", "no", "off"):
            return False
        raise ValueError(f"{key}: expected a boolean, got {value!r}")
    try:
        if isinstance(default, int):
            return int(value)
        if isinstance(default, float):
            return float(value)
        if isinstance(default, (list, tuple)):
            return [float(v) for v in value.split(",")]
    except ValueError:
        raise ValueError(f"{key}: expected {type(default).__name__}, got {value!r}") from None
    return value
