#!/usr/bin/env python3
"""Minari datasets of maze envs written by envc (dict observations), loaded by the real minari.

    .venv/bin/python tests/reference/check_maze_minari.py --root DIR --dataset-id ID --env-id ENV \
        --seeds S1,S2 [--format arrow|hdf5]

Loads the dataset with `minari.load_dataset`, checks the observation space is the reference env's
Dict space, the dict observations have T+1 rows per key, and replays every episode in
Gymnasium-Robotics (reset with the episode's seed, the stored float32 actions): observations,
rewards, terminations, truncations and info["success"] must be bit-identical.
"""
import argparse
import os
import sys
import warnings

import numpy as np

warnings.filterwarnings("ignore")
# Gymnasium-Robotics 1.4.2 writes every maze's MJCF to <tmpdir>/ant_maze<time>.xml and never deletes it
# (reference trap M14): point its temp dir at a private one, removed at exit.
import atexit  # noqa: E402
import shutil  # noqa: E402
import tempfile  # noqa: E402

tempfile.tempdir = tempfile.mkdtemp(prefix="envc-maze-ref-")
atexit.register(shutil.rmtree, tempfile.tempdir, True)
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numerics_profile  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--root", required=True)
    ap.add_argument("--dataset-id", required=True)
    ap.add_argument("--env-id", required=True)
    ap.add_argument("--max-episode-steps", type=int, default=None)
    args = ap.parse_args()
    os.environ["MINARI_DATASETS_PATH"] = args.root
    import gymnasium as gym
    import gymnasium_robotics
    import minari

    gym.register_envs(gymnasium_robotics)
    ds = minari.load_dataset(args.dataset_id)
    kw = {"max_episode_steps": args.max_episode_steps} if args.max_episode_steps else {}
    env = gym.make(args.env_id, **kw)
    assert ds.observation_space == env.observation_space, (ds.observation_space, env.observation_space)
    assert ds.action_space == env.action_space, (ds.action_space, env.action_space)
    bad, n = [], 0
    for ep in ds.iterate_episodes():
        n += 1
        obs = ep.observations
        assert isinstance(obs, dict) and set(obs) == {"observation", "achieved_goal", "desired_goal"}
        T = len(ep.rewards)
        seed = next(iter(ds.storage.get_episode_metadata([ep.id])))["seed"]
        o, info = env.reset(seed=int(seed))
        ref = {k: [o[k]] for k in obs}
        rew, term, trunc, succ = [], [], [], [info["success"]]
        for t in range(T):
            o, r, te, tr, info = env.step(ep.actions[t])
            for k in obs:
                ref[k].append(o[k])
            rew.append(r), term.append(te), trunc.append(tr), succ.append(info["success"])
        for k in obs:
            if obs[k].shape != (T + 1, ref[k][0].shape[0]) or not np.array_equal(obs[k], np.array(ref[k])):
                bad.append(f"episode {ep.id}: observations[{k}]")
        for name, a, b in (("rewards", ep.rewards, rew), ("terminations", ep.terminations, term),
                           ("truncations", ep.truncations, trunc)):
            if not np.array_equal(a, np.array(b)):
                bad.append(f"episode {ep.id}: {name}")
        if not np.array_equal(np.asarray(ep.infos["success"]).astype(bool), np.array(succ)):
            bad.append(f"episode {ep.id}: infos[success]")
    print(f"check_maze_minari: {args.dataset_id}: {n} episodes, {ds.total_steps} steps, "
          f"{'ok' if not bad else 'MISMATCH ' + '; '.join(bad[:5])} (reference numerics {numerics_profile.profile_name()})",
          file=sys.stderr)
    sys.exit(1 if bad or n == 0 else 0)


if __name__ == "__main__":
    main()
