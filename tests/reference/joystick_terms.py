"""Recompute the Go1 joystick's observation and reward terms with numpy from MuJoCo Playground's
published formulas (mujoco_playground/_src/locomotion/go1/joystick.py, base.py), on states dumped
by tests/joystick_terms.rs from envc's env. Independent of envc's code: the sensors Playground
reads are rebuilt from mjData (cvel, subtree_com, site_xmat, the contact list) as MuJoCo defines
them, and names, ranges and the keyframe come from the model loaded with the `mujoco` package.

usage: joystick_terms.py ROLLOUT.json SCENE.xml     (exit status 1 on a disagreement)

Tolerance: 1e-12 relative (1e-15 absolute near zero). Not bit-exact because (1) numpy sums of 8+
elements use pairwise blocks while a few of these are written as np.sum of short rows either
way, (2) np.exp and glibc exp may differ in the last bit, (3) MuJoCo's cross product and matrix
products in C may round differently (FMA) from numpy's.
"""
import json
import sys

import mujoco
import numpy as np

import term_checks

DT = 0.02
SIGMA = 0.25
FEET = ["FR", "FL", "RR", "RL"]
W = 0.02  # every weight is Playground's scale × dt


def main():
    rows = json.load(open(sys.argv[1]))
    m = mujoco.MjModel.from_xml_path(sys.argv[2])
    imu = m.site("imu").id
    feet_geoms = [m.geom(n).id for n in FEET]
    floor = m.geom("floor").id
    feet_sites = [m.site(n).id for n in FEET]
    default_pose = m.keyframe("home").qpos[7:].copy()
    lowers, uppers = m.jnt_range[1:].T
    soft_lo, soft_hi = lowers * 0.95, uppers * 0.95

    def site_vel(r, s, local):
        return term_checks.site_vel(m, r, s, local)

    close = term_checks.Close("step")

    ok = True
    checked = 0
    gates = {"moving": 0, "standing": 0}
    nonzero = {}
    for t, r in enumerate(rows):
        obs = np.array(r["obs"])
        qpos, qvel = np.array(r["qpos"]), np.array(r["qvel"])
        xmat = np.array(r["site_xmat"]).reshape(-1, 3, 3)[imu]
        gyro = site_vel(r, imu, True)[0]
        local_linvel = site_vel(r, imu, True)[1]
        global_angvel, global_linvel = site_vel(r, imu, False)
        upvector = xmat[:, 2]
        gravity = xmat.T @ np.array([0.0, 0.0, -1.0])
        # The observation: Playground's `state` without noise.
        if r["kind"] == "reset":
            last_act = np.zeros(12)
            air_time = np.zeros(4)
            last_contact = np.zeros(4, bool)
        want = np.hstack([local_linvel, gyro, gravity, qpos[7:] - default_pose, qvel[6:],
                          last_act, obs[45:48]])
        ok &= close("observation", obs, want, t)
        if r["kind"] == "reset":
            command = obs[45:48]
            continue
        act = np.array(r["action"])
        contacts = [tuple(c) for c in r["contacts"]]
        contact = np.array([(g, floor) in contacts or (floor, g) in contacts for g in feet_geoms])
        contact_filt = contact | last_contact
        first_contact = (air_time > 0.0) * contact_filt
        air_time = air_time + DT
        cmd_norm = np.linalg.norm(command)
        gates["moving" if cmd_norm > 0.01 else "standing"] += 1
        torques = np.array(r["actuator_force"])
        feet_vel = np.array([site_vel(r, s, False)[1] for s in feet_sites])
        vel_xy = feet_vel[..., :2]
        out_of_limits = -np.clip(qpos[7:] - soft_lo, None, 0.0)
        out_of_limits += np.clip(qpos[7:] - soft_hi, 0.0, None)
        pose_w = np.array([1.0, 1.0, 0.1] * 4)
        terms = {
            "reward_tracking_lin_vel": W * 1.0 * np.exp(-np.sum(np.square(command[:2] - local_linvel[:2])) / SIGMA),
            "reward_tracking_ang_vel": W * 0.5 * np.exp(-np.square(command[2] - gyro[2]) / SIGMA),
            "reward_lin_vel_z": -W * 0.5 * np.square(global_linvel[2]),
            "reward_ang_vel_xy": -W * 0.05 * np.sum(np.square(global_angvel[:2])),
            "reward_orientation": -W * 5.0 * np.sum(np.square(upvector[:2])),
            "reward_dof_pos_limits": -W * 1.0 * np.sum(out_of_limits),
            "reward_pose": W * 0.5 * np.exp(-np.sum(np.square(qpos[7:] - default_pose) * pose_w)),
            "reward_stand_still": -W * 1.0 * np.sum(np.abs(qpos[7:] - default_pose)) * (cmd_norm < 0.01),
            "reward_torques_norm": -W * 0.0002 * np.sqrt(np.sum(np.square(torques))),
            "reward_torques_abs": -W * 0.0002 * np.sum(np.abs(torques)),
            "reward_action_rate": -W * 0.01 * np.sum(np.square(act - last_act)),
            "reward_feet_slip": -W * 0.1 * np.sum(np.sum(np.square(vel_xy), axis=-1) * contact) * (cmd_norm > 0.01),
            "reward_feet_air_time": W * 0.1 * np.sum((air_time - 0.1) * first_contact) * (cmd_norm > 0.01),
        }
        for k, v in terms.items():
            ok &= close(k, r["info"][k], v, t)
            nonzero[k] = nonzero.get(k, 0) + (v != 0.0)
        nonzero["terminated"] = nonzero.get("terminated", 0) + r["done"]
        # termination: −0.02 × done, written as 0.02 × healthy − 0.02.
        total = sum(terms.values()) + W * (0.0 if r["done"] else 1.0) - W
        ok &= close("reward", r["reward"], total, t)
        done = upvector[2] < 0.0
        if done != r["done"]:
            print(f"step {t}: terminated envc {r['done']} numpy {done}")
            ok = False
        air_time *= ~contact
        last_contact = contact
        last_act = act
        command = obs[45:48]
        checked += 1
    print(f"{checked} steps, gates {gates}, steps where each is nonzero: {nonzero}")
    print(f"largest relative difference: {close.worst:.3g}")
    if not ok:
        sys.exit(1)
    if min(gates.values()) == 0 or min(nonzero.values()) == 0:
        print("a gate side or a term's nonzero case never occurred")
        sys.exit(1)
    print("all terms agree")


main()
