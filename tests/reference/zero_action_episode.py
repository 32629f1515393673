"""The reference's zero-action Hopper-v5 episode from seed 0, in the line the crates made by
`envc new` (scripts/test.sh) and by hand (tests/wheel/crate.sh) print."""

import gymnasium as gym
import numpy as np

env = gym.make("Hopper-v5")
env.reset(seed=0)
n, ret = 0, 0.0
while True:
    _, r, term, trunc, _ = env.step(np.zeros(3))
    n += 1
    ret += r
    if term or trunc:
        break
print(f"Hopper-v5: one episode with zero actions, {n} steps, return {ret:.3f}")
