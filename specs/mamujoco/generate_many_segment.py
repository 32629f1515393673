#!/usr/bin/env python3
"""Generate the ManySegmentSwimmer / ManySegmentAnt models and specs from a segment count.

    python3 specs/mamujoco/generate_many_segment.py              # the bundled segment counts
    python3 specs/mamujoco/generate_many_segment.py --swimmer 12 --ant 5

Standard library only. For n segments it writes
  assets/mamujoco/many_segment_{swimmer,ant}_{n}.xml   the model, exactly as Gymnasium-Robotics
      1.4.2's gen_asset renders it (templates copied from the package: assets/mamujoco/*.template);
  specs/mamujoco/many_segment_{swimmer,ant}_{n}.toml   the factorization over Swimmer-v5 / Ant-v5
      with every conf "NxM" with N·M = n (the reference's agent_conf strings).
The ManySegmentAnt specs reproduce the reference's quirks (trap X6): wrong qpos/qvel ids for every
segment but the last, hip1/hip2 and ankle1/ankle2 actions swapped relative to the labels, and each
segment's link to its predecessor going to copies of the predecessor's hips. The *_v2 specs observe the right joints, drive the labelled motors and link real neighbours.
"""
import argparse
import os

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
ASSETS = os.path.join(ROOT, "assets", "mamujoco")
SWIMMERS = list(range(2, 21))
ANTS = list(range(1, 11))


def render(template, body, actuators):
    with open(os.path.join(ASSETS, template)) as f:
        t = f.read()
    # The templates use exactly these two jinja2 placeholders; jinja2 strips one trailing newline
    # of the template, which we reproduce.
    out = t.replace("{{ body }}", body).replace("{{ actuators }}", actuators)
    return out[:-1] if out.endswith("\n") else out


def swimmer_xml(n):
    body_t = """
    <body name="mid{:d}" pos="-1 0 0">
      <geom density="1000" fromto="0 0 0 -1 0 0" size="0.1" type="capsule"/>
      <joint axis="0 0 {:d}" limited="true" name="rot{:d}" pos="0 0 0" range="-100 100" type="hinge"/>
    """
    end_t = """
    <body name="back" pos="-1 0 0">
        <geom density="1000" fromto="0 0 0 -1 0 0" size="0.1" type="capsule"/>
        <joint axis="0 0 1" limited="true" name="rot{:d}" pos="0 0 0" range="-100 100" type="hinge"/>
      </body>
    """
    act_t = """\t <motor ctrllimited="true" ctrlrange="-1 1" gear="150.0" joint="rot{:d}"/>\n"""
    body = "".join(body_t.format(i, (-1) ** (i + 1), i) for i in range(1, n - 1))
    body += end_t.format(n - 1) + "</body>\n" * (n - 2)
    acts = "".join(act_t.format(i) for i in range(n))
    return render("many_segment_swimmer.xml.template", body, acts)


def ant_xml(n):
    body_t = """
    <body name="torso_{:d}" pos="-1 0 0">
       <!--<joint axis="0 1 0" name="nnn_{:d}" pos="0.0 0.0 0.0" range="-1 1" type="hinge"/>-->
        <geom density="100" fromto="1 0 0 0 0 0" size="0.1" type="capsule"/>
        <body name="front_right_leg_{:d}" pos="0 0 0">
          <geom fromto="0.0 0.0 0.0 0.0 0.2 0.0" name="aux1_geom_{:d}" size="0.08" type="capsule"/>
          <body name="aux_2_{:d}" pos="0.0 0.2 0">
            <joint axis="0 0 1" name="hip1_{:d}" pos="0.0 0.0 0.0" range="-30 30" type="hinge"/>
            <geom fromto="0.0 0.0 0.0 -0.2 0.2 0.0" name="right_leg_geom_{:d}" size="0.08" type="capsule"/>
            <body pos="-0.2 0.2 0">
              <joint axis="1 1 0" name="ankle1_{:d}" pos="0.0 0.0 0.0" range="-70 -30" type="hinge"/>
              <geom fromto="0.0 0.0 0.0 -0.4 0.4 0.0" name="right_ankle_geom_{:d}" size="0.08" type="capsule"/>
            </body>
          </body>
        </body>
        <body name="back_leg_{:d}" pos="0 0 0">
          <geom fromto="0.0 0.0 0.0 0.0 -0.2 0.0" name="aux2_geom_{:d}" size="0.08" type="capsule"/>
          <body name="aux2_{:d}" pos="0.0 -0.2 0">
            <joint axis="0 0 1" name="hip2_{:d}" pos="0.0 0.0 0.0" range="-30 30" type="hinge"/>
            <geom fromto="0.0 0.0 0.0 -0.2 -0.2 0.0" name="back_leg_geom_{:d}" size="0.08" type="capsule"/>
            <body pos="-0.2 -0.2 0">
              <joint axis="-1 1 0" name="ankle2_{:d}" pos="0.0 0.0 0.0" range="-70 -30" type="hinge"/>
              <geom fromto="0.0 0.0 0.0 -0.4 -0.4 0.0" name="third_ankle_geom_{:d}" size="0.08" type="capsule"/>
            </body>
          </body>
        </body>
    """
    act_t = """\t     <motor ctrllimited="true" ctrlrange="-1.0 1.0" joint="hip1_{:d}" gear="150"/>
                                      <motor ctrllimited="true" ctrlrange="-1.0 1.0" joint="ankle1_{:d}" gear="150"/>
                                      <motor ctrllimited="true" ctrlrange="-1.0 1.0" joint="hip2_{:d}" gear="150"/>
                                      <motor ctrllimited="true" ctrlrange="-1.0 1.0" joint="ankle2_{:d}" gear="150"/>\n"""
    body = "".join(body_t.format(*([i] * 16)) for i in range(1, n)) + "</body>\n" * (n - 1)
    acts = "".join(act_t.format(*([i] * 8)) for i in range(n))
    return render("many_segment_ant.xml.template", body, acts)


def confs(n):
    return [(a, n // a) for a in range(1, n + 1) if n % a == 0]


def q(s):
    return '"' + s + '"'


def lst(xs):
    return "[" + ", ".join(q(x) for x in xs) + "]"


def swimmer_spec(n):
    nodes = [f"rot{i}" for i in range(n)]
    out = [
        f"# MaMuJoCo v1 \"ManySegmentSwimmer\" with {n} segments (Gymnasium-Robotics 1.4.2), generated by",
        "# specs/mamujoco/generate_many_segment.py: Swimmer-v5 on the generated model, one node per rotor.",
        "# The reference has no global nodes here, so the state cannot be rebuilt from the local observations.",
        "[agents]",
        f'id = "MaMuJoCo-ManySegmentSwimmer{n}-v1"',
        'base = "../gymnasium/swimmer.toml"',
        f'base_params = {{ xml_file = "../../assets/mamujoco/many_segment_swimmer_{n}.xml" }}',
        f'doc = "Swimmer with {n} segments; agent_conf \\"NxM\\": N agents of M consecutive rotors."',
        f'agent_conf = "{confs(n)[1][0] if len(confs(n)) > 1 else 1}x{n // (confs(n)[1][0] if len(confs(n)) > 1 else 1)}"',
        "agent_obsk = 1",
        'action_bounds = "first_element"',
        "edges = [" + ", ".join(lst([nodes[i], nodes[i + 1]]) for i in range(n - 1)) + "]",
        "",
        "[agents.confs]",
    ]
    for a, m in confs(n):
        parts = [lst(nodes[i * m:(i + 1) * m]) for i in range(a)]
        out.append(f'"{a}x{m}" = [' + ", ".join(parts) + "]")
    out += ["", "[agents.nodes]"]
    out += [f'rot{i} = {{ joint = "rot{i}" }}' for i in range(n)]
    return "\n".join(out) + "\n"


def ant_spec(n, fixed):
    out = []
    if fixed:
        out += [
            f"# ManySegmentAnt with {n} segments, version 2 (envc): MaMuJoCo v1's factorization with its bugs",
            f"# fixed (see many_segment_ant_{n}.toml for the parity spec): every node observes its own joint,",
            "# drives its own motor, and neighbouring segments' hips are linked to each other in both directions.",
            "# Generated by specs/mamujoco/generate_many_segment.py.",
        ]
    else:
        out += [
            f"# MaMuJoCo v1 \"ManySegmentAnt\" with {n} segments (Gymnasium-Robotics 1.4.2), generated by",
            "# specs/mamujoco/generate_many_segment.py: Ant-v5 on the generated model.",
            "# Quirks kept for parity (trap X6): qpos/qvel ids are wrong for every segment but the last (the",
            "# reference's ids, counted from the start of qpos/qvel); the hip1_s node drives motor hip2_s and",
            "# vice versa (ankles likewise); a segment's link to its predecessor goes to copies of the",
            f"# predecessor's hips (same label, graph-only nodes). many_segment_ant_{n}_v2.toml fixes them.",
        ]
    out += [
        "[agents]",
        f'id = "MaMuJoCo-ManySegmentAnt{n}-v{2 if fixed else 1}"',
        'base = "../gymnasium/ant.toml"',
        f'base_params = {{ xml_file = "../../assets/mamujoco/many_segment_ant_{n}.xml" }}',
        f'doc = "Chain of {n} ant segments; agent_conf \\"NxM\\": N agents of M consecutive segments."',
    ]
    cs = confs(n)
    default = cs[1] if len(cs) > 1 else cs[0]
    out += [
        f'agent_conf = "{default[0]}x{default[1]}"',
        "agent_obsk = 1",
        *([] if fixed else ['action_bounds = "first_element"']),
        'local_categories = [["qpos", "qvel", "cfrc_ext"], ["qpos"]]',
        "body_clip = [-1.0, 1.0]",
    ]
    edges = []
    for s in range(n):
        edges += [[f"ankle1_{s}", f"hip1_{s}"], [f"ankle2_{s}", f"hip2_{s}"], [f"hip1_{s}", f"hip2_{s}"]]
        if s:
            prev = ([f"hip1_{s-1}", f"hip2_{s-1}"] if fixed else [f"hip1_{s-1}_copy", f"hip2_{s-1}_copy"])
            edges.append(prev + [f"hip1_{s}", f"hip2_{s}"])
    out.append("edges = [\n" + "".join(f"  {lst(e)},\n" for e in edges) + "]")
    out += ["", "[agents.confs]"]
    seg_nodes = lambda s: [f"hip1_{s}", f"ankle1_{s}", f"hip2_{s}", f"ankle2_{s}"]
    for a, m in cs:
        parts = [lst([x for s in range(i * m, (i + 1) * m) for x in seg_nodes(s)]) for i in range(a)]
        out.append(f'"{a}x{m}" = [' + ", ".join(parts) + "]")
    out += ["", "[agents.nodes]"]
    for s in range(n):
        torso = 1 + 7 * s
        bodies = {
            "hip1": [torso, torso + 1], "ankle1": [torso + 1, torso + 2, torso + 3],
            "hip2": [torso, torso + 4], "ankle2": [torso + 4, torso + 5, torso + 6],
        }
        off = -4 * (n - 1 - s)
        ids = {"hip1": -4 - off, "ankle1": -3 - off, "hip2": -2 - off, "ankle2": -1 - off}
        acts = {"hip1": 4 * s + 2, "ankle1": 4 * s + 3, "hip2": 4 * s, "ankle2": 4 * s + 1}
        for kind in ["hip1", "ankle1", "hip2", "ankle2"]:
            b = "[" + ", ".join(str(x) for x in bodies[kind]) + "]"
            if fixed:
                out.append(f'{kind}_{s} = {{ joint = "{kind}_{s}", bodies = {b} }}')
            else:
                i = ids[kind]
                out.append(f'{kind}_{s} = {{ qpos = "qpos[{i}]", qvel = "qvel[{i}]", actuator = {acts[kind]}, bodies = {b} }}')
                if kind in ("hip1", "hip2") and s < n - 1:
                    out.append(f'{kind}_{s}_copy = {{ label = "{kind}_{s}", qpos = "qpos[{i}]", qvel = "qvel[{i}]", bodies = {b} }}')
    out += [
        "",
        "[agents.globals.free]",
        'extra = { qpos = "qpos[2:7]", qvel = "qvel[0:6]", cfrc_ext = { source = "cfrc_ext[0]", clip = [-1.0, 1.0] } }',
    ]
    return "\n".join(out) + "\n"


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--swimmer", type=int, nargs="*", default=SWIMMERS)
    ap.add_argument("--ant", type=int, nargs="*", default=ANTS)
    args = ap.parse_args()
    for n in args.swimmer:
        assert n >= 2, "ManySegmentSwimmer needs at least 2 segments"
        write(os.path.join(ASSETS, f"many_segment_swimmer_{n}.xml"), swimmer_xml(n))
        write(os.path.join(HERE, f"many_segment_swimmer_{n}.toml"), swimmer_spec(n))
    for n in args.ant:
        assert n >= 1
        write(os.path.join(ASSETS, f"many_segment_ant_{n}.xml"), ant_xml(n))
        write(os.path.join(HERE, f"many_segment_ant_{n}.toml"), ant_spec(n, fixed=False))
        write(os.path.join(HERE, f"many_segment_ant_{n}_v2.toml"), ant_spec(n, fixed=True))


if __name__ == "__main__":
    main()
