"""Gymnasium environments over the native SIL loop (needs the `gymnasium` package: the `rl` or
`test` extra). `import kiloloop` registers them when gymnasium is installed (as ale_py and
gymnasium_robotics do), so the usual import is enough:

    import gymnasium
    import kiloloop  # noqa: F401  (registers the kiloloop/ environments)
    env = gymnasium.make("kiloloop/QuadrupedTrot-v0")                            # one robot
    vec = gymnasium.make_vec("kiloloop/QuadrupedTrot-v0", num_envs=8,
                             vectorization_mode="vector_entry_point")           # batch runner

Registration only: the entry points are strings, so neither MuJoCo nor an environment's module
is imported until gymnasium makes that environment. The older ids with the module prefix,
"kiloloop.envs:kiloloop/QuadrupedTrot-v0", still work (gymnasium imports this module first).

kiloloop/QuadrupedTrot-v0 (envs/quadruped_trot.py): the quadruped trots under the compiled
controller; the action adds foot-target offsets to its footholds.
"""
from __future__ import annotations

import gymnasium

QUADRUPED_TROT = "kiloloop/QuadrupedTrot-v0"

# Every environment of the package: id -> (entry point, vector entry point), as strings.
ENVS: dict[str, tuple[str, str | None]] = {
    QUADRUPED_TROT: ("kiloloop.envs.quadruped_trot:QuadrupedTrotEnv",
                     "kiloloop.envs.quadruped_trot:QuadrupedTrotVecEnv"),
}


def register_envs() -> None:
    """Register every environment of ENVS with gymnasium (once: an id already there is left as
    it is, so importing twice or reloading warns about nothing)."""
    for env_id, (entry_point, vector_entry_point) in ENVS.items():
        if env_id not in gymnasium.registry:
            gymnasium.register(id=env_id, entry_point=entry_point,
                               vector_entry_point=vector_entry_point)


register_envs()
