"""Frames per second at 480×480, envc against Gymnasium's rgb_array (MUJOCO_GL=egl), in one
interleaved run: rounds alternate between the two so machine noise hits both alike. Each frame is
one step (zero action) and one render(). Prints a markdown table (docs/PERFORMANCE.md).

    .venv/bin/python tests/reference/bench_render.py [--frames 60] [--rounds 5] [ENV ...]
"""

import argparse
import os
import statistics
import time

os.environ.setdefault("MUJOCO_GL", "egl")

import gymnasium as gym  # noqa: E402
import numpy as np  # noqa: E402

import envc  # noqa: E402


def rate(env, frames):
    env.reset(seed=0)
    a = np.zeros(env.action_space.shape, dtype=np.float32)
    env.render()  # the renderer is made on the first frame: not timed
    t = time.perf_counter()
    for _ in range(frames):
        _, _, term, trunc, _ = env.step(a)
        env.render()
        if term or trunc:
            env.reset()
    return frames / (time.perf_counter() - t)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("envs", nargs="*", default=["Hopper-v5", "Ant-v5", "Humanoid-v5"])
    p.add_argument("--frames", type=int, default=60)
    p.add_argument("--rounds", type=int, default=5)
    args = p.parse_args()
    print("| env | envc frames/s | Gymnasium frames/s | ratio |")
    print("|---|---:|---:|---:|")
    for eid in args.envs:
        ours_env = envc.make(eid, render_mode="rgb_array")
        ref_env = gym.make(eid, render_mode="rgb_array")
        ours, ref = [], []
        for _ in range(args.rounds):
            ours.append(rate(ours_env, args.frames))
            ref.append(rate(ref_env, args.frames))
        o, r = statistics.median(ours), statistics.median(ref)
        print(f"| {eid} | {o:.1f} | {r:.1f} | {o / r:.2f} |")
        ref_env.close()
        ours_env.close()


if __name__ == "__main__":
    main()
