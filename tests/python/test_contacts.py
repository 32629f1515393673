"""``[derived.*] kind = "contact"`` against MuJoCo's own contact list, read from the live
Gymnasium-Robotics ``FetchPickAndPlace-v4`` run with the same seed and actions.

The spec is the bundled one with contact tables and info entries appended (the observation is
unchanged, so it still matches the reference bit for bit). A scripted pick moves the gripper to
the block, closes it and lifts, so the fingers touch the block and the block leaves the table.
Every step, each contact value is computed from the reference env's ``data.contact`` with
``mujoco.mj_contactForce`` as docs/spec-reference.md §23 defines it, and compared exactly.
"""

from __future__ import annotations

import os
import sys

import gymnasium as gym
import mujoco
import numpy as np
import pytest

import envc

gymnasium_robotics = pytest.importorskip("gymnasium_robotics")
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "reference"))
import robotics_patch  # noqa: E402,F401

gym.register_envs(gymnasium_robotics)

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")
SPEC = os.path.join(ROOT, "specs", "robotics", "fetch", "pick_and_place.toml")
XML = os.path.abspath(os.path.join(ROOT, "assets", "robotics", "fetch", "pick_and_place.xml"))
LIVE_SEED = int(os.environ.get("ENVC_LIVE_SEED", np.random.SeedSequence().entropy % 2**32))

LEFT, RIGHT = "robot0:l_gripper_finger_link", "robot0:r_gripper_finger_link"
# name: (between, value)
TABLES = {
    "block_table": (["object0", "table0"], "count"),
    "block_table_normal": (["object0", "table0"], "normal_force"),
    "block_table_force": (["object0", "table0"], "force"),
    "left_touch": ([LEFT, "object0"], "touching"),
    "right_touch": ([RIGHT, "object0"], "touching"),
    "left_force": ([LEFT, "object0"], "force"),
    "left_anything": ([LEFT], "count"),
    "block_anything": (["object0"], "force"),
}
EXTRA = "".join(
    f'\n[derived.{name}]\nkind = "contact"\nbetween = {between!r}\nvalue = "{value}"\n'.replace("'", '"')
    for name, (between, value) in TABLES.items()
) + "".join(f'\n[info.{name}]\nsource = "derived[{name}]"\nin_reset = false\n' for name in TABLES) + (
    # A grasp: a constant reward counted while both fingers touch the block.
    '\n[reward.grasp]\nkind = "constant"\nweight = 1.0\ninfo = "grasp"\n'
    'only_if = [{ source = "derived[left_touch]", op = ">", value = 0.5 },'
    ' { source = "derived[right_touch]", op = ">", value = 0.5 }]\n'
)


def element(model, name):
    """(id, is_body), a geom name first, as the resolver looks names up."""
    g = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, name)
    if g >= 0:
        return g, False
    return mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name), True


def expected(model, data, between, value):
    """The contact value from MuJoCo's contact list, as §23 defines it."""
    sides = [element(model, n) for n in between]

    def matches(g, side):
        i, body = side
        return model.geom_bodyid[g] == i if body else g == i

    def other(g):
        return len(sides) == 1 or matches(g, sides[1])

    count, normal, force = 0, 0.0, [0.0, 0.0, 0.0]
    f = np.zeros(6)
    for i in range(data.ncon):
        c = data.contact[i]
        g0, g1 = int(c.geom[0]), int(c.geom[1])
        if matches(g1, sides[0]) and other(g0):
            sign = 1.0
        elif matches(g0, sides[0]) and other(g1):
            sign = -1.0
        else:
            continue
        count += 1
        mujoco.mj_contactForce(model, data, i, f)
        normal += float(f[0])
        fr = c.frame
        for k in range(3):
            force[k] += sign * (float(fr[k]) * f[0] + float(fr[3 + k]) * f[1] + float(fr[6 + k]) * f[2])
    return {
        "touching": float(count > 0),
        "count": float(count),
        "normal_force": normal,
        "force": np.array(force),
    }[value]


def scripted(obs, t):
    """Above the block, down, close, lift: a pick of the block."""
    o = obs["observation"]
    grip, block = o[0:3], o[3:6]
    target = block + [0.0, 0.0, 0.08 if t < 12 else 0.0]
    if t >= 26:
        target = block + [0.0, 0.0, 0.2]
    a = np.clip((target - grip) * 10.0, -1.0, 1.0)
    return np.append(a, 1.0 if t < 20 else -1.0)


@pytest.mark.parametrize("seed", [0, LIVE_SEED])
def test_contact_values_match_mujocos_contact_list(tmp_path, seed):
    spec = tmp_path / "pick_and_place_contacts.toml"
    with open(SPEC) as f:
        spec.write_text(f.read() + EXTRA)
    ours = envc.make(str(spec), xml_file=XML)
    ref = gym.make("FetchPickAndPlace-v4")
    o1, _ = ref.reset(seed=seed)
    o2, _ = ours.reset(seed=seed)
    model, data = ref.unwrapped.model, ref.unwrapped.data
    seen = {"grasp": 0, "lifted": 0, "resting": 0}
    for t in range(40):
        a = scripted(o1, t)
        o1, _, _, _, _ = ref.step(a)
        o2, _, _, _, info = ours.step(a)
        for k in o1:
            assert o1[k].tobytes() == o2[k].tobytes(), (seed, t, k)
        for name, (between, value) in TABLES.items():
            want = expected(model, data, between, value)
            got = info[name]
            assert np.asarray(got).tobytes() == np.asarray(want, dtype=np.float64).reshape(np.shape(got)).tobytes(), (
                seed, t, name, got, want)
        assert info["grasp"] == (1.0 if info["left_touch"] and info["right_touch"] else 0.0)
        if info["left_touch"] and info["right_touch"]:
            seen["grasp"] += 1
        if info["block_table"] > 0:
            # The table pushes the block up: the force on the block has a positive z.
            assert info["block_table_force"][2] > 0.0, (seed, t)
            assert info["block_table_normal"] > 0.0, (seed, t)
            seen["resting"] += 1
        else:
            seen["lifted"] += 1
    # The script grasps the block and lifts it off the table, so every branch above ran.
    print(seed, seen)
    assert seen["grasp"] > 0 and seen["lifted"] > 0 and seen["resting"] > 0, seen


def test_contact_tables_are_checked(tmp_path):
    base = open(SPEC).read()
    cases = {
        '\n[derived.x]\nkind = "contact"\nbetween = ["object0", "no_such_geom"]\n': "E0134",
        '\n[derived.x]\nkind = "contact"\nbetween = ["object0"]\nvalue = "forces"\n': "E0104",
        '\n[derived.x]\nkind = "contact"\nbetween = []\n': "E0102",
        '\n[derived.x]\nkind = "contact"\n': "E0103",
    }
    for extra, code in cases.items():
        spec = tmp_path / "bad.toml"
        spec.write_text(base + extra)
        with pytest.raises(envc.SpecError) as e:
            envc.make(str(spec), xml_file=XML)
        assert code in str(e.value), (extra, str(e.value))
