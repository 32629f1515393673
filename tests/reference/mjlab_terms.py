"""Recompute the observation and reward terms of specs/examples/mjlab_velocity_flat_go1.toml and
mjlab_velocity_flat_g1.toml with numpy from mjlab 1.6.0's term functions and robot configs, on
states dumped by tests/mjlab_terms.rs from envc's env.

mjlab's step (ManagerBasedRlEnv.step) computes terminations and rewards from the derived
quantities the last physics substep left (stale by one substep), then calls sim.forward() and
computes the observation from fresh ones; each row holds both ("stale", "fresh").

Written from mjlab's sources (the wheel's tasks/velocity/mdp/rewards.py: track_linear_velocity,
track_angular_velocity, upright, variable_posture, body_angular_velocity_penalty,
angular_momentum_penalty, feet_clearance, feet_slip; envs/mdp/rewards.py: joint_pos_limits,
action_rate_l2; envs/mdp/observations.py and the robots' sensors; envs/mdp/terminations.py:
bad_orientation; entity/entity.py: soft_joint_pos_limits; the robots' *_constants.py: action
scales; tasks/velocity/config/*/env_cfgs.py: the posture widths, as mjlab's regular expressions),
independent of envc's code: root-link and site velocities from cvel, subtree_com and the frames
(as mj_objectVelocity defines them), the subtree angular momentum from the bodies' inertias and
velocities (as the subtreeangmom sensor defines it), the foot height as the foot height scan's
ray gives it on flat ground, names, ranges and gains from the compiled model (MJB) loaded with the
`mujoco` package.

usage: mjlab_terms.py ROBOT ROLLOUT.json MODEL.mjb     (ROBOT: go1 or g1; exit status 1 on a
disagreement)
Tolerance: 1e-12 relative (1e-15 absolute near zero), as tests/reference/joystick_terms.py (the
angular momentum too, although numpy sums the bodies in another order than MuJoCo).
"""
import json
import re
import sys

import mujoco
import numpy as np

import term_checks

DT = 0.02
# sim.py's MujocoCfg defaults that MujocoCfg.apply writes over the compiled model, whatever the
# MJCF says (the velocity env config sets timestep, iterations and ls_iterations).
MUJOCO_CFG = dict(timestep=0.005, integrator=mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
                  tolerance=1e-8, ls_tolerance=0.01, solver=mujoco.mjtSolver.mjSOL_NEWTON)
G1_WALK = {r".*hip_pitch.*": 0.3, r".*hip_roll.*": 0.15, r".*hip_yaw.*": 0.15, r".*knee.*": 0.35,
           r".*ankle_pitch.*": 0.25, r".*ankle_roll.*": 0.1, r".*waist_yaw.*": 0.2,
           r".*waist_roll.*": 0.08, r".*waist_pitch.*": 0.1, r".*shoulder_pitch.*": 0.15,
           r".*shoulder_roll.*": 0.15, r".*shoulder_yaw.*": 0.1, r".*elbow.*": 0.15,
           r".*wrist.*": 0.3}
G1_RUN = {r".*hip_pitch.*": 0.5, r".*hip_roll.*": 0.2, r".*hip_yaw.*": 0.2, r".*knee.*": 0.6,
          r".*ankle_pitch.*": 0.35, r".*ankle_roll.*": 0.15, r".*waist_yaw.*": 0.3,
          r".*waist_roll.*": 0.08, r".*waist_pitch.*": 0.2, r".*shoulder_pitch.*": 0.5,
          r".*shoulder_roll.*": 0.2, r".*shoulder_yaw.*": 0.15, r".*elbow.*": 0.35,
          r".*wrist.*": 0.3}
GO1_LEGS = r".*(FR|FL|RR|RL)_(hip|thigh)_joint.*"
GO1_CALF = r".*(FR|FL|RR|RL)_calf_joint.*"
ROBOTS = {
    # feet: (foot geoms or bodies, "geom"/"body"); sites: the foot sites; root: the root body;
    # upright: the body upright reads; weights: mjlab's (before × dt).
    "go1": dict(
        keyframe="init_state", imu="imu", base="base", upright="base", root="trunk",
        feet=(["FR_foot_collision", "FL_foot_collision", "RR_foot_collision", "RL_foot_collision"], "geom"),
        sites=["FR", "FL", "RR", "RL"],
        pose=[{GO1_LEGS: 0.05, GO1_CALF: 0.1}, {GO1_LEGS: 0.3, GO1_CALF: 0.6}, {GO1_LEGS: 0.3, GO1_CALF: 0.6}],
        weights={"track_linear_velocity": 2.0, "track_angular_velocity": 2.0, "upright": 1.0,
                 "pose": 1.0, "dof_pos_limits": -1.0, "action_rate_l2": -0.1,
                 "foot_clearance": -2.0, "foot_slip": -0.1, "foot_swing_height": -0.25,
                 "soft_landing": -1e-5},
        solver=dict(iterations=10, ls_iterations=20, ccd_iterations=50, impratio=10.0,
                    cone=mujoco.mjtCone.mjCONE_ELLIPTIC, **MUJOCO_CFG),
        # go1_constants.FULL_COLLISION (first-match dicts over geom_names_expr's matches).
        collision=dict(expr=r".*_collision\d*", contype=1, conaffinity=1,
                       condim={r"^[FR][LR]_foot_collision$": 6, r".*_collision\d*": 1},
                       priority={r"^[FR][LR]_foot_collision$": 1, ".*": 0},
                       friction={r"^[FR][LR]_foot_collision$": (1, 5e-3, 5e-4)},
                       solref=(0.01, 1)),
    ),
    "g1": dict(
        keyframe="knees_bent", imu="imu_in_pelvis", base="base", upright="torso", root="pelvis",
        feet=(["left_ankle_roll_link", "right_ankle_roll_link"], "body"),
        sites=["left_foot", "right_foot"],
        pose=[{r".*": 0.05}, G1_WALK, G1_RUN],
        weights={"track_linear_velocity": 2.0, "track_angular_velocity": 2.0, "upright": 1.0,
                 "pose": 1.0, "body_ang_vel": -0.05, "angular_momentum": -0.02,
                 "dof_pos_limits": -1.0, "action_rate_l2": -0.1, "foot_clearance": -2.0,
                 "foot_slip": -0.1, "foot_swing_height": -0.25, "soft_landing": -1e-5,
                 "self_collisions": -1.0},
        solver=dict(iterations=10, ls_iterations=20, ccd_iterations=50, impratio=1.0,
                    cone=mujoco.mjtCone.mjCONE_PYRAMIDAL, **MUJOCO_CFG),
        # g1_constants.FULL_COLLISION.
        collision=dict(expr=".*_collision", contype=1, conaffinity=1,
                       condim={r"^(left|right)_foot[1-7]_collision$": 3, ".*_collision": 1},
                       priority={r"^(left|right)_foot[1-7]_collision$": 1, ".*": 0},
                       friction={r"^(left|right)_foot[1-7]_collision$": (0.6,)},
                       solref=None),
    ),
}


def resolve_matching(data, names):
    """mjlab's resolve_matching_names_values: each name takes the value of the one key (a regular
    expression, matched whole) that matches it."""
    out = []
    for n in names:
        hits = [v for k, v in data.items() if re.fullmatch(k, n)]
        assert len(hits) == 1, (n, hits)
        out.append(hits[0])
    return np.array(out)


def main():
    cfg = ROBOTS[sys.argv[1]]
    rows = json.load(open(sys.argv[2]))
    m = mujoco.MjModel.from_binary_path(sys.argv[3])
    W = {f"reward_{k}": w * DT for k, w in cfg["weights"].items()}
    ok = True
    for k, want in cfg["solver"].items():
        if getattr(m.opt, k) != want:
            print(f"opt.{k}: envc {getattr(m.opt, k)} mjlab {want}")
            ok = False
    ok &= check_collision(m, cfg["collision"])
    imu, base, up = (m.site(cfg[k]).id for k in ("imu", "base", "upright"))
    feet_names, feet_kind = cfg["feet"]
    floor = m.geom("floor").id
    feet_sites = [m.site(n).id for n in cfg["sites"]]
    joints = [m.joint(j).name for j in range(1, m.njnt)]
    default = m.keyframe(cfg["keyframe"]).qpos[7:].copy()
    nu = m.nu
    # Action scale: 0.25 · effort_limit / stiffness per actuator (G1_ACTION_SCALE,
    # GO1_ACTION_SCALE), from the compiled actuators' force range and gain.
    scale = 0.25 * m.actuator_forcerange[:, 1] / m.actuator_gainprm[:, 0]
    std = [resolve_matching(t, joints) for t in cfg["pose"]]
    # Entity.soft_joint_pos_limits: mean ∓ 0.5 · range · soft_joint_pos_limit_factor (0.9).
    lo, hi = m.jnt_range[1:].T
    mean, rng = (lo + hi) / 2, hi - lo
    soft_lo, soft_hi = mean - 0.5 * rng * 0.9, mean + 0.5 * rng * 0.9
    root = m.body(cfg["root"]).id
    subtree = [b for b in range(m.nbody) if b == root or _descends(m, b, root)]

    def frame(r, s):
        return np.array(r["site_xmat"]).reshape(-1, 3, 3)[s]

    def root_vel(r):
        """(ω_b, v_b): the root link's velocities in its frame (EntityData's root_link_*_b)."""
        return term_checks.site_vel(m, r, base, True)

    def angmom(r):
        """subtreeangmom of the root: Σ R I Rᵀ ω + m (x − c) × (v − v_c) over its subtree, about
        the subtree's centre of mass, each body's velocity at its own centre of mass."""
        cvel = np.array(r["cvel"]).reshape(-1, 6)
        com = np.array(r["subtree_com"]).reshape(-1, 3)
        xipos = np.array(r["xipos"]).reshape(-1, 3)
        ximat = np.array(r["ximat"]).reshape(-1, 3, 3)
        mass = m.body_mass[subtree]
        vel = np.array([cvel[b, 3:] - np.cross(xipos[b] - com[m.body_rootid[b]], cvel[b, :3])
                        for b in subtree])
        c = com[root]
        vc = (mass[:, None] * vel).sum(0) / mass.sum()
        L = np.zeros(3)
        for i, b in enumerate(subtree):
            R = ximat[b]
            L += R @ (m.body_inertia[b] * (R.T @ cvel[b, :3]))
            L += mass[i] * np.cross(xipos[b] - c, vel[i] - vc)
        return L

    def in_contact(contacts, foot):
        if feet_kind == "geom":
            g = m.geom(foot).id
            return (g, floor) in contacts or (floor, g) in contacts
        b = m.body(foot).id
        return any((m.geom_bodyid[x] == b and y == floor) or (m.geom_bodyid[y] == b and x == floor)
                   for x, y in contacts)

    # The physics substeps replayed with MuJoCo (mujoco.mj_step from the dumped pre-step state):
    # mjlab's contact sensors are updated after each one (ManagerBasedRlEnv.step).
    replay = mujoco.MjData(m)
    frame_skip = 4
    physics_dt = np.float32(m.opt.timestep)
    feet_bodies = ([m.geom(f).bodyid[0] for f in feet_names] if feet_kind == "geom"
                   else [m.body(f).id for f in feet_names])
    foot_geoms = [[m.geom(f).id] if feet_kind == "geom"
                  else [g for g in range(m.ngeom) if _descends_or_is(m, m.geom_bodyid[g], b)]
                  for f, b in zip(feet_names, feet_bodies)]
    floor_body = m.geom_bodyid[floor]
    robot = [b for b in range(m.nbody) if _descends_or_is(m, b, root)]
    # ContactSensor state: contact time (float32, as mjlab's tensors); the swing peaks.
    contact_time = np.zeros(len(feet_names), np.float32)
    peak = np.zeros(len(feet_names))

    def feet_found(d):
        """Per foot: any contact between its geoms (mode geom or subtree) and the floor's body."""
        out = []
        for geoms in foot_geoms:
            found = False
            for c in d.contact[:d.ncon]:
                g1, g2 = c.geom
                if (g1 in geoms and m.geom_bodyid[g2] == floor_body) or \
                   (g2 in geoms and m.geom_bodyid[g1] == floor_body):
                    found = True
            out.append(found)
        return np.array(out)

    def netforce(d, geoms):
        """The contact sensor's netforce: the sum of the foot's contact forces, world frame, on
        the foot."""
        total = np.zeros(3)
        f6 = np.zeros(6)
        for k, c in enumerate(d.contact[:d.ncon]):
            g1, g2 = c.geom
            if g2 in geoms and m.geom_bodyid[g1] == floor_body:
                sign = 1.0
            elif g1 in geoms and m.geom_bodyid[g2] == floor_body:
                sign = -1.0
            else:
                continue
            mujoco.mj_contactForce(m, d, k, f6)
            total += sign * (np.array(c.frame).reshape(3, 3).T @ f6[:3])
        return np.linalg.norm(total)

    def first_self_contact_force(d):
        """num_slots = 1, reduce = "none": the first contact between two robot geoms, its force."""
        f6 = np.zeros(6)
        for k, c in enumerate(d.contact[:d.ncon]):
            if m.geom_bodyid[c.geom[0]] in robot and m.geom_bodyid[c.geom[1]] in robot:
                mujoco.mj_contactForce(m, d, k, f6)
                return np.linalg.norm(f6[:3])
        return None

    close = term_checks.Close("row")
    checked, regimes, gates, nonzero = 0, [0, 0, 0], {"active": 0, "inactive": 0}, {}
    n_obs = 9 + 3 * nu
    for t, r in enumerate(rows):
        obs = np.array(r["obs"])
        fresh, stale = r["fresh"], r["stale"]
        qpos, qvel = np.array(fresh["qpos"]), np.array(fresh["qvel"])
        down = np.array([0.0, 0.0, -1.0])
        imu_ang, imu_lin = term_checks.site_vel(m, fresh, imu, True)
        if r["kind"] == "reset":
            last_act = np.zeros(nu)
        # last_action: action_manager.action, the action this step applied (zeros after a reset).
        applied = np.zeros(nu) if r["kind"] == "reset" else np.array(r["action"])
        want = np.hstack([imu_lin, imu_ang, frame(fresh, base).T @ down, qpos[7:] - default,
                          qvel[6:], applied, obs[n_obs:n_obs + 3]])
        ok &= close("observation", obs, want, t)
        if r["kind"] == "reset":
            command = obs[n_obs:n_obs + 3]
            contact_time[:] = 0.0  # ContactSensor.reset
            # mjlab's feet_swing_height has no reset (its peaks cross episodes); envc clears them
            # so that reset(seed) repeats a trajectory (docs/mjlab.md).
            peak[:] = 0.0
            continue
        act = np.array(r["action"])
        ok &= close("ctrl", r["ctrl"], default + scale * act, t)
        pre = r["pre"]
        replay.qpos[:], replay.qvel[:] = pre["qpos"], pre["qvel"]
        replay.qacc_warmstart[:], replay.time = pre["qacc_warmstart"], pre["time"]
        replay.ctrl[:] = default + scale * act
        self_hits = 0
        for _ in range(frame_skip):
            mujoco.mj_step(m, replay)
            # ContactSensor._update_air_time_tracking(dt = physics_dt), float32 as mjlab's.
            found_k = feet_found(replay)
            contact_time = np.where(found_k, contact_time + physics_dt, np.float32(0.0))
            f = first_self_contact_force(replay)
            self_hits += f is not None and f > 10.0
        if not np.array_equal(replay.qpos, np.array(r["fresh"]["qpos"])):
            print(f"row {t}: MuJoCo's replay of the substeps left another state")
            ok = False
        # compute_first_contact(dt = step_dt): contact time in (0, dt + 1e-6).
        first = (contact_time > 0.0) & (contact_time < np.float32(DT + 1e-6))
        in_air = ~feet_found(replay)
        contacts = [tuple(c) for c in r["contacts"]]
        sqp = np.array(stale["qpos"])
        ang_b, lin_b = root_vel(stale)
        gravity_b = frame(stale, base).T @ down
        speed = np.linalg.norm(command[:2]) + abs(command[2])
        active = speed > 0.05
        gates["active" if active else "inactive"] += 1
        regime = 0 if speed < 0.05 else (1 if speed < 1.5 else 2)
        regimes[regime] += 1
        found = np.array([in_contact(contacts, f) for f in feet_names], float)
        feet_vel_xy = np.array([term_checks.site_vel(m, stale, s, False)[1][:2] for s in feet_sites])
        feet_z = np.array(stale["site_xpos"]).reshape(-1, 3)[feet_sites, 2]
        # The foot height scan on flat ground: a ray down from the site of max_distance 1.0 hits
        # the plane at z = 0 (height z); from below it or farther it misses: clamp(z, 0, 1).
        height = np.clip(feet_z, 0.0, 1.0)
        vel_norm = np.linalg.norm(feet_vel_xy, axis=-1)
        upright_g = frame(stale, up).T @ down
        torso_w = term_checks.site_vel(m, stale, up, False)[0]
        out_of_limits = -np.clip(sqp[7:] - soft_lo, None, 0.0) + np.clip(sqp[7:] - soft_hi, 0.0, None)
        terms = {
            "track_linear_velocity": np.exp(-(np.sum(np.square(command[:2] - lin_b[:2]))
                                              + np.square(lin_b[2])) / 0.25),
            "track_angular_velocity": np.exp(-(np.square(command[2] - ang_b[2])
                                               + np.sum(np.square(ang_b[:2]))) / 0.5),
            "upright": np.exp(-np.sum(np.square(upright_g[:2])) / 0.2),
            "pose": np.exp(-np.mean(np.square(sqp[7:] - default) / np.square(std[regime]))),
            "body_ang_vel": np.sum(np.square(torso_w[:2])),
            "angular_momentum": np.sum(np.square(angmom(stale))),
            "dof_pos_limits": np.sum(out_of_limits),
            "action_rate_l2": np.sum(np.square(act - last_act)),
            "foot_clearance": np.sum(np.abs(height - 0.1) * vel_norm) * float(active),
            "foot_slip": np.sum(np.square(vel_norm) * found) * float(active),
        }
        # feet_swing_height: the peak while in the air, the cost at landing, the peak cleared.
        peak = np.where(in_air, np.maximum(peak, height), peak)
        terms["foot_swing_height"] = np.sum(np.square(peak / 0.1 - 1.0) * first) * float(active)
        peak = np.where(first, 0.0, peak)
        # soft_landing: the net force's norm at landing.
        forces = np.array([netforce(replay, g) for g in foot_geoms])
        terms["soft_landing"] = np.sum(forces * first) * float(active)
        terms["self_collisions"] = float(self_hits)
        total = 0.0
        for k, w in W.items():
            v = terms[k.removeprefix("reward_")]
            ok &= close(k, r["info"][k], w * v, t)
            nonzero[k] = nonzero.get(k, 0) + (v != 0.0)
            total += w * v
        ok &= close("reward", r["reward"], total, t)
        # bad_orientation(limit_angle = 70°): acos(−g_z) > 70°.
        done = bool(np.abs(np.arccos(-gravity_b[2])) > np.deg2rad(70.0))
        nonzero["terminated"] = nonzero.get("terminated", 0) + done
        if done != r["done"]:
            print(f"row {t}: terminated envc {r['done']} numpy {done}")
            ok = False
        last_act = act
        command = obs[n_obs:n_obs + 3]
        checked += 1
    print(f"{checked} steps, gates {gates}, posture regimes (standing, walking, running) {regimes}, "
          f"steps where each is nonzero: {nonzero}")
    print(f"largest relative difference: {close.worst:.3g}")
    if not ok:
        sys.exit(1)
    if min(gates.values()) == 0 or min(regimes) == 0 or min(nonzero.values()) == 0:
        print("a gate side, a posture regime or a term's nonzero case never occurred")
        sys.exit(1)
    print("all terms agree")


def check_collision(m, c):
    """CollisionCfg.edit_spec: every geom the expression matches gets the structural fields (a
    dict's first matching pattern) and the patches (their leading entries); compared with the
    compiled model's geom arrays."""
    def first(field, name):
        if not isinstance(field, dict):
            return field
        return next((v for k, v in field.items() if re.match(k, name)), None)

    good = True
    for g in range(m.ngeom):
        name = m.geom(g).name
        if not name or not re.match(c["expr"], name):
            continue
        for key, arr in [("contype", m.geom_contype), ("conaffinity", m.geom_conaffinity),
                         ("condim", m.geom_condim), ("priority", m.geom_priority)]:
            if arr[g] != first(c[key], name):
                print(f"geom {name}: {key} envc {arr[g]} mjlab {first(c[key], name)}")
                good = False
        for key, arr in [("friction", m.geom_friction), ("solref", m.geom_solref)]:
            want = first(c[key], name) if c[key] is not None else None
            if want is not None and not np.array_equal(arr[g][:len(want)], want):
                print(f"geom {name}: {key} envc {arr[g]} mjlab {want}")
                good = False
    return good


def _descends_or_is(m, b, root):
    return b == root or _descends(m, b, root)


def _descends(m, b, root):
    while b > 0:
        b = m.body_parentid[b]
        if b == root:
            return True
    return False


main()
