"""The batched GPU executor (envc.gpu, MJX backend) checked on CPU against the exact CPU core and
C MuJoCo: term parity on identical states, one-step physics, masked resets, refusals, and episode
statistics under a fixed policy. Expected values come from the Rust core and C MuJoCo only.

JAX runs on CPU here (float32, as on a GPU); the bounds are those docs/gpu.md states."""

from __future__ import annotations

import os

import numpy as np
import pytest

# Cheaper XLA CPU compiles (the MJX step is a large program; run time here is negligible).
os.environ.setdefault(
    "XLA_FLAGS", "--xla_backend_optimization_level=0 --xla_llvm_disable_expensive_passes=true"
)
# XLA's compiled programs kept between runs (keyed by program, flags and jax version): a warm
# suite skips the compiles that are most of this file's time.
os.environ.setdefault(
    "JAX_COMPILATION_CACHE_DIR",
    os.path.join(os.path.dirname(__file__), "..", "..", "target", "jax-cache"),
)
jax = pytest.importorskip("jax")
pytest.importorskip("mujoco.mjx")

import jax.numpy as jnp  # noqa: E402
import mujoco  # noqa: E402
from mujoco import mjx  # noqa: E402

import envc  # noqa: E402
from envc import _envc, gpu  # noqa: E402
from envc.gpu import _mjx  # noqa: E402
from envc.gpu._executor import Executor  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
GO1_XML = os.path.abspath(os.path.join(ROOT, "..", "shared", "models", "unitree_go1", "scene.xml"))

# Term parity bound (docs/gpu.md): |gpu − cpu| ≤ ATOL + RTOL·|cpu| per element, float32 terms
# on the CPU core's own float64 states.
RTOL, ATOL = 1e-5, 1e-4


def _replay(spec_id, overrides, seed, steps, rng):
    """Run the CPU core for `steps` steps (random actions, no autoreset) and replay the same
    calls in C MuJoCo (Gymnasium's reset: mj_resetData, qpos/qvel, mj_forward; then ctrl and
    frame_skip × mj_step, mj_rnePostConstraint). Yields (data before, data after, action, CPU
    core's step output) for every step; the replay's state must equal the core's bit for bit."""
    kind, core = _envc.open(spec_id, envc.overrides_to_toml(overrides))
    assert kind == "task"
    p = gpu.plan(spec_id, **overrides)
    m = _mjx.load_mjmodel(p.mjb)
    d = mujoco.MjData(m)
    core.reset(seed)
    qpos, qvel = core.state()
    mujoco.mj_resetData(m, d)
    d.qpos[:], d.qvel[:] = qpos, qvel
    mujoco.mj_forward(m, d)
    lo, hi = core.act_low, core.act_high
    out = []
    for _ in range(steps):
        a = rng.uniform(lo, hi)
        before = mujoco.MjData(m)
        mujoco.mj_copyData(before, m, d)
        step = core.step(a)
        d.ctrl[:] = a
        for _ in range(p["frame_skip"]):
            mujoco.mj_step(m, d)
        if p["needs_rne_post_constraint"]:
            mujoco.mj_rnePostConstraint(m, d)
        q, v = core.state()
        np.testing.assert_array_equal(d.qpos, q)
        np.testing.assert_array_equal(d.qvel, v)
        out.append((before, _copy(m, d), a, step))
        if step[2] or step[3]:
            break
    return p, m, out


def _newton(p):
    """The plan with its model's solver set to Newton when MJX refuses the model's (PGS:
    Humanoid): the terms read fields of given states, which no solver touches."""
    m = _mjx.load_mjmodel(p.mjb)
    if m.opt.solver != mujoco.mjtSolver.mjSOL_PGS:
        return p
    m.opt.solver = mujoco.mjtSolver.mjSOL_NEWTON
    buf = np.zeros(mujoco.mj_sizeModel(m), np.uint8)
    mujoco.mj_saveModel(m, None, buf)
    return gpu.Plan(p.raw, buf.tobytes())


def _copy(m, d):
    c = mujoco.MjData(m)
    mujoco.mj_copyData(c, m, d)
    return c


def _stack(ds):
    return jax.tree_util.tree_map(lambda *xs: jnp.stack(xs), *ds)


@pytest.mark.parametrize(
    "spec_id,overrides,seeds,steps",
    [
        ("Ant-v5", {"reset_noise_scale": 0.3}, range(3), 60),
        ("Humanoid-v5", {}, range(2), 40),
        ("Hopper-v5", {}, range(2), 60),
        ("Reacher-v5", {}, range(2), 50),
    ],
)
def test_term_parity_with_the_cpu_core(spec_id, overrides, seeds, steps):
    rng = np.random.default_rng(7)
    worst = 0.0
    for seed in seeds:
        p, m, rows = _replay(spec_id, overrides, seed, steps, rng)
        backend = _mjx.MjxBackend(_newton(p), None)
        ex = Executor(p, backend, 1)
        before = _stack([mjx.put_data(m, r[0], impl="jax") for r in rows])
        after = _stack([mjx.put_data(m, r[1], impl="jax") for r in rows])
        act = jnp.asarray(np.stack([r[2] for r in rows]), jnp.float32)

        def world(db, da, a):
            from envc.gpu import _terms

            f0 = backend.fields(db, a)
            bv = _terms.before_values(p, f0)
            pv, pu = _terms.terms(p, f0, bv, jnp.bool_(True), ex.dt, ex.timestep, True)
            return ex.evaluate(da, a, bv, pv, pu)

        obs, rew, term, info = jax.jit(jax.vmap(world))(before, after, act)
        for k, (_, _, _, (o, r, t, _tr, inf)) in enumerate(rows):
            err = np.abs(np.asarray(obs[k], np.float64) - o)
            assert np.all(err <= ATOL + RTOL * np.abs(o)), (spec_id, seed, k, err.max())
            worst = max(worst, float(err.max()), abs(float(rew[k]) - r))
            assert abs(float(rew[k]) - r) <= ATOL + RTOL * abs(r), (spec_id, k, float(rew[k]), r)
            assert bool(term[k]) == t
            assert set(info) == set(inf), (set(info), set(inf))
            for key, v in inf.items():
                g = np.asarray(info[key][k], np.float64)
                assert np.all(np.abs(g - v) <= ATOL + RTOL * np.abs(v)), (key, g, v)
    print(f"{spec_id}: worst |gpu - cpu| = {worst:.3g}")


def test_one_step_physics_matches_c_mujoco():
    """One `mjx.step` from C MuJoCo's states matches one `mj_step` (float32 MJX against float64
    C MuJoCo; bound in docs/gpu.md)."""
    rng = np.random.default_rng(3)
    p, m, rows = _replay("Hopper-v5", {}, 0, 40, rng)
    states = [r[0] for r in rows[::4]]
    want = []
    for s in states:
        c = _copy(m, s)
        c.ctrl[:] = rng.uniform(-1, 1, m.nu)
        want.append(c)
    mx = mjx.put_model(m, impl="jax")
    dx = _stack([mjx.put_data(m, c, impl="jax") for c in want])
    got = jax.jit(jax.vmap(lambda d: mjx.step(mx, d)))(dx)
    for k, c in enumerate(want):
        mujoco.mj_step(m, c)
        np.testing.assert_allclose(np.asarray(got.qpos[k]), c.qpos, atol=1e-4, rtol=1e-4)
        np.testing.assert_allclose(np.asarray(got.qvel[k]), c.qvel, atol=5e-3, rtol=1e-3)


N_PENDULUM = 256


@pytest.fixture(scope="module")
def pendulum():
    """One batched InvertedPendulum-v5 for the executor-level tests (compiled once)."""
    return envc.make_vec(
        "InvertedPendulum-v5", num_envs=N_PENDULUM, backend="mjx", device="cpu", seed=1
    )


def test_the_gpu_env_has_gymnasiums_vector_attributes(pendulum):
    """`single_observation_space`, `single_action_space` and the batched spaces, as every
    Gymnasium vector env has them: the action range is the CPU vector env's (the spec's), and the
    views hand on the same spaces."""
    cpu = envc.make_vec("InvertedPendulum-v5", 2)
    try:
        assert pendulum.single_action_space == cpu.single_action_space
        assert pendulum.single_action_space.low.tolist() == [-3.0]
        assert pendulum.single_observation_space.shape == cpu.single_observation_space.shape
        assert pendulum.single_observation_space.dtype == np.float32
        assert pendulum.action_space.shape == (N_PENDULUM, 1)
        assert pendulum.observation_space.shape == (N_PENDULUM, 4)
        view = pendulum.as_gymnasium()
        assert view.single_action_space == pendulum.single_action_space
        assert view.observation_space == pendulum.observation_space
    finally:
        cpu.close()


def test_masked_reset_touches_only_its_worlds(pendulum):
    env = pendulum
    env.reset(seed=1)
    for _ in range(3):
        env.step(jnp.full((N_PENDULUM, 1), 0.0, jnp.float32))
    before = env.state
    mask = np.arange(N_PENDULUM) % 3 == 0
    env.reset(mask=mask)
    after = env.state
    keep = ~mask
    for a, b in zip(jax.tree_util.tree_leaves(before.data), jax.tree_util.tree_leaves(after.data)):
        np.testing.assert_array_equal(np.asarray(a)[keep], np.asarray(b)[keep])
    np.testing.assert_array_equal(np.asarray(before.obs)[keep], np.asarray(after.obs)[keep])
    assert np.all(np.asarray(after.elapsed)[mask] == 0)
    assert np.all(np.asarray(after.elapsed)[keep] == 3)
    # The reset worlds start from the spec's draws: qpos0 + U(±0.01), qvel U(±0.01).
    q = np.asarray(after.data.qpos)[mask]
    assert np.all(np.abs(q) <= 0.01 + 1e-7)
    assert not np.allclose(q, np.asarray(before.data.qpos)[mask])


def test_resampled_reset_draws_follow_the_cpu_cores_distribution():
    """Reacher-v5's goal is drawn until its norm is below 0.2 (`resample_until`): the executor's
    goals (512 worlds) and the CPU core's (300 seeds) agree in distribution (KS on the radius and
    on x), and every goal meets the condition."""
    from scipy import stats

    env = envc.make_vec("Reacher-v5", num_envs=512, backend="mjx", device="cpu", seed=3)
    env.reset()
    goal = np.asarray(env.state.data.qpos)[:, 2:4]
    cpu = []
    for seed in range(300):
        _, core = _envc.open("Reacher-v5", [])
        core.reset(seed)
        cpu.append(core.state()[0][2:4])
    cpu = np.array(cpu)
    r_gpu, r_cpu = np.linalg.norm(goal, axis=1), np.linalg.norm(cpu, axis=1)
    assert np.all(r_gpu < 0.2) and np.all(np.abs(goal) <= 0.2)
    assert stats.ks_2samp(r_gpu, r_cpu).pvalue > 1e-3
    assert stats.ks_2samp(goal[:, 0], cpu[:, 0]).pvalue > 1e-3


def test_a_model_mjx_cannot_run_is_refused_with_the_code():
    with pytest.raises(gpu.Unsupported) as e:
        envc.make_vec("Humanoid-v5", num_envs=2, backend="mjx", device="cpu")
    assert e.value.code == "E1700"
    assert e.value.parts == ["the compiled model: MJX says: mjtSolver.mjSOL_PGS"]


def test_unsupported_parts_are_refused_with_one_coded_error():
    with pytest.raises(gpu.Unsupported) as e:
        envc.make_vec(
            os.path.join(ROOT, "specs", "examples", "go1_joystick.toml"),
            num_envs=2,
            backend="mjx",
            device="cpu",
            xml_file=GO1_XML,
        )
    err = e.value
    assert err.code == "E1700" and "error[E1700]" in str(err)
    parts = "\n".join(err.parts)
    for want in (
        "[commands.base_velocity]",
        '[actions] kind = "pd_position"',
        '[reward.tracking_lin_vel] kind = "tracking"',
        '[reward.feet_air_time] kind = "feet_air_time"',
        "site_local_linvel",
        "last_action",
        "the compiled model: MJX says: condim=1 with ConeType.ELLIPTIC not implemented",
    ):
        assert want in parts, (want, parts)
    assert isinstance(err, envc.SpecError)


def test_gymnasium_view_and_episode_statistics_match_the_cpu_core(pendulum):
    """Zero actions on InvertedPendulum-v5: the pole falls after a number of steps set by the
    reset draws. Episode lengths (= returns) from the GPU executor and from the CPU core over
    many seeds agree (two-sample KS test, and the means within 4 standard errors), and every
    return equals its length minus the unrewarded terminal step, as on the CPU core."""
    from scipy import stats

    n = N_PENDULUM
    view = pendulum.as_gymnasium()
    obs, _ = view.reset(seed=5)
    assert obs.shape == (n, 4) and obs.dtype == np.float32
    # Each world's first episode only: later ones would over-sample short episodes.
    lengths, returns, ret = [], [], np.zeros(n)
    steps = np.zeros(n, int)
    first = np.ones(n, bool)
    act = np.zeros((n, 1), np.float32)
    for _ in range(120):
        obs, rew, term, trunc, info = view.step(act)
        assert set(info) >= {"final_obs", "reward_survive"}
        ret += rew
        steps += 1
        done = term | trunc
        lengths += list(steps[done & first])
        returns += list(ret[done & first])
        first &= ~done
        ret[done] = 0
        steps[done] = 0
    assert not first.any(), "every world ends an episode within 120 steps"
    gpu_len, gpu_ret = np.array(lengths), np.array(returns)
    cpu_len, cpu_ret = [], []
    for seed in range(300):
        _, core = _envc.open("InvertedPendulum-v5", [])
        core.reset(seed)
        total = 0.0
        for t in range(1000):
            _, r, term, trunc, _ = core.step(np.zeros(1))
            total += r
            if term or trunc:
                cpu_len.append(t + 1)
                cpu_ret.append(total)
                break
    for name, g, c in (("length", gpu_len, cpu_len), ("return", gpu_ret, cpu_ret)):
        c = np.array(c)
        se = np.sqrt(g.var() / len(g) + c.var() / len(c))
        p = stats.ks_2samp(g, c).pvalue
        print(f"{name}: gpu {g.mean():.2f} (n={len(g)}), cpu {c.mean():.2f}, KS p={p:.3g}")
        assert abs(g.mean() - c.mean()) <= 4 * se + 0.5, (name, g.mean(), c.mean(), se)
        assert p > 1e-3, (name, p)


def _reacher_goal_below(tmp_path, bound: float) -> str:
    with open(os.path.join(ROOT, "specs", "gymnasium", "reacher.toml")) as f:
        text = f.read()
    text = text.replace("resample_until = { norm_below = 0.2 }", f"resample_until = {{ norm_below = {bound} }}")
    text = text.replace("../../assets/", os.path.join(ROOT, "assets") + "/")
    path = tmp_path / "reacher.toml"
    path.write_text(text)
    return str(path)


def test_rare_resample_conditions_hold_in_every_world_and_impossible_ones_are_e1104(tmp_path):
    """A goal that must lie within 0.005 (one candidate in ~2,000 passes): every world's goal
    meets it, as on the CPU core, instead of the 64th candidate being kept."""
    env = envc.make_vec(
        _reacher_goal_below(tmp_path, 0.005), num_envs=64, backend="mjx", device="cpu", seed=2
    )
    env.reset()
    goal = np.asarray(env.state.data.qpos)[:, 2:4]
    assert np.all(np.linalg.norm(goal, axis=1) < 0.005)
    # Met by no draw within the limit (about one in 10¹⁰): E1104, as the CPU core.
    env = envc.make_vec(
        _reacher_goal_below(tmp_path, 2e-6), num_envs=2, backend="mjx", device="cpu", seed=2
    )
    with pytest.raises(envc.Error) as e:
        env.reset()
    assert e.value.code == "E1104"


def test_bad_calls_carry_codes_and_nonfinite_actions_are_e1102(pendulum):
    env = envc.gpu.make_vec("InvertedPendulum-v5", num_envs=2, backend="mjx", device="cpu")
    with pytest.raises(envc.Error) as e:
        env.step(jnp.zeros((2, 1)))
    assert e.value.code == "E1103"
    env.reset(seed=0)
    for bad in (jnp.zeros((3, 1)), jnp.zeros((2,)), np.array([["0"], ["0"]])):
        with pytest.raises(envc.Error) as e:
            env.step(bad)
        assert e.value.code == "E1101", bad
    for x in (np.nan, np.inf, -np.inf):
        with pytest.raises(envc.Error) as e:
            env.step(jnp.full((2, 1), x))
        assert e.value.code == "E1102"
    env.step(jnp.zeros((2, 1)))
    for kwargs, code in (({"backend": "nope"}, "E1105"), ({"device": "tpu9"}, "E1105")):
        with pytest.raises(envc.Error) as e:
            envc.gpu.make_vec("InvertedPendulum-v5", num_envs=2, **{"device": "cpu", **kwargs})
        assert e.value.code == code


def test_physics_options_mjx_ignores_are_e1700(tmp_path):
    with open(os.path.join(ROOT, "specs", "gymnasium", "inverted_pendulum.toml")) as f:
        text = f.read().replace("../../assets/", os.path.join(ROOT, "assets") + "/")
    path = tmp_path / "ip.toml"
    path.write_text(text + "\n[physics]\nnoslip_iterations = 3\nccd_iterations = 50\n")
    with pytest.raises(gpu.Unsupported) as e:
        envc.gpu.make_vec(str(path), num_envs=2, backend="mjx", device="cpu")
    parts = "\n".join(e.value.parts)
    assert "noslip_iterations" in parts and "ccd_iterations" in parts


def test_gpu_is_an_attribute_of_envc():
    import subprocess
    import sys

    code = "import envc; print(envc.gpu.backends())"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert "mjx" in out.stdout
