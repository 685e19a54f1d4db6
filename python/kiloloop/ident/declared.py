"""The actuation delay a robot file declares: robot files carry delays in their scenario tables
([scenario.<name>] measurement_delay for arms, motor_delay for multirotors and quadrupeds; no
[sim] key exists for them), so the delay of a family is read from, and written to, every scenario
of that family whose settings have the key."""
from __future__ import annotations

# The setting that holds the command-to-measurement delay, per family.
DELAY_KEY = {"arm": "measurement_delay", "aerial": "motor_delay", "quadruped": "motor_delay"}
_PREFIX = {"arm": "arm-", "aerial": "aerial-", "quadruped": "quadruped-"}


def delay_scenarios(kind: str) -> list[str]:
    """Names of the scenarios of this family whose settings take the family's delay key."""
    from .. import scenarios

    key = DELAY_KEY[kind]
    return [n for n in scenarios.names() if n.startswith(_PREFIX[kind])
            and key in getattr(scenarios.get(n), "DEFAULTS", {})]


def declared_delay(robot) -> float:
    """[s] the delay the file declares for its family (the first of its scenario tables that
    sets it), else the scenarios' default."""
    from .. import scenarios

    key = DELAY_KEY[robot.kind]
    names = delay_scenarios(robot.kind)
    for name in names:
        table = robot.scenario_overrides(name)
        if key in table:
            return float(table[key])
    return float(scenarios.get(names[0]).DEFAULTS[key]) if names else 0.0
