"""A model needing more memory than the process may have is a ``ValueError`` with E1001, not a
crash (MuJoCo's uncaught ``std::bad_alloc`` would end the Python process; docs/limits.md).

The model is within envc's limits: a 10,000 x 10,000 heightfield, for which MuJoCo's compiler asks
400 MB in one ``std::vector``. The child process caps its address space at what it uses after
``import envc`` plus 200 MB, so that allocation fails whatever the interpreter's own footprint;
it fails the same way three times, and the process then builds and steps Hopper-v5.
"""

from __future__ import annotations

import os
import subprocess
import sys

MODEL = """<mujoco>
  <asset><hfield name="terrain" nrow="10000" ncol="10000" size="1 1 1 1"/></asset>
  <worldbody>
    <body name="arm">
      <joint name="hinge" type="hinge" axis="0 0 1"/>
      <geom type="box" size="0.1 0.1 0.1"/>
    </body>
  </worldbody>
  <actuator><motor joint="hinge" ctrlrange="-1 1"/></actuator>
</mujoco>
"""

SPEC = """[env]
id = "Big-v0"
[params]
xml_file = { default = "model.xml" }
frame_skip = { default = 1 }
max_episode_steps = { default = 10 }
[observation.qpos]
source = "qpos"
"""

CHILD = """
import resource, sys
import envc
vm = next(int(l.split()[1]) for l in open("/proc/self/status") if l.startswith("VmSize:"))
cap = (vm + 200 * 1024) * 1024
hard = resource.getrlimit(resource.RLIMIT_AS)[1]
resource.setrlimit(resource.RLIMIT_AS, (cap, hard))
for _ in range(3):  # the same error every time: nothing is left half-done
    try:
        envc.make(sys.argv[1])
    except ValueError as e:
        print(e)
    else:
        print("compiled")
resource.setrlimit(resource.RLIMIT_AS, (hard, hard))
env = envc.make("Hopper-v5")
env.reset(seed=0)
env.step(env.action_space.sample())
print("hopper steps")
"""


def test_out_of_memory_compile_is_a_coded_error(tmp_path):
    (tmp_path / "model.xml").write_text(MODEL)
    (tmp_path / "spec.toml").write_text(SPEC)
    out = subprocess.run(
        [sys.executable, "-c", CHILD, str(tmp_path / "spec.toml")],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=tmp_path,
        env=os.environ,
    )
    assert out.returncode == 0, f"status {out.returncode}: {out.stderr}"
    assert out.stdout.count("error[E1001]") == 3, out.stdout + out.stderr
    assert out.stdout.count("MuJoCo threw std::bad_alloc: the model needs more memory") == 3
    assert out.stdout.strip().endswith("hopper steps"), out.stdout
    assert "terminat" not in out.stderr, out.stderr
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()
