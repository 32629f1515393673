"""Recompute specs/examples/mjlab_velocity_flat_go1.toml's observation and reward terms with numpy
from mjlab 1.6.0's term functions, on states dumped by tests/mjlab_terms.rs from envc's env.

mjlab's step (ManagerBasedRlEnv.step) computes terminations and rewards from the derived
quantities the last physics substep left (stale by one substep), then calls sim.forward() and
computes the observation from fresh ones; each row holds both ("stale", "fresh").

Written from mjlab's sources (the wheel's tasks/velocity/mdp/rewards.py: track_linear_velocity,
track_angular_velocity, feet_slip; envs/mdp/rewards.py: joint_pos_limits, action_rate_l2;
envs/mdp/observations.py and the Go1's sensors; envs/mdp/terminations.py: bad_orientation;
entity/entity.py: soft_joint_pos_limits), independent of envc's code: root-link velocities come
from cvel, subtree_com and the root's frame (EntityData.root_link_vel_w), orientations from the
root's frame, site velocities from cvel and subtree_com as MuJoCo defines them, names and ranges from the compiled model (MJB) loaded with the
`mujoco` package.

The spec cannot say one part of mjlab's terms (docs/mjlab.md): feet_slip's gate
`‖cmd_xy‖ + |cmd_wz| > 0.05` (the spec gates on ‖cmd‖₂ > 0.05). numpy checks the spec's form and
reports how far mjlab's own is from it.

usage: mjlab_terms.py ROLLOUT.json MODEL.mjb     (exit status 1 on a disagreement)
Tolerance: 1e-12 relative (1e-15 absolute near zero), as tests/reference/joystick_terms.py.
"""
import json
import sys

import mujoco
import numpy as np

import term_checks

DT = 0.02
FEET_GEOMS = ["FR_foot_collision", "FL_foot_collision", "RR_foot_collision", "RL_foot_collision"]
FEET_SITES = ["FR", "FL", "RR", "RL"]
W = {  # mjlab's weights × dt (RewardManager scales by dt)
    "reward_track_linear_velocity": 2.0 * DT,
    "reward_track_angular_velocity": 2.0 * DT,
    "reward_dof_pos_limits": -1.0 * DT,
    "reward_action_rate_l2": -0.1 * DT,
    "reward_foot_slip": -0.1 * DT,
}


def main():
    rows = json.load(open(sys.argv[1]))
    m = mujoco.MjModel.from_binary_path(sys.argv[2])
    imu = m.site("imu").id
    base = m.site("base").id  # at the trunk's (the root link's) frame
    feet_geoms = [m.geom(n).id for n in FEET_GEOMS]
    floor = m.geom("floor").id
    feet_sites = [m.site(n).id for n in FEET_SITES]
    default = m.keyframe("init_state").qpos[7:].copy()
    # Entity.soft_joint_pos_limits: mean ∓ 0.5 · range · soft_joint_pos_limit_factor (0.9).
    lo, hi = m.jnt_range[1:].T
    mean, rng = (lo + hi) / 2, hi - lo
    soft_lo, soft_hi = mean - 0.5 * rng * 0.9, mean + 0.5 * rng * 0.9

    def root(r):
        """(R, v_b, ω_b): the root link's frame and its velocities in it (EntityData's
        root_link_*_b: the velocity at the frame's origin, from cvel)."""
        ang, lin = term_checks.site_vel(m, r, base, True)
        return np.array(r["site_xmat"]).reshape(-1, 3, 3)[base], lin, ang

    def site_vel(r, s, local):
        return term_checks.site_vel(m, r, s, local)

    close = term_checks.Close("row")
    mjlab_gap = {k: 0.0 for k in W}

    ok, checked, gate_mismatch = True, 0, 0
    gates = {"active": 0, "inactive": 0}
    nonzero = {}
    for t, r in enumerate(rows):
        obs = np.array(r["obs"])
        fresh, stale = r["fresh"], r["stale"]
        qpos, qvel = np.array(fresh["qpos"]), np.array(fresh["qvel"])
        down = np.array([0.0, 0.0, -1.0])
        # The observation, after sim.forward(): the imu's gyro and velocimeter, projected gravity.
        imu_ang, imu_lin = site_vel(fresh, imu, True)
        gravity_obs = root(fresh)[0].T @ down
        # Rewards and terminations, from the last substep's kinematics.
        R, lin_b, ang_b = root(stale)
        gravity_b = R.T @ down
        if r["kind"] == "reset":
            last_act = np.zeros(12)
        want = np.hstack([imu_lin, imu_ang, gravity_obs, qpos[7:] - default, qvel[6:], last_act, obs[45:48]])
        ok &= close("observation", obs, want, t)
        if r["kind"] == "reset":
            command = obs[45:48]
            continue
        act = np.array(r["action"])
        contacts = [tuple(c) for c in r["contacts"]]
        found = np.array([(g, floor) in contacts or (floor, g) in contacts for g in feet_geoms], float)
        feet_vel_xy = np.array([site_vel(stale, s, False)[1][:2] for s in feet_sites])
        out_of_limits = -np.clip(qpos[7:] - soft_lo, None, 0.0) + np.clip(qpos[7:] - soft_hi, 0.0, None)
        active_spec = np.linalg.norm(command) > 0.05
        active_mjlab = np.linalg.norm(command[:2]) + abs(command[2]) > 0.05
        gate_mismatch += active_spec != active_mjlab
        gates["active" if active_spec else "inactive"] += 1
        slip = np.sum(np.square(np.linalg.norm(feet_vel_xy, axis=-1)) * found)
        xy_err = np.sum(np.square(command[:2] - lin_b[:2]))
        z_err = np.square(command[2] - ang_b[2])
        terms = {
            "reward_track_linear_velocity": np.exp(-(xy_err + np.square(lin_b[2])) / 0.25),
            "reward_track_angular_velocity": np.exp(-(z_err + np.sum(np.square(ang_b[:2]))) / 0.5),
            "reward_dof_pos_limits": np.sum(out_of_limits),
            "reward_action_rate_l2": np.sum(np.square(act - last_act)),
            "reward_foot_slip": slip * float(active_spec),
        }
        mjlab = dict(terms, reward_foot_slip=slip * float(active_mjlab))
        total = 0.0
        for k, v in terms.items():
            ok &= close(k, r["info"][k], W[k] * v, t)
            nonzero[k] = nonzero.get(k, 0) + (v != 0.0)
            mjlab_gap[k] = max(mjlab_gap[k], abs(W[k] * (mjlab[k] - v)))
            total += W[k] * v
        ok &= close("reward", r["reward"], total, t)
        # bad_orientation(limit_angle = 70°): acos(−g_z) > 70°.
        done = bool(np.abs(np.arccos(-gravity_b[2])) > np.deg2rad(70.0))
        nonzero["terminated"] = nonzero.get("terminated", 0) + done
        if done != r["done"]:
            print(f"row {t}: terminated envc {r['done']} numpy {done}")
            ok = False
        last_act = act
        command = obs[45:48]
        checked += 1
    print(f"{checked} steps, gates {gates}, steps where each is nonzero: {nonzero}")
    print(f"largest relative difference: {close.worst:.3g}")
    print("mjlab's own formula differs from the spec's by at most (weighted, per step): "
          + ", ".join(f"{k} {v:.3g}" for k, v in mjlab_gap.items())
          + f"; feet_slip's gate differs on {gate_mismatch} steps")
    if not ok:
        sys.exit(1)
    if min(gates.values()) == 0 or min(nonzero.values()) == 0:
        print("a gate side or a term's nonzero case never occurred")
        sys.exit(1)
    print("all terms agree")


main()
