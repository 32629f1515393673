"""Specs of one's own by id: ``envc.register(path_or_dir)`` and ``ENVC_SPEC_PATH``; a file never
takes over a bundled id. Checked against the live reference."""

from __future__ import annotations

import os
import subprocess
import sys

import gymnasium as gym
import numpy as np
import pytest

import envc

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
HOPPER = os.path.join(ROOT, "specs", "gymnasium", "hopper.toml")
MODEL = os.path.join(ROOT, "assets", "gymnasium", "hopper.xml")


def spec_text(env_id: str, frame_skip: int | None = None) -> str:
    with open(HOPPER) as f:
        text = f.read().replace('id = "Hopper-v5"', f'id = "{env_id}"')
    text = text.replace("../../assets/gymnasium/hopper.xml", MODEL)
    if frame_skip is not None:
        text = text.replace("frame_skip = { default = 4,", f"frame_skip = {{ default = {frame_skip},")
    return text


def write(dir_, name: str, text: str) -> str:
    path = os.path.join(dir_, name)
    with open(path, "w") as f:
        f.write(text)
    return path


def same_rollout(ours, ref, seed: int, steps: int = 20) -> None:
    rng = np.random.default_rng(seed)
    o1, _ = ours.reset(seed=seed)
    o2, _ = ref.reset(seed=seed)
    assert o1.tobytes() == o2.tobytes()
    for _ in range(steps):
        a = rng.uniform(-1, 1, 3)
        s1, s2 = ours.step(a), ref.step(a)
        assert s1[0].tobytes() == s2[0].tobytes() and float(s1[1]) == float(s2[1])
        assert s1[2:4] == s2[2:4]
        if s2[2] or s2[3]:
            break


def test_register_a_directory_then_make_by_id(tmp_path):
    write(tmp_path, "a.toml", spec_text("RegHopperA-v0"))
    write(tmp_path, "b.toml", spec_text("RegHopperB-v0"))
    assert sorted(envc.register(tmp_path)) == ["RegHopperA-v0", "RegHopperB-v0"]
    same_rollout(gym.make("envc/RegHopperA-v0"), gym.make("Hopper-v5"), 7)
    same_rollout(envc.make("RegHopperB-v0"), gym.make("Hopper-v5"), 8)
    # the same file again: nothing changes
    assert sorted(envc.register(tmp_path)) == ["RegHopperA-v0", "RegHopperB-v0"]


def test_register_refuses_a_bundled_id(tmp_path):
    path = write(tmp_path, "mine.toml", spec_text("Hopper-v5", frame_skip=1))
    with pytest.raises(envc.SpecError) as e:
        envc.register(path)
    assert e.value.code == "E0603" and "bundled" in str(e.value)
    assert gym.make("envc/Hopper-v5").unwrapped.dt == 0.008


def test_register_refuses_an_id_registered_from_another_file(tmp_path):
    envc.register(write(tmp_path, "first.toml", spec_text("RegTwice-v0")))
    other = tmp_path / "other"
    other.mkdir()
    with pytest.raises(envc.SpecError) as e:
        envc.register(write(other, "second.toml", spec_text("RegTwice-v0", frame_skip=2)))
    assert e.value.code == "E0603"


def test_a_file_with_a_bundled_id_does_not_take_it_over(tmp_path):
    path = write(tmp_path, "hopper_fs1.toml", spec_text("Hopper-v5", frame_skip=1))
    env = envc.make(path)
    assert env.unwrapped.dt == 0.002  # the file's env
    assert gym.make("envc/Hopper-v5").unwrapped.dt == 0.008  # the bundled one, still
    assert envc.make("Hopper-v5").unwrapped.dt == 0.008


def test_envc_spec_path_registers_at_import(tmp_path):
    write(tmp_path, "mine.toml", spec_text("PathHopper-v0"))
    code = (
        "import gymnasium as gym, envc, numpy as np;"
        "e = gym.make('envc/PathHopper-v0'); r = gym.make('Hopper-v5');"
        "a = e.reset(seed=3)[0]; b = r.reset(seed=3)[0];"
        "print(a.tobytes() == b.tobytes(), 'PathHopper-v0' in [x[0] for x in envc._envc.registry()])"
    )
    out = subprocess.run(
        [sys.executable, "-c", code],
        env={**os.environ, "ENVC_SPEC_PATH": str(tmp_path)},
        capture_output=True,
        text=True,
        check=True,
    )
    assert out.stdout.split() == ["True", "True"]


def test_versions_agree():
    with open(os.path.join(ROOT, "Cargo.toml")) as f:
        cargo = next(line.split('"')[1] for line in f if line.startswith("version = "))
    assert envc.__version__ == cargo
    assert envc._envc.bundle_root()[0] == ROOT  # an editable install reads its checkout


def test_a_broken_or_unregistrable_spec_on_the_path_never_breaks_import(tmp_path):
    write(tmp_path, "good.toml", spec_text("PathGood-v0"))
    write(tmp_path, "broken.toml", "[env\nid = 'x'\n")
    write(tmp_path, "space.toml", spec_text("a b-v0"))
    write(tmp_path, "slash.toml", spec_text("envc/Foo-v0"))
    write(tmp_path, "empty.toml", spec_text(""))
    (tmp_path / "sub").mkdir()
    os.symlink(tmp_path, tmp_path / "sub" / "loop1")
    os.symlink("..", tmp_path / "sub" / "loop2")
    code = (
        "import warnings; warnings.simplefilter('always');"
        "import gymnasium as gym, envc;"
        "gym.make('envc/PathGood-v0');"
        "envc.register(envc.__file__.rsplit('/', 1)[0] + '/../../specs/gymnasium/hopper.toml');"
        "print('ok')"
    )
    out = subprocess.run(
        [sys.executable, "-c", code],
        env={**os.environ, "ENVC_SPEC_PATH": str(tmp_path)},
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 0 and out.stdout.split() == ["ok"], out.stderr
    for name in ("broken.toml", "E0111"):
        assert name in out.stderr, out.stderr
    # The same directory registered directly: the first problem is the error, nothing registered.
    with pytest.raises(envc.SpecError) as e:
        envc.register(tmp_path)
    assert e.value.code in ("E0111",) or "broken.toml" in str(e.value)
    with pytest.raises(envc.SpecError) as e:
        envc.register(tmp_path / "broken.toml")
    assert "holds no spec" not in str(e.value) and "broken.toml" in str(e.value)
    with pytest.raises(envc.SpecError) as e:
        envc.register(tmp_path / "space.toml")
    assert e.value.code == "E0111"


def test_one_id_in_two_files_of_a_directory_is_e0603_naming_both(tmp_path):
    write(tmp_path, "one.toml", spec_text("RegDup-v0"))
    write(tmp_path, "two.toml", spec_text("RegDup-v0", frame_skip=2))
    with pytest.raises(envc.SpecError) as e:
        envc.register(tmp_path)
    assert e.value.code == "E0603"
    assert "one.toml" in str(e.value) and "two.toml" in str(e.value)
    assert "envc/RegDup-v0" not in gym.registry


def test_making_a_second_file_with_the_same_id_does_not_take_the_id_over(tmp_path):
    a = write(tmp_path, "a.toml", spec_text("MadeTwice-v0"))
    sub = tmp_path / "b"
    sub.mkdir()
    b = write(sub, "b.toml", spec_text("MadeTwice-v0", frame_skip=2))
    assert envc.make(a).unwrapped.dt == 0.008
    assert envc.make(b).unwrapped.dt == 0.004  # b's own env...
    assert gym.make("envc/MadeTwice-v0").unwrapped.dt == 0.008  # ...but the id is still a's
    assert envc.make(a).unwrapped.dt == 0.008


def test_registering_file_after_file_stays_linear(tmp_path):
    import time

    paths = [write(tmp_path, f"s{i}.toml", spec_text(f"Lin{i}-v0")) for i in range(60)]
    t0 = time.perf_counter()
    for p in paths[:30]:
        envc.register(p)
    first = time.perf_counter() - t0
    t0 = time.perf_counter()
    for p in paths[30:]:
        envc.register(p)
    second = time.perf_counter() - t0
    # Each registration reads its own file, not every one registered before it.
    assert second < 3 * first + 0.5, (first, second)
