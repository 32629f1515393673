#!/usr/bin/env python3
"""`envc rollout` on multi-agent specs, checked from outside against MaMuJoCo v1 (fresh seed).

    .venv/bin/python tests/reference/check_mamujoco_rollout.py --envc target/debug/envc [--seed N]

For every scenario, conf and k = 0, 1, 2 of record_mamujoco.SCENARIOS: draw global actions, run
`envc rollout specs/mamujoco/<spec>.toml --set agent_conf=C --set agent_obsk=K`, run
mamujoco_v1.parallel_env(scenario, C, agent_obsk=K) on the same seed and actions, and require
obs.<agent>, state, reward, terminated and truncated to be bit-identical (Pusher agent_0 modulo
the reference's address-dependent order of its two nodes labelled "r_wrist_roll_joint").
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np
from gymnasium_robotics import mamujoco_v1

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from record_mamujoco import KS, OVERRIDES, SCENARIOS, SINGLE, make_env, spec_for  # noqa: E402
import numerics_profile  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


make = make_env


def reference(scenario, conf, k, seed, actions):
    env = make(scenario, conf, k)
    agents = env.possible_agents
    obs, _ = env.reset(seed=seed)
    out = {f"obs.{a}": [obs[a]] for a in agents}
    out["state"] = [env.state()]
    rew, term, trunc = [], [], []
    for g in actions:
        obs, r, te, tr, _ = env.step(env.map_global_action_to_local_actions(g))
        for a in agents:
            out[f"obs.{a}"].append(obs[a])
        out["state"].append(env.state())
        rew.append(r[agents[0]])
        term.append(te[agents[0]])
        trunc.append(tr[agents[0]])
        if te[agents[0]] or tr[agents[0]]:
            break
    env.close()
    res = {key: np.array(v, dtype=np.float64) for key, v in out.items()}
    res["reward"] = np.array(rew, dtype=np.float64)
    res["terminated"] = np.array(term, dtype=bool)
    res["truncated"] = np.array(trunc, dtype=bool)
    return res


def same(a, b):
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--envc", required=True)
    ap.add_argument("--seed", type=int, default=None)
    ap.add_argument("--steps", type=int, default=40)
    args = ap.parse_args()
    seed = args.seed if args.seed is not None else int.from_bytes(os.urandom(4), "little")
    seed %= 2**31
    rng = np.random.default_rng(seed)
    failures, n = [], 0
    with tempfile.TemporaryDirectory() as tmp:
        for spec, scenario, confs in SCENARIOS:
            combos = [(c, k) for c in confs for k in KS]
            if "{n}" not in spec:
                combos.append((SINGLE, 0))
            for conf, k in combos:
                probe = make(scenario, conf, k)
                space = probe.single_agent_env.action_space
                probe.close()
                acts = rng.uniform(space.low.astype(np.float64), space.high.astype(np.float64),
                                   size=(args.steps, space.shape[0]))
                s = int(rng.integers(2**31))
                a_path, t_path = os.path.join(tmp, "a.npy"), os.path.join(tmp, "t.npz")
                np.save(a_path, acts)
                cmd = [args.envc, "rollout", os.path.join(ROOT, "specs", "mamujoco", spec_for(spec, conf) + ".toml"),
                       "--set", f"agent_conf={conf}", "--set", f"agent_obsk={k}", "--seed", str(s),
                       *[x for kv in OVERRIDES.get(scenario, {}).items() for x in ("--set", f"{kv[0]}={kv[1]}")],
                       "--actions", a_path, "--out", t_path]
                subprocess.run(cmd, check=True, stderr=subprocess.DEVNULL)
                ours = dict(np.load(t_path))
                ref = reference(scenario, conf, k, s, acts)
                name = f"{scenario} {conf} k={k} seed={s}"
                n += 1
                for key, want in ref.items():
                    got = ours.get(key)
                    if got is None:
                        failures.append(f"{name}: {key} missing")
                        continue
                    if same(got, want):
                        continue
                    if scenario == "Pusher" and key == "obs.agent_0":
                        sw = got.copy()
                        sw[:, [2, 3, 4, 5]] = got[:, [4, 5, 2, 3]]
                        if same(sw, want):
                            continue
                    failures.append(f"{name}: {key} differs")
    print(f"envc rollout vs mamujoco_v1, seed {seed}: {n - len({f.split(':')[0] for f in failures})} of {n} "
          f"scenario/conf/k combinations bit-identical (reference numerics {numerics_profile.profile_name()})",
          file=sys.stderr)
    if failures:
        print("\n".join(failures), file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
