"""Gymnasium environments over the native SIL loop (needs the `gymnasium` package: the `rl` or
`test` extra). Importing this module registers them:

    import gymnasium
    env = gymnasium.make("kiloloop.envs:kiloloop/QuadrupedTrot-v0")            # one robot
    vec = gymnasium.make_vec("kiloloop.envs:kiloloop/QuadrupedTrot-v0", num_envs=8,
                             vectorization_mode="vector_entry_point")           # batch runner

kiloloop/QuadrupedTrot-v0 (envs/quadruped_trot.py): the quadruped trots under the compiled
controller; the action adds foot-target offsets to its footholds.
"""
from __future__ import annotations

import gymnasium

QUADRUPED_TROT = "kiloloop/QuadrupedTrot-v0"

if QUADRUPED_TROT not in gymnasium.registry:
    gymnasium.register(
        id=QUADRUPED_TROT,
        entry_point="kiloloop.envs.quadruped_trot:QuadrupedTrotEnv",
        vector_entry_point="kiloloop.envs.quadruped_trot:QuadrupedTrotVecEnv",
    )
