#!/usr/bin/env python3
"""Record MaMuJoCo v1 (Gymnasium-Robotics 1.4.2) multi-agent trajectories for envc's parity test.

    .venv/bin/python tests/reference/record_mamujoco.py                         # committed fixtures
    .venv/bin/python tests/reference/record_mamujoco.py --out DIR --seed N --quick  # live cross-check

One case = (scenario, agent_conf, agent_obsk, seed). Protocol: reset(seed); then `steps` steps of
global actions drawn uniformly from the single-agent action space with numpy default_rng(action
seed), mapped to the agents with map_global_action_to_local_actions; after an episode ends the env
is reset without a seed. Files (npz, float64): actions [T, act_dim]; obs_<agent> [T + R, dim] and
state [T + R, state_dim] where row order is: reset obs, then one row per step, and a reset row
after every step that ended an episode (R resets in all); reward, terminated, truncated [T]
(0/1 for the flags). manifest.json lists the cases with the k-hop levels (labels) of every agent.
"""
import argparse
import json
import os
import sys

import numpy as np
from gymnasium_robotics import mamujoco_v1
from gymnasium_robotics.envs.multiagent_mujoco.coupled_half_cheetah import CoupledHalfCheetahEnv
from gymnasium_robotics.envs.multiagent_mujoco.mujoco_multi import MultiAgentMujocoEnv

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numerics_profile  # noqa: E402


# The reference writes a many-segment scenario's model into its own package directory
# (`many_segment_*_<n>_segments.auto.xml`), loads it and deletes it, so two processes building the
# same scenario at once (scripts/test.sh runs pytest beside the live checks) delete each other's
# file. Every process that imports this module builds the reference under one lock.
_orig_multi_init = MultiAgentMujocoEnv.__init__


def _locked_multi_init(self, *args, **kwargs):
    import fcntl
    import tempfile

    with open(os.path.join(tempfile.gettempdir(), "envc-mamujoco-reference.lock"), "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        _orig_multi_init(self, *args, **kwargs)


MultiAgentMujocoEnv.__init__ = _locked_multi_init


# CoupledHalfCheetah reads the tendon Jacobian `ten_J` as the dense ntendon × nv matrix of MuJoCo
# <= 3.5; MuJoCo 3.17 stores it sparse and the installed reference crashes. We run the reference's
# own code with `data.ten_J` seen as the dense matrix (its original semantics), nothing else changed.
class _DenseTenJ:
    def __init__(self, model, data):
        while isinstance(data, _DenseTenJ):
            data = data._data
        self._model, self._data = model, data

    def __getattr__(self, name):
        if name != "ten_J":
            return getattr(self._data, name)
        m, d = self._model, self._data
        dense = np.zeros((m.ntendon, m.nv))
        for r in range(m.ntendon):
            a, n = m.ten_J_rowadr[r], m.ten_J_rownnz[r]
            dense[r, m.ten_J_colind[a:a + n]] = d.ten_J[a:a + n]
        return dense


def _with_dense_ten_j(env, call):
    real = env.data
    if isinstance(real, _DenseTenJ):
        return call()
    env.data = _DenseTenJ(env.model, real)
    try:
        return call()
    finally:
        env.data = real


_orig_get_obs = CoupledHalfCheetahEnv._get_obs
CoupledHalfCheetahEnv._get_obs = lambda self: _with_dense_ten_j(self, lambda: _orig_get_obs(self))
_orig_get_obs_agent = MultiAgentMujocoEnv._get_obs_agent


def _get_obs_agent(self, agent_id, data=None):
    u = self.single_agent_env.unwrapped
    if data is None and isinstance(u, CoupledHalfCheetahEnv):
        return _with_dense_ten_j(u, lambda: _orig_get_obs_agent(self, agent_id))
    return _orig_get_obs_agent(self, agent_id, data)


MultiAgentMujocoEnv._get_obs_agent = _get_obs_agent

# (spec file stem in specs/mamujoco, scenario, confs)
SCENARIOS = [
    ("ant", "Ant", ["2x4", "2x4d", "4x2", "8x1"]),  # 8x1: the docs' custom agent_factorization
    ("half_cheetah", "HalfCheetah", ["2x3", "6x1"]),
    ("hopper", "Hopper", ["3x1"]),
    ("humanoid", "Humanoid", ["9|8"]),
    ("humanoidstandup", "HumanoidStandup", ["9|8"]),
    ("reacher", "Reacher", ["2x1"]),
    ("swimmer", "Swimmer", ["2x1"]),
    ("walker2d", "Walker2d", ["2x3"]),
    ("pusher", "Pusher", ["3p"]),
    ("coupled_half_cheetah", "CoupledHalfCheetah", ["1p1"]),  # reference patched: dense ten_J
    ("inverted_pendulum", "InvertedPendulum", []),
    # A custom factorization of a robot the reference does not ship: specs/examples/go1_agents.toml
    # against the reference's machinery (Ant-v5's task on the Go1 model as gym_env, and the same
    # graph written as obsk Nodes below).
    ("../examples/go1_agents", "Go1", ["front_hind", "legs"]),
    ("inverted_double_pendulum", "InvertedDoublePendulum", []),
    # Generated specs (specs/mamujoco/generate_many_segment.py): one per segment count n = N·M.
    ("many_segment_swimmer_{n}", "ManySegmentSwimmer", ["10x2", "6x1", "2x3", "1x2", "4x2", "3x5"]),
    ("many_segment_ant_{n}", "ManySegmentAnt", ["2x3", "3x1", "1x2", "2x2", "1x1", "5x2"]),
]


ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
GO1_XML = os.path.normpath(os.path.join(ROOT, "..", "shared", "models", "unitree_go1", "scene.xml"))
# Parameter overrides of the envc spec per scenario (passed as --set / Override).
OVERRIDES = {"Go1": {"xml_file": GO1_XML}}


def _go1_env():
    """specs/examples/go1.toml's task: Ant-v5 with the Go1 model and go1.toml's parameters."""
    import gymnasium
    return gymnasium.make("Ant-v5", xml_file=GO1_XML, frame_skip=25, ctrl_cost_weight=0.05,
                          contact_cost_weight=5e-4, healthy_reward=1.0, main_body="trunk",
                          healthy_z_range=(0.195, 0.75), contact_force_range=(-1.0, 1.0),
                          reset_noise_scale=0.1, exclude_current_positions_from_observation=False,
                          include_cfrc_ext_in_observation=True)


def _go1_factorization(env, conf):
    """specs/examples/go1_agents.toml as obsk Nodes (ids looked up in the compiled model)."""
    from gymnasium_robotics.envs.multiagent_mujoco.obsk import HyperEdge, Node
    m = env.unwrapped.model
    clip = lambda _id, x: np.clip(x, -1, 1).tolist()  # noqa: E731
    legs = ["FR", "FL", "RR", "RL"]
    bodies = {"hip": lambda l: ("trunk", f"{l}_hip"), "thigh": lambda l: (f"{l}_thigh",),
              "calf": lambda l: (f"{l}_calf",)}
    nodes = {}
    for l in legs:
        for part in ["hip", "thigh", "calf"]:
            j = m.joint(f"{l}_{part}_joint")
            act = [i for i in range(m.nu) if m.actuator_trnid[i][0] == j.id][0]
            nodes[f"{l}_{part}"] = Node(f"{l}_{part}", int(j.qposadr[0]), int(j.dofadr[0]), act,
                                        bodies=tuple(m.body(b).id for b in bodies[part](l)), body_fn=clip)
    edges = [HyperEdge(nodes[f"{l}_hip"], nodes[f"{l}_thigh"]) for l in legs]
    edges += [HyperEdge(nodes[f"{l}_thigh"], nodes[f"{l}_calf"]) for l in legs]
    edges.append(HyperEdge(*[nodes[f"{l}_hip"] for l in legs]))
    trunk = Node("trunk", None, None, None,
                 extra_obs={"qpos": lambda d: d.qpos[2:7], "qvel": lambda d: d.qvel[0:6]})
    leg = lambda l: tuple(nodes[f"{l}_{p}"] for p in ["hip", "thigh", "calf"])  # noqa: E731
    partition = {"front_hind": [leg("FR") + leg("FL"), leg("RR") + leg("RL")],
                 "legs": [leg(l) for l in legs]}[conf]
    return {"partition": partition, "edges": edges, "globals": [trunk]}


# Custom factorizations (agent_factorization), keyed by (scenario, conf name in the envc spec).
def _custom(scenario, conf):
    if (scenario, conf) == ("Ant", "8x1"):
        parts, edges, globals_ = mamujoco_v1.get_parts_and_edges("Ant", None)
        return {"partition": [(n,) for n in parts[0]], "edges": edges, "globals": globals_}
    return None


def make_env(scenario, conf, k):
    """The reference env of a case (envc's "none" is agent_conf=None)."""
    if scenario == "Go1":
        g = _go1_env()
        if conf == SINGLE:
            return mamujoco_v1.parallel_env("Ant", None, gym_env=g)
        return mamujoco_v1.parallel_env("Ant", conf, agent_obsk=k, gym_env=g,
                                        agent_factorization=_go1_factorization(g, conf))
    if conf == SINGLE:
        return mamujoco_v1.parallel_env(scenario, None)
    fac = _custom(scenario, conf)
    if fac is not None:
        return mamujoco_v1.parallel_env(scenario, conf, agent_obsk=k, agent_factorization=fac)
    return mamujoco_v1.parallel_env(scenario, conf, agent_obsk=k)


def spec_for(spec, conf):
    """The spec file stem of a scenario's conf (ManySegment* specs exist per segment count)."""
    if "{n}" in spec:
        a, m = conf.split("x")
        return spec.format(n=int(a) * int(m))
    return spec
KS = [0, 1, 2]
# agent_conf None (single-agent mode, k irrelevant) is recorded for every scenario with a fixed
# base env; envc spells it agent_conf = "none".
SINGLE = "none"


def record(spec, scenario, conf, k, seed, action_seed, steps, out):
    spec = spec_for(spec, conf)
    env = make_env(scenario, conf, k)
    single = env.single_agent_env
    lo, hi = single.action_space.low.astype(np.float64), single.action_space.high.astype(np.float64)
    rng = np.random.default_rng(action_seed)
    agents = list(env.possible_agents)
    obs_rows = {a: [] for a in agents}
    state_rows = []
    obs, _ = env.reset(seed=seed)
    for a in agents:
        obs_rows[a].append(np.asarray(obs[a], dtype=np.float64))
    state_rows.append(np.asarray(env.state(), dtype=np.float64))
    actions, rewards, terms, truncs, resets = [], [], [], [], 1
    for _t in range(steps):
        g = rng.uniform(lo, hi)
        actions.append(g)
        local = env.map_global_action_to_local_actions(g)
        obs, rew, term, trunc, _info = env.step(local)
        r = {rew[a] for a in agents}
        assert len(r) == 1
        rewards.append(float(rew[agents[0]]))
        terms.append(float(term[agents[0]]))
        truncs.append(float(trunc[agents[0]]))
        for a in agents:
            obs_rows[a].append(np.asarray(obs[a], dtype=np.float64))
        state_rows.append(np.asarray(env.state(), dtype=np.float64))
        if term[agents[0]] or trunc[agents[0]]:
            obs, _ = env.reset()
            resets += 1
            for a in agents:
                obs_rows[a].append(np.asarray(obs[a], dtype=np.float64))
            state_rows.append(np.asarray(env.state(), dtype=np.float64))
    name = f"{os.path.basename(spec)}_{conf.replace('|', '-')}_k{k}_s{seed}"
    arrays = dict(
        actions=np.array(actions), state=np.array(state_rows), reward=np.array(rewards),
        terminated=np.array(terms), truncated=np.array(truncs),
    )
    for a in agents:
        arrays[f"obs_{a}"] = np.array(obs_rows[a])
    np.savez_compressed(os.path.join(out, name + ".npz"), **arrays)
    if getattr(env, "k_dicts", None) is None:
        levels = {a: [] for a in agents}
    else:
        levels = {a: [[str(n) for n in env.k_dicts[i][d]] for d in sorted(env.k_dicts[i])]
                  for i, a in enumerate(agents)}
    env.close()
    return dict(name=name, spec=spec, scenario=scenario, agent_conf=conf, agent_obsk=k, seed=seed,
                # Paths relative to the repository root (the Rust test resolves them there).
                overrides={k: os.path.relpath(v, ROOT) for k, v in OVERRIDES.get(scenario, {}).items()},
                action_seed=action_seed, steps=steps, resets=resets, agents=agents, levels=levels)


def main():
    ap = argparse.ArgumentParser()
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--out", default=os.path.join(here, "fixtures", "mamujoco"))
    ap.add_argument("--seed", type=int, default=None, help="fresh base seed (live check)")
    ap.add_argument("--quick", action="store_true", help="one seed, fewer steps")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    if args.seed is None:
        seeds, steps = [0, 1], 80
    else:
        seeds, steps = [args.seed % (2**31)], 60
    if args.quick:
        steps = 60
    cases = []
    for spec, scenario, confs in SCENARIOS:
        combos = [(c, k) for c in confs for k in KS]
        if "{n}" not in spec:
            combos.append((SINGLE, 0))
        for conf, k in combos:
            for s in seeds:
                n = min(steps, 25) if scenario.startswith("Humanoid") else steps
                n = min(n, 40) if scenario in ("ManySegmentAnt", "Go1") else n
                cases.append(record(spec, scenario, conf, k, s, s + 7919, n, args.out))
    import gymnasium, gymnasium_robotics, mujoco
    with open(os.path.join(args.out, "manifest.json"), "w") as f:
        json.dump(dict(gymnasium=gymnasium.__version__, gymnasium_robotics=gymnasium_robotics.__version__,
                       mujoco=mujoco.__version__, numerics=numerics_profile.profile_name(),
                       numerics_settings=numerics_profile.settings(), cases=cases), f, indent=1)
    print(f"recorded {len(cases)} MaMuJoCo cases into {args.out} (numerics {numerics_profile.profile_name()})",
          file=sys.stderr)


if __name__ == "__main__":
    main()
